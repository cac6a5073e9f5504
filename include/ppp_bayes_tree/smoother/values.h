#pragma once
// Values: one dynamic-dimension vector per key. Variables live in vector spaces, so the
// retraction is plain addition (x (+) delta = x + delta). The same class holds deltas.
#include <Eigen/Core>

#include <cstddef>
#include <unordered_map>

#include "ppp_bayes_tree/smoother/key.h"

namespace ppp::smoother {

using Vector = Eigen::VectorXd;
using Matrix = Eigen::MatrixXd;

class Values {
 public:
  using Map = std::unordered_map<Key, Vector>;

  /// Inserts a new variable; throws std::invalid_argument if the key exists.
  void insert(Key key, const Vector& value);
  /// Inserts or overwrites.
  void insertOrAssign(Key key, const Vector& value) { values_[key] = value; }
  /// Overwrites an existing variable (same dimension); throws std::out_of_range otherwise.
  void update(Key key, const Vector& value);
  bool exists(Key key) const { return values_.count(key) != 0; }
  /// Throws std::out_of_range naming the key when absent.
  const Vector& at(Key key) const;
  Vector& at(Key key);
  void erase(Key key) { values_.erase(key); }
  void clear() { values_.clear(); }
  std::size_t size() const { return values_.size(); }
  bool empty() const { return values_.empty(); }
  /// Total dimension (sum of the variables' dimensions).
  std::size_t dim() const;
  /// Sorted keys.
  KeyVector keys() const;

  /// Retraction by addition: result[k] = this[k] + delta[k] for keys of delta that are
  /// also here; keys of `delta` missing here throw std::out_of_range.
  Values retract(const Values& delta) const;
  /// this[k] - other[k] over this' keys (local coordinates; other must hold them).
  Values localCoordinates(const Values& other) const;

  /// Same as `x (+) 0` with every variable set to zero.
  static Values zeroLike(const Values& like);

  Map::const_iterator begin() const { return values_.begin(); }
  Map::const_iterator end() const { return values_.end(); }

 private:
  Map values_;
};

}  // namespace ppp::smoother
