#include "ppp_bayes_tree/io/file_summary.h"

#include <cstdio>
#include <limits>
#include <sstream>

#include "ppp_bayes_tree/io/transport/untrusted_text.h"

namespace ppp {

namespace {
std::string shortTime(const GnssTime& t) { return t.toString(TimeSystem::GPS, 1); }
/// Text read from a file (header fields, problem texts quoting it), safe for a terminal.
std::string printable(const std::string& text) { return printableText(text, std::numeric_limits<std::size_t>::max()); }

}  // namespace

std::string formatSummary(const FileSummary& s) {
  std::ostringstream os;
  os << "== " << s.path << "\n";
  os << "  type      " << s.type;
  if (!s.version.empty()) os << ", version " << s.version;
  os << "\n";
  if (s.first_epoch && s.last_epoch) {
    char dur[64];
    std::snprintf(dur, sizeof(dur), "%.1f min", (*s.last_epoch - *s.first_epoch) / 60.0);
    os << "  span      " << shortTime(*s.first_epoch) << " .. " << shortTime(*s.last_epoch) << " ("
       << dur << ")\n";
  }
  if (s.interval_s || s.epoch_count > 0) {
    os << "  count     " << s.epoch_count << " " << s.count_label;
    if (s.interval_s) os << ", " << s.interval_label << " " << *s.interval_s << " s";
    os << "\n";
  }
  for (const auto& [system, sats] : s.satellites) {
    os << "  " << systemLetter(system) << " " << systemName(system) << ": " << sats.size()
       << " satellite(s):";
    for (const auto& sat : sats) os << " " << sat.toString();
    os << "\n";
  }
  for (const auto& [system, signals] : s.signals) {
    os << "  " << systemLetter(system) << " signals:";
    for (const auto& sig : signals) os << " " << printable(sig);
    os << "\n";
  }
  for (const auto& fact : s.facts) os << "  " << printable(fact) << "\n";
  for (const auto& [what, n] : s.report.counters()) os << "  " << printable(what) << ": " << n << "\n";
  if (s.report.problemCount() == 0) {
    os << "  problems: none\n";
  } else {
    os << "  problems: " << s.report.problemCount() << "\n";
    std::size_t shown = 0;
    for (const auto& p : s.report.problems()) {
      if (shown++ == 20) break;
      os << "    ";
      if (p.line > 0) os << "line " << p.line << ": ";
      os << printable(p.reason) << "\n";
    }
    if (s.report.problemCount() > 20) os << "    ... and " << (s.report.problemCount() - 20) << " more\n";
  }
  os << "\n";
  return os.str();
}

}  // namespace ppp
