#include "ppp_bayes_tree/smoother/values.h"

#include <algorithm>
#include <stdexcept>

namespace ppp::smoother {

void Values::insert(Key key, const Vector& value) {
  if (!values_.emplace(key, value).second)
    throw std::invalid_argument("Values::insert: key exists: " + keyToString(key));
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

std::size_t Values::dim() const {
  std::size_t n = 0;
  for (const auto& [k, v] : values_) n += static_cast<std::size_t>(v.size());
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
  for (const auto& [k, d] : delta.values_) {
    Vector& v = out.at(k);
    if (v.size() != d.size()) throw std::invalid_argument("Values::retract: dimension mismatch for " + keyToString(k));
    v += d;
  }
  return out;
}

Values Values::localCoordinates(const Values& other) const {
  Values out;
  for (const auto& [k, v] : values_) out.values_.emplace(k, v - other.at(k));
  return out;
}

Values Values::zeroLike(const Values& like) {
  Values out;
  for (const auto& [k, v] : like.values_) out.values_.emplace(k, Vector::Zero(v.size()));
  return out;
}

}  // namespace ppp::smoother
