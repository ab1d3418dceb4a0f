// Spatial Timoshenko beam on co-rotational coordinates (thesis 3.3, C.2): the rigid motion is
// carried by a frame built from both end sections, the deformation relative to it by a linear
// shear-flexible beam; exact under large rotations, linear in the small deformational ones.
#pragma once

#include "elements/corotational_beam_kernel.hpp"
#include "elements/element.hpp"
#include "elements/section.hpp"

#include <array>

namespace latticedyn {

struct BeamProperties {
  Material material;
  SectionProperties section;
  double length = 0.0;              ///< L0, the element's unstressed length
  double shear_coefficient = 0.0;   ///< kappa of kappa G A; <= 0: from the section (Cowper)
  void validate() const;
};

/// Slots: [translation 1, rotation 1, translation 2, rotation 2]; the end frames' x axis lies
/// along the unstressed beam, y and z are the section's principal axes.
///
/// Elastic part (Battini & Pacoste 2002 co-rotational frame, elements/corotational_beam_kernel.hpp):
/// the local deformation relative to a frame built from both end sections, the exact Timoshenko
/// stiffness of a beam with zero end deflections, Phi = 12 EI/(kappa G A L0^2) (standard engineering
/// shear strain and kappa, not the thesis's GA/4: see docs/elements.md). Internal force and
/// consistent tangent in closed form; strain_energy<S> keeps the energy for automatic
/// differentiation, the tests' oracle.
///
/// Inertia: translations with the consistent mass of linear interpolation, rho A L0/6 [2I I; I 2I];
/// rotary inertia of each half lumped at its end section, J = rho L0/2 diag(Iy + Iz, Iy, Iz),
/// with the gyroscopic term omega x J omega. Gravity: half the weight on each end.
///
/// Damping (the material's Rayleigh alpha, beta): alpha times the mass matrix above on the
/// absolute velocities; beta as Kelvin-Voigt damping of the co-rotated deformation
/// (u, theta_1, theta_2) with the local stiffness, f = beta J^T K_l J v (J = d(u, theta)/dq):
/// beta K on the deformation rates, zero on rigid motion even under load (beta K_T v would damp
/// a prestressed beam's rigid rotation through its geometric stiffness).
class TimoshenkoBeam final : public Element {
 public:
  static constexpr int kAxisPoints = 5;  ///< points along a drawn axis
  static constexpr std::array<SlotKind, 4> kSlots = {SlotKind::translation, SlotKind::rotation,
                                                      SlotKind::translation, SlotKind::rotation};

  explicit TimoshenkoBeam(const BeamProperties& p);

  std::string_view type_name() const override { return "timoshenko_beam"; }
  bool expensive() const override { return true; }
  std::span<const SlotKind> slots() const override { return kSlots; }
  void residual(std::span<const SlotState<double>> state, const ElementContext& ctx,
                Eigen::Ref<VecX> r) const override;
  void tangents(std::span<const SlotState<double>> state, const ElementContext& ctx,
                ElementTangents& out) const override;
  ElementEnergy energy(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  /// Four beams at once: the co-rotational kernel on the lanes of Pack4 (a lattice's members).
  int batch_size() const override { return Pack4::kLanes; }
  void residual_batch(std::span<const Element* const> elements,
                      std::span<const std::span<const SlotState<double>>> states, const ElementContext& ctx,
                      std::span<VecX> out) const override;
  void tangents_batch(std::span<const Element* const> elements,
                      std::span<const std::span<const SlotState<double>>> states, const ElementContext& ctx,
                      std::span<ElementTangents> out) const override;
  std::optional<double> axial_force(std::span<const SlotState<double>> state,
                                    const ElementContext& ctx) const override;
  /// Five points along the deformed axis (the local cubic deflection of the end rotations).
  std::vector<Vec3> axis_points(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  void output(std::span<const SlotState<double>> state, const ElementContext& ctx, ElementOutput& out) const override;
  /// From one evaluation of the co-rotational frame at end 1 = r1, d = r2 - r1: the strain energy,
  /// the axial force E A (l - L0)/L0, the five axis points and the member's section forces and
  /// stresses, each where asked for.
  void deformed_state(const Vec3& r1, const Vec3& d, const Mat3& R1, const Mat3& R2, double* strain, double* axial,
                      std::vector<Vec3>* axis, MemberStress* stress = nullptr) const;

  const BeamProperties& properties() const { return props_; }

  /// The strain energy as a function of d = r2 - r1 and the end rotations (templated for AD).
  template <class S>
  S strain_energy(const Vec3T<S>& d, const Mat3T<S>& R1, const Mat3T<S>& R2) const {
    return corotational_strain_energy<S>(stiffness_, corotational_deformation<S>(stiffness_, d, R1, R2));
  }
  /// Internal force in (d, delta_1, delta_2) and, with K, its consistent tangent (closed form).
  void elastic_force(const Vec3& d, const Mat3& R1, const Mat3& R2, Vec9& f, Mat9* K) const {
    corotational_force(stiffness_, d, R1, R2, f, K);
  }
  const CorotationalStiffness& stiffness() const { return stiffness_; }

 private:
  void inertia(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
               ElementTangents* t) const;
  /// Adds the Rayleigh damping force to r and, with t, its K and C (nothing when undamped or at rest).
  void add_damping(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
                   ElementTangents* t) const;

  BeamProperties props_;
  double mass_ = 0.0;
  Vec3 rotary_ = Vec3::Zero();  ///< lumped rotary inertia per end (body axes)
  CorotationalStiffness stiffness_;
};

}  // namespace latticedyn
