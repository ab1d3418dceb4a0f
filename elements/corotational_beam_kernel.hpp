// Co-rotational Timoshenko beam kernel: local deformation and strain energy (templated, so that
// automatic differentiation can check them), and the internal force with its consistent tangent in
// closed form, shared by the full lattice's members and every member inside a super truss.
#pragma once

#include "core/pack.hpp"
#include "core/rotation.hpp"
#include "core/types.hpp"
#include "elements/section_stress.hpp"

namespace latticedyn {

/// The kernel's variables x = (d = r2 - r1, delta_1, delta_2) on the DoFs [r1, theta1, r2, theta2]
/// of two frames: a row (a derivative in x) becomes [-row_d, row_1, row_d, row_2]; a force f in x
/// becomes P f and a tangent K9 becomes P K9 P^T, P = [-I 0 0; 0 I 0; I 0 0; 0 0 I].
inline Row12 expand_row(const Row9& row) {
  Row12 out;
  out << -row.segment<3>(0), row.segment<3>(3), row.segment<3>(0), row.segment<3>(6);
  return out;
}
inline Vec12 expand_force(const Vec9& f) {
  Vec12 out;
  out << -f.segment<3>(0), f.segment<3>(3), f.segment<3>(0), f.segment<3>(6);
  return out;
}
inline void add_expanded(const Mat9& K9, Eigen::Ref<Eigen::MatrixXd> K) {
  static constexpr int kBlock[4] = {0, 3, 0, 6};       // block of x behind each DoF slot
  static constexpr double kSign[4] = {-1, 1, 1, 1};  // d = r2 - r1
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) K.block<3, 3>(3 * i, 3 * j) += (kSign[i] * kSign[j]) * K9.block<3, 3>(kBlock[i], kBlock[j]);
}

/// Constants of the local linear beam: the unstressed length L0, EA/L0, GJ/L0 and, per bending
/// plane, the coefficients (4 + Phi) EI/(L0 (1 + Phi)) and (2 - Phi) EI/(L0 (1 + Phi)) of the
/// end rotations (the exact Timoshenko stiffness of a beam with zero end deflections).
/// K is double for one beam, Pack4 for four beams evaluated together.
template <class K>
struct CorotationalStiffnessT {
  K length = K(0.0);
  K ea = K(0.0), gj = K(0.0);
  K kz[2] = {K(0.0), K(0.0)};  ///< bending about z (deflection along y)
  K ky[2] = {K(0.0), K(0.0)};  ///< bending about y
};
using CorotationalStiffness = CorotationalStiffnessT<double>;

/// Lane l of four beams' constants set from one beam's.
inline void set_lane(CorotationalStiffnessT<Pack4>& k, int l, const CorotationalStiffness& one) {
  k.length[l] = one.length;
  k.ea[l] = one.ea;
  k.gj[l] = one.gj;
  for (int i = 0; i < 2; ++i) k.kz[i][l] = one.kz[i], k.ky[i][l] = one.ky[i];
}

/// Stretch u = l - L0 and end rotations theta_i = log(Rr^T R_i) relative to the co-rotational
/// frame Rr = [e1 e2 e3]: e1 = d/l, e3 along e1 x (R1 e_y + R2 e_y), e2 = e3 x e1
/// (Battini & Pacoste 2002).
template <class S>
struct CorotationalDeformation {
  S u;
  Vec3T<S> th1, th2;
  Mat3T<S> Rr;
  Mat3T<S> Rb1, Rb2;  ///< the end frames in the co-rotational frame, Rr^T R_i = exp(skew(theta_i))
  S l;                ///< the chord's length |d|
  Vec3T<S> q;         ///< (R1 e_y + R2 e_y) / 2, which fixes e3
  S qe2;              ///< q . e2 = |e1 x q|
};

