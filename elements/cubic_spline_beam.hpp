// Cubic spline beam of thesis 3.4 / C.4: the axis is a cubic Hermite curve in absolute
// coordinates through the end positions with end tangents |r'| R e_x, the sections' orientation
// follows relative Cardan angles (bending from the tangent, torsion interpolated linearly).
#pragma once

#include "elements/autodiff_element.hpp"
#include "elements/timoshenko_beam.hpp"

#include <span>
#include <vector>

namespace latticedyn {

struct CubicSplineBeamProperties {
  BeamProperties beam;
  int gauss_points = 5;  ///< Gauss-Legendre points of the strain energy integral
  void validate() const;
};

/// Slots: [translation 1, rotation 1, scalar |r'|_1, translation 2, rotation 2, scalar |r'|_2]
/// (14 DoFs, 3-54). With X = [r1, L s1 R1 e_x, r2, L s2 R2 e_x], r(xi) = sum_k H_k(xi) X_k.
/// Strains at the Gauss points: eps = |r'| - 1 (3-71) and the curvature kappa = T(phi) phi' of
/// the Cardan angles phi = [xi phi_12, psi, theta] relative to section 1 (3-64..3-67, 3-72),
/// psi and theta from the tangent n = r'/|r'| in section 1's frame, phi_12 the x angle of R1^T R2.
/// Strain energy L/2 sum_g w_g (EA eps^2 + GJ kx^2 + EIy ky^2 + EIz kz^2) (3-77); its gradient
/// and Hessian by automatic differentiation. Euler-Bernoulli: no shear deformation.
/// Inertia: consistent mass of the cubic for the translations (3-73, 3-74); the sections' rotary
/// inertia lumped at the ends like the Timoshenko beam; gravity consistent with the cubic.
/// Damping: the material's Rayleigh alpha times the mass above on the velocities; beta as
/// Kelvin-Voigt damping of the strains, beta (EA eps_dot, GJ kx_dot, EIy ky_dot, EIz kz_dot).
/// Limits: the Cardan angles are singular at 90 degrees of bending within one element (8.1.1).
class CubicSplineBeam final : public AutoDiffElement<CubicSplineBeam, 14> {
 public:
  static constexpr std::array<SlotKind, 6> kSlots = {SlotKind::translation, SlotKind::rotation, SlotKind::scalar,
                                                      SlotKind::translation, SlotKind::rotation, SlotKind::scalar};

  explicit CubicSplineBeam(const CubicSplineBeamProperties& p);

