#include "ppp_bayes_tree/types/beidou_ephemeris.h"

#include "ppp_bayes_tree/types/broadcast_accuracy.h"

namespace ppp {

// BDS-SIS-ICD-B1I 5.2.4.5 defines the URA index as IS-GPS-200 does: one table
// (types/broadcast_accuracy.h), the nominal values RINEX and convbin write.
double beidouUra_m(int index) { return gpsUra_m(index); }

int beidouUraIndex(double ura_m) { return gpsUraIndex(ura_m); }

}  // namespace ppp
