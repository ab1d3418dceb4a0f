// Rigid body of thesis 3.1 / C.1: one reference frame (origin r0, orientation R), custom mass,
// centroid and inertia; residual = Newton-Euler equations about the origin in the body frame.
#pragma once

#include "elements/autodiff_element.hpp"

namespace latticedyn {

struct RigidBodyProperties {
  double mass = 0.0;
  Vec3 centroid = Vec3::Zero();            ///< centroid in the body frame, relative to the origin
  Mat3 inertia_centroid = Mat3::Zero();    ///< inertia tensor about the centroid, body axes
  double damping_alpha = 0.0;              ///< mass-proportional (Rayleigh alpha) damping [1/s]
  /// Throws std::invalid_argument unless mass > 0 and the inertia is symmetric positive
  /// definite and satisfies the triangle inequalities of a physical body.
  void validate() const;
};

/// Slots: [translation of the origin, rotation of the body frame]. With c = centroid and
/// Theta_0 the inertia about the origin (parallel axis theorem), the residual is (C-3, C-5)
///   r_t = m (r0_ddot + R (omega_dot x c + omega x (omega x c)) - g)
///   r_r = Theta_0 omega_dot + omega x Theta_0 omega + m c x R^T (r0_ddot - g).
/// (The thesis's printed D_e and C-2 carry a sign error in the centripetal term; this form is
/// derived from the kinematics r = r0 + R rho and checked by energy and momentum tests.)
/// Damping alpha adds alpha M(q) v, alpha times the body's momentum and angular momentum about
/// the origin: a viscous drag on its absolute motion (a rigid body has no stiffness for beta).
class RigidBody final : public AutoDiffElement<RigidBody, 6> {
 public:
  static constexpr std::array<SlotKind, 2> kSlots = {SlotKind::translation, SlotKind::rotation};

  explicit RigidBody(const RigidBodyProperties& p);

  std::string_view type_name() const override { return "rigid_body"; }
  ElementEnergy energy(std::span<const SlotState<double>> state,
                       const ElementContext& ctx) const override;
  std::vector<Vec3> axis_points(std::span<const SlotState<double>>, const ElementContext&) const override { return {}; }

  const RigidBodyProperties& properties() const { return props_; }
  const Mat3& inertia_origin() const { return inertia_origin_; }

  template <class S>
  void compute_residual(std::span<const SlotState<S>> s, const ElementContext& ctx,
                        Eigen::Matrix<S, 6, 1>& r) const {
    const Mat3T<S>& R = s[1].rot;
    const Vec3T<S>& w = s[1].vel;
    const Vec3T<S>& wd = s[1].acc;
    const Vec3T<S> c = cast_to<S>(props_.centroid);
    const Mat3T<S> J0 = cast_to<S>(inertia_origin_);
    const Vec3T<S> a_rel = s[0].acc - cast_to<S>(ctx.gravity);
    const S m(props_.mass);
    r.template head<3>() = m * (a_rel + R * (wd.cross(c) + w.cross(w.cross(c))));
    r.template tail<3>() = J0 * wd + w.cross(J0 * w) + m * c.cross(R.transpose() * a_rel);
    if (props_.damping_alpha > 0) {
      const S alpha(props_.damping_alpha);
      const Vec3T<S>& v0 = s[0].vel;
      r.template head<3>() += alpha * m * (v0 + R * w.cross(c));
      r.template tail<3>() += alpha * (J0 * w + m * c.cross(R.transpose() * v0));
    }
  }

 private:
  RigidBodyProperties props_;
  Mat3 inertia_origin_;
};

/// Mass properties of a homogeneous solid or hollow cylinder along the body x axis from the
/// origin (the thesis's "round tube" rigid bodies, e.g. the load of Table D-12).
RigidBodyProperties cylinder_body(double density, double length, double outer_radius,
                                  double inner_radius);

}  // namespace latticedyn
