// Turbulent orifice flow between two hydraulic nodes (thesis 5.1.2's throttle, relief and reversing
// valves): Q = C_d A(opening) sqrt(2 |dp| / rho) sign(dp), with a laminar core so that it is smooth.
#pragma once

#include "core/drive.hpp"
#include "elements/autodiff_element.hpp"
#include "elements/hydraulic_fluid.hpp"

#include <algorithm>
#include <optional>
#include <string>

namespace latticedyn {

/// How much of the orifice's area is open.
enum class OrificeOpening {
  fixed,           ///< always fully open: a throttle
  drive,           ///< the drive's value, clamped to [0, 1]: a proportional valve
  spool_positive,  ///< max(u, 0) of a spool position u (drive, -1..1): P->A, B->T of a reversing valve
  spool_negative,  ///< max(-u, 0): P->B, A->T
  relief,          ///< by the pressure difference: closed below the cracking pressure, fully open at
                   ///< full_open_pressure, a smooth (C1) ramp between: a relief / back-pressure valve
};

struct HydraulicOrificeProperties {
  double area = 0.0;                    ///< m^2, fully open
  double discharge_coefficient = 0.62;  ///< C_d (sharp-edged orifice)
  double transition_pressure = 1e4;     ///< Pa: below it the flow turns laminar (linear in dp)
  OrificeOpening opening = OrificeOpening::fixed;
  std::optional<Drive> drive;           ///< for drive and spool openings
  double cracking_pressure = 0.0;       ///< Pa, relief
  double full_open_pressure = 0.0;      ///< Pa, relief, above cracking
  HydraulicFluid fluid;
  std::string flow_name = "Q";          ///< its flow column (a reversing valve's four: Q_PA, ...)
  void validate() const;
};

/// Slots: [scalar p_1, scalar p_2]. With dp = p_1 - p_2 and the opening x in [0, 1]:
///   Q = C_d x A sqrt(2 / rho) dp / (dp^2 + p_t^2)^(1/4)
/// which is the orifice equation C_d x A sqrt(2 |dp| / rho) sign(dp) for |dp| >> p_t and linear
/// (laminar) near dp = 0, with a continuous derivative for Newton. Rows: r_1 = k Q (taken from
/// node 1), r_2 = -k Q (brought to node 2), k = kHydraulicRowScale.
class HydraulicOrifice final : public AutoDiffElement<HydraulicOrifice, 2> {
 public:
  static constexpr std::array<SlotKind, 2> kSlots = {SlotKind::scalar, SlotKind::scalar};

  explicit HydraulicOrifice(HydraulicOrificeProperties p);

  std::string_view type_name() const override { return "hydraulic_orifice"; }
  ElementEnergy energy(std::span<const SlotState<double>>, const ElementContext&) const override { return {}; }
  std::vector<Vec3> axis_points(std::span<const SlotState<double>>, const ElementContext&) const override { return {}; }

  /// Throttling turns dp Q into heat.
  ElementPower power(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  std::span<const std::string> flow_names() const override { return {&props_.flow_name, 1}; }
  /// Q from node 1 to node 2.
  void flows(std::span<const SlotState<double>> state, const ElementContext& ctx, std::span<double> out) const override {
    out[0] = flow(state[0].pos(0), state[1].pos(0), ctx.time);
  }

  const HydraulicOrificeProperties& properties() const { return props_; }
  /// Q from node 1 to node 2 at pressures p1, p2 and time t, m^3/s.
  double flow(double p1, double p2, double t) const;

  template <class S>
  void compute_residual(std::span<const SlotState<S>> s, const ElementContext& ctx, Eigen::Matrix<S, 2, 1>& r) const {
    using std::sqrt;
    const S dp = s[0].pos(0) - s[1].pos(0);
    const S open = opening<S>(dp, ctx.time);
    const S pt(props_.transition_pressure);
    const S Q = S(props_.discharge_coefficient * props_.area * std::sqrt(2.0 / props_.fluid.density)) * open * dp /
                sqrt(sqrt(dp * dp + pt * pt));
    r(0) = S(kHydraulicRowScale) * Q;
    r(1) = -S(kHydraulicRowScale) * Q;
  }

 private:
  template <class S>
  S opening(const S& dp, double t) const {
    switch (props_.opening) {
      case OrificeOpening::fixed:
        return S(1.0);
      case OrificeOpening::drive:
        return S(std::clamp(props_.drive->evaluate(t).value, 0.0, 1.0));
      case OrificeOpening::spool_positive:
        return S(std::clamp(props_.drive->evaluate(t).value, 0.0, 1.0));
      case OrificeOpening::spool_negative:
        return S(std::clamp(-props_.drive->evaluate(t).value, 0.0, 1.0));
      case OrificeOpening::relief: {
        const double span = props_.full_open_pressure - props_.cracking_pressure;
        const double x = (scalar_value(dp) - props_.cracking_pressure) / span;
        if (x <= 0.0) return S(0.0);
        if (x >= 1.0) return S(1.0);
        const S y = (dp - S(props_.cracking_pressure)) / S(span);
        return y * y * (S(3.0) - S(2.0) * y);  // smoothstep: C1 at both ends
      }
    }
    return S(1.0);
  }

  HydraulicOrificeProperties props_;
};

}  // namespace latticedyn
