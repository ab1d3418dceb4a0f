// Co-rotational Timoshenko beam: the internal force and its consistent tangent in closed form,
// linearised by hand in 9 directions at once (each varied quantity a 3 x 9 or 1 x 9 matrix).
#include "elements/corotational_beam_kernel.hpp"

namespace latticedyn {

namespace {

using Mat39 = Eigen::Matrix<double, 3, 9>;

// dU/dtheta_1, dU/dtheta_2 of the local linear beam (linear in the rotations).
void local_moments(const CorotationalStiffness& k, const Vec3& a, const Vec3& b, Vec3& m1, Vec3& m2) {
  const double twist = b(0) - a(0);
  m1 = Vec3(-k.gj * twist, k.ky[0] * a(1) + k.ky[1] * b(1), k.kz[0] * a(2) + k.kz[1] * b(2));
  m2 = Vec3(k.gj * twist, k.ky[0] * b(1) + k.ky[1] * a(1), k.kz[0] * b(2) + k.kz[1] * a(2));
}

}  // namespace

void corotational_force(const CorotationalStiffness& k, const Vec3& d, const Mat3& R1, const Mat3& R2, Vec9& f,
                        Mat9* K) {
  const CorotationalDeformation<double> def = corotational_deformation<double>(k, d, R1, R2);
  const Vec3 e1 = def.Rr.col(0), e2 = def.Rr.col(1), e3 = def.Rr.col(2);
  const Mat3 &Rb1 = def.Rb1, &Rb2 = def.Rb2;
  const double l = d.norm(), il = 1.0 / l;
  const Vec3 q = 0.5 * (R1.col(1) + R2.col(1));
  const double qe1 = q.dot(e1), qe2 = q.dot(e2), eta = qe1 / qe2, h = 0.5 / qe2;

  Vec3 m1, m2;
  local_moments(k, def.th1, def.th2, m1, m2);
  const double N = k.ea * def.u;
  const Vec3 mu1 = tangent_inverse_transpose_times(def.th1, m1), mu2 = tangent_inverse_transpose_times(def.th2, m2);
  const Vec3 nu = Rb1 * mu1 + Rb2 * mu2;
  const Vec3 ey = Vec3::UnitY();
  const Vec3 s1 = Rb1.row(2).transpose(), s2 = Rb2.row(2).transpose();  // R_i^T e3 = R_bar_i^T e_z
  const Vec3 z1 = ey.cross(s1), z2 = ey.cross(s2);
  const double a = (eta * nu(0) + nu(1)) * il, b = nu(2) * il;
  f.segment<3>(0) = N * e1 + a * e3 - b * e2;
  f.segment<3>(3) = mu1 - (nu(0) * h) * z1;
  f.segment<3>(6) = mu2 - (nu(0) * h) * z2;
  if (!K) return;

  // Variations in the 9 directions (eps_d, eps_1, eps_2).
  const Mat3 Ti1 = tangent_operator_inverse<double>(def.th1), Ti2 = tangent_operator_inverse<double>(def.th2);
  Row9 dl = Row9::Zero();
  dl.segment<3>(0) = e1.transpose();
  Mat39 G = Mat39::Zero();  // omega_r, components in Rr
  G.block<1, 3>(0, 0) = (-eta * il) * e3.transpose();
  G.block<1, 3>(0, 3) = h * z1.transpose();
  G.block<1, 3>(0, 6) = h * z2.transpose();
  G.block<1, 3>(1, 0) = -il * e3.transpose();
  G.block<1, 3>(2, 0) = il * e2.transpose();
  const Mat39 de1 = e2 * G.row(2) - e3 * G.row(1);
  const Mat39 de2 = e3 * G.row(0) - e1 * G.row(2);
  const Mat39 de3 = e1 * G.row(1) - e2 * G.row(0);

  Mat39 dth1 = -(Ti1 * Rb1.transpose()) * G, dth2 = -(Ti2 * Rb2.transpose()) * G;
  dth1.block<3, 3>(0, 3) += Ti1;
  dth2.block<3, 3>(0, 6) += Ti2;
  Mat39 dm1, dm2;
  const Row9 dtwist = dth2.row(0) - dth1.row(0);
  dm1.row(0) = -k.gj * dtwist;
  dm1.row(1) = k.ky[0] * dth1.row(1) + k.ky[1] * dth2.row(1);
  dm1.row(2) = k.kz[0] * dth1.row(2) + k.kz[1] * dth2.row(2);
  dm2.row(0) = k.gj * dtwist;
  dm2.row(1) = k.ky[0] * dth2.row(1) + k.ky[1] * dth1.row(1);
  dm2.row(2) = k.kz[0] * dth2.row(2) + k.kz[1] * dth1.row(2);
  const Mat39 dmu1 = tangent_inverse_transpose_derivative(def.th1, m1) * dth1 + Ti1.transpose() * dm1;
  const Mat39 dmu2 = tangent_inverse_transpose_derivative(def.th2, m2) * dth2 + Ti2.transpose() * dm2;
  // d(R_bar_i mu_i) = R_bar_i mu_i x omega_r - R_bar_i (mu_i x eps_i) + R_bar_i d(mu_i).
  Mat39 dnu = skew<double>(nu) * G + Rb1 * dmu1 + Rb2 * dmu2;
  dnu.block<3, 3>(0, 3) -= Rb1 * skew<double>(mu1);
  dnu.block<3, 3>(0, 6) -= Rb2 * skew<double>(mu2);

  Mat39 dq = Mat39::Zero();
  const Mat3 Sy = skew<double>(ey);
  dq.block<3, 3>(0, 3) = -0.5 * R1 * Sy;
  dq.block<3, 3>(0, 6) = -0.5 * R2 * Sy;
  // q.e3 = 0, so q.de1 = (q.e2) omega_z and q.de2 = -(q.e1) omega_z.
  const Row9 dqe1 = e1.transpose() * dq + qe2 * G.row(2);
  const Row9 dqe2 = e2.transpose() * dq - qe1 * G.row(2);
  const Row9 deta = (dqe1 - eta * dqe2) / qe2;
  const Row9 dh = (-2.0 * h * h) * dqe2;
  Mat39 dz1 = Sy * (R1.transpose() * de3), dz2 = Sy * (R2.transpose() * de3);
  dz1.block<3, 3>(0, 3) += Sy * skew<double>(s1);
  dz2.block<3, 3>(0, 6) += Sy * skew<double>(s2);
  const Row9 da = (nu(0) * deta + eta * dnu.row(0) + dnu.row(1)) * il - (a * il) * dl;
  const Row9 db = dnu.row(2) * il - (b * il) * dl;

  K->topRows<3>() = e1 * (k.ea * dl) + N * de1 + e3 * da + a * de3 - e2 * db - b * de2;
  K->middleRows<3>(3) = dmu1 - z1 * (h * dnu.row(0) + nu(0) * dh) - (nu(0) * h) * dz1;
  K->bottomRows<3>() = dmu2 - z2 * (h * dnu.row(0) + nu(0) * dh) - (nu(0) * h) * dz2;
}

}  // namespace latticedyn
