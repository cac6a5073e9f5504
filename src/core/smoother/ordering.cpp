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

Ordering computeOrdering(const std::vector<const KeyVector*>& factor_keys, const KeyVector& keys,
                         const std::unordered_map<Key, int>* groups) {
  const int n_col = static_cast<int>(keys.size());
  if (n_col <= 1) return keys;
  std::unordered_map<Key, int> column;
  column.reserve(keys.size());
  for (int j = 0; j < n_col; ++j)
    if (!column.emplace(keys[j], j).second)
      throw std::invalid_argument("computeOrdering: duplicate key " + keyToString(keys[j]));

  // Column-major pattern of the factor (row) x variable (column) incidence matrix, in
  // two passes (count per column, then fill): each column's rows in increasing order.
  std::vector<int> entry_column;  // per (factor, key) entry: its column, or -1
  std::vector<int> p(n_col + 1, 0);
  int n_row = 0, nnz = 0;
  for (const KeyVector* f : factor_keys) {
    bool any = false;
    for (Key k : *f) {
      auto it = column.find(k);
      entry_column.push_back(it == column.end() ? -1 : it->second);
      if (it == column.end()) continue;
      ++p[it->second + 1];
      ++nnz;
      any = true;
    }
    if (any) ++n_row;
  }
  for (int j = 0; j < n_col; ++j) p[j + 1] += p[j];
  const std::size_t alen = ccolamd_recommended(nnz, n_row, n_col);
  if (alen == 0) throw std::runtime_error("computeOrdering: problem too large for CCOLAMD");
  std::vector<int> a(alen);
  std::vector<int> fill(p.begin(), p.end() - 1);
  int row = 0;
  std::size_t e = 0;
  for (const KeyVector* f : factor_keys) {
    bool any = false;
    for (std::size_t i = 0; i < f->size(); ++i, ++e) {
      const int j = entry_column[e];
      if (j < 0) continue;
      a[fill[j]++] = row;
      any = true;
    }
    if (any) ++row;
  }

  std::vector<int> cmember;
  if (groups && !groups->empty()) {
    cmember.assign(n_col, 0);
    for (int j = 0; j < n_col; ++j) {
      auto it = groups->find(keys[j]);
      if (it != groups->end()) cmember[j] = it->second;
    }
  }
  double knobs[CCOLAMD_KNOBS];
  int stats[CCOLAMD_STATS];
  ccolamd_set_defaults(knobs);
  const int ok = ccolamd(n_row, n_col, static_cast<int>(alen), a.data(), p.data(), knobs, stats,
                         cmember.empty() ? nullptr : cmember.data());
  if (!ok) throw std::runtime_error("CCOLAMD failed with status " + std::to_string(stats[CCOLAMD_STATUS]));
  Ordering out(n_col);
  for (int k = 0; k < n_col; ++k) out[k] = keys[p[k]];
  return out;
}

}  // namespace ppp::smoother
