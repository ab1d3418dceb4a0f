// Stresses of round tubes, frames and custom sections at their checked points.
#include "elements/section_stress.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace latticedyn {

namespace {

struct Point {
  double sigma, tau;
};

void take(SectionStress& s, const Point& p) {
  s.normal = std::max(s.normal, std::abs(p.sigma));
  s.shear = std::max(s.shear, std::abs(p.tau));
  s.von_mises = std::max(s.von_mises, std::sqrt(p.sigma * p.sigma + 3 * p.tau * p.tau));
}

double normal_stress(const SectionProperties& c, const SectionForces& f, double y, double z) {
  return f.N / c.area + f.My * z / c.Iy - f.Mz * y / c.Iz;
}

constexpr int kTubePoints = 72;  // even: the points come in opposite pairs

// cos and sin of the tube's checked angles 2 pi i / kTubePoints, computed once.
const std::array<std::array<double, 2>, kTubePoints>& tube_angles() {
  static const auto table = [] {
    std::array<std::array<double, 2>, kTubePoints> t{};
    for (int i = 0; i < kTubePoints; ++i) {
      const double phi = 2 * std::numbers::pi * i / kTubePoints;
      t[static_cast<std::size_t>(i)] = {std::cos(phi), std::sin(phi)};
    }
    return t;
  }();
  return table;
}

SectionStress round_tube(const SectionProperties& c, const SectionForces& f) {
  const double ro = c.outer_radius, ri = c.inner_radius;
  const double k = 4.0 / 3.0 * (ro * ro + ro * ri + ri * ri) / (ro * ro + ri * ri);
  // On the outer fibre (y, z) = ro (cos phi, sin phi) both stresses are linear in (cos, sin):
  // sigma = N/A + My z/Iy - Mz y/Iz, and along the tangent (-sin, cos) the torsion's and the shear
  // force's flow tau = T ro/J + k (-Qy sin + Qz cos)/A. Their coefficients once per section, no
  // division or root per point: the stresses were a quarter of the reduced crane's run (1.5e9 of
  // 5.9e9 instructions, callgrind, combined maneuver) when each point evaluated them afresh.
  const double s0 = f.N / c.area, s_cos = -f.Mz * ro / c.Iz, s_sin = f.My * ro / c.Iy;
  const double t0 = f.T * ro / c.torsion_constant, t_cos = k * f.Qz / c.area, t_sin = -k * f.Qy / c.area;
  double normal = 0.0, shear = 0.0, vm2 = 0.0;
  auto at = [&](double cos_phi, double sin_phi) {
    const double sigma = s0 + s_cos * cos_phi + s_sin * sin_phi;
    const double tau = t0 + t_cos * cos_phi + t_sin * sin_phi;
    normal = std::max(normal, std::abs(sigma));
    shear = std::max(shear, std::abs(tau));
    vm2 = std::max(vm2, sigma * sigma + 3 * tau * tau);
  };
  // The checked points in opposite pairs (phi, phi + pi), where the linear parts p and q of sigma
  // and tau change sign: sigma^2 + 3 tau^2 = s0^2 + 3 t0^2 + p^2 + 3 q^2 +- 2 (s0 p + 3 t0 q),
  // the larger of the two with the sum's magnitude (every term then non-negative). Only von Mises
  // needs the grid: the normal and the shear stress take their exact maxima at the extremes below.
  const double base = s0 * s0 + 3 * t0 * t0;
  const auto& angles = tube_angles();
  for (int i = 0; i < kTubePoints / 2; ++i) {
    const auto& [cos_phi, sin_phi] = angles[static_cast<std::size_t>(i)];
    const double p = s_cos * cos_phi + s_sin * sin_phi, q = t_cos * cos_phi + t_sin * sin_phi;
    vm2 = std::max(vm2, base + p * p + 3 * q * q + 2 * std::abs(s0 * p + 3 * t0 * q));
  }
  // The extremes of bending, at (y, z) along (-Mz, My), and of the shear force's flow, where the
  // tangent lies along Q: exact maxima of the normal and the shear stress. The directions'
  // cosines and sines by normalising, not through atan2, cos and sin (a third of this function).
  for (const auto& [x, y] : {std::array{-f.Mz, f.My}, std::array{f.Qz, -f.Qy}}) {
    const double r = std::sqrt(x * x + y * y);
    const double cos_phi = r > 0 ? x / r : 1.0, sin_phi = r > 0 ? y / r : 0.0;
    at(cos_phi, sin_phi);
    at(-cos_phi, -sin_phi);
  }
  return SectionStress{normal, shear, std::sqrt(vm2)};
}

SectionStress frame(const SectionProperties& c, const SectionForces& f) {
  const double h = c.height, b = c.width, t = c.thickness;
  SectionStress s;
  const bool solid = 2 * t >= std::min(h, b);
  double tau_t, tau_qy, tau_qz;  // at the wall middles
  if (solid) {
    const double a = std::max(h, b), d = std::min(h, b);
    tau_t = std::abs(f.T) * (3 * a + 1.8 * d) / (a * a * d * d);  // Roark, Table 10.1 case 4
    tau_qy = 1.5 * std::abs(f.Qy) / c.area;
    tau_qz = 1.5 * std::abs(f.Qz) / c.area;
  } else {
    tau_t = std::abs(f.T) / (2 * (b - t) * (h - t) * t);  // Bredt
    // First moments of half the section about the neutral axis (flange plus two half webs).
    const double s_y = b * t * (h - t) / 2 + t * (h / 2 - t) * (h / 2 - t);
    const double s_z = h * t * (b - t) / 2 + t * (b / 2 - t) * (b / 2 - t);
    tau_qz = std::abs(f.Qz) * s_y / (c.Iy * 2 * t);
    tau_qy = std::abs(f.Qy) * s_z / (c.Iz * 2 * t);
  }
  for (double y : {-b / 2, b / 2})
    for (double z : {-h / 2, h / 2}) take(s, Point{normal_stress(c, f, y, z), tau_t});
  for (double y : {-b / 2, b / 2}) take(s, Point{normal_stress(c, f, y, 0.0), tau_t + tau_qz});
  for (double z : {-h / 2, h / 2}) take(s, Point{normal_stress(c, f, 0.0, z), tau_t + tau_qy});
  return s;
}

SectionStress custom(const SectionProperties& c, double nu, const SectionForces& f) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!(c.fibre_y > 0 && c.fibre_z > 0)) return SectionStress{nan, nan, nan};
  const double r = std::hypot(c.fibre_y, c.fibre_z);
  const double tau = std::abs(f.T) * r / c.torsion_constant +
                     std::hypot(f.Qy, f.Qz) / (c.shear_coefficient(nu) * c.area);
  SectionStress s;
  for (double y : {-c.fibre_y, c.fibre_y})
    for (double z : {-c.fibre_z, c.fibre_z}) take(s, Point{normal_stress(c, f, y, z), tau});
  return s;
}

}  // namespace

