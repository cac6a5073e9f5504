#pragma once
// How a factor reads a typed value from the smoother's storage. Every variable is
// stored as a dynamic Eigen vector (Values); a factor built on NoiseModelFactorN names
// the type it works with instead, and ValueTraits<T>::read converts (or, for the
// dynamic vector itself, passes through without a copy), checking the dimension:
//   Vector                     any dimension, passed by reference;
//   Eigen::Matrix<double,N,1>  exactly N components (copied, element by element);
//   double                     exactly 1 component (a scalar variable, e.g. a bias).
// A wrong dimension throws std::invalid_argument naming the key.
#include <Eigen/Core>

#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/smoother/key.h"
#include "ppp_bayes_tree/smoother/values.h"

namespace ppp::smoother {

template <typename T>
struct ValueTraits;

template <>
struct ValueTraits<Vector> {
  static constexpr int kDim = Eigen::Dynamic;
  static const Vector& read(const Vector& stored, Key /*key*/) { return stored; }
};

template <int N>
struct ValueTraits<Eigen::Matrix<double, N, 1>> {
  static_assert(N > 0, "fixed-size values only; use Vector for a dynamic one");
  static constexpr int kDim = N;
  static Eigen::Matrix<double, N, 1> read(const Vector& stored, Key key) {
    if (stored.size() != N)
      throw std::invalid_argument("factor expects " + std::to_string(N) + " components for " + keyToString(key) +
                                  ", the value has " + std::to_string(stored.size()));
    return stored;
  }
};

template <>
struct ValueTraits<double> {
  static constexpr int kDim = 1;
  static double read(const Vector& stored, Key key) {
    if (stored.size() != 1)
      throw std::invalid_argument("factor expects a scalar for " + keyToString(key) + ", the value has " +
                                  std::to_string(stored.size()) + " components");
    return stored(0);
  }
};

}  // namespace ppp::smoother
