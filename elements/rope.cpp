// Rope element: tension-only elastic energy (its gradient in closed form, its Hessian by AD),
// inertia and gravity in closed form with the rest length and its rates from the drive.
#include "elements/rope.hpp"

#include "core/quadrature.hpp"
#include "elements/energy_ad.hpp"
#include "elements/strain_rate_damping.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace latticedyn {

namespace {

using RopeAD = EnergyAD<9>;  // d = r2 - r1 (0..2), r1' (3..5), r2' (6..8)

Eigen::Matrix<double, 12, 9> energy_to_dofs() {
  Eigen::Matrix<double, 12, 9> P = Eigen::Matrix<double, 12, 9>::Zero();
  P.block<3, 3>(0, 0) = -Mat3::Identity();
  P.block<3, 3>(3, 3) = Mat3::Identity();
  P.block<3, 3>(6, 0) = Mat3::Identity();
  P.block<3, 3>(9, 6) = Mat3::Identity();
  return P;
}

// Unit Hermite functions on [0, 1] (slopes d/dxi) and their integrals.
Eigen::Vector4d unit_hermite(double x) {
  const double x2 = x * x, x3 = x2 * x;
  return Eigen::Vector4d(1 - 3 * x2 + 2 * x3, x - 2 * x2 + x3, 3 * x2 - 2 * x3, x3 - x2);
}
const Eigen::Vector4d kHermiteIntegral(0.5, 1.0 / 12, 0.5, -1.0 / 12);

}  // namespace

void RopeProperties::validate() const {
  if (!(std::isfinite(material.density) && material.density > 0))
    throw std::invalid_argument("rope density must be positive");
  if (!(std::isfinite(material.youngs_modulus) && material.youngs_modulus > 0))
    throw std::invalid_argument("rope Young's modulus must be positive");
  if (!(section.area > 0)) throw std::invalid_argument("rope section area must be positive");
  if (!drive && !(std::isfinite(rest_length) && rest_length > 0))
    throw std::invalid_argument("rope rest length must be positive");
  if (!(fraction > 0)) throw std::invalid_argument("rope length fraction must be positive");
  if (gauss_points < 1 || gauss_points > 64) throw std::invalid_argument("rope Gauss points must be 1..64");
  material.damping.validate();
  if (material.damping.alpha != 0)
    throw std::invalid_argument("a rope takes stiffness-proportional damping only (beta, or a ratio at one frequency), not alpha");
}

Rope::Rope(RopeProperties p) : props_(std::move(p)) {
  props_.validate();
  rho_a_ = props_.section.effective_density(props_.material) * props_.section.area;
  ea_ = props_.material.youngs_modulus * props_.section.area;
  const GaussRule rule = gauss_legendre_on(props_.gauss_points, 0.0, 1.0);
  xi_ = rule.points;
  w_ = rule.weights;
  // The mass integral of cubics times cubics is exact with 4 points.
  hermite_mass_.setZero();
  const GaussRule exact = gauss_legendre_on(4, 0.0, 1.0);
  for (std::size_t g = 0; g < exact.points.size(); ++g) {
    const Eigen::Vector4d h = unit_hermite(exact.points[g]);
    hermite_mass_ += exact.weights[g] * h * h.transpose();
  }
}

DriveValue Rope::rest_length(double t) const {
  if (!props_.drive) return DriveValue{props_.rest_length, 0.0, 0.0};
  const DriveValue v = props_.drive->evaluate(t);
  return DriveValue{props_.fraction * v.value, props_.fraction * v.rate, props_.fraction * v.accel};
}

