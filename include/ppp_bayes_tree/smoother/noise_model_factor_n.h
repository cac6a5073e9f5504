#pragma once
// Typed base of the nonlinear factors on a fixed number of variables (as GTSAM's
// NoiseModelFactorN, written anew): a factor on N variables of types T1..TN supplies only
//
//   Vector evaluateError(const T1& x1, ..., const TN& xN, Matrix* H1, ..., Matrix* HN) const
//
// returning the unwhitened error h(x) - z and, for each non-null Hj, filling the
// Jacobian d(error)/d(xj) (dim() x dim(xj)). The base looks the values up by key and
// converts them (ValueTraits: a dynamic Vector, a fixed-size vector or a double), and
// NonlinearFactor whitens with the noise model, applies the robust kernel (IRLS) and
// linearizes. Factors of a run-time number of variables (FunctionFactor,
// LinearContainerFactor) derive from NonlinearFactor directly.
#include <array>
#include <cstddef>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "ppp_bayes_tree/smoother/nonlinear_factor.h"
#include "ppp_bayes_tree/smoother/value_traits.h"

namespace ppp::smoother {

/// Jacobian output of evaluateError for a value of type T: null when not wanted.
template <typename T>
struct JacobianOutput {
  using type = Matrix*;
};

template <typename... ValueTypes>
class NoiseModelFactorN : public NonlinearFactor {
 public:
  static constexpr std::size_t kArity = sizeof...(ValueTypes);
  static_assert(kArity > 0, "a factor involves at least one variable");
  template <std::size_t I>
  using ValueType = std::tuple_element_t<I, std::tuple<ValueTypes...>>;

  /// One key per value type, in the same order.
  NoiseModelFactorN(NoiseModel::Ptr noise, const std::array<Key, kArity>& keys)
      : NonlinearFactor(KeyVector(keys.begin(), keys.end()), std::move(noise)) {}

  /// Key of the I-th variable (0-based).
  template <std::size_t I>
  Key key() const {
    static_assert(I < kArity, "no such variable");
    return keys()[I];
  }

  /// The factor's error at typed values (see top).
  virtual Vector evaluateError(const ValueTypes&... x, typename JacobianOutput<ValueTypes>::type... h) const = 0;

  /// Looks the values up by key and calls evaluateError.
  Vector unwhitenedError(const Values& x, std::vector<Matrix>* jacobians) const final {
    return evaluate(x, jacobians, std::index_sequence_for<ValueTypes...>{});
  }

 private:
  template <std::size_t... I>
  Vector evaluate(const Values& x, std::vector<Matrix>* jacobians, std::index_sequence<I...>) const {
    return evaluateError(ValueTraits<ValueTypes>::read(x.at(keys()[I]), keys()[I])...,
                         (jacobians != nullptr ? &(*jacobians)[I] : nullptr)...);
  }
};

template <typename T>
using NoiseModelFactor1 = NoiseModelFactorN<T>;
template <typename T1, typename T2>
using NoiseModelFactor2 = NoiseModelFactorN<T1, T2>;

}  // namespace ppp::smoother
