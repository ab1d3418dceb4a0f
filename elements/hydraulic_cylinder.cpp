// Hydraulic cylinder: parameter checks, areas, energy and force output.
#include "elements/hydraulic_cylinder.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace latticedyn {

double HydraulicCylinderProperties::piston_area() const {
  return std::numbers::pi / 4 * piston_diameter * piston_diameter;
}

double HydraulicCylinderProperties::rod_side_area() const {
  return std::numbers::pi / 4 * (piston_diameter * piston_diameter - rod_diameter * rod_diameter);
}

void HydraulicCylinderProperties::validate() const {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
  };
  require(piston_diameter > 0, "piston_diameter must be positive");
  require(rod_diameter > 0 && rod_diameter < piston_diameter, "rod_diameter must be positive and below piston_diameter");
  require(stroke > 0, "stroke must be positive");
  require(retracted_length > 0, "retracted_length must be positive");
  require(dead_volume_piston > 0 && dead_volume_rod > 0,
          "dead volumes must be positive (a chamber with no oil left has no stiffness to compute)");
  require(viscous_friction >= 0 && coulomb_friction >= 0 && friction_velocity > 0 && leakage >= 0 && mass >= 0,
          "friction, leakage and mass must not be negative, friction_velocity positive");
  require(fluid.bulk_modulus > 0 && fluid.density > 0, "the fluid's bulk_modulus and density must be positive");
  require(end_stop_stiffness >= 0 && end_stop_damping >= 0, "end_stop_stiffness and end_stop_damping must not be negative");
  require(end_stop_transition > 0 && end_stop_transition < stroke, "end_stop_transition must be positive and below the stroke");
}

double end_stop_ramp_energy(double d, double w) {
  if (d <= 0) return 0.0;
  return d < w ? d * d * d / (6 * w) : 0.5 * (d * d - w * d) + w * w / 6;
}

HydraulicCylinder::HydraulicCylinder(const HydraulicCylinderProperties& p) : props_(p) {
  props_.validate();
  area1_ = props_.piston_area();
  area2_ = props_.rod_side_area();
  constexpr double kSteelModulus = 2.1e11;
  const double rod_area = std::numbers::pi / 4 * props_.rod_diameter * props_.rod_diameter;
  stop_stiffness_ = props_.end_stop_stiffness > 0 ? props_.end_stop_stiffness
                                                  : kSteelModulus * rod_area / props_.retracted_length;
}

ElementEnergy HydraulicCylinder::energy(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  ElementEnergy out;
  const double half = 0.5 * props_.mass;
  out.kinetic = 0.5 * half * (s[0].vel.squaredNorm() + s[1].vel.squaredNorm());
  out.gravity_potential = -half * ctx.gravity.dot(s[0].pos + s[1].pos);
  // The compressed oil's energy, V p^2 / (2 beta) per chamber (linear compressibility).
  const double stroke_now = stroke(s), beta = props_.fluid.bulk_modulus;
  const double V1 = props_.dead_volume_piston + area1_ * stroke_now;
  const double V2 = props_.dead_volume_rod + area2_ * (props_.stroke - stroke_now);
  out.fluid = V1 * s[2].pos(0) * s[2].pos(0) / (2 * beta) + V2 * s[3].pos(0) * s[3].pos(0) / (2 * beta);
  const double w = props_.end_stop_transition;
  out.strain = stop_stiffness_ * (end_stop_ramp_energy(-stroke_now, w) + end_stop_ramp_energy(stroke_now - props_.stroke, w));
  return out;
}

ElementPower HydraulicCylinder::power(std::span<const SlotState<double>> s, const ElementContext&) const {
  const Vec3 e = (s[1].pos - s[0].pos).normalized();
  const double rate = e.dot(s[1].vel - s[0].vel), stroke_now = stroke(s), w = props_.end_stop_transition;
  const double p1 = s[2].pos(0), p2 = s[3].pos(0), beta = props_.fluid.bulk_modulus;
  const double stop_weight = end_stop_weight(-stroke_now, w) + end_stop_weight(stroke_now - props_.stroke, w);
  ElementPower out;
  out.dissipated = (props_.viscous_friction + props_.end_stop_damping * stop_weight) * rate * rate +
                   props_.coulomb_friction * std::tanh(rate / props_.friction_velocity) * rate +
                   props_.leakage * (p1 - p2) * (p1 - p2);
  const double V1 = props_.dead_volume_piston + area1_ * stroke_now;
  const double V2 = props_.dead_volume_rod + area2_ * (props_.stroke - stroke_now);
  out.compression = (p1 * V1 * s[2].vel(0) + p2 * V2 * s[3].vel(0)) / beta;
  return out;
}

void HydraulicCylinder::flows(std::span<const SlotState<double>> s, const ElementContext& ctx, std::span<double> out) const {
  Eigen::Matrix<double, 8, 1> r;
  compute_residual<double>(s, ctx, r);
  out[0] = r(6) / kHydraulicRowScale;
  out[1] = r(7) / kHydraulicRowScale;
}

std::optional<double> HydraulicCylinder::axial_force(std::span<const SlotState<double>> s,
                                                     const ElementContext& ctx) const {
  Eigen::Matrix<double, 8, 1> r;
  std::array<SlotState<double>, 4> still{s[0], s[1], s[2], s[3]};
  for (auto& slot : still) slot.acc.setZero();
  ElementContext weightless = ctx;
  weightless.gravity.setZero();
  compute_residual<double>(std::span<const SlotState<double>>(still), weightless, r);
  const Vec3 e = (s[1].pos - s[0].pos).normalized();
  return -r.segment<3>(0).dot(e);  // r_A = F e: the extending force F is compression
}

}  // namespace latticedyn
