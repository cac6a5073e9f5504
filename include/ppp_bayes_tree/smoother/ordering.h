#pragma once
// Fill-reducing elimination orderings from SuiteSparse COLAMD/CCOLAMD (Davis et al.,
// "A column approximate minimum degree ordering algorithm", ACM TOMS 30(3), 2004; CCOLAMD
// adds constraint groups). The matrix ordered is the factor-variable incidence pattern
// (one row per factor, one column per variable).
//
// Constraint groups: every variable of group g is eliminated before any variable of
// group g+1. iSAM2 puts the most recent variables, named by the caller, in the last group
// so that they land in the root clique (Kaess et al. IJRR 2012, Sec. 5.2).
#include <unordered_map>
#include <vector>

#include "ppp_bayes_tree/smoother/key.h"

namespace ppp::smoother {

using Ordering = KeyVector;

/// Orders `keys` (each must be distinct) by CCOLAMD on the pattern of `factor_keys`
/// (keys not in `keys` are ignored). `groups` gives a key's constraint group (absent
/// keys: group 0); null or empty means unconstrained (COLAMD behaviour).
/// Throws std::runtime_error if CCOLAMD reports an error.
Ordering computeOrdering(const std::vector<KeyVector>& factor_keys, const KeyVector& keys,
                         const std::unordered_map<Key, int>* groups = nullptr);
/// The same, the factors' keys given by pointer (iSAM2 orders the keys of factors it
/// holds, without copying them).
Ordering computeOrdering(const std::vector<const KeyVector*>& factor_keys, const KeyVector& keys,
                         const std::unordered_map<Key, int>* groups = nullptr);

}  // namespace ppp::smoother
