// Double-acting hydraulic cylinder (thesis 5.1.2): a force element between two end nodes whose
// piston and rod chambers are hydraulic nodes, with compressible fluid, dead volumes and friction.
#pragma once

#include "elements/autodiff_element.hpp"
#include "elements/hydraulic_fluid.hpp"

namespace latticedyn {

struct HydraulicCylinderProperties {
  double piston_diameter = 0.0;     ///< m
  double rod_diameter = 0.0;        ///< m, below the piston's
  double stroke = 0.0;              ///< m, the piston's travel
  double retracted_length = 0.0;    ///< m, pin-to-pin length at zero stroke
  double dead_volume_piston = 0.0;  ///< m^3, oil in the piston chamber at zero stroke (hoses included)
  double dead_volume_rod = 0.0;     ///< m^3, oil in the rod chamber at full stroke
  double viscous_friction = 0.0;    ///< N s/m
  double coulomb_friction = 0.0;    ///< N, smoothed as F_c tanh(s_dot / friction_velocity)
  double friction_velocity = 0.01;  ///< m/s
  double leakage = 0.0;             ///< m^3/(s Pa), internal leakage across the piston
  double mass = 0.0;                ///< kg, half at each end node
  /// The end stops at s = 0 and s = stroke: a penalty spring (N/m) and damper (N s/m) acting on
  /// the travel past them. Stiffness 0 takes the steel rod's axial stiffness E A_rod / l_0
  /// (E = 2.1e11 Pa): the stop is the tube and the rod bearing the load.
  double end_stop_stiffness = 0.0;
  double end_stop_damping = 0.0;
  /// m: the spring's force grows smoothly (C1) over the first end_stop_transition of travel past a
  /// stop, and its damper comes in over the same travel, so Newton sees no kink.
  double end_stop_transition = 1e-4;
  HydraulicFluid fluid;
  double piston_area() const;
  double rod_side_area() const;
  /// Throws std::invalid_argument naming the first bad field.
  void validate() const;
};

/// Travel past an end stop, d: the stop spring's force per unit stiffness (0, d^2 / (2 w), d - w/2:
/// C1), its energy per unit stiffness (the integral), and the damper's weight (smoothstep 0..1).
template <class S>
S end_stop_ramp(const S& d, double w) {
  const double x = scalar_value(d);
  if (x <= 0) return S(0.0);
  if (x < w) return S(d * d / S(2 * w));
  return S(d - S(0.5 * w));
}
double end_stop_ramp_energy(double d, double w);
template <class S>
S end_stop_weight(const S& d, double w) {
  const double x = scalar_value(d);
  if (x <= 0) return S(0.0);
  if (x >= w) return S(1.0);
  const S y = d / S(w);
  return S(y * y * (S(3.0) - S(2.0) * y));
}

/// Slots: [translation of the cap end A, translation of the rod end B, scalar p_1 (piston chamber
/// pressure), scalar p_2 (rod chamber pressure)]. With d = r_B - r_A, l = |d|, e = d / l, the
/// stroke s = l - l_0 and its rate s_dot = e . (v_B - v_A):
///   F = p_1 A_1 - p_2 A_2 - c s_dot - F_c tanh(s_dot / v_f) + F_stop  (the force extending it)
///   F_stop = k_s [ramp(-s) - ramp(s - s_max)] - c_s [weight(-s) + weight(s - s_max)] s_dot
///   r_A = m/2 (a_A - g) + F e,  r_B = m/2 (a_B - g) - F e
///   r_1 = k [V_1(s)/beta p_1_dot + A_1 s_dot + C_L (p_1 - p_2)],  V_1 = V_1,0 + A_1 s
///   r_2 = k [V_2(s)/beta p_2_dot - A_2 s_dot - C_L (p_1 - p_2)],  V_2 = V_2,0 + A_2 (s_max - s)
/// The chamber rows are the flow the chamber takes from its node (compression plus volume growth,
/// pressure-build-up equation dp/dt = beta/V (Q - dV/dt)), k = kHydraulicRowScale; the valves
/// and pumps at the same node add the flows they take away or bring.
class HydraulicCylinder final : public AutoDiffElement<HydraulicCylinder, 8> {
 public:
  static constexpr std::array<SlotKind, 4> kSlots = {SlotKind::translation, SlotKind::translation, SlotKind::scalar,
                                                     SlotKind::scalar};

