// The super truss's kinematic map: precomputed node data, and the internal nodes' Cardan angles
// with their Jacobian in closed form, their rates from time jets, their second derivatives by
// HyperDual<9> and the rates' derivatives by jets of Dual<9> (a function of 3 outputs only).
#include "elements/super_truss_map.hpp"

#include "elements/energy_ad.hpp"

#include <cmath>
#include <stdexcept>

namespace latticedyn {

namespace {

using Mat39 = Eigen::Matrix<double, 3, 9>;

struct Hermite {
  double h[4], g[4];  // values and derivatives in xi of the cubic Hermite basis
  explicit Hermite(double x) {
    const double x2 = x * x, x3 = x2 * x;
    h[0] = 1 - 3 * x2 + 2 * x3, h[1] = x - 2 * x2 + x3, h[2] = 3 * x2 - 2 * x3, h[3] = x3 - x2;
    g[0] = -6 * x + 6 * x2, g[1] = 1 - 4 * x + 3 * x2, g[2] = 6 * x - 6 * x2, g[3] = 3 * x2 - 2 * x;
  }
};

}  // namespace

SuperTrussMap::SuperTrussMap(const TrussSectionSpec& spec, const TrussGeometry& g) {
  const int n1 = static_cast<int>(spec.end1.size());
  const Vec3 end2_origin(spec.length, 0, 0);
  for (const TrussNode& tn : g.nodes) {
    Node d;
    if (tn.kind == TrussNode::Kind::end1) d.end = 1, d.point.alpha[0] = 1, d.point.c[0] = tn.position;
    if (tn.kind == TrussNode::Kind::end2) d.end = 2, d.point.alpha[1] = 1, d.point.c[1] = tn.position - end2_origin;
    if (tn.kind == TrussNode::Kind::internal) d.main_beam = tn.main_beam, d.xi = double(tn.station) / spec.order;
    nodes_.push_back(d);
  }
  for (std::size_t m = 0; m < spec.main_beams.size(); ++m) {
    MainBeam mb;
    mb.start = spec.main_beams[m][0];
    mb.end = n1 + spec.main_beams[m][1];
    for (const TrussMember& member : g.members)
      if (member.kind == TrussMemberKind::main && member.face == static_cast<int>(m)) mb.frame = member.frame0;
    const Vec3 s0 = nodes_[mb.start].point.c[0], s2 = nodes_[mb.end].point.c[1];
    // The end tangents L_m R_i a_m: the undeformed chord of the main beam in either end frame.
    const Vec3 a = g.nodes[mb.end].position - g.nodes[mb.start].position;
    for (std::size_t n = 0; n < g.nodes.size(); ++n) {
      if (g.nodes[n].kind != TrussNode::Kind::internal || g.nodes[n].main_beam != static_cast<int>(m)) continue;
      Node& d = nodes_[n];
      const Hermite H(d.xi);
      d.point.alpha[0] = H.h[0];
      d.point.alpha[1] = H.h[2];
      d.point.c[0] = H.h[0] * s0 + H.h[1] * a;
      d.point.c[1] = H.h[2] * s2 + H.h[3] * a;
      d.g2 = H.g[2];  // g0 = -g2: the end positions enter the tangent as g2 (r2 - r1)
      d.t1 = H.g[0] * s0 + H.g[1] * a;
      d.t2 = H.g[2] * s2 + H.g[3] * a;
      mb.internal.push_back(static_cast<int>(n));
      internal_.push_back(static_cast<int>(n));
    }
    // internal_rotations steps the twist from station to station: the k-th internal node must
    // sit at xi = k / order (the geometry numbers a beam's stations in order).
    for (std::size_t k = 0; k < mb.internal.size(); ++k)
      if (std::abs(nodes_[mb.internal[k]].xi - double(k + 1) / spec.order) > 1e-12)
        throw std::logic_error("SuperTrussMap: the internal nodes of a main beam are not in station order");
    main_beams_.push_back(mb);
  }
}

namespace {

// First and second time derivatives of atan2(y(t), x(t)), without its value.
void angle_rates(const Jet<double>& y, const Jet<double>& x, double& rate, double& accel) {
  const double D = x.x * x.x + y.x * y.x;
  const double N = x.x * y.dx - y.x * x.dx;
  const double dD = 2.0 * (x.x * x.dx + y.x * y.dx);
  rate = N / D;
  accel = (x.x * y.ddx - y.x * x.ddx) / D - N * dD / (D * D);
}

Mat3 value_of(const Mat3T<Jet<double>>& m) {
  Mat3 v;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v(i, j) = m(i, j).x;
  return v;
}

}  // namespace

Vec12 internal_node_moment(const InternalRotation& o, const Mat3& F, const Vec3& v) {
  // Jw = T Y + [0, C^T F^T, 0, 0] with the rows of Y expand_row(dphi), expand_row(gpsi dm),
  // expand_row(gtheta dm): Y^T u = expand_row(u0 dphi + (u1 gpsi + u2 gtheta) dm)^T, u = T^T v.
  const Vec3 u = o.T.transpose() * v;
  const Row9 g = u(0) * o.dphi + (u(1) * o.gpsi + u(2) * o.gtheta) * o.dm;
  Vec12 out = expand_row(g).transpose();
  out.segment<3>(3) += F * (o.C * v);
  return out;
}

void internal_rotations(const SuperTrussMap& map, std::span<const SlotState<double>> s,
                        std::vector<InternalRotation>& out, RotationDetail detail) {
  const bool gradients = detail != RotationDetail::frames;
  const Mat3 &R1 = s[1].rot, &R2 = s[3].rot;
  const Vec3 d = s[2].pos - s[0].pos;
  // The relative pose and its rates, from jets along the current motion.
  using J = Jet<double>;
  Vec3T<J> dj;
  for (int i = 0; i < 3; ++i) dj(i) = J(d(i), s[2].vel(i) - s[0].vel(i), s[2].acc(i) - s[0].acc(i));
  const auto relj = SuperTrussMap::relative_pose<J>(dj, rotation_jet<double>(R1, s[1].vel, s[1].acc),
                                                    rotation_jet<double>(R2, s[3].vel, s[3].acc));
  const Mat3 Q = value_of(relj.Q), R1t = R1.transpose();
  out.resize(map.internal_nodes().size());
  std::size_t k = 0;
  for (const SuperTrussMap::MainBeam& mb : map.main_beams()) {
    const Mat3& F = mb.frame;
    const Mat3 A = R1 * F, Ft = F.transpose(), FtQ = Ft * Q;
    const J phi12 = SuperTrussMap::twist<J>(mb, relj.Q);
    // d(phi12)/d(delta_1, delta_2) from C12' = -skew(F^T d1) C12 + C12 skew(F^T d2).
    const Mat3 C12 = FtQ * F;
    const double c21 = C12(2, 1), c22 = C12(2, 2), q = c21 * c21 + c22 * c22;
    // With A_l = -skew(e_l) C12 and B_l = C12 skew(e_l) the changes of C12 under delta_1, delta_2
    // along F e_l, d(phi12) = (c22 dC(2,1) - c21 dC(2,2)) / q takes these values (rows 2 of A_l
    // and B_l written out):
    Row9 dphi12 = Row9::Zero();
    if (gradients) {
      const double gA0 = (c21 * C12(1, 2) - c22 * C12(1, 1)) / q, gA1 = (c22 * C12(0, 1) - c21 * C12(0, 2)) / q;
      const double gB1 = -c21 * C12(2, 0) / q, gB2 = -c22 * C12(2, 0) / q;  // gB0 = (c21^2 + c22^2) / q = 1
      dphi12.segment<3>(3) = (gA0 * F.col(0) + gA1 * F.col(1)).transpose();
      dphi12.segment<3>(6) = (F.col(0) + gB1 * F.col(1) + gB2 * F.col(2)).transpose();
    }
    const Mat3 dm_d = Ft * R1t;  // times g2: dm/d(d)
    // The twist phi = xi phi12 at the beam's stations xi = k / order: sines and cosines by the
    // angle-addition recurrence from those of one step instead of a sincos per node.
    const double dxi = mb.internal.empty() ? 0.0 : map.node(mb.internal.front()).xi;
    const double s1 = std::sin(dxi * phi12.x), c1 = std::cos(dxi * phi12.x);
    double sk = 0.0, ck = 1.0;  // sin, cos of k dxi phi12
    for (int n : mb.internal) {
      const SuperTrussMap::Node& nd = map.node(n);
      InternalRotation& o = out[k++];
      // The tangent in A, m = F^T (g2 R1^T d + t1 + Q t2), as a jet; its direction gives theta
      // and psi, the twist phi = xi phi12.
      const Vec3T<J> wj = relj.d * nd.g2 + relj.Q * nd.t2;
      const Vec3T<J> mj = Ft * Vec3T<J>(wj + nd.t1.cast<J>());
      const Vec3 m(mj(0).x, mj(1).x, mj(2).x);
      const J rhoj = sqrt(mj(0) * mj(0) + mj(1) * mj(1));
      angle_rates(mj(1), mj(0), o.ydot(2), o.yddot(2));
      angle_rates(-mj(2), rhoj, o.ydot(1), o.yddot(1));
      o.ydot(0) = nd.xi * phi12.dx;
      o.yddot(0) = nd.xi * phi12.ddx;
      // Two divisions for the node's sines, cosines and angle gradients.
      const double rho = rhoj.x, rho2 = rho * rho, mm = rho2 + m(2) * m(2), mn = std::sqrt(mm);
      const double irho = 1.0 / rho, imn = 1.0 / mn, irho2 = irho * irho, imm = imn * imn;
      const double sn = sk * c1 + ck * s1, cn = ck * c1 - sk * s1;
      sk = sn, ck = cn;
      o.sphi = sn, o.cphi = cn;
      o.spsi = -m(2) * imn, o.cpsi = rho * imn;
      const double st = m(1) * irho, ct = m(0) * irho;
      // C = Rz(theta) Ry(psi) Rx(phi): the first column is m / |m|.
      Mat3 Rzy;
      Rzy << ct * o.cpsi, -st, ct * o.spsi, st * o.cpsi, ct, st * o.spsi, -o.spsi, 0.0, o.cpsi;
      // C = Rzy Rx(phi): Rx mixes the last two columns only.
      o.C.col(0) = Rzy.col(0);
      o.C.col(1) = o.cphi * Rzy.col(1) + o.sphi * Rzy.col(2);
      o.C.col(2) = o.cphi * Rzy.col(2) - o.sphi * Rzy.col(1);
      o.T << 1, 0, -o.spsi, 0, o.cphi, o.sphi * o.cpsi, 0, -o.sphi, o.cphi * o.cpsi;
      o.A = A;
      o.m = m;
      if (!gradients) continue;
      const double dphi = o.ydot(0), dpsi = o.ydot(1);
      o.Tdot << 0, 0, -o.cpsi * dpsi, 0, -o.sphi * dphi, o.cphi * o.cpsi * dphi - o.sphi * o.spsi * dpsi, 0,
          -o.cphi * dphi, -o.sphi * o.cpsi * dphi - o.cphi * o.spsi * dpsi;
      // Y: dy/d(d, delta_1, delta_2) through dm = [g2 F^T R1^T, F^T skew(w), -F^T Q skew(t2)].
      const Vec3 w(wj(0).x, wj(1).x, wj(2).x);  // g2 R1^T d + Q t2
      const Eigen::RowVector3d gtheta(-m(1) * irho2, m(0) * irho2, 0.0);
      const double gk = m(2) * irho * imm;
      const Eigen::RowVector3d gpsi(gk * m(0), gk * m(1), -rho * imm);
      o.dm.block<3, 3>(0, 0) = nd.g2 * dm_d;
      o.dm.block<3, 3>(0, 3) = Ft * skew<double>(w);
      o.dm.block<3, 3>(0, 6) = -FtQ * skew<double>(nd.t2);
      o.dphi = nd.xi * dphi12;
      o.gpsi = gpsi;
      o.gtheta = gtheta;
      if (detail != RotationDetail::jacobians) continue;
      o.Y.row(0) = expand_row(o.dphi);
      o.Y.row(1) = expand_row(gpsi * o.dm);
      o.Y.row(2) = expand_row(gtheta * o.dm);
      o.Jw.noalias() = o.T * o.Y;
      o.Jw.block<3, 3>(0, 3) += o.C.transpose() * Ft;
    }
  }
}

void internal_rotation_tangents(const SuperTrussMap& map, std::span<const SlotState<double>> s,
                                std::vector<InternalRotationTangent>& out) {
  const Vec3 d = s[2].pos - s[0].pos;
  out.resize(map.internal_nodes().size());
  // d(y')/d eps and d(y'')/d eps: jets along the current motion from the perturbed state.
  EnergyAD<9>::FirstOrder ad;
  using D = EnergyAD<9>::FirstOrder::S;
  using J = Jet<D>;
  const Vec3T<D> dD = ad.vec(d, 0);
  const Mat3T<D> R1 = ad.rot(s[1].rot, 3), R2 = ad.rot(s[3].rot, 6);
  Vec3T<J> dj;
  for (int i = 0; i < 3; ++i) dj(i) = J(dD(i), D(s[2].vel(i) - s[0].vel(i)), D(s[2].acc(i) - s[0].acc(i)));
  auto constant = [](const Vec3& v) { return Vec3T<D>(D(v(0)), D(v(1)), D(v(2))); };
  const Mat3T<J> R1j = rotation_jet<D>(R1, constant(s[1].vel), constant(s[1].acc));
  const Mat3T<J> R2j = rotation_jet<D>(R2, constant(s[3].vel), constant(s[3].acc));
  std::vector<Vec3T<J>> yj;
  map.all_cardan_angles<J>(dj, R1j, R2j, yj);
  for (std::size_t k = 0; k < yj.size(); ++k)
    for (int i = 0; i < 3; ++i) {
      Row9 a, b;
      for (int j = 0; j < 9; ++j) a(j) = yj[k](i).dx.g[j], b(j) = yj[k](i).ddx.g[j];
      out[k].dydot.row(i) = expand_row(a);
      out[k].dyddot.row(i) = expand_row(b);
    }
}

}  // namespace latticedyn