template <class S, class K>
CorotationalDeformation<S> corotational_deformation(const CorotationalStiffnessT<K>& k, const Vec3T<S>& d,
                                                    const Mat3T<S>& R1, const Mat3T<S>& R2) {
  using std::sqrt;
  // Constants multiply as doubles: a product with S(constant) would cost a full AD product.
  const S l = sqrt(d.squaredNorm());
  const Vec3T<S> e1 = d * (1.0 / l);
  const Vec3T<S> q = (R1.col(1) + R2.col(1)) * 0.5;
  Vec3T<S> e3 = e1.cross(q);
  CorotationalDeformation<S> out;
  out.qe2 = sqrt(e3.squaredNorm());
  e3 *= 1.0 / out.qe2;
  out.l = l;
  out.q = q;
  out.Rr.col(0) = e1;
  out.Rr.col(1) = e3.cross(e1);
  out.Rr.col(2) = e3;
  out.u = l - k.length;
  out.Rb1 = out.Rr.transpose() * R1;
  out.Rb2 = out.Rr.transpose() * R2;
  out.th1 = small_rotation_vector(out.Rb1);  // unqualified: the Pack4 overload by ADL
  out.th2 = small_rotation_vector(out.Rb2);
  return out;
}

/// A point of the deformed axis at xi in [0, 1] (drawing): r1 + xi d plus the cubic deflection in
/// the co-rotational frame with zero end displacements and end slopes v' = theta_z, w' = -theta_y
/// (the Hermite slope shapes L (xi - 2 xi^2 + xi^3) and L (xi^3 - xi^2)).
template <class S>
Vec3T<S> corotational_axis_point(const CorotationalDeformation<S>& def, const Vec3T<S>& r1, const Vec3T<S>& d,
                                 double xi) {
  const double n1 = xi - 2.0 * xi * xi + xi * xi * xi, n3 = xi * xi * xi - xi * xi;
  const S v = (def.th1(2) * n1 + def.th2(2) * n3) * def.l;
  const S w = -((def.th1(1) * n1 + def.th2(1) * n3) * def.l);
  return r1 + d * S(xi) + def.Rr.col(1) * v + def.Rr.col(2) * w;
}

/// U = EA/(2 L0) u^2 + GJ/(2 L0) (th2x - th1x)^2
///   + sum over bending planes EI/(2 L0 (1 + Phi)) [(4 + Phi)(th1^2 + th2^2) + 2 (2 - Phi) th1 th2].
template <class S, class K>
S corotational_strain_energy(const CorotationalStiffnessT<K>& k, const CorotationalDeformation<S>& def) {
  const Vec3T<S>& a = def.th1;
  const Vec3T<S>& b = def.th2;
  const S twist = b(0) - a(0);
  return (def.u * def.u) * (0.5 * k.ea) + (twist * twist) * (0.5 * k.gj) +
         (a(2) * a(2) + b(2) * b(2)) * (0.5 * k.kz[0]) + (a(2) * b(2)) * k.kz[1] +
         (a(1) * a(1) + b(1) * b(1)) * (0.5 * k.ky[0]) + (a(1) * b(1)) * k.ky[1];
}

/// dU/dtheta_1, dU/dtheta_2 of the local linear beam (linear in the rotations).
template <class S, class K>
void local_moments(const CorotationalStiffnessT<K>& k, const Vec3T<S>& a, const Vec3T<S>& b, Vec3T<S>& m1,
                   Vec3T<S>& m2) {
  const S twist = b(0) - a(0);
  m1 = Vec3T<S>(-(twist * k.gj), a(1) * k.ky[0] + b(1) * k.ky[1], a(2) * k.kz[0] + b(2) * k.kz[1]);
  m2 = Vec3T<S>(twist * k.gj, b(1) * k.ky[0] + a(1) * k.ky[1], b(2) * k.kz[0] + a(2) * k.kz[1]);
}

