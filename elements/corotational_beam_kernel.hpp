// Co-rotational Timoshenko beam kernel: local deformation and strain energy (templated, so that
// automatic differentiation can check them), and the internal force with its consistent tangent in
// closed form, shared by the full lattice's members and every member inside a super truss.
#pragma once

#include "core/rotation.hpp"
#include "core/types.hpp"

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
struct CorotationalStiffness {
  double length = 0.0;
  double ea = 0.0, gj = 0.0;
  double kz[2] = {0.0, 0.0};  ///< bending about z (deflection along y)
  double ky[2] = {0.0, 0.0};  ///< bending about y
};

/// Stretch u = l - L0 and end rotations theta_i = log(Rr^T R_i) relative to the co-rotational
/// frame Rr = [e1 e2 e3]: e1 = d/l, e3 along e1 x (R1 e_y + R2 e_y), e2 = e3 x e1
/// (Battini & Pacoste 2002).
template <class S>
struct CorotationalDeformation {
  S u;
  Vec3T<S> th1, th2;
  Mat3T<S> Rr;
  Mat3T<S> Rb1, Rb2;  ///< the end frames in the co-rotational frame, Rr^T R_i = exp(skew(theta_i))
};

template <class S>
CorotationalDeformation<S> corotational_deformation(const CorotationalStiffness& k, const Vec3T<S>& d,
                                                    const Mat3T<S>& R1, const Mat3T<S>& R2) {
  using std::sqrt;
  // Constants multiply as doubles: a product with S(constant) would cost a full AD product.
  const S l = sqrt(d.squaredNorm());
  const Vec3T<S> e1 = d * (1.0 / l);
  const Vec3T<S> q = (R1.col(1) + R2.col(1)) * 0.5;
  Vec3T<S> e3 = e1.cross(q);
  e3 *= 1.0 / sqrt(e3.squaredNorm());
  CorotationalDeformation<S> out;
  out.Rr.col(0) = e1;
  out.Rr.col(1) = e3.cross(e1);
  out.Rr.col(2) = e3;
  out.u = l - k.length;
  out.Rb1 = out.Rr.transpose() * R1;
  out.Rb2 = out.Rr.transpose() * R2;
  out.th1 = small_rotation_vector<S>(out.Rb1);
  out.th2 = small_rotation_vector<S>(out.Rb2);
  return out;
}

/// U = EA/(2 L0) u^2 + GJ/(2 L0) (th2x - th1x)^2
///   + sum over bending planes EI/(2 L0 (1 + Phi)) [(4 + Phi)(th1^2 + th2^2) + 2 (2 - Phi) th1 th2].
template <class S>
S corotational_strain_energy(const CorotationalStiffness& k, const CorotationalDeformation<S>& def) {
  const Vec3T<S>& a = def.th1;
  const Vec3T<S>& b = def.th2;
  const S twist = b(0) - a(0);
  return (def.u * def.u) * (0.5 * k.ea) + (twist * twist) * (0.5 * k.gj) +
         (a(2) * a(2) + b(2) * b(2)) * (0.5 * k.kz[0]) + (a(2) * b(2)) * k.kz[1] +
         (a(1) * a(1) + b(1) * b(1)) * (0.5 * k.ky[0]) + (a(1) * b(1)) * k.ky[1];
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