void Rope::inertia_and_gravity(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
                                ElementTangents* t) const {
  const DriveValue L = rest_length(ctx.time);
  if (!(L.value > 0))
  {
    char buf[160];
    std::snprintf(buf, sizeof buf, "rope rest length %.6g m at t = %.6g s is not positive", L.value, ctx.time);
    throw std::domain_error(buf);
  }
  const double m = rho_a_ * L.value;
  // Hermite coordinates X = [r1, L0 r1', r2, L0 r2'] and their second time derivative.
  const double c[4] = {1.0, L.value, 1.0, L.value};
  Vec3 Xdd[4];
  for (int k = 0; k < 4; ++k) {
    const SlotState<double>& x = s[k];
    Xdd[k] = (k % 2 == 0) ? x.acc : Vec3(L.value * x.acc + 2 * L.rate * x.vel + L.accel * x.pos);
  }
  for (int a = 0; a < 4; ++a) {
    Vec3 f = -m * kHermiteIntegral(a) * ctx.gravity;
    for (int b = 0; b < 4; ++b) f += m * hermite_mass_(a, b) * Xdd[b];
    r.segment<3>(3 * a) = c[a] * f;
  }
  if (!t) return;
  t->K.setZero();
  t->C.setZero();
  t->M.setZero();
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      const double mab = m * hermite_mass_(a, b) * c[a];
      t->M.block<3, 3>(3 * a, 3 * b) = mab * c[b] * Mat3::Identity();
      if (b % 2 == 1) {
        t->C.block<3, 3>(3 * a, 3 * b) = mab * 2 * L.rate * Mat3::Identity();
        t->K.block<3, 3>(3 * a, 3 * b) = mab * L.accel * Mat3::Identity();
      }
    }
}

void Rope::add_damping(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
                       ElementTangents* t) const {
  const double beta = props_.material.damping.beta;
  if (!(beta > 0) || ctx.at_rest) return;
  // Variables d = r2 - r1, r1', r2' and the rest length L0, whose rate the drive gives: a rope
  // paid out at constant tension has eps_dot = 0 although its slopes' rates are not zero.
  const DriveValue L = rest_length(ctx.time);
  Eigen::Matrix<double, 10, 1> v;
  v << s[2].vel - s[0].vel, s[1].vel, s[3].vel, L.rate;
  const int ng = static_cast<int>(xi_.size());
  MatX Cd = MatX::Zero(ng, ng);
  Eigen::Matrix<double, 10, 1> f = Eigen::Matrix<double, 10, 1>::Zero();
  static const Eigen::Matrix<double, 12, 9> P = energy_to_dofs();
  const Vec3 d = s[2].pos - s[0].pos;
  auto fill = [&](const auto& ad, auto& eps) {
    const auto Ls = ad.scalar(L.value, 9);
    const auto dd = ad.vec(d, 0), t1 = ad.vec(s[1].pos, 3), t2 = ad.vec(s[3].pos, 6);
    for (int g = 0; g < ng; ++g) {
      eps[static_cast<std::size_t>(g)] = gauss_strain(dd, t1, t2, Ls, static_cast<std::size_t>(g));
      if (eps[static_cast<std::size_t>(g)].v >= -kSlackTolerance) Cd(g, g) = beta * ea_ * L.value * w_[static_cast<std::size_t>(g)];
    }
  };
  if (!t) {
    const EnergyAD<10>::FirstOrder ad;
    std::vector<Dual<10>> eps(static_cast<std::size_t>(ng));
    fill(ad, eps);
    add_strain_rate_damping_force<10>(eps, Cd, v, f);
    r += P * f.head<9>();
    return;
  }
  const EnergyAD<10>::SecondOrder ad;
  std::vector<HyperDual<10>> eps(static_cast<std::size_t>(ng));
  fill(ad, eps);
  Eigen::Matrix<double, 10, 10> K = Eigen::Matrix<double, 10, 10>::Zero(), C = Eigen::Matrix<double, 10, 10>::Zero();
  add_strain_rate_damping<10>(eps, ad, Cd, v, f, K, C);
  r += P * f.head<9>();
  t->K += P * K.topLeftCorner<9, 9>() * P.transpose();
  t->C += P * C.topLeftCorner<9, 9>() * P.transpose();
}

void Rope::residual(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r) const {
  inertia_and_gravity(s, ctx, r, nullptr);
  const double L0 = rest_length(ctx.time).value;
  const Eigen::Matrix<double, 9, 1> g = strain_energy_gradient(s[2].pos - s[0].pos, s[1].pos, s[3].pos, L0);
  static const Eigen::Matrix<double, 12, 9> P = energy_to_dofs();
  r += P * g;
  add_damping(s, ctx, r, nullptr);
}

