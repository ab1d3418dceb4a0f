// Cubic Hermite (thesis A.3) and linear (thesis 3-18) shape functions on one element of length L.
// Header-only and templated on the scalar so kernels can run them under automatic differentiation.
#pragma once

#include <array>

namespace latticedyn {

/// Cubic Hermite shape functions and their derivatives with respect to the physical coordinate
/// x = xi * L (thesis eqs. ). Entry order matches the dof vector
/// [y(0), y'(0), y(L), y'(L)], i.e. the thesis's N_1^0, N_1^1, N_2^0, N_2^1 (eq. A-8), so
/// y(x) = sum_k N[k] * dof[k], y'(x) = sum_k dN[k] * dof[k], y''(x) = sum_k ddN[k] * dof[k].
template <class S>
struct HermiteCubic {
  std::array<S, 4> N;    ///< values
  std::array<S, 4> dN;   ///< d/dx
  std::array<S, 4> ddN;  ///< d^2/dx^2
};

/// Evaluates the cubic Hermite shape functions at the local coordinate xi in [0, 1] of an element
/// of length L (thesis eqs. ). The slope dofs are d/dx, which is why N[1] and N[3]
/// carry a factor L and the derivative rows carry 1/L per differentiation.
template <class S>
HermiteCubic<S> hermite_cubic(const S& xi, double L) {
  const double inv_L = 1.0 / L;
  const double inv_L2 = inv_L * inv_L;
  // Named temporaries keep Eigen::AutoDiffScalar from building long expression templates.
  const S xi2 = xi * xi;
  const S xi3 = xi2 * xi;
  HermiteCubic<S> h;
  h.N = {S(1.0 - 3.0 * xi2 + 2.0 * xi3), S(L * (xi - 2.0 * xi2 + xi3)),
         S(3.0 * xi2 - 2.0 * xi3), S(L * (xi3 - xi2))};
  h.dN = {S(inv_L * (6.0 * xi2 - 6.0 * xi)), S(1.0 - 4.0 * xi + 3.0 * xi2),
          S(inv_L * (6.0 * xi - 6.0 * xi2)), S(3.0 * xi2 - 2.0 * xi)};
  h.ddN = {S(inv_L2 * (12.0 * xi - 6.0)), S(inv_L * (6.0 * xi - 4.0)),
           S(inv_L2 * (6.0 - 12.0 * xi)), S(inv_L * (6.0 * xi - 2.0))};
  return h;
}

/// Linear two-node shape functions and their derivative with respect to x = xi * L
/// (thesis eq. 3-18), order [node 1, node 2].
template <class S>
struct LinearShape {
  std::array<S, 2> N;   ///< values
  std::array<S, 2> dN;  ///< d/dx, constant over the element
};

/// Evaluates the linear shape functions N = [1 - xi, xi], N' = [-1, 1] / L (thesis eq. 3-18).
template <class S>
LinearShape<S> linear_shape(const S& xi, double L) {
  const double inv_L = 1.0 / L;
  LinearShape<S> s;
  s.N = {S(1.0 - xi), S(xi)};
  // The derivative does not depend on xi; built from it anyway so an AutoDiffScalar result
  // carries a derivative vector of the right size (zero) instead of an empty one.
  s.dN = {S(-inv_L + 0.0 * xi), S(inv_L + 0.0 * xi)};
  return s;
}

}  // namespace latticedyn
