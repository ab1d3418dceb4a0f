// The super truss's kinematic map: precomputed node data, and the internal nodes' Cardan angles
// with their Jacobian in closed form, their rates from time jets, their second derivatives by
// HyperDual<9> and the rates' derivatives by jets of Dual<9> (a function of 3 outputs only).
#include "elements/super_truss_map.hpp"

#include "elements/energy_ad.hpp"

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
    main_beams_.push_back(mb);
  }
}

void internal_rotations(const SuperTrussMap& map, std::span<const SlotState<double>> s,
                        std::vector<InternalRotation>& out) {
  const Mat3 &R1 = s[1].rot, &R2 = s[3].rot;
  const Vec3 d = s[2].pos - s[0].pos;
  // Angles and their rates from jets of the relative pose along the current motion.
  using J = Jet<double>;
  Vec3T<J> dj;
  for (int i = 0; i < 3; ++i) dj(i) = J(d(i), s[2].vel(i) - s[0].vel(i), s[2].acc(i) - s[0].acc(i));
  const auto relj = SuperTrussMap::relative_pose<J>(dj, rotation_jet<double>(R1, s[1].vel, s[1].acc),
                                                    rotation_jet<double>(R2, s[3].vel, s[3].acc));
  out.resize(map.internal_nodes().size());
  std::size_t k = 0;
  for (const SuperTrussMap::MainBeam& mb : map.main_beams()) {
    const Mat3& F = mb.frame;
    const J phi12j = SuperTrussMap::twist<J>(mb, relj.Q);
    // d(phi12)/d(delta_1, delta_2) from C12' = -skew(F^T d1) C12 + C12 skew(F^T d2).
    Mat3 Q;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Q(i, j) = relj.Q(i, j).x;
    const Mat3 C12 = F.transpose() * Q * F;
    const double c21 = C12(2, 1), c22 = C12(2, 2), q = c21 * c21 + c22 * c22;
    Row9 dphi12 = Row9::Zero();
    for (int l = 0; l < 3; ++l) {
      const Mat3 Sl = skew<double>(Vec3(Vec3::Unit(l)));
      const Mat3 dA = -Sl * C12, dB = C12 * Sl;
      const double gA = (c22 * dA(2, 1) - c21 * dA(2, 2)) / q, gB = (c22 * dB(2, 1) - c21 * dB(2, 2)) / q;
      dphi12.segment<3>(3) += gA * F.col(l).transpose();
      dphi12.segment<3>(6) += gB * F.col(l).transpose();
    }
    for (int n : mb.internal) {
      const SuperTrussMap::Node& nd = map.node(n);
      InternalRotation& o = out[k++];
      const Vec3T<J> yj = map.cardan_angles<J>(nd, relj, phi12j);
      for (int i = 0; i < 3; ++i) o.y(i) = yj(i).x, o.ydot(i) = yj(i).dx, o.yddot(i) = yj(i).ddx;
      // The tangent in A and its derivative in (d, delta_1, delta_2):
      // m = F^T w, w = g2 R1^T d + t1 + Q t2; dw = g2 R1^T dd + skew(w - t1) d1 - Q skew(t2) d2.
      const Vec3 w = Vec3(relj.d(0).x, relj.d(1).x, relj.d(2).x) * nd.g2 + Q * nd.t2;
      const Vec3 m = F.transpose() * (w + nd.t1);
      Mat39 dm;
      dm.block<3, 3>(0, 0) = nd.g2 * (F.transpose() * R1.transpose());
      dm.block<3, 3>(0, 3) = F.transpose() * skew<double>(w);
      dm.block<3, 3>(0, 6) = -(F.transpose() * Q) * skew<double>(nd.t2);
      const double rho2 = m(0) * m(0) + m(1) * m(1), rho = std::sqrt(rho2), mm = rho2 + m(2) * m(2);
      const Eigen::RowVector3d gtheta(-m(1) / rho2, m(0) / rho2, 0.0);
      const Eigen::RowVector3d gpsi(m(2) * m(0) / (rho * mm), m(2) * m(1) / (rho * mm), -rho / mm);
      o.Y.row(0) = expand_row(nd.xi * dphi12);
      o.Y.row(1) = expand_row(gpsi * dm);
      o.Y.row(2) = expand_row(gtheta * dm);
      o.C = rotation_z<double>(o.y(2)) * rotation_y<double>(o.y(1)) * rotation_x<double>(o.y(0));
      o.T = cardan_zyx_tangent<double>(o.y);
      o.A = R1 * F;
      o.Jw = o.T * o.Y;
      o.Jw.block<3, 3>(0, 3) += o.C.transpose() * F.transpose();
    }
  }
}

void internal_rotation_tangents(const SuperTrussMap& map, std::span<const SlotState<double>> s,
                                std::vector<InternalRotationTangent>& out) {
  const Vec3 d = s[2].pos - s[0].pos;
  out.resize(map.internal_nodes().size());
  // Second derivatives of the angles in (d, delta_1, delta_2).
  {
    EnergyAD<9>::SecondOrder ad;
    using HD = EnergyAD<9>::SecondOrder::S;
    std::vector<Vec3T<HD>> y;
    map.all_cardan_angles<HD>(ad.vec(d, 0), ad.rot(s[1].rot, 3), ad.rot(s[3].rot, 6), y);
    for (std::size_t k = 0; k < y.size(); ++k)
      for (int i = 0; i < 3; ++i) out[k].y[i] = y[k](i);
  }
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
