// Co-rotational Timoshenko beam: elastic force and stiffness from the strain energy by AD, closed-
// form inertia and gravity.
#include "elements/timoshenko_beam.hpp"

#include "core/hermite.hpp"
#include "elements/energy_ad.hpp"

#include <cmath>
#include <stdexcept>

namespace latticedyn {

namespace {

// 9 energy variables: d = r2 - r1 (0..2), rotation 1 (3..5), rotation 2 (6..8), mapped onto the
// element's 12 DoFs [r1, theta1, r2, theta2].
using BeamAD = EnergyAD<9>;

Eigen::Matrix<double, 12, 9> energy_to_dofs() {
  Eigen::Matrix<double, 12, 9> P = Eigen::Matrix<double, 12, 9>::Zero();
  P.block<3, 3>(0, 0) = -Mat3::Identity();
  P.block<3, 3>(3, 3) = Mat3::Identity();
  P.block<3, 3>(6, 0) = Mat3::Identity();
  P.block<3, 3>(9, 6) = Mat3::Identity();
  return P;
}

}  // namespace

void BeamProperties::validate() const {
  material.validate();
  section.validate();
  if (!(std::isfinite(length) && length > 0)) throw std::invalid_argument("beam length must be positive");
  if (!std::isfinite(shear_coefficient)) throw std::invalid_argument("shear coefficient must be finite");
}

TimoshenkoBeam::TimoshenkoBeam(const BeamProperties& p) : props_(p) {
  props_.validate();
  const Material& m = p.material;
  const SectionProperties& s = p.section;
  const double L = p.length, E = m.youngs_modulus, G = m.shear_modulus();
  const double kappa = p.shear_coefficient > 0 ? p.shear_coefficient : s.shear_coefficient(m.poisson_ratio);
  props_.shear_coefficient = kappa;
  const double rho = s.effective_density(m);
  mass_ = rho * s.area * L;
  rotary_ = 0.5 * rho * L * Vec3(s.Iy + s.Iz, s.Iy, s.Iz);
  ea_ = E * s.area / L;
  gj_ = G * s.torsion_constant / L;
  // Bending about z (deflection along y) uses Iz, about y uses Iy.
  const double phi_z = 12 * E * s.Iz / (kappa * G * s.area * L * L);
  const double phi_y = 12 * E * s.Iy / (kappa * G * s.area * L * L);
  kz_[0] = E * s.Iz / (L * (1 + phi_z)) * (4 + phi_z);
  kz_[1] = E * s.Iz / (L * (1 + phi_z)) * (2 - phi_z);
  ky_[0] = E * s.Iy / (L * (1 + phi_y)) * (4 + phi_y);
  ky_[1] = E * s.Iy / (L * (1 + phi_y)) * (2 - phi_y);
}

void TimoshenkoBeam::inertia(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
                             ElementTangents* t) const {
  const double m6 = mass_ / 6.0;
  const Mat3 J = rotary_.asDiagonal();
  r.segment<3>(0) = m6 * (2 * s[0].acc + s[2].acc) - 3 * m6 * ctx.gravity;
  r.segment<3>(6) = m6 * (s[0].acc + 2 * s[2].acc) - 3 * m6 * ctx.gravity;
  for (int e = 0; e < 2; ++e) {
    const Vec3& w = s[1 + 2 * e].vel;
    r.segment<3>(3 + 6 * e) = J * s[1 + 2 * e].acc + w.cross(J * w);
  }
  if (!t) return;
  t->K.setZero();
  t->C.setZero();
  t->M.setZero();
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) t->M.block<3, 3>(6 * a, 6 * b) = (a == b ? 2 * m6 : m6) * Mat3::Identity();
  for (int e = 0; e < 2; ++e) {
    const Vec3& w = s[1 + 2 * e].vel;
    t->M.block<3, 3>(3 + 6 * e, 3 + 6 * e) = J;
    t->C.block<3, 3>(3 + 6 * e, 3 + 6 * e) = skew(w) * J - skew<double>(J * w);
  }
}

void TimoshenkoBeam::residual(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r) const {
  inertia(s, ctx, r, nullptr);
  BeamAD::FirstOrder ad;
  const auto U = strain_energy<decltype(ad)::S>(ad.vec(s[2].pos - s[0].pos, 0), ad.rot(s[1].rot, 3), ad.rot(s[3].rot, 6));
  BeamAD::Gradient g;
  BeamAD::extract(U, nullptr, &g);
  static const Eigen::Matrix<double, 12, 9> P = energy_to_dofs();
  r += P * g;
}

void TimoshenkoBeam::tangents(std::span<const SlotState<double>> s, const ElementContext& ctx, ElementTangents& out) const {
  out.resize(12);
  inertia(s, ctx, out.residual, &out);
  BeamAD::SecondOrder ad;
  const auto U = strain_energy<decltype(ad)::S>(ad.vec(s[2].pos - s[0].pos, 0), ad.rot(s[1].rot, 3), ad.rot(s[3].rot, 6));
  BeamAD::Gradient g;
  BeamAD::Stiffness K;
  BeamAD::extract(U, ad, nullptr, &g, &K);
  static const Eigen::Matrix<double, 12, 9> P = energy_to_dofs();
  out.residual += P * g;
  out.K += P * K * P.transpose();
}

ElementEnergy TimoshenkoBeam::energy(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  ElementEnergy e;
  const Vec3 &v1 = s[0].vel, &v2 = s[2].vel;
  e.kinetic = mass_ / 6.0 * (v1.squaredNorm() + v1.dot(v2) + v2.squaredNorm());
  for (int k = 0; k < 2; ++k) e.kinetic += 0.5 * s[1 + 2 * k].vel.dot(rotary_.asDiagonal() * s[1 + 2 * k].vel);
  e.gravity_potential = -mass_ * ctx.gravity.dot(0.5 * (s[0].pos + s[2].pos));
  e.strain = strain_energy<double>(s[2].pos - s[0].pos, s[1].rot, s[3].rot);
  return e;
}

std::optional<double> TimoshenkoBeam::axial_force(std::span<const SlotState<double>> s, const ElementContext&) const {
  return ea_ * ((s[2].pos - s[0].pos).norm() - props_.length);
}

std::vector<Vec3> TimoshenkoBeam::axis_points(std::span<const SlotState<double>> s, const ElementContext&) const {
  double u;
  Vec3 a, b;
  Mat3 Rr;
  const Vec3 d = s[2].pos - s[0].pos;
  local_deformation<double>(d, s[1].rot, s[3].rot, u, a, b, &Rr);
  const double l = d.norm();
  std::vector<Vec3> pts;
  for (int k = 0; k <= 4; ++k) {
    const double xi = k / 4.0;
    const HermiteCubic<double> h = hermite_cubic(xi, l);
    // Deflection with zero end displacements and end slopes v' = theta_z, w' = -theta_y.
    const double v = h.N[1] * a(2) + h.N[3] * b(2);
    const double w = -(h.N[1] * a(1) + h.N[3] * b(1));
    pts.push_back(s[0].pos + xi * d + Rr.col(1) * v + Rr.col(2) * w);
  }
  return pts;
}

}  // namespace latticedyn
