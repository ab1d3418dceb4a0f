// Two-node strut tie of thesis 3.2 / C.3: a bar carrying only axial stress, linear interpolation
// between its end points, stress averaged over the smoothing time h, section rotary inertia.
#pragma once

#include "elements/autodiff_element.hpp"
#include "elements/section.hpp"

namespace latticedyn {

struct StrutTieProperties {
  Material material;
  SectionProperties section;
  double rest_length = 0.0;  ///< L0, the unstressed length
  double smoothing = 0.0;    ///< h of (3-16): sigma = E (eps + h/2 eps_dot + h^2/6 eps_ddot)
  void validate() const;
};

/// Slots: [translation of end 1, translation of end 2]. With d = r2 - r1, l = |d|, n = d/l:
///   eps = l/L0 - 1 (C-74), axial force N = E A (eps + h/2 eps_dot + h^2/6 eps_ddot) (C-76),
///   r = [M_t a - m g/2 - N n ; M_t a - m g/2 + N n] + rotary inertia,
/// with the consistent mass M_t = rho A L0/6 [2I I; I 2I] (C-82). The sections' rotary inertia
/// (C-82's T_phi^T J T_phi) enters through the kinetic energy 1/2 rho I_m L0 |P d_dot|^2 / l^2
/// of the bar's rotation about its axis' normals, with I_m = (Iy + Iz)/2: the bar's roll is not
/// a DoF, so only this axisymmetric part is well defined (the thesis's frame choice (3-9) is
/// singular when the bar points along -x). Mass stays constant as the bar stretches (3.2.1, 4).
/// Damping: the material's Rayleigh beta adds beta eps_dot to the stress's strain (Kelvin-Voigt,
/// like the smoothing's h/2 eps_dot), alpha adds alpha times the generalized momentum M(d) v.
class StrutTie final : public AutoDiffElement<StrutTie, 6> {
 public:
  static constexpr std::array<SlotKind, 2> kSlots = {SlotKind::translation, SlotKind::translation};

  explicit StrutTie(const StrutTieProperties& p);

  std::string_view type_name() const override { return "strut_tie"; }
  ElementEnergy energy(std::span<const SlotState<double>> state,
                       const ElementContext& ctx) const override;
  /// The default output plus the bar's axial stress and utilization.
  void output(std::span<const SlotState<double>> state, const ElementContext& ctx, ElementOutput& out) const override;
  std::optional<double> axial_force(std::span<const SlotState<double>> state,
                                    const ElementContext& ctx) const override;

  const StrutTieProperties& properties() const { return props_; }
  double mass() const { return mass_; }

  template <class S>
  void compute_residual(std::span<const SlotState<S>> s, const ElementContext& ctx,
                        Eigen::Matrix<S, 6, 1>& r) const {
    using std::sqrt;
    const Vec3T<S> d = s[1].pos - s[0].pos;
    const Vec3T<S> dv = s[1].vel - s[0].vel;
    const Vec3T<S> da = s[1].acc - s[0].acc;
    const S l2 = d.squaredNorm();
    const S l = sqrt(l2);
    const Vec3T<S> n = d / l;
    const S N = axial_force_from(d, dv, da);
    const Vec3T<S> g = cast_to<S>(ctx.gravity);
    const S m6(mass_ / 6.0);
    r.template head<3>() = m6 * (S(2) * s[0].acc + s[1].acc) - S(3) * m6 * g - N * n;
    r.template tail<3>() = m6 * (s[0].acc + S(2) * s[1].acc) - S(3) * m6 * g + N * n;
    if (rotary_inertia_ > 0.0) {
      // Lagrange's equations of T = c/2 |P d_dot|^2 (c = J / l^2, P = I - n n^T: the axis turning
      // about its normals) reduce to Q = c (P d_ddot - 2 (n . d_dot) / l P d_dot), acting with -Q
      // on end 1 and +Q on end 2.
      const S c = S(rotary_inertia_) / l2;
      const Vec3T<S> dv_perp = dv - n * n.dot(dv);
      const Vec3T<S> da_perp = da - n * n.dot(da);
      const Vec3T<S> Q = c * (da_perp - S(2) * n.dot(dv) / l * dv_perp);
      r.template head<3>() -= Q;
      r.template tail<3>() += Q;
    }
    const double alpha = props_.material.damping.alpha;
    if (alpha > 0) {
      // alpha times the generalized momentum M(d) v: the consistent translational mass and the
      // rotary part c P d_dot.
      const S a6(alpha * mass_ / 6.0);
      r.template head<3>() += a6 * (S(2) * s[0].vel + s[1].vel);
      r.template tail<3>() += a6 * (s[0].vel + S(2) * s[1].vel);
      if (rotary_inertia_ > 0.0) {
        const Vec3T<S> p = (S(alpha * rotary_inertia_) / l2) * (dv - n * n.dot(dv));
        r.template head<3>() -= p;
        r.template tail<3>() += p;
      }
    }
  }

  /// Closed-form tangents (the AD ones of AutoDiffElement cost ~50 residuals); tests compare them
  /// with both automatic and finite differences.
  void tangents(std::span<const SlotState<double>> state, const ElementContext& ctx,
                ElementTangents& out) const override;
  /// The automatically differentiated tangents, kept as the reference for the closed form.
  void tangents_by_ad(std::span<const SlotState<double>> state, const ElementContext& ctx,
                      ElementTangents& out) const {
    AutoDiffElement<StrutTie, 6>::tangents(state, ctx, out);
  }

 private:
  template <class S>
  S axial_force_from(const Vec3T<S>& d, const Vec3T<S>& dv, const Vec3T<S>& da) const {
    using std::sqrt;
    const S l = sqrt(d.squaredNorm());
    const Vec3T<S> n = d / l;
    const S L0(props_.rest_length);
    const S nv = n.dot(dv);
    const S eps = l / L0 - S(1);
    const S eps_dot = nv / L0;
    const S eps_ddot = (n.dot(da) + (dv.squaredNorm() - nv * nv) / l) / L0;
    const S h(props_.smoothing);
    return S(ea_) * (eps + (h / S(2) + S(props_.material.damping.beta)) * eps_dot + h * h / S(6) * eps_ddot);
  }

  StrutTieProperties props_;
  double mass_ = 0.0;
  double ea_ = 0.0;
  double rotary_inertia_ = 0.0;  ///< rho (Iy + Iz)/2 L0
};

}  // namespace latticedyn
