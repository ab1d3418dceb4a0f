// The hydraulic fluid and the flow-balance rows every hydraulic element writes into: the pressure of
// a hydraulic node is a scalar DoF whose residual row is the node's net volume flow, scaled.
#pragma once

namespace latticedyn {

struct HydraulicFluid {
  double bulk_modulus = 1.4e9;  ///< beta, Pa (mineral oil with some entrained air: 1.2e9 to 1.6e9)
  double density = 870.0;       ///< rho, kg/m^3
};

/// Scale of the flow-balance rows, N s/m^3: a row's residual is kHydraulicRowScale times the net
/// volume flow out of its node (m^3/s), so that Newton's residual norm weighs a flow error of
/// 1e-6 m^3/s (1 cm^3/s) like a force error of 1 N. Every hydraulic element uses the same scale
/// (a node's row sums the contributions of all elements at it).
inline constexpr double kHydraulicRowScale = 1e6;

}  // namespace latticedyn
