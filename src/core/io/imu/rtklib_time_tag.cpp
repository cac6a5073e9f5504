#include "ppp_bayes_tree/io/imu/rtklib_time_tag.h"

#include <cstring>
#include <fstream>
#include <iterator>

namespace ppp {
namespace {

constexpr std::size_t kHeaderTextBytes = 60;
constexpr std::size_t kHeaderBytes = kHeaderTextBytes + 4 + 4 + 8;
constexpr std::size_t kRecordBytes = 8;
constexpr const char* kMagic = "TIMETAG RTKLIB";

template <typename T>
T readLittleEndian(const std::string& bytes, std::size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));  // x86 and ARM hosts are little-endian
  return value;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileOpenError("cannot open time-tag file " + path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

GnssTime RtklibTimeTag::lastRecordTime() const {
  return records.empty() ? start : start + records.back().elapsed_ms * 1e-3;
}

RtklibTimeTag readRtklibTimeTag(const std::string& path) {
  const std::string bytes = fileBytes(path);
  if (bytes.size() < kHeaderBytes)
    throw ParseError(path, 0, "time-tag header needs " + std::to_string(kHeaderBytes) + " bytes, file has " +
                                  std::to_string(bytes.size()));
  RtklibTimeTag tag;
  tag.report.setFile(path);
  tag.header_text = std::string(bytes.c_str(), strnlen(bytes.c_str(), kHeaderTextBytes));
  if (tag.header_text.rfind(kMagic, 0) != 0)
    throw ParseError(path, 0, "not an RTKLIB time-tag file (header '" + tag.header_text + "')");
  tag.start_tick_ms = readLittleEndian<std::uint32_t>(bytes, kHeaderTextBytes);
  const auto whole_s = readLittleEndian<std::uint32_t>(bytes, kHeaderTextBytes + 4);
  const auto fraction_s = readLittleEndian<double>(bytes, kHeaderTextBytes + 8);
  if (!(fraction_s >= 0.0 && fraction_s < 1.0))
    throw ParseError(path, 0, "start-time fraction at byte " + std::to_string(kHeaderTextBytes + 8) +
                                  " is not in [0, 1): " + std::to_string(fraction_s));
  tag.start = GnssTime::fromGpsSeconds(static_cast<std::int64_t>(whole_s) - kUnixToGpsEpoch_s, fraction_s);
  std::size_t offset = kHeaderBytes;
  for (; offset + kRecordBytes <= bytes.size(); offset += kRecordBytes)
    tag.records.push_back({readLittleEndian<std::uint32_t>(bytes, offset),
                           readLittleEndian<std::uint32_t>(bytes, offset + 4)});
  if (offset != bytes.size()) {
    tag.report.count("cut record");
    tag.report.addProblem(0, "cut record: " + std::to_string(bytes.size() - offset) + " bytes at byte offset " +
                                 std::to_string(offset));
  }
  return tag;
}

}  // namespace ppp
