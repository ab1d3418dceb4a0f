// Kelvin-Voigt damping of an element's strain measures: the form a stiffness-proportional
// (Rayleigh beta) damping takes on co-rotated and nonlinear strains, with its exact tangents.
#pragma once

#include "elements/energy_ad.hpp"

#include <span>
#include <vector>

namespace latticedyn {

/// Kelvin-Voigt damping of strain measures e(x) given as HyperDual numbers in the NV element
/// variables x (rotations seeded as right perturbations, as for EnergyAD): with the dissipation
/// function D = 1/2 e_dot^T Cd e_dot and e_dot = J v (J = de/dx, v the rates of x), adds
///   f += J^T Cd J v,   C += J^T Cd J,
///   K += sum_k s_k K_k + J^T Cd W,   s = Cd J v,  row k of W = v^T K_k,
/// to f, K, C, where K_k is the "stiffness" of e_k (its Hessian plus the rotation terms of
/// EnergyAD::extract): d(J^T s)/dx at fixed s, and d(e_dot)/dx at fixed v. Rigid motion has
/// e_dot = 0, so it is never damped, whatever the element's prestress.
template <int NV>
void add_strain_rate_damping(std::span<const HyperDual<NV>> e, const typename EnergyAD<NV>::SecondOrder& seeds,
                             const MatX& Cd, const Eigen::Matrix<double, NV, 1>& v,
                             Eigen::Matrix<double, NV, 1>& f, Eigen::Matrix<double, NV, NV>& K,
                             Eigen::Matrix<double, NV, NV>& C) {
  using AD = EnergyAD<NV>;
  const int ns = static_cast<int>(e.size());
  Eigen::Matrix<double, Eigen::Dynamic, NV> J(ns, NV), W(ns, NV);
  std::vector<typename AD::Stiffness> Kk(static_cast<std::size_t>(ns));
  for (int k = 0; k < ns; ++k) {
    typename AD::Gradient g;
    AD::extract(e[k], seeds, nullptr, &g, &Kk[static_cast<std::size_t>(k)]);
    J.row(k) = g.transpose();
    W.row(k) = v.transpose() * Kk[static_cast<std::size_t>(k)];
  }
  const VecX s = Cd * (J * v);
  f += J.transpose() * s;
  C += J.transpose() * Cd * J;
  K += J.transpose() * Cd * W;
  for (int k = 0; k < ns; ++k) K += s(k) * Kk[static_cast<std::size_t>(k)];
}

/// The force J^T Cd J v alone, from strain measures given as Dual numbers (the residual's need).
template <int NV>
void add_strain_rate_damping_force(std::span<const Dual<NV>> e, const MatX& Cd, const Eigen::Matrix<double, NV, 1>& v,
                                   Eigen::Matrix<double, NV, 1>& f) {
  const int ns = static_cast<int>(e.size());
  Eigen::Matrix<double, Eigen::Dynamic, NV> J(ns, NV);
  for (int k = 0; k < ns; ++k)
    for (int i = 0; i < NV; ++i) J(k, i) = e[k].g[i];
  f += J.transpose() * (Cd * (J * v));
}

}  // namespace latticedyn
