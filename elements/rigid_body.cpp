// Rigid body: validation of mass properties, energy, and the cylinder mass properties used for
// "round tube" rigid bodies in the thesis's tables.
#include "elements/rigid_body.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace latticedyn {

void RigidBodyProperties::validate() const {
  if (!(std::isfinite(mass) && mass > 0)) throw std::invalid_argument("mass must be positive");
  if (!centroid.allFinite()) throw std::invalid_argument("centroid must be finite");
  if (!(std::isfinite(damping_alpha) && damping_alpha >= 0))
    throw std::invalid_argument("damping alpha must be a number >= 0 (1/s)");
  const Mat3& J = inertia_centroid;
  if (!J.allFinite() || (J - J.transpose()).cwiseAbs().maxCoeff() > 1e-12 * J.cwiseAbs().maxCoeff())
    throw std::invalid_argument("inertia must be a finite symmetric matrix");
  Eigen::SelfAdjointEigenSolver<Mat3> es(J);
  const Vec3 p = es.eigenvalues();
  if (!(p.minCoeff() > 0)) throw std::invalid_argument("inertia must be positive definite");
  const double tol = 1e-9 * p.sum();
  if (p(0) + p(1) < p(2) - tol || p(0) + p(2) < p(1) - tol || p(1) + p(2) < p(0) - tol)
    throw std::invalid_argument(
        "principal moments of inertia violate the triangle inequality (no physical body has them)");
}

RigidBody::RigidBody(const RigidBodyProperties& p) : props_(p) {
  props_.validate();
  const Vec3& c = p.centroid;
  inertia_origin_ = p.inertia_centroid + p.mass * (c.squaredNorm() * Mat3::Identity() - c * c.transpose());
}

ElementEnergy RigidBody::energy(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  const Mat3& R = s[1].rot;
  const Vec3& w = s[1].vel;
  const Vec3& v0 = s[0].vel;
  const double m = props_.mass;
  const Vec3& c = props_.centroid;
  ElementEnergy e;
  e.kinetic = 0.5 * m * v0.squaredNorm() + m * v0.dot(R * w.cross(c)) + 0.5 * w.dot(inertia_origin_ * w);
  e.gravity_potential = -m * ctx.gravity.dot(s[0].pos + R * c);
  return e;
}

RigidBodyProperties cylinder_body(double density, double length, double ro, double ri) {
  if (!(density > 0 && length > 0 && ro > 0 && ri >= 0 && ri < ro))
    throw std::invalid_argument("cylinder needs density > 0, length > 0 and 0 <= inner < outer radius");
  RigidBodyProperties p;
  const double r2 = ro * ro + ri * ri;
  p.mass = density * std::numbers::pi * (ro * ro - ri * ri) * length;
  p.centroid = Vec3(0.5 * length, 0, 0);
  const double transverse = p.mass * (3 * r2 + length * length) / 12;
  p.inertia_centroid = Vec3(0.5 * p.mass * r2, transverse, transverse).asDiagonal();
  return p;
}

}  // namespace latticedyn