/// The deformation measures e = (u, theta_1, theta_2) of the local beam, U = e^T K_l e / 2.
template <class S>
std::array<S, 7> corotational_deformation_measures(const CorotationalDeformation<S>& def) {
  return {def.u, def.th1(0), def.th1(1), def.th1(2), def.th2(0), def.th2(1), def.th2(2)};
}

/// K_l of U = e^T K_l e / 2 in the measures above (Kelvin-Voigt damping acts through it).
inline Eigen::MatrixXd corotational_local_stiffness(const CorotationalStiffness& k) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(7, 7);
  K(0, 0) = k.ea;
  K(1, 1) = K(4, 4) = k.gj;
  K(1, 4) = K(4, 1) = -k.gj;
  K(2, 2) = K(5, 5) = k.ky[0];
  K(2, 5) = K(5, 2) = k.ky[1];
  K(3, 3) = K(6, 6) = k.kz[0];
  K(3, 6) = K(6, 3) = k.kz[1];
  return K;
}

/// Stress resultants at the two ends of the local linear beam, in the co-rotational frame: N = EA
/// u/L0, the end moments m_i = dU/dtheta_i acting on the beam (section moments -m_1 at end 1,
/// +m_2 at end 2), the shears from the beam's equilibrium under them, Qy = -(m1z + m2z)/L0,
/// Qz = (m1y + m2y)/L0, constant along it.
template <class S, class K>
std::array<SectionForcesT<S>, 2> corotational_section_forces(const CorotationalStiffnessT<K>& k,
                                                            const CorotationalDeformation<S>& def) {
  Vec3T<S> m1, m2;
  local_moments(k, def.th1, def.th2, m1, m2);
  const S inv_l = S(1.0) / S(k.length);
  std::array<SectionForcesT<S>, 2> out;
  for (SectionForcesT<S>& f : out) {
    f.N = def.u * k.ea;
    f.Qy = -(m1(2) + m2(2)) * inv_l;
    f.Qz = (m1(1) + m2(1)) * inv_l;
    f.T = m2(0);
  }
  out[0].My = -m1(1);
  out[0].Mz = -m1(2);
  out[1].My = m2(1);
  out[1].Mz = m2(2);
  return out;
}

/// The internal force of corotational_force (below) with the intermediates its tangent reuses.
template <class S>
struct CorotationalForce {
  CorotationalDeformation<S> def;
  S il, qe1, eta, h, N, a, b;
  Vec3T<S> m1, m2, mu1, mu2, nu, s1, s2, z1, z2;
  Eigen::Matrix<S, 9, 1> f;
};

/// f of corotational_force for a scalar S: double for one beam, Pack4 for four at once.
template <class S, class K>
void corotational_internal_force(const CorotationalStiffnessT<K>& k, const Vec3T<S>& d, const Mat3T<S>& R1,
                                 const Mat3T<S>& R2, CorotationalForce<S>& o) {
  o.def = corotational_deformation<S>(k, d, R1, R2);
  const CorotationalDeformation<S>& def = o.def;
  const Vec3T<S> e1 = def.Rr.col(0), e2 = def.Rr.col(1), e3 = def.Rr.col(2);
  o.il = S(1.0) / def.l;
  o.qe1 = def.q.dot(e1);
  o.eta = o.qe1 / def.qe2;
  o.h = S(0.5) / def.qe2;
  local_moments(k, def.th1, def.th2, o.m1, o.m2);
  o.N = def.u * k.ea;
  o.mu1 = tangent_inverse_transpose_times(def.th1, o.m1);  // unqualified: the Pack4 overload by ADL
  o.mu2 = tangent_inverse_transpose_times(def.th2, o.m2);
  o.nu = def.Rb1 * o.mu1 + def.Rb2 * o.mu2;
  o.s1 = def.Rb1.row(2).transpose();  // R_i^T e3 = R_bar_i^T e_z
  o.s2 = def.Rb2.row(2).transpose();
  o.z1 = Vec3T<S>(o.s1(2), S(0.0), -o.s1(0));  // e_y x s1
  o.z2 = Vec3T<S>(o.s2(2), S(0.0), -o.s2(0));
  o.a = (o.eta * o.nu(0) + o.nu(1)) * o.il;
  o.b = o.nu(2) * o.il;
  o.f.template segment<3>(0) = e1 * o.N + e3 * o.a - e2 * o.b;
  const S nh = o.nu(0) * o.h;
  o.f.template segment<3>(3) = o.mu1 - o.z1 * nh;
  o.f.template segment<3>(6) = o.mu2 - o.z2 * nh;
}