  std::string_view type_name() const override { return "cubic_spline_beam"; }
  bool expensive() const override { return true; }
  void residual(std::span<const SlotState<double>> state, const ElementContext& ctx,
                Eigen::Ref<VecX> r) const override;
  void tangents(std::span<const SlotState<double>> state, const ElementContext& ctx,
                ElementTangents& out) const override;
  ElementEnergy energy(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  std::optional<double> axial_force(std::span<const SlotState<double>> state,
                                    const ElementContext& ctx) const override;
  std::vector<Vec3> axis_points(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;

  const CubicSplineBeamProperties& properties() const { return props_; }

  /// Inertia and gravity (the part differentiated by AutoDiffElement).
  template <class S>
  void compute_residual(std::span<const SlotState<S>> s, const ElementContext& ctx,
                        Eigen::Matrix<S, 14, 1>& r) const;
  /// Strain energy from d = r2 - r1, the end rotations and the end stretches.
  template <class S>
  S strain_energy(const Vec3T<S>& d, const Mat3T<S>& R1, const S& s1, const Mat3T<S>& R2, const S& s2) const;
  /// The strains (eps, kappa_x, kappa_y, kappa_z) of every Gauss point, four per point, into strains.
  template <class S>
  void gauss_strains(const Vec3T<S>& d, const Mat3T<S>& R1, const S& s1, const Mat3T<S>& R2, const S& s2,
                     std::span<S> strains) const {
    strains_at(d, R1, s1, R2, s2, std::span<const double>(xi_), strains);
  }
  /// The same strains at the points xi in [0, 1] along the element.
  template <class S>
  void strains_at(const Vec3T<S>& d, const Mat3T<S>& R1, const S& s1, const Mat3T<S>& R2, const S& s2,
                  std::span<const double> xi, std::span<S> strains) const;
  /// The default output plus section forces at both ends from the strains (N = EA eps, T = GJ kx,
  /// My = EIy ky, Mz = EIz kz; Qy = -dMz/ds, Qz = dMy/ds across the element), the von Mises
  /// stress the largest over the ends and the Gauss points.
  void output(std::span<const SlotState<double>> state, const ElementContext& ctx, ElementOutput& out) const override;

 private:
  void add_damping(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
                   ElementTangents* t) const;

  CubicSplineBeamProperties props_;
  double rho_a_ = 0.0, L_ = 0.0;
  Vec3 rotary_ = Vec3::Zero();
  Vec3 stiffness_ = Vec3::Zero();  ///< GJ, EIy, EIz
  double ea_ = 0.0;
  Eigen::Matrix4d hermite_mass_;
  std::vector<double> xi_, w_;
};

template <class S>
void CubicSplineBeam::compute_residual(std::span<const SlotState<S>> s, const ElementContext& ctx,
                                       Eigen::Matrix<S, 14, 1>& r) const {
  const Vec3T<S> ex = Vec3T<S>(S(1), S(0), S(0));
  const S L(L_), m(rho_a_ * L_);
  // X and its second time derivative; t = L s R e_x.
  Vec3T<S> Xdd[4], Xd[4];
  Vec3T<S> axis[2];
  for (int e = 0; e < 2; ++e) {
    const SlotState<S>& rot = s[1 + 3 * e];
    const S sv = s[2 + 3 * e].pos(0), sd = s[2 + 3 * e].vel(0), sdd = s[2 + 3 * e].acc(0);
    const Vec3T<S>& w = rot.vel;
    const Vec3T<S> wx = w.cross(ex);
    axis[e] = rot.rot * ex;
    Xdd[2 * e] = s[3 * e].acc;
    Xdd[2 * e + 1] = L * (rot.rot * (ex * sdd + S(2) * sd * wx + sv * (rot.acc.cross(ex) + w.cross(wx))));
    Xd[2 * e] = s[3 * e].vel;
    Xd[2 * e + 1] = L * (rot.rot * (ex * sd + sv * wx));
  }
  const double alpha = props_.beam.material.damping.alpha;
  const double integral[4] = {0.5, 1.0 / 12, 0.5, -1.0 / 12};
  Vec3T<S> f[4];
  for (int a = 0; a < 4; ++a) {
    f[a] = -m * S(integral[a]) * cast_to<S>(ctx.gravity);
    for (int b = 0; b < 4; ++b) f[a] += m * S(hermite_mass_(a, b)) * Xdd[b];
    // Mass-proportional damping: alpha M v, the momentum of the cubic mapped like its inertia.
    if (alpha > 0)
      for (int b = 0; b < 4; ++b) f[a] += (m * S(alpha * hermite_mass_(a, b))) * Xd[b];
  }
  const Mat3T<S> J = cast_to<S>(Mat3(rotary_.asDiagonal()));
  for (int e = 0; e < 2; ++e) {
    const SlotState<S>& rot = s[1 + 3 * e];
    const S sv = s[2 + 3 * e].pos(0);
    r.template segment<3>(7 * e) = f[2 * e];
    // dt/d(theta) = -L s R skew(e_x), dt/ds = L R e_x.
    r.template segment<3>(7 * e + 3) =
        L * sv * ex.cross(rot.rot.transpose() * f[2 * e + 1]) + J * rot.acc + rot.vel.cross(J * rot.vel);
    if (alpha > 0) r.template segment<3>(7 * e + 3) += S(alpha) * (J * rot.vel);
    r(7 * e + 6) = L * axis[e].dot(f[2 * e + 1]);
  }
}

template <class S>
void CubicSplineBeam::strains_at(const Vec3T<S>& d, const Mat3T<S>& R1, const S& s1, const Mat3T<S>& R2, const S& s2,
                                 std::span<const double> xis, std::span<S> strains) const {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  // Constants multiply as doubles: a product with S(constant) would cost a full AD product.
  const double L = L_;
  const Vec3T<S> t1 = R1.col(0) * (s1 * L), t2 = R2.col(0) * (s2 * L);
  const Mat3T<S> R12 = R1.transpose() * R2;
  const S phi12 = atan2(R12(2, 1), R12(2, 2));
  for (std::size_t g = 0; g < xis.size(); ++g) {
    const double x = xis[g], x2 = x * x;
    const Vec3T<S> rp = d * ((6 * x - 6 * x2) / L) + t1 * ((1 - 4 * x + 3 * x2) / L) + t2 * ((3 * x2 - 2 * x) / L);
    const Vec3T<S> rpp = d * ((6 - 12 * x) / (L * L)) + t1 * ((6 * x - 4) / (L * L)) + t2 * ((6 * x - 2) / (L * L));
    const S len = sqrt(rp.squaredNorm());
    const S inv_len = 1.0 / len;
    const Vec3T<S> n = rp * inv_len;
    const Vec3T<S> n_s = (rpp - n * n.dot(rpp)) * inv_len;  // dn/ds
    const Vec3T<S> m = R1.transpose() * n, m_s = R1.transpose() * n_s;
    const S cos_psi = sqrt(m(0) * m(0) + m(1) * m(1));
    const S psi = atan2(-m(2), cos_psi);
    const S inv_cos_psi = 1.0 / cos_psi;
    const S psi_s = -m_s(2) * inv_cos_psi;
    const S theta_s = (m(0) * m_s(1) - m(1) * m_s(0)) * (inv_cos_psi * inv_cos_psi);
    const S phi = phi12 * x, phi_s = phi12 * (1.0 / L);
    const S sf = sin(phi), cf = cos(phi), sp = sin(psi), cp = cos(psi);
    // kappa = T(phi, psi) [phi', psi', theta']^T, T of (B-19) rederived (core/rotation.hpp).
    const S kx = phi_s - sp * theta_s;
    const S ky = cf * psi_s + sf * cp * theta_s;
    const S kz = -sf * psi_s + cf * cp * theta_s;
    strains[4 * g] = len - 1.0;
    strains[4 * g + 1] = kx;
    strains[4 * g + 2] = ky;
    strains[4 * g + 3] = kz;
  }
}

template <class S>
S CubicSplineBeam::strain_energy(const Vec3T<S>& d, const Mat3T<S>& R1, const S& s1, const Mat3T<S>& R2,
                                 const S& s2) const {
  std::vector<S> e(4 * xi_.size());
  gauss_strains(d, R1, s1, R2, s2, std::span<S>(e));
  S U(0.0);
  for (std::size_t g = 0; g < xi_.size(); ++g) {
    const S *x = &e[4 * g];
    U += ((x[0] * x[0]) * ea_ + (x[1] * x[1]) * stiffness_(0) + (x[2] * x[2]) * stiffness_(1) +
          (x[3] * x[3]) * stiffness_(2)) *
         (0.5 * L_ * w_[g]);
  }
  return U;
}

}  // namespace latticedyn
