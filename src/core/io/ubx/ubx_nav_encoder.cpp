#include "ppp_bayes_tree/io/ubx/ubx_nav_encoder.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ubx_nav_layout.h"

namespace ppp {
namespace {

using namespace ubx_nav;

void putU4(std::vector<std::uint8_t>& p, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}

UbxFrameBytes sfrbxFrame(int gnss_id, int sv_id, int sig_id, int freq_id, const std::vector<std::uint32_t>& words) {
  std::vector<std::uint8_t> p(8 + 4 * words.size(), 0);
  p[0] = static_cast<std::uint8_t>(gnss_id);
  p[1] = static_cast<std::uint8_t>(sv_id);
  p[2] = static_cast<std::uint8_t>(sig_id);
  p[3] = static_cast<std::uint8_t>(freq_id);
  p[4] = static_cast<std::uint8_t>(words.size());
  p[6] = 2;  // version
  for (std::size_t i = 0; i < words.size(); ++i) putU4(p, 8 + 4 * i, words[i]);
  return encodeUbxFrame(0x02, 0x13, p);
}

}  // namespace

std::vector<UbxFrameBytes> encodeGlonassSfrbx(const GlonassEphemeris& eph, std::uint16_t frame_id) {
  std::array<Unit, 5> s{};
  const bool sm = true;
  for (int m = 1; m <= 5; ++m) setBits(s[static_cast<std::size_t>(m - 1)], 1, 4, static_cast<std::uint64_t>(m));
  putField(s, glo::kX, eph.position_m.x() * 1e-3, "x", sm);
  putField(s, glo::kY, eph.position_m.y() * 1e-3, "y", sm);
  putField(s, glo::kZ, eph.position_m.z() * 1e-3, "z", sm);
  putField(s, glo::kVx, eph.velocity_mps.x() * 1e-3, "vx", sm);
  putField(s, glo::kVy, eph.velocity_mps.y() * 1e-3, "vy", sm);
  putField(s, glo::kVz, eph.velocity_mps.z() * 1e-3, "vz", sm);
  putField(s, glo::kAx, eph.acceleration_mps2.x() * 1e-3, "ax", sm);
  putField(s, glo::kAy, eph.acceleration_mps2.y() * 1e-3, "ay", sm);
  putField(s, glo::kAz, eph.acceleration_mps2.z() * 1e-3, "az", sm);
  putField(s, glo::kGammaN, eph.gamma_n, "gamma_n", sm);
  putField(s, glo::kTauN, -eph.minus_tau_n_s, "tau_n", sm);
  putField(s, glo::kBn, eph.health ? 4.0 : 0.0, "Bn");
  putField(s, glo::kEn, eph.age_days, "E_n");
  putField(s, glo::kSlot, eph.satellite.prn, "slot n");
  putField(s, glo::kM, 1.0, "M");
  // tb: 15-min index of the Moscow day; tk: Moscow time of day to 30 s.
  const double tb_index = glonassSecondsOfDay(eph.tb) / 900.0;
  if (std::fabs(tb_index - std::round(tb_index)) > 1e-6)
    throw std::invalid_argument("SFRBX encoder: GLONASS tb is not on a 15-min boundary of the Moscow day");
  putField(s, glo::kTb, std::round(tb_index), "tb");
  const double tk_sod = glonassSecondsOfDayFromUtc(eph.message_frame_time_s);
  const int tk30 = static_cast<int>(std::floor(tk_sod / 30.0 + 1e-9));
  putField(s, glo::kTkHours, tk30 / 120, "tk hours");
  putField(s, glo::kTkMinutes, (tk30 / 2) % 60, "tk minutes");
  putField(s, glo::kTkHalfMinute, tk30 % 2, "tk 30 s");
  std::vector<UbxFrameBytes> out;
  for (auto& str : s) {
    setGlonassHamming(str);
    std::vector<std::uint32_t> words(4, 0);
    for (int w = 0; w < 3; ++w) words[static_cast<std::size_t>(w)] = static_cast<std::uint32_t>(getBits(str, 32 * w, 32));
    words[2] &= 0xFFFFF800u;  // bits after b1 are not part of the string
    words[3] = static_cast<std::uint32_t>(frame_id) << 16;
    out.push_back(sfrbxFrame(6, eph.satellite.prn, 0, eph.frequency_channel + 7, words));
  }
  return out;
}

std::vector<UbxFrameBytes> encodeBeidouSfrbx(const BeidouEphemeris& eph, std::uint32_t sow) {
  const bool geo = eph.isGeo();
  const int urai = beidouUraIndex(eph.ura_m);
  const int week13 = eph.bdt_week % 8192;
  const double toc_sow = toBdtWeek(eph.clock.toc).seconds_of_week;
  std::vector<UbxFrameBytes> out;
  auto emit = [&](Unit& u, int fra, std::uint32_t part_sow, int sig) {
    setBits(u, 0, 11, 0x712u);  // preamble
    setBits(u, 15, 3, static_cast<std::uint64_t>(fra));
    setBits(u, 18, 8, part_sow >> 12);
    setBits(u, 30, 12, part_sow & 0xFFFu);
    for (int w = 0; w < 10; ++w) setBdsParity(u, w);
    std::vector<std::uint32_t> words(10);
    for (int w = 0; w < 10; ++w) words[static_cast<std::size_t>(w)] = static_cast<std::uint32_t>(getBits(u, 30 * w, 30));
    out.push_back(sfrbxFrame(3, eph.satellite.prn, sig, 0, words));
  };
  std::array<Unit, 10> u{};
  writeBeidou(u, geo ? kBdsD2 : kBdsD1, eph, {urai, week13, toc_sow});
  if (!geo) {
    for (int k = 0; k < 3; ++k) emit(u[static_cast<std::size_t>(k)], k + 1, sow + 6u * static_cast<std::uint32_t>(k), 0);
    return out;
  }
  for (int k = 0; k < 10; ++k) {
    setBits(u[static_cast<std::size_t>(k)], 42, 4, static_cast<std::uint64_t>(k + 1));  // Pnum
    emit(u[static_cast<std::size_t>(k)], 1, sow + 3u * static_cast<std::uint32_t>(k), 1);
  }
  return out;
}

UbxFrameBytes encodeRawxTime(const GnssTime& t) {
  const GpsWeekTime w = t.gpsWeek();
  std::vector<std::uint8_t> p(16, 0);
  double tow = w.seconds_of_week;
  std::uint64_t bits;
  std::memcpy(&bits, &tow, sizeof bits);
  for (int i = 0; i < 8; ++i) p[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(bits >> (8 * i));
  p[8] = static_cast<std::uint8_t>(w.week & 0xFF);
  p[9] = static_cast<std::uint8_t>(w.week >> 8);
  p[10] = 18;   // leapS
  p[11] = 0;    // numMeas
  p[12] = 0x01; // recStat: leap seconds valid
  p[13] = 1;    // version
  return encodeUbxFrame(0x02, 0x15, p);
}

}  // namespace ppp