  explicit HydraulicCylinder(const HydraulicCylinderProperties& p);

  std::string_view type_name() const override { return "hydraulic_cylinder"; }
  ElementEnergy energy(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  /// Friction, leakage and end stop damping dissipate; the chambers' oil takes p_i V_i p_i_dot / beta.
  ElementPower power(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  /// Q_piston, Q_rod: the flows each chamber takes from its node (volume growth plus compression
  /// plus leakage), m^3/s.
  std::span<const std::string> flow_names() const override { return kFlowNames; }
  void flows(std::span<const SlotState<double>> state, const ElementContext& ctx, std::span<double> out) const override;
  /// Tension positive, like a bar: a cylinder holding a load up is in compression.
  std::optional<double> axial_force(std::span<const SlotState<double>> state,
                                    const ElementContext& ctx) const override;
  std::vector<Vec3> axis_points(std::span<const SlotState<double>> state, const ElementContext&) const override {
    return {state[0].pos, state[1].pos};
  }

  const HydraulicCylinderProperties& properties() const { return props_; }
  /// The end stops' spring stiffness in use, N/m.
  double end_stop_stiffness() const { return stop_stiffness_; }
  /// The stroke s = |r_B - r_A| - l_0 at a state.
  double stroke(std::span<const SlotState<double>> state) const { return (state[1].pos - state[0].pos).norm() - props_.retracted_length; }

  template <class S>
  void compute_residual(std::span<const SlotState<S>> s, const ElementContext& ctx, Eigen::Matrix<S, 8, 1>& r) const {
    using std::sqrt;
    using std::tanh;
    const Vec3T<S> d = s[1].pos - s[0].pos;
    const S l = sqrt(d.squaredNorm());
    const Vec3T<S> e = d / l;
    const S stroke = l - S(props_.retracted_length);
    const S rate = e.dot(s[1].vel - s[0].vel);
    const S p1 = s[2].pos(0), p2 = s[3].pos(0);
    const double w = props_.end_stop_transition;
    const S below = -stroke, beyond = stroke - S(props_.stroke);
    const S stop = S(stop_stiffness_) * (end_stop_ramp(below, w) - end_stop_ramp(beyond, w)) -
                   S(props_.end_stop_damping) * (end_stop_weight(below, w) + end_stop_weight(beyond, w)) * rate;
    const S F = p1 * S(area1_) - p2 * S(area2_) - S(props_.viscous_friction) * rate -
                S(props_.coulomb_friction) * tanh(rate / S(props_.friction_velocity)) + stop;
    const Vec3T<S> g = cast_to<S>(ctx.gravity);
    const S half(0.5 * props_.mass);
    r.template segment<3>(0) = half * (s[0].acc - g) + F * e;
    r.template segment<3>(3) = half * (s[1].acc - g) - F * e;
    const S V1 = S(props_.dead_volume_piston) + S(area1_) * stroke;
    const S V2 = S(props_.dead_volume_rod) + S(area2_) * (S(props_.stroke) - stroke);
    const S leak = S(props_.leakage) * (p1 - p2);
    const S k(kHydraulicRowScale), beta(props_.fluid.bulk_modulus);
    r(6) = k * (V1 / beta * s[2].vel(0) + S(area1_) * rate + leak);
    r(7) = k * (V2 / beta * s[3].vel(0) - S(area2_) * rate - leak);
  }

 private:
  inline static const std::array<std::string, 2> kFlowNames = {"Q_piston", "Q_rod"};
  HydraulicCylinderProperties props_;
  double area1_ = 0.0, area2_ = 0.0;
  double stop_stiffness_ = 0.0;  ///< end_stop_stiffness, or the rod's when that is 0
};

}  // namespace latticedyn