/// K = d f(x (+) eps) / d eps of corotational_force, from its internal force's intermediates.
template <class S, class K>
void corotational_tangent(const CorotationalStiffnessT<K>& k, const Mat3T<S>& R1, const Mat3T<S>& R2,
                          const CorotationalForce<S>& o, Eigen::Matrix<S, 9, 9>& Kt) {
  using Mat39S = Eigen::Matrix<S, 3, 9>;
  using Row9S = Eigen::Matrix<S, 1, 9>;
  const CorotationalDeformation<S>& def = o.def;
  const Vec3T<S> e1 = def.Rr.col(0), e2 = def.Rr.col(1), e3 = def.Rr.col(2);
  const Mat3T<S> &Rb1 = def.Rb1, &Rb2 = def.Rb2;
  const S il = o.il, eta = o.eta, h = o.h, qe1 = o.qe1, qe2 = def.qe2, N = o.N, a = o.a, b = o.b;
  const Vec3T<S> &m1 = o.m1, &m2 = o.m2, &mu1 = o.mu1, &mu2 = o.mu2, &nu = o.nu;
  const Vec3T<S> &s1 = o.s1, &s2 = o.s2, &z1 = o.z1, &z2 = o.z2;
  const Vec3T<S> ey(S(0.0), S(1.0), S(0.0));

  // Variations in the 9 directions (eps_d, eps_1, eps_2).
  const Mat3T<S> Ti1 = tangent_operator_inverse(def.th1), Ti2 = tangent_operator_inverse(def.th2);  // unqualified: ADL
  Row9S dl = Row9S::Zero();
  dl.template segment<3>(0) = e1.transpose();
  Mat39S G = Mat39S::Zero();  // omega_r, components in Rr
  G.template block<1, 3>(0, 0) = e3.transpose() * (-eta * il);
  G.template block<1, 3>(0, 3) = z1.transpose() * h;
  G.template block<1, 3>(0, 6) = z2.transpose() * h;
  G.template block<1, 3>(1, 0) = e3.transpose() * (-il);
  G.template block<1, 3>(2, 0) = e2.transpose() * il;
  const Mat39S de1 = e2 * G.row(2) - e3 * G.row(1);
  const Mat39S de2 = e3 * G.row(0) - e1 * G.row(2);
  const Mat39S de3 = e1 * G.row(1) - e2 * G.row(0);

  Mat39S dth1 = -(Ti1 * Rb1.transpose()) * G;
  Mat39S dth2 = -(Ti2 * Rb2.transpose()) * G;
  dth1.template block<3, 3>(0, 3) += Ti1;
  dth2.template block<3, 3>(0, 6) += Ti2;
  Mat39S dm1, dm2;
  const Row9S dtwist = dth2.row(0) - dth1.row(0);
  dm1.row(0) = dtwist * (-k.gj);
  dm1.row(1) = dth1.row(1) * k.ky[0] + dth2.row(1) * k.ky[1];
  dm1.row(2) = dth1.row(2) * k.kz[0] + dth2.row(2) * k.kz[1];
  dm2.row(0) = dtwist * k.gj;
  dm2.row(1) = dth2.row(1) * k.ky[0] + dth1.row(1) * k.ky[1];
  dm2.row(2) = dth2.row(2) * k.kz[0] + dth1.row(2) * k.kz[1];
  const Mat39S dmu1 = tangent_inverse_transpose_derivative(def.th1, m1) * dth1 + Ti1.transpose() * dm1;
  const Mat39S dmu2 = tangent_inverse_transpose_derivative(def.th2, m2) * dth2 + Ti2.transpose() * dm2;
  // d(R_bar_i mu_i) = R_bar_i mu_i x omega_r - R_bar_i (mu_i x eps_i) + R_bar_i d(mu_i).
  Mat39S dnu = skew(nu) * G + Rb1 * dmu1 + Rb2 * dmu2;
  dnu.template block<3, 3>(0, 3) -= Rb1 * skew(mu1);
  dnu.template block<3, 3>(0, 6) -= Rb2 * skew(mu2);

  Mat39S dq = Mat39S::Zero();
  const Mat3T<S> Sy = skew(ey);
  dq.template block<3, 3>(0, 3) = R1 * Sy * S(-0.5);
  dq.template block<3, 3>(0, 6) = R2 * Sy * S(-0.5);
  // q.e3 = 0, so q.de1 = (q.e2) omega_z and q.de2 = -(q.e1) omega_z.
  const Row9S dqe1 = e1.transpose() * dq + G.row(2) * qe2;
  const Row9S dqe2 = e2.transpose() * dq - G.row(2) * qe1;
  const Row9S deta = (dqe1 - dqe2 * eta) / qe2;
  const Row9S dh = dqe2 * (S(-2.0) * h * h);
  Mat39S dz1 = Sy * (R1.transpose() * de3);
  Mat39S dz2 = Sy * (R2.transpose() * de3);
  dz1.template block<3, 3>(0, 3) += Sy * skew(s1);
  dz2.template block<3, 3>(0, 6) += Sy * skew(s2);
  const Row9S da = (deta * nu(0) + dnu.row(0) * eta + dnu.row(1)) * il - dl * (a * il);
  const Row9S db = dnu.row(2) * il - dl * (b * il);

  Kt.template topRows<3>() = e1 * (dl * k.ea) + de1 * N + e3 * da + de3 * a - e2 * db - de2 * b;
  Kt.template middleRows<3>(3) = dmu1 - z1 * (dnu.row(0) * h + dh * nu(0)) - dz1 * (nu(0) * h);
  Kt.template bottomRows<3>() = dmu2 - z2 * (dnu.row(0) * h + dh * nu(0)) - dz2 * (nu(0) * h);
}

