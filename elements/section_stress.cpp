// Stresses of round tubes, frames and custom sections at their checked points.
#include "elements/section_stress.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

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

// The largest of (s0 + s.u)^2 + 3 (t0 + t.u)^2 over the unit circle |u| = 1: the quadratic
// u^T A u + 2 b^T u + c with A = s s^T + 3 t t^T, b = s0 s + 3 t0 t, c = s0^2 + 3 t0^2, maximised
// on a circle like a trust-region subproblem (More & Sorensen 1983): at the maximum
// (mu I - A) u = b with mu >= lambda_1, the larger eigenvalue of A, so that with b's components
// beta_i along A's eigenvectors and x = mu - lambda_1 >= 0 the secular equation
// beta_1^2 / x^2 + beta_2^2 / (x + g)^2 = 1 (g = lambda_1 - lambda_2) has one root, and there
// f = c + mu + b^T u = c + lambda_1 + x + beta_1^2 / x + beta_2^2 / (x + g): a sum of
// non-negative terms, stationary in x at the root (its error is second order in x's). Exact to
// round-off where a grid of checked points falls short by up to (pi / n)^2 / 2 of the stress.
// Plain roots, not std::hypot: glibc's overflow-safe hypot cost half of this function, and squares
// of A's entries (stresses to the fourth power, 1e36 Pa^4 for 1 GPa) stay far from overflow.
double largest_on_circle(double s0, double sc, double ss, double t0, double tc, double ts) {
  const double c = s0 * s0 + 3 * t0 * t0;
  const double axx = sc * sc + 3 * tc * tc, ayy = ss * ss + 3 * ts * ts, axy = sc * ss + 3 * tc * ts;
  const double bx = s0 * sc + 3 * t0 * tc, by = s0 * ss + 3 * t0 * ts;
  const double mean = 0.5 * (axx + ayy), half = 0.5 * (axx - ayy), r = std::sqrt(half * half + axy * axy);
  const double lambda1 = mean + r, g = 2 * r;
  const double b_norm = std::sqrt(bx * bx + by * by);
  if (b_norm == 0.0) return c + lambda1;
  // The eigenvector of lambda_1 from the larger of A - lambda_2 I's columns (no cancellation).
  double v1x = 1.0, v1y = 0.0;
  if (r > 0) {
    const double ex = half >= 0 ? half + r : axy, ey = half >= 0 ? axy : r - half, e = std::sqrt(ex * ex + ey * ey);
    v1x = ex / e;
    v1y = ey / e;
  }
  const double beta1 = v1x * bx + v1y * by, beta2 = -v1y * bx + v1x * by;
  const double q1 = beta1 * beta1, q2 = beta2 * beta2;
  // The root lies in [lo, hi]: each term alone must not exceed 1, both together reach 1 by |b|.
  const double lo = std::max({std::abs(beta1), std::abs(beta2) - g, 0.0}), hi = std::max(lo, b_norm);
  auto secular = [&](double x) {  // beta_1^2 / x^2 + beta_2^2 / (x + g)^2 and its derivative
    double value = 0.0, slope = 0.0;
    if (q1 > 0) {
      value += q1 / (x * x);
      slope -= 2 * q1 / (x * x * x);
    }
    if (q2 > 0) {
      const double y = x + g;
      value += q2 / (y * y);
      slope -= 2 * q2 / (y * y * y);
    }
    return std::array{value, slope};
  };
  // In the hard case (beta_1 = 0, the circle's maximum where A's own direction fills it) x stays
  // at lo; otherwise Newton on 1/sqrt(S(x)) - 1, concave and increasing (More & Sorensen): from
  // lo, where it is not positive, every iterate stays left of the root and approaches it
  // monotonically.
  double x = lo;
  const bool hard_case = q1 == 0.0 && (lo == 0.0 || secular(lo)[0] <= 1.0);
  for (int it = 0; !hard_case && it < 100; ++it) {
    const auto [value, slope] = secular(x);
    const double inv = 1.0 / std::sqrt(value);
    const double step = (inv - 1.0) / (0.5 * inv * inv * inv * slope);  // -psi / psi'
    const double next = std::clamp(x + step, lo, hi);
    const bool converged = !(std::abs(next - x) > 4 * std::numeric_limits<double>::epsilon() * next);
    x = next;
    if (converged) break;
  }
  double f = c + lambda1 + x;
  if (q1 > 0) f += q1 / x;
  if (q2 > 0) f += q2 / (x + g);
  return f;
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
  double normal = 0.0, shear = 0.0;
  double vm2 = largest_on_circle(s0, s_cos, s_sin, t0, t_cos, t_sin);
  // The extremes below may still raise vm2 by an ulp of the closed form's round-off.
  auto at = [&](double cos_phi, double sin_phi) {
    const double sigma = s0 + s_cos * cos_phi + s_sin * sin_phi;
    const double tau = t0 + t_cos * cos_phi + t_sin * sin_phi;
    normal = std::max(normal, std::abs(sigma));
    shear = std::max(shear, std::abs(tau));
    vm2 = std::max(vm2, sigma * sigma + 3 * tau * tau);
  };
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
