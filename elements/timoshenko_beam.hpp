// Spatial Timoshenko beam on co-rotational coordinates (thesis 3.3, C.2): the rigid motion is
// carried by a frame built from both end sections, the deformation relative to it by a linear
// shear-flexible beam; exact under large rotations, linear in the small deformational ones.
#pragma once

#include "core/rotation.hpp"
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
/// Elastic part (Battini & Pacoste 2002 co-rotational frame): e1 = (r2 - r1)/l; e3 along
/// e1 x (R1 e_y + R2 e_y), e2 = e3 x e1; local rotations theta_i = log(R_r^T R_i); strain energy
///   U = EA/(2 L0) (l - L0)^2 + GJ/(2 L0) (theta_2x - theta_1x)^2
///     + sum over bending planes EI/(2 L0 (1 + Phi)) [(4 + Phi)(th1^2 + th2^2) + 2 (2 - Phi) th1 th2],
/// the exact Timoshenko stiffness of a beam with zero end deflections, Phi = 12 EI/(kappa G A L0^2)
/// (standard engineering shear strain and kappa, not the thesis's GA/4: see docs/elements.md).
/// Internal force and stiffness are the gradient and Hessian of U by automatic differentiation.
///
/// Inertia: translations with the consistent mass of linear interpolation, rho A L0/6 [2I I; I 2I];
/// rotary inertia of each half lumped at its end section, J = rho L0/2 diag(Iy + Iz, Iy, Iz),
/// with the gyroscopic term omega x J omega. Gravity: half the weight on each end.
class TimoshenkoBeam final : public Element {
 public:
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
  std::optional<double> axial_force(std::span<const SlotState<double>> state,
                                    const ElementContext& ctx) const override;
  /// Five points along the deformed axis (the local cubic deflection of the end rotations).
  std::vector<Vec3> axis_points(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;

  const BeamProperties& properties() const { return props_; }

  /// The strain energy as a function of d = r2 - r1 and the end rotations (templated for AD).
  template <class S>
  S strain_energy(const Vec3T<S>& d, const Mat3T<S>& R1, const Mat3T<S>& R2) const;

 private:
  template <class S>
  void local_deformation(const Vec3T<S>& d, const Mat3T<S>& R1, const Mat3T<S>& R2, S& u, Vec3T<S>& th1,
                         Vec3T<S>& th2, Mat3T<S>* Rr) const;
  void inertia(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
               ElementTangents* t) const;

  BeamProperties props_;
  double mass_ = 0.0;
  Vec3 rotary_ = Vec3::Zero();  ///< lumped rotary inertia per end (body axes)
  double ea_ = 0.0, gj_ = 0.0;
  double kz_[2] = {0, 0}, ky_[2] = {0, 0};  ///< bending stiffness (4+Phi, 2-Phi) EI/(L0(1+Phi))
};

template <class S>
void TimoshenkoBeam::local_deformation(const Vec3T<S>& d, const Mat3T<S>& R1, const Mat3T<S>& R2, S& u,
                                       Vec3T<S>& th1, Vec3T<S>& th2, Mat3T<S>* Rr_out) const {
  using std::sqrt;
  // Constants multiply as doubles: a product with S(constant) would cost a full AD product.
  const S l = sqrt(d.squaredNorm());
  const Vec3T<S> e1 = d * (1.0 / l);
  const Vec3T<S> q = (R1.col(1) + R2.col(1)) * 0.5;
  Vec3T<S> e3 = e1.cross(q);
  e3 *= 1.0 / sqrt(e3.squaredNorm());
  const Vec3T<S> e2 = e3.cross(e1);
  Mat3T<S> Rr;
  Rr.col(0) = e1;
  Rr.col(1) = e2;
  Rr.col(2) = e3;
  u = l - props_.length;
  th1 = small_rotation_vector<S>(Rr.transpose() * R1);
  th2 = small_rotation_vector<S>(Rr.transpose() * R2);
  if (Rr_out) *Rr_out = Rr;
}

template <class S>
S TimoshenkoBeam::strain_energy(const Vec3T<S>& d, const Mat3T<S>& R1, const Mat3T<S>& R2) const {
  S u;
  Vec3T<S> a, b;
  local_deformation<S>(d, R1, R2, u, a, b, nullptr);
  const S twist = b(0) - a(0);
  return (u * u) * (0.5 * ea_) + (twist * twist) * (0.5 * gj_) +
         (a(2) * a(2) + b(2) * b(2)) * (0.5 * kz_[0]) + (a(2) * b(2)) * kz_[1] +
         (a(1) * a(1) + b(1) * b(1)) * (0.5 * ky_[0]) + (a(1) * b(1)) * ky_[1];
}

}  // namespace latticedyn
