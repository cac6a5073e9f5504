#include "ppp_bayes_tree/smoother/ordering.h"

#include <ccolamd.h>

#include <stdexcept>
#include <string>

namespace ppp::smoother {

Ordering computeOrdering(const std::vector<KeyVector>& factor_keys, const KeyVector& keys,
                         const std::unordered_map<Key, int>* groups) {
  std::vector<const KeyVector*> pointers;
  pointers.reserve(factor_keys.size());
  for (const KeyVector& f : factor_keys) pointers.push_back(&f);
  return computeOrdering(pointers, keys, groups);
}

namespace {

/// The factor (row) x variable (column) incidence pattern in CCOLAMD's column-major
/// form: a (rows of each column, in increasing order, with CCOLAMD's workspace) and
/// p (column starts; CCOLAMD leaves the ordering in it).
struct IncidencePattern {
  int n_row = 0;
  std::vector<int> a, p;
};

/// The pattern in two passes (count per column, then fill); factors without a key
/// of `column` take no row.
IncidencePattern incidencePattern(const std::vector<const KeyVector*>& factor_keys,
                                  const std::unordered_map<Key, int>& column, int n_col) {
  IncidencePattern m;
  std::vector<int> entry_column;  // per (factor, key) entry: its column, or -1
  m.p.assign(n_col + 1, 0);
  int nnz = 0;
  for (const KeyVector* f : factor_keys) {
    bool any = false;
    for (Key k : *f) {
      auto it = column.find(k);
      entry_column.push_back(it == column.end() ? -1 : it->second);
      if (it == column.end()) continue;
      ++m.p[it->second + 1];
      ++nnz;
      any = true;
    }
    if (any) ++m.n_row;
  }
  for (int j = 0; j < n_col; ++j) m.p[j + 1] += m.p[j];
  const std::size_t alen = ccolamd_recommended(nnz, m.n_row, n_col);
  if (alen == 0) throw std::runtime_error("computeOrdering: problem too large for CCOLAMD");
  m.a.assign(alen, 0);
  std::vector<int> fill(m.p.begin(), m.p.end() - 1);
  int row = 0;
  std::size_t e = 0;
  for (const KeyVector* f : factor_keys) {
    bool any = false;
    for (std::size_t i = 0; i < f->size(); ++i, ++e) {
      const int j = entry_column[e];
      if (j < 0) continue;
      m.a[fill[j]++] = row;
      any = true;
    }
    if (any) ++row;
  }
  return m;
}

}  // namespace

Ordering computeOrdering(const std::vector<const KeyVector*>& factor_keys, const KeyVector& keys,
                         const std::unordered_map<Key, int>* groups) {
  const int n_col = static_cast<int>(keys.size());
  if (n_col <= 1) return keys;
  // 1. A column per key.
  std::unordered_map<Key, int> column;
  column.reserve(keys.size());
  for (int j = 0; j < n_col; ++j)
    if (!column.emplace(keys[j], j).second)
      throw std::invalid_argument("computeOrdering: duplicate key " + keyToString(keys[j]));
  // 2. The incidence pattern of the factors.
  IncidencePattern m = incidencePattern(factor_keys, column, n_col);
  // 3. The constraint group of each column (none: one group).
  std::vector<int> cmember;
  if (groups && !groups->empty()) {
    cmember.assign(n_col, 0);
    for (int j = 0; j < n_col; ++j) {
      auto it = groups->find(keys[j]);
      if (it != groups->end()) cmember[j] = it->second;
    }
  }
  // 4. CCOLAMD; p then holds the columns in elimination order.
  double knobs[CCOLAMD_KNOBS];
  int stats[CCOLAMD_STATS];
  ccolamd_set_defaults(knobs);
  const int ok = ccolamd(m.n_row, n_col, static_cast<int>(m.a.size()), m.a.data(), m.p.data(), knobs, stats,
                         cmember.empty() ? nullptr : cmember.data());
  if (!ok) throw std::runtime_error("CCOLAMD failed with status " + std::to_string(stats[CCOLAMD_STATUS]));
  Ordering out(n_col);
  for (int k = 0; k < n_col; ++k) out[k] = keys[m.p[k]];
  return out;
}

}  // namespace ppp::smoother
