#pragma once
// The satellite antenna model a precise product file says its orbits and clocks
// were estimated with: the SP3 comment "/* PCV:<model>" (e.g. "PCV:IGS14_2108")
// or the RINEX clock header's "SYS / PCVS APPLIED" file name (e.g.
// "igs14_2108.atx"). The product assembly reads it; the PPP-AR gate compares it
// with the ANTEX (ppp/ambiguity/antenna_model_consistency.h).
#include <string>

namespace ppp {

/// The antenna model a product file names in its header: the "/* PCV:" comment of an SP3 file,
/// or the "SYS / PCVS APPLIED" file name of a RINEX clock file (extension removed). Plain or gzip.
/// Empty when the header names none. Throws FileOpenError when the file cannot be opened.
std::string productAntennaModel(const std::string& path);

}  // namespace ppp
