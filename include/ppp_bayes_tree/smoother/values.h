#pragma once
// Values: one dynamic-dimension vector per key. A variable lives in a vector space
// (the retraction is plain addition, x (+) delta = x + delta, and its dimension is its
// size) unless it was inserted with a Manifold (manifold.h): then the vector is its
// storage, it retracts through the Manifold and its dimension is the Manifold's tangent
// dimension. The same class holds deltas (always vectors in the tangent space).
#include <Eigen/Core>

#include <cstddef>
#include <unordered_map>

#include "ppp_bayes_tree/smoother/key.h"
#include "ppp_bayes_tree/smoother/manifold.h"

namespace ppp::smoother {

using Vector = Eigen::VectorXd;
using Matrix = Eigen::MatrixXd;

class Values {
 public:
  using Map = std::unordered_map<Key, Vector>;

  /// Inserts a new variable; throws std::invalid_argument if the key exists.
  void insert(Key key, const Vector& value);
  /// Inserts a new manifold variable (`storage` of manifold->storageDim() components; a
  /// null manifold inserts a vector variable); throws std::invalid_argument if the key
  /// exists or the storage has the wrong size.
  void insert(Key key, const Vector& storage, Manifold::Ptr manifold);
  /// Inserts `key` of `other` with its manifold (if any).
  void insertFrom(const Values& other, Key key) { insert(key, other.at(key), other.manifold(key)); }
  /// Inserts or overwrites (a vector variable).
  void insertOrAssign(Key key, const Vector& value) {
    values_[key] = value;
    if (!manifolds_.empty()) manifolds_.erase(key);
  }
  /// Overwrites an existing variable (same dimension); throws std::out_of_range otherwise.
  void update(Key key, const Vector& value);
  bool exists(Key key) const { return values_.count(key) != 0; }
  /// Throws std::out_of_range naming the key when absent.
  const Vector& at(Key key) const;
  Vector& at(Key key);
  /// The variable's manifold, null for a vector variable.
  Manifold::Ptr manifold(Key key) const;
  /// Tangent dimension of one variable (its size for a vector variable).
  int dim(Key key) const;
  void erase(Key key) {
    values_.erase(key);
    if (!manifolds_.empty()) manifolds_.erase(key);
  }
  void clear() {
    values_.clear();
    manifolds_.clear();
  }
  std::size_t size() const { return values_.size(); }
  bool empty() const { return values_.empty(); }
  /// Total dimension (sum of the variables' tangent dimensions).
  std::size_t dim() const;
  /// Sorted keys.
  KeyVector keys() const;

  /// Retraction: result[k] = this[k] (+) delta[k] for keys of delta that are also here
  /// (addition for a vector variable); keys of `delta` missing here throw
  /// std::out_of_range.
  Values retract(const Values& delta) const;
  /// this[k] (+)= delta in place (addition for a vector variable).
  void retractInPlace(Key key, const Vector& delta);
  /// this[k] (-) other[k] over this' keys (local coordinates: the tangent d with
  /// other[k] (+) d == this[k]; this[k] - other[k] for a vector variable; other must
  /// hold them).
  Values localCoordinates(const Values& other) const;

  /// A zero tangent vector (a delta) for every variable of `like`.
  static Values zeroLike(const Values& like);

  Map::const_iterator begin() const { return values_.begin(); }
  Map::const_iterator end() const { return values_.end(); }

 private:
  Map values_;
  std::unordered_map<Key, Manifold::Ptr> manifolds_;  // manifold variables only
};

}  // namespace ppp::smoother
