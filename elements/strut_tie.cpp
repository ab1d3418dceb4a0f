// Strut tie: validation, energy (kinetic incl. rotary inertia, gravity, strain) and the axial
// force reported in the results.
#include "elements/strut_tie.hpp"

#include <cmath>
#include <stdexcept>

namespace latticedyn {

void StrutTieProperties::validate() const {
  material.validate();
  section.validate();
  if (!(std::isfinite(rest_length) && rest_length > 0))
    throw std::invalid_argument("strut tie rest length must be positive");
  if (!(std::isfinite(smoothing) && smoothing >= 0))
    throw std::invalid_argument("strut tie smoothing factor h must be >= 0");
}

StrutTie::StrutTie(const StrutTieProperties& p) : props_(p) {
  props_.validate();
  mass_ = p.section.effective_density(p.material) * p.section.area * p.rest_length;
  ea_ = p.material.youngs_modulus * p.section.area;
  rotary_inertia_ = p.section.effective_density(p.material) * 0.5 * (p.section.Iy + p.section.Iz) * p.rest_length;
}

ElementEnergy StrutTie::energy(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  const Vec3& v1 = s[0].vel;
  const Vec3& v2 = s[1].vel;
  const Vec3 d = s[1].pos - s[0].pos;
  const Vec3 dv = v2 - v1;
  const double l2 = d.squaredNorm();
  const double l = std::sqrt(l2);
  const double L0 = props_.rest_length;
  ElementEnergy e;
  e.kinetic = mass_ / 6.0 * (v1.squaredNorm() + v1.dot(v2) + v2.squaredNorm()) +
              0.5 * rotary_inertia_ / l2 * (dv - d * d.dot(dv) / l2).squaredNorm();
  e.gravity_potential = -mass_ * ctx.gravity.dot(0.5 * (s[0].pos + s[1].pos));
  const double eps = l / L0 - 1.0;
  const double eps_dot = d.dot(dv) / (l * L0);
  // The h^2/6 eps_ddot part of the averaged stress stores energy like a mass on eps_dot.
  const double h = props_.smoothing;
  e.strain = 0.5 * ea_ * L0 * (eps * eps + h * h / 6.0 * eps_dot * eps_dot);
  return e;
}

void StrutTie::tangents(std::span<const SlotState<double>> s, const ElementContext& ctx, ElementTangents& out) const {
  // F(d, v, a) = N n + Q is the force on end 2 (minus it on end 1), with d = r2 - r1, v, a its
  // rates; the tangents of the element follow from F_d, F_v, F_a by the signs of d.
  const Vec3 d = s[1].pos - s[0].pos, v = s[1].vel - s[0].vel, a = s[1].acc - s[0].acc;
  const double l2 = d.squaredNorm(), l = std::sqrt(l2), L0 = props_.rest_length, h = props_.smoothing;
  const double visc = h / 2 + props_.material.damping.beta;  // coefficient of eps_dot in the stress's strain
  const Vec3 n = d / l;
  const Mat3 P = Mat3::Identity() - n * n.transpose();
  const double nv = n.dot(v), na = n.dot(a);
  const Vec3 Pv = P * v, Pa = P * a;
  const double eps = l / L0 - 1, eps_dot = nv / L0, eps_ddot = (na + Pv.squaredNorm() / l) / L0;
  const double N = ea_ * (eps + visc * eps_dot + h * h / 6 * eps_ddot);

  // dN/d(d), dN/dv, dN/da (row vectors) and the axial force's derivatives, d(N n) = n dN + N P/l dd.
  const Eigen::RowVector3d vP = Pv.transpose(), aP = Pa.transpose(), nt = n.transpose();
  const Eigen::RowVector3d dN_dd =
      ea_ / L0 * (nt + visc * vP / l + h * h / 6 * (aP / l - 2 * nv / l2 * vP - Pv.squaredNorm() / l2 * nt));
  const Eigen::RowVector3d dN_dv = ea_ / L0 * (visc * nt + h * h / 3 * vP / l);
  const Eigen::RowVector3d dN_da = ea_ / L0 * (h * h / 6) * nt;
  Mat3 Fd = n * dN_dd + N / l * P;
  Mat3 Fv = n * dN_dv;
  Mat3 Fa = n * dN_da;
  Vec3 F = N * n;

  if (rotary_inertia_ > 0.0) {
    // Q = c y, y = P a - 2 (n.v)/l P v, c = J / l^2.
    const double c = rotary_inertia_ / l2;
    const Vec3 y = Pa - 2 * nv / l * Pv;
    const Mat3 dPa = -(na * P + n * aP) / l;    // d(P a)/dd
    const Mat3 dPv = -(nv * P + n * vP) / l;    // d(P v)/dd
    const Eigen::RowVector3d d_nv_over_l = vP / l2 - nv / l2 * nt;  // d((n.v)/l)/dd
    const Mat3 dy = dPa - 2 * (Pv * d_nv_over_l + nv / l * dPv);
    Fd += y * (-2 * c / l * nt) + c * dy;
    Fv += -2 * c / l * (Pv * nt + nv * P);
    Fa += c * P;
    F += c * y;
    const double alpha = props_.material.damping.alpha;
    if (alpha > 0) {  // alpha c P v, the rotary part of alpha M(d) v
      Fd += alpha * (Pv * (-2 * c / l * nt) + c * dPv);
      Fv += alpha * c * P;
      F += alpha * c * Pv;
    }
  }

  out.resize(6);
  const double m6 = mass_ / 6.0;
  out.residual.head<3>() = m6 * (2 * s[0].acc + s[1].acc) - 3 * m6 * ctx.gravity - F;
  out.residual.tail<3>() = m6 * (s[0].acc + 2 * s[1].acc) - 3 * m6 * ctx.gravity + F;
  auto place = [](MatX& M, const Mat3& X) {
    M.topLeftCorner<3, 3>() = X;
    M.topRightCorner<3, 3>() = -X;
    M.bottomLeftCorner<3, 3>() = -X;
    M.bottomRightCorner<3, 3>() = X;
  };
  place(out.K, Fd);
  place(out.C, Fv);
  place(out.M, Fa);
  out.M.topLeftCorner<3, 3>().diagonal().array() += 2 * m6;
  out.M.bottomRightCorner<3, 3>().diagonal().array() += 2 * m6;
  out.M.topRightCorner<3, 3>().diagonal().array() += m6;
  out.M.bottomLeftCorner<3, 3>().diagonal().array() += m6;
  const double a6 = props_.material.damping.alpha * m6;
  if (a6 > 0) {
    out.residual.head<3>() += a6 * (2 * s[0].vel + s[1].vel);
    out.residual.tail<3>() += a6 * (s[0].vel + 2 * s[1].vel);
    out.C.topLeftCorner<3, 3>().diagonal().array() += 2 * a6;
    out.C.bottomRightCorner<3, 3>().diagonal().array() += 2 * a6;
    out.C.topRightCorner<3, 3>().diagonal().array() += a6;
    out.C.bottomLeftCorner<3, 3>().diagonal().array() += a6;
  }
}

std::optional<double> StrutTie::axial_force(std::span<const SlotState<double>> s, const ElementContext&) const {
  return axial_force_from<double>(s[1].pos - s[0].pos, s[1].vel - s[0].vel, s[1].acc - s[0].acc);
}

void StrutTie::output(std::span<const SlotState<double>> s, const ElementContext& ctx, ElementOutput& out) const {
  Element::output(s, ctx, out);
  out.members.assign(1, bar_stress(props_.section, props_.material, out.axial_force.value_or(0.0)));
}

}  // namespace latticedyn