SectionStress section_stress(const SectionProperties& section, double poisson_ratio, const SectionForces& f) {
  switch (section.shape) {
    case SectionProperties::Shape::round_tube: return round_tube(section, f);
    case SectionProperties::Shape::frame: return frame(section, f);
    case SectionProperties::Shape::custom: return custom(section, poisson_ratio, f);
  }
  return custom(section, poisson_ratio, f);
}

MemberStress member_stress(const SectionProperties& section, const Material& material, const SectionForces& end1,
                           const SectionForces& end2, std::span<const SectionForces> between) {
  MemberStress m;
  m.end = {end1, end2};
  double vm = section_stress(section, material.poisson_ratio, end1).von_mises;
  vm = std::max(vm, section_stress(section, material.poisson_ratio, end2).von_mises);
  for (const SectionForces& f : between) vm = std::max(vm, section_stress(section, material.poisson_ratio, f).von_mises);
  m.von_mises = vm;  // NaN stays NaN: std::max(NaN, x) returns NaN as its first argument
  if (material.yield_stress > 0) m.utilization = vm / material.yield_stress;
  return m;
}

MemberStress bar_stress(const SectionProperties& section, const Material& material, double axial_force) {
  SectionForces f;
  f.N = axial_force;
  MemberStress m;
  m.end = {f, f};
  m.von_mises = std::abs(axial_force) / section.area;
  if (material.yield_stress > 0) m.utilization = m.von_mises / material.yield_stress;
  return m;
}

}  // namespace latticedyn