Eigen::Matrix<double, 9, 1> Rope::strain_energy_gradient(const Vec3& d, const Vec3& t1, const Vec3& t2,
                                                         double L0) const {
  Eigen::Matrix<double, 9, 1> grad = Eigen::Matrix<double, 9, 1>::Zero();
  for (std::size_t g = 0; g < xi_.size(); ++g) {
    const Vec3 rs = gauss_slope(d, t1, t2, L0, g);
    const double stretch = rs.norm(), eps = stretch - 1.0;
    if (eps < -kSlackTolerance) continue;  // slack: no energy (the same test as strain_energy's)
    const Vec3 f = (ea_ * L0 * w_[g] * eps / stretch) * rs;
    const auto [dh1, dh2, dh4] = hermite_slopes(g);
    grad.segment<3>(0) += (dh1 / L0) * f;
    grad.segment<3>(3) += dh2 * f;
    grad.segment<3>(6) += dh4 * f;
  }
  return grad;
}

void Rope::tangents(std::span<const SlotState<double>> s, const ElementContext& ctx, ElementTangents& out) const {
  out.resize(12);
  inertia_and_gravity(s, ctx, out.residual, &out);
  RopeAD::SecondOrder ad;
  const double L0 = rest_length(ctx.time).value;
  const auto U = strain_energy<decltype(ad)::S>(ad.vec(s[2].pos - s[0].pos, 0), ad.vec(s[1].pos, 3), ad.vec(s[3].pos, 6), L0);
  RopeAD::Gradient g;
  RopeAD::Stiffness K;
  RopeAD::extract(U, ad, nullptr, &g, &K);
  static const Eigen::Matrix<double, 12, 9> P = energy_to_dofs();
  out.residual += P * g;
  out.K += P * K * P.transpose();
  add_damping(s, ctx, out.residual, &out);
}

ElementEnergy Rope::energy(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  const DriveValue L = rest_length(ctx.time);
  const double m = rho_a_ * L.value;
  Vec3 X[4], Xd[4];
  for (int k = 0; k < 4; ++k) {
    X[k] = k % 2 == 0 ? s[k].pos : Vec3(L.value * s[k].pos);
    Xd[k] = k % 2 == 0 ? s[k].vel : Vec3(L.value * s[k].vel + L.rate * s[k].pos);
  }
  ElementEnergy e;
  for (int a = 0; a < 4; ++a) {
    e.gravity_potential -= m * kHermiteIntegral(a) * ctx.gravity.dot(X[a]);
    for (int b = 0; b < 4; ++b) e.kinetic += 0.5 * m * hermite_mass_(a, b) * Xd[a].dot(Xd[b]);
  }
  e.strain = strain_energy<double>(s[2].pos - s[0].pos, s[1].pos, s[3].pos, L.value);
  return e;
}

std::optional<double> Rope::axial_force(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  const DriveValue L = rest_length(ctx.time);
  // dr/dS at the middle, xi = 1/2: (1.5 (r2 - r1))/L0 - r1'/4 - r2'/4.
  const Vec3 d = s[2].pos - s[0].pos;
  const Vec3 rs = 1.5 * d / L.value - 0.25 * (s[1].pos + s[3].pos);
  const double eps = rs.norm() - 1.0;
  if (eps < 0) return 0.0;
  const double beta = props_.material.damping.beta;
  if (!(beta > 0)) return ea_ * eps;
  // The viscous part of the tension, beta E A eps_dot.
  const Vec3 rs_dot = 1.5 * (s[2].vel - s[0].vel) / L.value - 1.5 * d * L.rate / (L.value * L.value) -
                      0.25 * (s[1].vel + s[3].vel);
  return std::max(ea_ * (eps + beta * rs.dot(rs_dot) / rs.norm()), 0.0);
}

std::vector<Vec3> Rope::axis_points(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  const double L0 = rest_length(ctx.time).value;
  std::vector<Vec3> pts;
  for (int k = 0; k <= 4; ++k) {
    const Eigen::Vector4d h = unit_hermite(k / 4.0);
    pts.push_back(h(0) * s[0].pos + h(1) * L0 * s[1].pos + h(2) * s[2].pos + h(3) * L0 * s[3].pos);
  }
  return pts;
}

void Rope::output(std::span<const SlotState<double>> s, const ElementContext& ctx, ElementOutput& out) const {
  Element::output(s, ctx, out);
  out.members.assign(1, bar_stress(props_.section, props_.material, out.axial_force.value_or(0.0)));
}

}  // namespace latticedyn
