#include "ppp_bayes_tree/smoother/values.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace ppp::smoother {

void Values::insert(Key key, const Vector& value) {
  if (!values_.emplace(key, value).second)
    throw std::invalid_argument("Values::insert: key exists: " + keyToString(key));
}

void Values::insert(Key key, const Vector& storage, Manifold::Ptr manifold) {
  if (manifold && storage.size() != manifold->storageDim())
    throw std::invalid_argument("Values::insert: " + keyToString(key) + " is a " + manifold->name() + " of " +
                                std::to_string(manifold->storageDim()) + " stored components, given " +
                                std::to_string(storage.size()));
  insert(key, storage);
  if (manifold) manifolds_.emplace(key, std::move(manifold));
}

void Values::update(Key key, const Vector& value) {
  Vector& v = at(key);
  if (v.size() != value.size())
    throw std::invalid_argument("Values::update: dimension change for " + keyToString(key));
  v = value;
}

const Vector& Values::at(Key key) const {
  auto it = values_.find(key);
  if (it == values_.end()) throw std::out_of_range("Values: no variable " + keyToString(key));
  return it->second;
}

Vector& Values::at(Key key) {
  auto it = values_.find(key);
  if (it == values_.end()) throw std::out_of_range("Values: no variable " + keyToString(key));
  return it->second;
}

Manifold::Ptr Values::manifold(Key key) const {
  if (manifolds_.empty()) return nullptr;
  auto it = manifolds_.find(key);
  return it == manifolds_.end() ? nullptr : it->second;
}

int Values::dim(Key key) const {
  const Vector& v = at(key);
  const Manifold::Ptr m = manifold(key);
  return m ? m->tangentDim() : static_cast<int>(v.size());
}

std::size_t Values::dim() const {
  std::size_t n = 0;
  for (const auto& [k, v] : values_) n += static_cast<std::size_t>(dim(k));
  return n;
}

KeyVector Values::keys() const {
  KeyVector keys;
  keys.reserve(values_.size());
  for (const auto& [k, v] : values_) keys.push_back(k);
  std::sort(keys.begin(), keys.end());
  return keys;
}

Values Values::retract(const Values& delta) const {
  Values out = *this;
  for (const auto& [k, d] : delta.values_) out.retractInPlace(k, d);
  return out;
}

void Values::retractInPlace(Key key, const Vector& delta) {
  Vector& v = at(key);
  if (delta.size() != dim(key))
    throw std::invalid_argument("Values::retract: dimension mismatch for " + keyToString(key));
  const Manifold::Ptr m = manifold(key);
  if (m)
    v = m->retract(v, delta);
  else
    v += delta;
}

Values Values::localCoordinates(const Values& other) const {
  Values out;
  for (const auto& [k, v] : values_) {
    const Manifold::Ptr m = manifold(k);
    out.values_.emplace(k, m ? m->localCoordinates(other.at(k), v) : Vector(v - other.at(k)));
  }
  return out;
}

Values Values::zeroLike(const Values& like) {
  Values out;
  for (const auto& [k, v] : like.values_) out.values_.emplace(k, Vector::Zero(like.dim(k)));
  return out;
}

}  // namespace ppp::smoother
