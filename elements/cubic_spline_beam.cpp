// Cubic spline beam: elastic force and stiffness from the Cardan-angle strain energy by AD, the
// Hermite inertia and gravity through AutoDiffElement.
#include "elements/cubic_spline_beam.hpp"

#include "core/quadrature.hpp"
#include "elements/energy_ad.hpp"
#include "elements/strain_rate_damping.hpp"

#include <cmath>
#include <stdexcept>

namespace latticedyn {

namespace {

// 11 energy variables: d = r2 - r1 (0..2), rotation 1 (3..5), s1 (6), rotation 2 (7..9), s2 (10),
// mapped onto the 14 DoFs [r1, theta1, s1, r2, theta2, s2].
using SplineAD = EnergyAD<11>;
using Projection = Eigen::Matrix<double, 14, 11>;

Projection energy_to_dofs() {
  Projection P = Projection::Zero();
  P.block<3, 3>(0, 0) = -Mat3::Identity();
  P.block<3, 3>(3, 3) = Mat3::Identity();
  P(6, 6) = 1.0;
  P.block<3, 3>(7, 0) = Mat3::Identity();
  P.block<3, 3>(10, 7) = Mat3::Identity();
  P(13, 10) = 1.0;
  return P;
}

Eigen::Vector4d unit_hermite(double x) {
  const double x2 = x * x, x3 = x2 * x;
  return Eigen::Vector4d(1 - 3 * x2 + 2 * x3, x - 2 * x2 + x3, 3 * x2 - 2 * x3, x3 - x2);
}
const Eigen::Vector4d kHermiteIntegral(0.5, 1.0 / 12, 0.5, -1.0 / 12);

template <class Seeds>
auto spline_energy(const CubicSplineBeam& beam, std::span<const SlotState<double>> s, Seeds& ad) {
  return beam.strain_energy<typename Seeds::S>(ad.vec(s[3].pos - s[0].pos, 0), ad.rot(s[1].rot, 3),
                                               ad.scalar(s[2].pos(0), 6), ad.rot(s[4].rot, 7),
                                               ad.scalar(s[5].pos(0), 10));
}

}  // namespace

void CubicSplineBeamProperties::validate() const {
  beam.validate();
  if (gauss_points < 1 || gauss_points > 64)
    throw std::invalid_argument("cubic spline beam Gauss points must be 1..64");
}

CubicSplineBeam::CubicSplineBeam(const CubicSplineBeamProperties& p) : props_(p) {
  props_.validate();
  const Material& m = p.beam.material;
  const SectionProperties& sec = p.beam.section;
  L_ = p.beam.length;
  const double rho = sec.effective_density(m);
  rho_a_ = rho * sec.area;
  rotary_ = 0.5 * rho * L_ * Vec3(sec.Iy + sec.Iz, sec.Iy, sec.Iz);
  ea_ = m.youngs_modulus * sec.area;
  stiffness_ = Vec3(m.shear_modulus() * sec.torsion_constant, m.youngs_modulus * sec.Iy, m.youngs_modulus * sec.Iz);
  const GaussRule rule = gauss_legendre_on(props_.gauss_points, 0.0, 1.0);
  xi_ = rule.points;
  w_ = rule.weights;
  hermite_mass_.setZero();
  const GaussRule exact = gauss_legendre_on(4, 0.0, 1.0);  // cubic x cubic is exact with 4 points
  for (std::size_t g = 0; g < exact.points.size(); ++g) {
    const Eigen::Vector4d h = unit_hermite(exact.points[g]);
    hermite_mass_ += exact.weights[g] * h * h.transpose();
  }
}

void CubicSplineBeam::add_damping(std::span<const SlotState<double>> s, const ElementContext& ctx,
                                  Eigen::Ref<VecX> r, ElementTangents* t) const {
  const double beta = props_.beam.material.damping.beta;
  if (!(beta > 0) || ctx.at_rest) return;
  const std::size_t ng = xi_.size();
  MatX Cd = MatX::Zero(4 * static_cast<Eigen::Index>(ng), 4 * static_cast<Eigen::Index>(ng));
  for (std::size_t g = 0; g < ng; ++g) {
    const double c = beta * L_ * w_[g];
    const Eigen::Index k = 4 * static_cast<Eigen::Index>(g);
    Cd(k, k) = c * ea_;
    for (int j = 0; j < 3; ++j) Cd(k + 1 + j, k + 1 + j) = c * stiffness_(j);
  }
  SplineAD::Gradient v;
  v << s[3].vel - s[0].vel, s[1].vel, s[2].vel(0), s[4].vel, s[5].vel(0);
  SplineAD::Gradient f = SplineAD::Gradient::Zero();
  static const Projection P = energy_to_dofs();
  auto strains = [&](auto& ad, auto& e) {
    gauss_strains(ad.vec(s[3].pos - s[0].pos, 0), ad.rot(s[1].rot, 3), ad.scalar(s[2].pos(0), 6), ad.rot(s[4].rot, 7),
                  ad.scalar(s[5].pos(0), 10), std::span(e));
  };
  if (!t) {
    SplineAD::FirstOrder ad;
    std::vector<Dual<11>> e(4 * ng);
    strains(ad, e);
    add_strain_rate_damping_force<11>(e, Cd, v, f);
    r += P * f;
    return;
  }
  SplineAD::SecondOrder ad;
  std::vector<HyperDual<11>> e(4 * ng);
  strains(ad, e);
  SplineAD::Stiffness K = SplineAD::Stiffness::Zero(), C = SplineAD::Stiffness::Zero();
  add_strain_rate_damping<11>(e, ad, Cd, v, f, K, C);
  r += P * f;
  t->K += P * K * P.transpose();
  t->C += P * C * P.transpose();
}

void CubicSplineBeam::residual(std::span<const SlotState<double>> s, const ElementContext& ctx,
                               Eigen::Ref<VecX> r) const {
  AutoDiffElement::residual(s, ctx, r);
  SplineAD::Gradient g;
  SplineAD::FirstOrder ad;
  SplineAD::extract(spline_energy(*this, s, ad), nullptr, &g);
  static const Projection P = energy_to_dofs();
  r += P * g;
  add_damping(s, ctx, r, nullptr);
}

void CubicSplineBeam::tangents(std::span<const SlotState<double>> s, const ElementContext& ctx,
                               ElementTangents& out) const {
  AutoDiffElement::tangents(s, ctx, out);
  SplineAD::Gradient g;
  SplineAD::Stiffness K;
  SplineAD::SecondOrder ad;
  const auto U = spline_energy(*this, s, ad);
  SplineAD::extract(U, ad, nullptr, &g, &K);
  static const Projection P = energy_to_dofs();
  out.residual += P * g;
  out.K += P * K * P.transpose();
  add_damping(s, ctx, out.residual, &out);
}

ElementEnergy CubicSplineBeam::energy(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  const Vec3 ex = Vec3::UnitX();
  const double m = rho_a_ * L_;
  Vec3 X[4], Xd[4];
  for (int e = 0; e < 2; ++e) {
    const SlotState<double>& rot = s[1 + 3 * e];
    const double sv = s[2 + 3 * e].pos(0), sd = s[2 + 3 * e].vel(0);
    X[2 * e] = s[3 * e].pos;
    Xd[2 * e] = s[3 * e].vel;
    X[2 * e + 1] = L_ * sv * (rot.rot * ex);
    Xd[2 * e + 1] = L_ * (rot.rot * (sd * ex + sv * rot.vel.cross(ex)));
  }
  ElementEnergy out;
  for (int a = 0; a < 4; ++a) {
    out.gravity_potential -= m * kHermiteIntegral(a) * ctx.gravity.dot(X[a]);
    for (int b = 0; b < 4; ++b) out.kinetic += 0.5 * m * hermite_mass_(a, b) * Xd[a].dot(Xd[b]);
  }
  for (int e = 0; e < 2; ++e) {
    const Vec3& w = s[1 + 3 * e].vel;
    out.kinetic += 0.5 * w.dot(rotary_.asDiagonal() * w);
  }
  out.strain = strain_energy<double>(s[3].pos - s[0].pos, s[1].rot, s[2].pos(0), s[4].rot, s[5].pos(0));
  return out;
}

std::optional<double> CubicSplineBeam::axial_force(std::span<const SlotState<double>> s, const ElementContext&) const {
  // r'(1/2) = 1.5 (r2 - r1)/L - t1/(4L) - t2/(4L) with t = L s R e_x.
  const Vec3 rp = 1.5 * (s[3].pos - s[0].pos) / L_ - 0.25 * (s[2].pos(0) * s[1].rot.col(0) + s[5].pos(0) * s[4].rot.col(0));
  return ea_ * (rp.norm() - 1.0);
}

std::vector<Vec3> CubicSplineBeam::axis_points(std::span<const SlotState<double>> s, const ElementContext&) const {
  const Vec3 t1 = L_ * s[2].pos(0) * s[1].rot.col(0), t2 = L_ * s[5].pos(0) * s[4].rot.col(0);
  std::vector<Vec3> pts;
  for (int k = 0; k <= 4; ++k) {
    const Eigen::Vector4d h = unit_hermite(k / 4.0);
    pts.push_back(h(0) * s[0].pos + h(1) * t1 + h(2) * s[3].pos + h(3) * t2);
  }
  return pts;
}

void CubicSplineBeam::output(std::span<const SlotState<double>> s, const ElementContext& ctx, ElementOutput& out) const {
  Element::output(s, ctx, out);
  // The ends, then the Gauss points (where the strain energy samples the strains).
  std::vector<double> xi = {0.0, 1.0};
  xi.insert(xi.end(), xi_.begin(), xi_.end());
  std::vector<double> e(4 * xi.size());
  strains_at<double>(s[3].pos - s[0].pos, s[1].rot, s[2].pos(0), s[4].rot, s[5].pos(0), xi, e);
  std::vector<SectionForces> f(xi.size());
  for (std::size_t k = 0; k < xi.size(); ++k) {
    f[k].N = ea_ * e[4 * k];
    f[k].T = stiffness_(0) * e[4 * k + 1];
    f[k].My = stiffness_(1) * e[4 * k + 2];
    f[k].Mz = stiffness_(2) * e[4 * k + 3];
  }
  // The cubic's curvature is linear to first order: the shear forces from the ends' moments.
  const double qy = -(f[1].Mz - f[0].Mz) / L_, qz = (f[1].My - f[0].My) / L_;
  for (SectionForces& g : f) g.Qy = qy, g.Qz = qz;
  const BeamProperties& b = props_.beam;
  out.members.assign(1, member_stress(b.section, b.material, f[0], f[1], std::span(f).subspan(2)));
}

}  // namespace latticedyn
