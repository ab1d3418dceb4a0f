// Chain-rule matrices of the rotation-vector parametrisation by forward AD over (phi, phi_dot).
#include "assembly/rotation_chain.hpp"

#include "core/rotation.hpp"

#include <unsupported/Eigen/AutoDiff>

namespace latticedyn {

RotationChain rotation_chain(const Mat3& R_ref, const Vec3& phi, const Vec3& phi_dot,
                             const Vec3& phi_ddot, bool with_derivatives) {
  RotationChain c;
  c.R = R_ref * rotation_matrix(phi);
  c.T = tangent_operator(phi);
  c.omega = c.T * phi_dot;
  c.omega_dot = c.T * phi_ddot + tangent_operator_rate(phi, phi_dot) * phi_dot;
  c.P.setZero();
  c.Q.setZero();
  c.S.setZero();
  if (!with_derivatives) return c;

  using AD = Eigen::AutoDiffScalar<Eigen::Matrix<double, 6, 1>>;
  Vec3T<AD> p, pd;
  for (int i = 0; i < 3; ++i) {
    p(i) = AD(phi(i), 6, i);
    pd(i) = AD(phi_dot(i), 6, 3 + i);
  }
  const Vec3T<AD> pdd = phi_ddot.cast<AD>();
  const Mat3T<AD> T = tangent_operator(p);
  const Vec3T<AD> w = T * pd;
  const Vec3T<AD> wd = T * pdd + tangent_operator_rate(p, pd) * pd;
  for (int i = 0; i < 3; ++i) {
    c.P.row(i) = w(i).derivatives().head<3>().transpose();
    c.Q.row(i) = wd(i).derivatives().head<3>().transpose();
    c.S.row(i) = wd(i).derivatives().tail<3>().transpose();
  }
  return c;
}

Mat3 tangent_transpose_derivative(const Vec3& phi, const Vec3& y) {
  using AD = Eigen::AutoDiffScalar<Eigen::Vector3d>;
  Vec3T<AD> p;
  for (int i = 0; i < 3; ++i) p(i) = AD(phi(i), 3, i);
  const Vec3T<AD> z = tangent_operator(p).transpose() * y.cast<AD>();
  Mat3 Y;
  for (int i = 0; i < 3; ++i) Y.row(i) = z(i).derivatives().transpose();
  return Y;
}

}  // namespace latticedyn
