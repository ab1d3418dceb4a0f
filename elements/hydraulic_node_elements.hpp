// One-node hydraulic elements: the oil volume of a node (hoses, pipes: its capacitance) and an ideal
// pump delivering a given flow into a node.
#pragma once

#include "core/drive.hpp"
#include "elements/autodiff_element.hpp"
#include "elements/hydraulic_fluid.hpp"

#include <optional>
#include <string>

namespace latticedyn {

/// Slot: [scalar p]. r = k V / beta p_dot: the flow that compresses the node's own volume V.
/// Every free hydraulic node has one, so that its row is a pressure build-up equation.
class HydraulicVolume final : public AutoDiffElement<HydraulicVolume, 1> {
 public:
  static constexpr std::array<SlotKind, 1> kSlots = {SlotKind::scalar};
  /// Throws std::invalid_argument unless volume and bulk modulus are positive.
  HydraulicVolume(double volume, const HydraulicFluid& fluid);

  std::string_view type_name() const override { return "hydraulic_volume"; }
  /// The node's oil, V p^2 / (2 beta).
  ElementEnergy energy(std::span<const SlotState<double>> state, const ElementContext&) const override;
  /// Compression p V p_dot / beta (exactly the rate of its energy: V is fixed).
  ElementPower power(std::span<const SlotState<double>> state, const ElementContext&) const override;
  std::vector<Vec3> axis_points(std::span<const SlotState<double>>, const ElementContext&) const override { return {}; }
  double volume() const { return volume_; }

  template <class S>
  void compute_residual(std::span<const SlotState<S>> s, const ElementContext&, Eigen::Matrix<S, 1, 1>& r) const {
    r(0) = S(kHydraulicRowScale * volume_ / bulk_modulus_) * s[0].vel(0);
  }

 private:
  double volume_, bulk_modulus_;
};

/// Slot: [scalar p of the outlet]. An ideal pump: Q = flow (m^3/s), times the drive's value if
/// it has one (a variable displacement or speed), whatever the pressure: r = -k Q.
class HydraulicPump final : public AutoDiffElement<HydraulicPump, 1> {
 public:
  static constexpr std::array<SlotKind, 1> kSlots = {SlotKind::scalar};
  /// Throws std::invalid_argument unless the flow is finite.
  HydraulicPump(double flow, std::optional<Drive> drive);

  std::string_view type_name() const override { return "hydraulic_pump"; }
  ElementEnergy energy(std::span<const SlotState<double>>, const ElementContext&) const override { return {}; }
  /// Supplies p Q, p its outlet's pressure.
  ElementPower power(std::span<const SlotState<double>> state, const ElementContext& ctx) const override {
    ElementPower out;
    out.supplied = state[0].pos(0) * flow(ctx.time);
    return out;
  }
  std::span<const std::string> flow_names() const override { return kFlowNames; }
  void flows(std::span<const SlotState<double>>, const ElementContext& ctx, std::span<double> out) const override {
    out[0] = flow(ctx.time);
  }
  std::vector<Vec3> axis_points(std::span<const SlotState<double>>, const ElementContext&) const override { return {}; }
  /// The delivered flow at time t, m^3/s.
  double flow(double t) const { return drive_ ? flow_ * drive_->evaluate(t).value : flow_; }

  template <class S>
  void compute_residual(std::span<const SlotState<S>>, const ElementContext& ctx, Eigen::Matrix<S, 1, 1>& r) const {
    r(0) = S(-kHydraulicRowScale * flow(ctx.time));
  }

 private:
  inline static const std::array<std::string, 1> kFlowNames = {"Q"};
  double flow_;
  std::optional<Drive> drive_;
};

}  // namespace latticedyn