namespace latticedyn {

namespace {

// Hessian of atan2(y, x) in (y, x): [f_yy, f_yx; f_xy, f_xx].
Eigen::Matrix2d atan2_hessian(double y, double x) {
  const double r2 = x * x + y * y, r4 = r2 * r2;
  Eigen::Matrix2d H;
  H << -2 * x * y / r4, (y * y - x * x) / r4, (y * y - x * x) / r4, 2 * x * y / r4;
  return H;
}

// Hessians of theta = atan2(m1, m0) and psi = atan2(-m2, |(m0, m1)|) in m.
void direction_hessians(const Vec3& m, Mat3& Htheta, Mat3& Hpsi) {
  Htheta.setZero();
  const Eigen::Matrix2d Ht = atan2_hessian(m(1), m(0));  // (y = m1, x = m0)
  Htheta(1, 1) = Ht(0, 0);
  Htheta(0, 1) = Htheta(1, 0) = Ht(0, 1);
  Htheta(0, 0) = Ht(1, 1);
  const double rho = std::hypot(m(0), m(1)), X = rho, Y = -m(2), D = X * X + Y * Y;
  const Vec3 gX(m(0) / rho, m(1) / rho, 0.0), gY(0.0, 0.0, -1.0);
  const Eigen::Matrix2d Hp = atan2_hessian(Y, X);
  Mat3 HX = Mat3::Zero();  // Hessian of rho: (I - n n^T) / rho in the (m0, m1) block
  const Eigen::Vector2d n(m(0) / rho, m(1) / rho);
  HX.topLeftCorner<2, 2>() = (Eigen::Matrix2d::Identity() - n * n.transpose()) / rho;
  const double fX = -Y / D;
  Hpsi = Hp(0, 0) * gY * gY.transpose() + Hp(1, 1) * gX * gX.transpose() +
         Hp(0, 1) * (gX * gY.transpose() + gY * gX.transpose()) + fX * HX;
}

}  // namespace

Mat9 contracted_angle_hessian(const SuperTrussMap& map, std::span<const SlotState<double>> s,
                              const std::vector<InternalRotation>& rot, const std::vector<Vec3>& c) {
  const Mat3 &R1 = s[1].rot, &R2 = s[3].rot;
  const Mat3 R1t = R1.transpose(), Q = R1t * R2;
  const Vec3 dloc = R1t * (s[2].pos - s[0].pos);
  Mat9 K = Mat9::Zero();
  Row9 g = Row9::Zero();  // the gradient of sum c_n . y_n
  // The weights' linear action on the relative pose: sum over nodes of lambda . H(m) becomes
  // H(v . dloc) + H(tr(B^T Q)).
  Vec3 v = Vec3::Zero();
  Mat3 B = Mat3::Zero();
  std::size_t k = 0;
  for (const SuperTrussMap::MainBeam& mb : map.main_beams()) {
    const Mat3& F = mb.frame;
    const Vec3 f1 = F.col(1), f2 = F.col(2);
    double w_twist = 0.0;  // sum over the beam's nodes of c_phi xi: the weight of phi12
    for (int n : mb.internal) {
      const SuperTrussMap::Node& nd = map.node(n);
      const InternalRotation& o = rot[k];
      const Vec3& cn = c[k];
      ++k;
      const Vec3& m = o.m;
      const double rho2 = m(0) * m(0) + m(1) * m(1), rho = std::sqrt(rho2), mm = rho2 + m(2) * m(2);
      const Vec3 gtheta(-m(1) / rho2, m(0) / rho2, 0.0);
      const Vec3 gpsi(m(2) * m(0) / (rho * mm), m(2) * m(1) / (rho * mm), -rho / mm);
      Mat3 Htheta, Hpsi;
      direction_hessians(m, Htheta, Hpsi);
      const Vec3 lambda = cn(1) * gpsi + cn(2) * gtheta;
      const Mat3 Lambda = cn(1) * Hpsi + cn(2) * Htheta;
      K.noalias() += o.dm.transpose() * Lambda * o.dm;
      const Vec3 Fl = F * lambda;
      v += nd.g2 * Fl;
      B += Fl * nd.t2.transpose();
      w_twist += cn(0) * nd.xi;
      for (int a = 0; a < 3; ++a) g += cn(a) * Eigen::Matrix<double, 1, 9>(
                                               (Row9() << o.Y.row(a).segment<3>(6), o.Y.row(a).segment<3>(3),
                                                o.Y.row(a).segment<3>(9))
                                                   .finished());
    }
    // phi12 = atan2(C21, C22), C2j = f2^T Q fj: its gradient part folds into B, its Hessian part
    // needs the entries' gradients, dC2j/d delta_1 = f2 x Q fj, dC2j/d delta_2 = fj x Q^T f2.
    const double c21 = f2.dot(Q * f1), c22 = f2.dot(Q * f2), q = c21 * c21 + c22 * c22;
    B += w_twist * (c22 / q) * f2 * f1.transpose() - w_twist * (c21 / q) * f2 * f2.transpose();
    Row9 dc21 = Row9::Zero(), dc22 = Row9::Zero();
    dc21.segment<3>(3) = f2.cross(Q * f1).transpose();
    dc21.segment<3>(6) = f1.cross(Q.transpose() * f2).transpose();
    dc22.segment<3>(3) = f2.cross(Q * f2).transpose();
    dc22.segment<3>(6) = f2.cross(Q.transpose() * f2).transpose();
    const Eigen::Matrix2d Ha = atan2_hessian(c21, c22);
    K += w_twist * (Ha(0, 0) * dc21.transpose() * dc21 + Ha(1, 1) * dc22.transpose() * dc22 +
                    Ha(0, 1) * (dc21.transpose() * dc22 + dc22.transpose() * dc21));
  }
  // H(v . dloc), dloc(x) = exp(-E1) R1^T (d + x_d): the second-order terms are
  // -E1 R1^T x_d + E1^2 dloc / 2.
  const Mat3 SvR = skew<double>(v) * R1t;
  K.block<3, 3>(3, 0) += SvR;
  K.block<3, 3>(0, 3) += SvR.transpose();
  K.block<3, 3>(3, 3) += 0.5 * (v * dloc.transpose() + dloc * v.transpose()) - v.dot(dloc) * Mat3::Identity();
  // H(tr(B^T Q)), Q(x) = exp(-E1) Q exp(E2): E1^2 Q / 2 - E1 Q E2 + Q E2^2 / 2.
  const Mat3 S1 = Q * B.transpose(), S2 = B.transpose() * Q;
  K.block<3, 3>(3, 3) += 0.5 * (S1 + S1.transpose()) - S1.trace() * Mat3::Identity();
  K.block<3, 3>(6, 6) += 0.5 * (S2 + S2.transpose()) - S2.trace() * Mat3::Identity();
  Mat3 M12;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      M12(i, j) = -(B.transpose() * skew<double>(Vec3(Vec3::Unit(i))) * Q * skew<double>(Vec3(Vec3::Unit(j)))).trace();
  K.block<3, 3>(3, 6) += M12;
  K.block<3, 3>(6, 3) += M12.transpose();
  // The right perturbation of the rotations: skew(g)/2 on their diagonal blocks.
  for (int b = 0; b < 2; ++b) K.block<3, 3>(3 + 3 * b, 3 + 3 * b) += 0.5 * skew<double>(Vec3(g.segment<3>(3 + 3 * b).transpose()));
  return K;
}

}  // namespace latticedyn
