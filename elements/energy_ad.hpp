// Gradient and stiffness of an elastic energy by forward automatic differentiation: an element
// writes its strain energy once, templated on the scalar, and gets the internal force (Dual,
// first order) and the tangent (HyperDual, second order) from it.
#pragma once

#include "core/dual.hpp"
#include "core/rotation.hpp"

#include <array>

namespace latticedyn {

/// NV perturbation variables, seeded on the element's position-level quantities. An additive
/// quantity x becomes x + delta. A rotation R becomes R exp(skew(delta)), to the order the
/// number type carries; the gradient is then dU/d(delta) at 0, the internal force in the right-
/// perturbed variables of the elements. The stiffness K(i, j) is the derivative of force i with
/// respect to a right perturbation j of the state: the symmetric Hessian of U(R exp(skew(delta)))
/// plus, on the diagonal block of each rotation, skew(g)/2 (g that rotation's gradient), the
/// part of R (I + skew(eps)) (I + skew(delta)) that the symmetric exponential does not carry.
template <int NV>
struct EnergyAD {
  using Gradient = Eigen::Matrix<double, NV, 1>;
  using Stiffness = Eigen::Matrix<double, NV, NV>;

  template <class Number>
  struct Seeds {
    using S = Number;
    S scalar(double x, int col) const { return S::variable(x, col); }
    Vec3T<S> vec(const Vec3& x, int col) const {
      return Vec3T<S>(S::variable(x(0), col), S::variable(x(1), col + 1), S::variable(x(2), col + 2));
    }
    /// R exp(skew(x)) = R + R skew(x) + R skew(x)^2 / 2 + ...: entries with value R, gradient
    /// R skew(e_m) and (second order) Hessian R (skew(e_m) skew(e_n) + skew(e_n) skew(e_m)) / 2,
    /// filled in directly (a product of HyperDual matrices would cost ten times more).
    Mat3T<S> rot(const Mat3& R, int col) {
      rotations_[count_++] = col;
      Mat3 dR[3], Sm[3];
      for (int m = 0; m < 3; ++m) {
        Sm[m] = skew(Vec3(Vec3::Unit(m)));
        dR[m] = R * Sm[m];
      }
      Mat3T<S> out;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          S e(R(i, j));
          for (int m = 0; m < 3; ++m) e.g[col + m] = dR[m](i, j);
          out(i, j) = e;
        }
      if constexpr (std::is_same_v<Number, HyperDual<NV>>) {
        for (int m = 0; m < 3; ++m)
          for (int n = m; n < 3; ++n) {
            const Mat3 H = 0.5 * R * (Sm[m] * Sm[n] + Sm[n] * Sm[m]);
            for (int i = 0; i < 3; ++i)
              for (int j = 0; j < 3; ++j) out(i, j).h[S::packed(col + m, col + n)] = H(i, j);
          }
      }
      return out;
    }
    std::array<int, NV / 3 + 1> rotations_{};
    int count_ = 0;
  };
  using FirstOrder = Seeds<Dual<NV>>;
  using SecondOrder = Seeds<HyperDual<NV>>;

  static void extract(const Dual<NV>& U, double* value, Gradient* grad) {
    if (value) *value = U.v;
    if (grad)
      for (int i = 0; i < NV; ++i) (*grad)(i) = U.g[i];
  }
  static void extract(const HyperDual<NV>& U, const SecondOrder& seeds, double* value, Gradient* grad, Stiffness* K) {
    if (value) *value = U.v;
    if (grad)
      for (int i = 0; i < NV; ++i) (*grad)(i) = U.g[i];
    if (!K) return;
    for (int i = 0; i < NV; ++i)
      for (int j = 0; j < NV; ++j) (*K)(i, j) = U.hessian(i, j);
    for (int r = 0; r < seeds.count_; ++r) {
      const int c = seeds.rotations_[r];
      const Vec3 g(U.g[c], U.g[c + 1], U.g[c + 2]);
      K->template block<3, 3>(c, c) += 0.5 * skew(g);
    }
  }
};

}  // namespace latticedyn
