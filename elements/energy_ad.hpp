// Gradient and stiffness of an elastic energy by forward automatic differentiation: an element
// writes its strain energy once, templated on the scalar, and gets the internal force (first
// order) and the tangent (nested, second order) from it.
#pragma once

#include "core/rotation.hpp"

#include <unsupported/Eigen/AutoDiff>

namespace latticedyn {

/// NV perturbation variables, seeded on the element's position-level quantities: an additive
/// quantity x becomes x + delta (first order) or x + eps + delta (second order); a rotation R
/// becomes R (I + skew(delta)) or R (I + skew(eps)) (I + skew(delta)). The gradient is then
/// dU/d(delta) at 0 (the internal force in the elements' right-perturbed variables) and the
/// stiffness K(i, j) = d/d(eps_j) dU/d(delta_i), the derivative of that force with respect to a
/// perturbation of the state — with the eps-delta cross term of rotations that makes it right.
template <int NV>
struct EnergyAD {
  using Inner = Eigen::AutoDiffScalar<Eigen::Matrix<double, NV, 1>>;
  using Outer = Eigen::AutoDiffScalar<Eigen::Matrix<Inner, NV, 1>>;
  using Gradient = Eigen::Matrix<double, NV, 1>;
  using Stiffness = Eigen::Matrix<double, NV, NV>;

  struct FirstOrder {
    using S = Inner;
    static S constant(double x) { return S(x); }
    static S scalar(double x, int col) { return S(x, NV, col); }
    static Vec3T<S> vec(const Vec3& x, int col) {
      Vec3T<S> v;
      for (int i = 0; i < 3; ++i) v(i) = scalar(x(i), col + i);
      return v;
    }
    static Mat3T<S> rot(const Mat3& R, int col) {
      Vec3T<S> d;
      for (int i = 0; i < 3; ++i) d(i) = scalar(0.0, col + i);
      return R.cast<S>() * (Mat3T<S>::Identity() + skew(d));
    }
  };

  struct SecondOrder {
    using S = Outer;
    static S constant(double x) { return S(Inner(x)); }
    static S scalar(double x, int col) {
      S s(Inner(x, NV, col));
      s.derivatives()(col) = Inner(1.0);
      return s;
    }
    static Vec3T<S> vec(const Vec3& x, int col) {
      Vec3T<S> v;
      for (int i = 0; i < 3; ++i) v(i) = scalar(x(i), col + i);
      return v;
    }
    static Mat3T<S> rot(const Mat3& R, int col) {
      Vec3T<S> eps, delta;
      for (int i = 0; i < 3; ++i) {
        eps(i) = S(Inner(0.0));
        eps(i).derivatives()(col + i) = Inner(1.0);
        delta(i) = S(Inner(0.0, NV, col + i));
      }
      return R.cast<Inner>().template cast<S>() * (Mat3T<S>::Identity() + skew(eps)) *
             (Mat3T<S>::Identity() + skew(delta));
    }
  };

  static void extract(const Inner& U, double* value, Gradient* grad) {
    if (value) *value = U.value();
    if (grad) *grad = U.derivatives().size() ? Gradient(U.derivatives()) : Gradient::Zero();
  }
  static void extract(const Outer& U, double* value, Gradient* grad, Stiffness* K) {
    extract(U.value(), value, grad);
    if (!K) return;
    for (int j = 0; j < NV; ++j) {
      const Inner& dj = U.derivatives()(j);
      for (int i = 0; i < NV; ++i) (*K)(i, j) = dj.derivatives().size() ? dj.derivatives()(i) : 0.0;
    }
  }
};

}  // namespace latticedyn