/// Internal force f = dU/dx in the variables x = (d = r2 - r1, delta_1, delta_2), the rotations
/// perturbed on the right, R_i exp(skew(delta_i)); with K, its consistent tangent
/// K = d f(x (+) eps) / d eps, the derivative of the force under a right perturbation of the state
/// (the symmetric Hessian of U plus skew(f_delta_i)/2 on each rotation's diagonal block).
///
/// With R_bar_i = Rr^T R_i, a variation gives delta theta_i = T(theta_i)^-1 (delta_i - R_bar_i^T
/// omega_r), omega_r the spin of Rr in its own axes: omega_x = -eta e3.dd/l + (e3.dq)/(q.e2),
/// omega_y = -e3.dd/l, omega_z = e2.dd/l, eta = (q.e1)/(q.e2). So with N = EA u/L0,
/// mu_i = T_i^-T dU/dtheta_i and nu = R_bar_1 mu_1 + R_bar_2 mu_2 (docs/elements.md):
///   f_d = N e1 + (eta nu_x + nu_y) e3 / l - nu_z e2 / l,
///   f_delta_i = mu_i - nu_x (e_y x R_i^T e3) / (2 q.e2);
/// K is the exact linearisation of these expressions, every intermediate varied as a 3 x 9
/// matrix of directional derivatives.
void corotational_force(const CorotationalStiffness& k, const Vec3& d, const Mat3& R1, const Mat3& R2, Vec9& f,
                        Mat9* K);

}  // namespace latticedyn
