// Cubic spline rope of thesis 7.2 / C.5 in absolute nodal coordinates [r1, r1', r2, r2']: axial
// stress only, tension only (max(sigma, 0)), gravity, and a rest length that a drive may change
// in time with the rope's mass following the length in the span.
#pragma once

#include "core/drive.hpp"
#include "elements/element.hpp"
#include "elements/section.hpp"

#include <array>
#include <optional>

namespace latticedyn {

struct RopeProperties {
  Material material;
  SectionProperties section;
  double rest_length = 0.0;     ///< L0 of this element when no drive is given
  std::optional<Drive> drive;   ///< L0(t) = fraction * drive(t) when given (hoisting, luffing)
  double fraction = 1.0;        ///< share of the driven length in this element (1/n for n elements)
  int gauss_points = 4;         ///< Gauss-Legendre points along the element
  void validate() const;
};

/// Slots: [translation r1, vector r1', translation r2, vector r2'], r' = dr/dS along the rest
/// length S in [0, L0]. r(S) = H1 r1 + L0 H2 r1' + H3 r2 + L0 H4 r2' (cubic Hermite, A-9).
/// Strain eps = |dr/dS| - 1 (C-150), stress E max(eps, 0) (7-1): strain energy
/// U = EA L0/2 sum_g w_g max(eps_g, 0)^2, force and stiffness by automatic differentiation.
/// Kinetic energy rho A L0/2 integral |r_dot|^2 dxi at fixed xi = S/L0: the mass is rho A L0(t),
/// so paying rope out adds mass; with L0(t) driven, r_dot includes L0_dot H2 r1' and the
/// accelerations L0_ddot and 2 L0_dot terms (the rope's axial transport through its ends is not
/// modelled). Gravity as the consistent load of the cubic.
/// Damping: the material's Rayleigh beta as a viscous axial stress beta E eps_dot where the rope
/// is taut (a slack rope dissipates nothing); a mass-proportional alpha is refused (it would
/// drag the hanging load's swing through the rope's own mass).
class Rope final : public Element {
 public:
  /// Strains above -kSlackTolerance count as tension (round-off of an unstressed rope).
  static constexpr double kSlackTolerance = 1e-12;

  static constexpr std::array<SlotKind, 4> kSlots = {SlotKind::translation, SlotKind::vector,
                                                      SlotKind::translation, SlotKind::vector};

  explicit Rope(RopeProperties p);

  std::string_view type_name() const override { return "rope"; }
  bool expensive() const override { return true; }
  std::span<const SlotKind> slots() const override { return kSlots; }
  void residual(std::span<const SlotState<double>> state, const ElementContext& ctx,
                Eigen::Ref<VecX> r) const override;
  void tangents(std::span<const SlotState<double>> state, const ElementContext& ctx,
                ElementTangents& out) const override;
  ElementEnergy energy(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  /// Tension at mid-element, elastic plus viscous (tension only: never negative).
  /// The default output plus the bar's axial stress and utilization.
  void output(std::span<const SlotState<double>> state, const ElementContext& ctx, ElementOutput& out) const override;
  std::optional<double> axial_force(std::span<const SlotState<double>> state,
                                    const ElementContext& ctx) const override;
  std::vector<Vec3> axis_points(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;

  const RopeProperties& properties() const { return props_; }
  /// L0, dL0/dt, d2L0/dt2 at time t.
  DriveValue rest_length(double t) const;
  double mass(double t) const { return rho_a_ * rest_length(t).value; }

  template <class S>
  S strain_energy(const Vec3T<S>& d, const Vec3T<S>& t1, const Vec3T<S>& t2, double L0) const;
  /// The axial strain |dr/dS| - 1 at Gauss point g (L0 a double, or a number of the AD type).
  template <class S, class L>
  S gauss_strain(const Vec3T<S>& d, const Vec3T<S>& t1, const Vec3T<S>& t2, const L& L0, std::size_t g) const;

 private:
  /// The strain energy's gradient with respect to (d, t1, t2) in closed form: at each taut Gauss
  /// point dU/d(dr/dS) = EA L0 w eps (dr/dS)/|dr/dS|, spread by the Hermite slopes. (The
  /// residual's; the tangents differentiate strain_energy by AD, which the tests compare it to.)
  Eigen::Matrix<double, 9, 1> strain_energy_gradient(const Vec3& d, const Vec3& t1, const Vec3& t2, double L0) const;
  /// dr/dS at Gauss point g.
  template <class S, class L>
  Vec3T<S> gauss_slope(const Vec3T<S>& d, const Vec3T<S>& t1, const Vec3T<S>& t2, const L& L0, std::size_t g) const {
    const auto [dh1, dh2, dh4] = hermite_slopes(g);
    return d * (dh1 / L0) + t1 * dh2 + t2 * dh4;  // constants as doubles: cheap AD products
  }
  /// Adds the Kelvin-Voigt force beta E A eps_dot of the taut Gauss points to r and, with t, its
  /// K and C; eps_dot includes the strain rate of a driven rest length.
  void add_damping(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
                   ElementTangents* t) const;
  void inertia_and_gravity(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
                           ElementTangents* t) const;

  struct HermiteSlopes {
    double dh1, dh2, dh4;
  };
  /// dH1/dxi, dH2/dxi, dH4/dxi at Gauss point g: dr/dS = (dH1/dxi r1 + dH3/dxi r2)/L0 +
  /// dH2/dxi r1' + dH4/dxi r2', with dH3 = -dH1.
  HermiteSlopes hermite_slopes(std::size_t g) const {
    const double x = xi_[g], x2 = x * x;
    return {6 * x - 6 * x2, 1 - 4 * x + 3 * x2, 3 * x2 - 2 * x};
  }

  RopeProperties props_;
  double rho_a_ = 0.0, ea_ = 0.0;
  Eigen::Matrix4d hermite_mass_;  ///< integral_0^1 H_i H_j dxi of the unit Hermite functions
  std::vector<double> xi_, w_;    ///< Gauss points on [0, 1]
};

template <class S, class L>
S Rope::gauss_strain(const Vec3T<S>& d, const Vec3T<S>& t1, const Vec3T<S>& t2, const L& L0, std::size_t g) const {
  using std::sqrt;
  return sqrt(gauss_slope(d, t1, t2, L0, g).squaredNorm()) - 1.0;
}

template <class S>
S Rope::strain_energy(const Vec3T<S>& d, const Vec3T<S>& t1, const Vec3T<S>& t2, double L0) const {
  S U(0.0);
  for (std::size_t g = 0; g < xi_.size(); ++g) {
    const S eps = gauss_strain(d, t1, t2, L0, g);
    // Zero strain counts as tension, to round-off: an unstressed straight rope (the usual start)
    // then has its axial stiffness at every Gauss point, instead of losing the points whose
    // strain rounds to -1e-16 and with them the tangent's rank.
    if (scalar_value(eps) >= -kSlackTolerance) U += (eps * eps) * (0.5 * ea_ * L0 * w_[g]);
  }
  return U;
}

}  // namespace latticedyn
