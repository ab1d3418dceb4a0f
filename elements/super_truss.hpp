// The super truss element (thesis 3.5): a whole lattice section reduced to the 12 coordinates
// of its two rigid end sections; every member's virtual power is projected through the
// kinematic map from the end sections to the lattice nodes.
#pragma once

#include "core/jet.hpp"
#include "elements/autodiff_element.hpp"
#include "elements/timoshenko_beam.hpp"
#include "elements/truss_section.hpp"

#include <memory>
#include <vector>

namespace latticedyn {

/// Slots: [translation 1, rotation 1, translation 2, rotation 2], the reference points of the two
/// end sections (on the truss axis at x = 0 and x = L) and the truss frame there (x along the
/// truss). The kinematic map (assumptions of 3.5.1):
/// - end-section nodes ride rigidly on their end frame: p = r_i + R_i s (3-87);
/// - each main beam is a cubic Hermite curve between its end nodes with end tangents L_m R_i a_m
///   (a_m its undeformed direction, no axial strain, rigid connection to the end sections, 3-90);
///   its internal nodes sit at equal parameter steps, oriented by relative Cardan angles from the
///   main beam's frame at end 1 (bending from the tangent, torsion interpolated, 3.4 / 3-92);
/// - every member is a co-rotational Timoshenko beam rigidly connected to its two nodes.
/// Elastic force and stiffness: the gradient and Hessian of the members' strain energy as a
/// function of the 12 coordinates (HyperDual<12> through map and members). Inertia: the members'
/// consistent translational mass and lumped rotary inertia at the nodes, projected with the
/// map's Jacobians (3-97..3-102); node velocities and accelerations from time jets of the map,
/// the tangents by automatic differentiation of that residual.
class SuperTrussElement final : public AutoDiffElement<SuperTrussElement, 12> {
 public:
  static constexpr std::array<SlotKind, 4> kSlots = {SlotKind::translation, SlotKind::rotation,
                                                      SlotKind::translation, SlotKind::rotation};

  SuperTrussElement(const TrussSectionSpec& spec, const TrussGeometry& geometry);

  std::string_view type_name() const override { return "super_truss"; }
  bool expensive() const override { return true; }
  void residual(std::span<const SlotState<double>> state, const ElementContext& ctx,
                Eigen::Ref<VecX> r) const override;
  void tangents(std::span<const SlotState<double>> state, const ElementContext& ctx,
                ElementTangents& out) const override;
  ElementEnergy energy(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  /// The members' axes, end to end (one polyline through every member would need repeats; the
  /// drawing takes the members as separate lines: see member_lines).
  std::vector<Vec3> axis_points(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  std::vector<double> polyline_axial_forces(std::span<const SlotState<double>> state,
                                            const ElementContext&) const override {
    return member_axial_forces(state);
  }
  std::vector<std::vector<Vec3>> axis_polylines(std::span<const SlotState<double>> state,
                                                const ElementContext& ctx) const override;

  int num_nodes() const { return static_cast<int>(nodes_.size()); }
  /// The lattice this element stands for (members in the order of member_axial_forces).
  const TrussGeometry& geometry() const { return geometry_; }
  int num_members() const { return static_cast<int>(members_.size()); }
  /// Positions and orientations of the lattice nodes for end-section states (for tests, drawing
  /// and the comparison with the full model).
  void node_poses(std::span<const SlotState<double>> state, std::vector<Vec3>& p, std::vector<Mat3>& R) const;
  /// The axial force of every member (Timoshenko: E A (l - L0) / L0) at a state.
  std::vector<double> member_axial_forces(std::span<const SlotState<double>> state) const;
  /// Velocities of the lattice nodes for the end sections' velocities in `state`.
  std::vector<Vec3> node_velocities(std::span<const SlotState<double>> state) const;

  template <class S>
  void compute_residual(std::span<const SlotState<S>> s, const ElementContext& ctx, Eigen::Matrix<S, 12, 1>& r) const;
  template <class T>
  void node_map(const Vec3T<T>& r1, const Mat3T<T>& R1, const Vec3T<T>& r2, const Mat3T<T>& R2,
                std::vector<Vec3T<T>>& p, std::vector<Mat3T<T>>& R) const;
  template <class T>
  T strain_energy(const Vec3T<T>& r1, const Mat3T<T>& R1, const Vec3T<T>& r2, const Mat3T<T>& R2) const;
  /// Strain energy of members [first, last) at the node poses p, R of node_map.
  template <class T>
  T member_energy(const std::vector<Vec3T<T>>& p, const std::vector<Mat3T<T>>& R, int first, int last) const;

 private:
  struct NodeData {
    int end = 0;          ///< 1 or 2 for end-section nodes, 0 for internal nodes
    Vec3 offset;          ///< end nodes: position relative to the end's reference point (truss frame)
    int main_beam = -1;   ///< internal nodes
    double xi = 0.0;      ///< internal nodes: parameter along the main beam
  };
  struct MainBeamData {
    int start = -1, end = -1;  ///< end-section nodes
    Vec3 direction;            ///< a_m, undeformed, truss frame
    double length = 0.0;
    Mat3 frame;                ///< the main beam's frame in the truss frame (internal nodes')
    std::vector<int> internal;  ///< its internal nodes
  };
  struct MemberData {
    int a = -1, b = -1;
    Mat3 offset_a, offset_b;  ///< member frame in the node frames (rigid connection)
    std::shared_ptr<TimoshenkoBeam> beam;
    double mass = 0.0;
    Vec3 rotary = Vec3::Zero();  ///< lumped rotary inertia per end, member frame
  };
  struct MassPair {
    int a, b;
    double m;
  };

  /// Node velocity Jacobians in closed form: pd_n = Jp_n dq_e, w_n = Jw_n dq_e (dq_e = [v1, w1,
  /// v2, w2]); internal nodes through the Hermite coordinates and the Cardan angle rates.
  template <class S>
  void node_jacobians(std::span<const SlotState<S>> s, std::vector<Eigen::Matrix<S, 3, 12>>& Jp,
                      std::vector<Eigen::Matrix<S, 3, 12>>& Jw) const;
  template <class S>
  void node_kinematics(std::span<const SlotState<S>> s, const Vec3T<S>& v1, const Vec3T<S>& w1, const Vec3T<S>& v2,
                       const Vec3T<S>& w2, const Vec3T<S>& a1, const Vec3T<S>& dw1, const Vec3T<S>& a2,
                       const Vec3T<S>& dw2, std::vector<Vec3T<S>>* p, std::vector<Vec3T<S>>& pd,
                       std::vector<Vec3T<S>>* pdd, std::vector<Vec3T<S>>& w, std::vector<Vec3T<S>>* dw) const;

  TrussSectionSpec spec_;
  TrussGeometry geometry_;
  std::vector<NodeData> nodes_;
  std::vector<Mat3> node_frames_;  ///< undeformed node frames in the truss frame
  std::vector<MainBeamData> main_beams_;
  std::vector<MemberData> members_;
  std::vector<MassPair> mass_pairs_;   ///< translational mass couplings, summed over members
  std::vector<Mat3> node_rotary_;      ///< lumped rotary inertia per node, node frame
  std::vector<double> node_weight_;    ///< mass whose weight acts at each node
};

// ---------------------------------------------------------------------------------------------

template <class T>
void SuperTrussElement::node_map(const Vec3T<T>& r1, const Mat3T<T>& R1, const Vec3T<T>& r2, const Mat3T<T>& R2,
                                 std::vector<Vec3T<T>>& p, std::vector<Mat3T<T>>& R) const {
  using std::atan2;
  using std::sqrt;
  p.resize(nodes_.size());
  R.resize(nodes_.size());
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    const NodeData& nd = nodes_[n];
    if (nd.end == 0) continue;
    const Mat3T<T>& Ri = nd.end == 1 ? R1 : R2;
    p[n] = (nd.end == 1 ? r1 : r2) + Ri * nd.offset;
    R[n] = Ri;
  }
  for (std::size_t b = 0; b < main_beams_.size(); ++b) {
    const MainBeamData& mb = main_beams_[b];
    const Vec3T<T> X0 = p[mb.start], X2 = p[mb.end];
    const Vec3T<T> X1 = R1 * (mb.direction * mb.length), X3 = R2 * (mb.direction * mb.length);
    const Mat3T<T> A = R1 * mb.frame, B = R2 * mb.frame;
    const Mat3T<T> C12 = A.transpose() * B;
    const T phi12 = atan2(C12(2, 1), C12(2, 2));
    for (int n : mb.internal) {
      const double x = nodes_[n].xi, x2 = x * x, x3 = x2 * x;
      p[n] = X0 * (1 - 3 * x2 + 2 * x3) + X1 * (x - 2 * x2 + x3) + X2 * (3 * x2 - 2 * x3) + X3 * (x3 - x2);
      // Only the tangent's direction enters the Cardan angles: dr/dxi will do.
      const Vec3T<T> rp = X0 * (-6 * x + 6 * x2) + X1 * (1 - 4 * x + 3 * x2) + X2 * (6 * x - 6 * x2) + X3 * (3 * x2 - 2 * x);
      const Vec3T<T> m = A.transpose() * rp;
      const T psi = atan2(-m(2), sqrt(m(0) * m(0) + m(1) * m(1)));
      const T theta = atan2(m(1), m(0));
      R[n] = A * rotation_z<T>(theta) * rotation_y<T>(psi) * rotation_x<T>(phi12 * x);
    }
  }
}

template <class T>
T SuperTrussElement::strain_energy(const Vec3T<T>& r1, const Mat3T<T>& R1, const Vec3T<T>& r2, const Mat3T<T>& R2) const {
  std::vector<Vec3T<T>> p;
  std::vector<Mat3T<T>> R;
  node_map<T>(r1, R1, r2, R2, p, R);
  return member_energy<T>(p, R, 0, static_cast<int>(members_.size()));
}

template <class T>
T SuperTrussElement::member_energy(const std::vector<Vec3T<T>>& p, const std::vector<Mat3T<T>>& R, int first,
                                   int last) const {
  T U(0.0);
  for (int k = first; k < last; ++k) {
    const MemberData& m = members_[k];
    U += m.beam->strain_energy<T>(Vec3T<T>(p[m.b] - p[m.a]), Mat3T<T>(R[m.a] * m.offset_a), Mat3T<T>(R[m.b] * m.offset_b));
  }
  return U;
}

// Node velocities (and, when asked, positions, accelerations and angular accelerations) from
// time jets of the map through the end sections' motion.
template <class S>
void SuperTrussElement::node_kinematics(std::span<const SlotState<S>> s, const Vec3T<S>& v1, const Vec3T<S>& w1,
                                        const Vec3T<S>& v2, const Vec3T<S>& w2, const Vec3T<S>& a1, const Vec3T<S>& dw1,
                                        const Vec3T<S>& a2, const Vec3T<S>& dw2, std::vector<Vec3T<S>>* p,
                                        std::vector<Vec3T<S>>& pd, std::vector<Vec3T<S>>* pdd,
                                        std::vector<Vec3T<S>>& w, std::vector<Vec3T<S>>* dw) const {
  using J = Jet<S>;
  Vec3T<J> r1, r2;
  for (int i = 0; i < 3; ++i) {
    r1(i) = J(s[0].pos(i), v1(i), a1(i));
    r2(i) = J(s[2].pos(i), v2(i), a2(i));
  }
  const Mat3T<J> R1 = rotation_jet<S>(s[1].rot, w1, dw1), R2 = rotation_jet<S>(s[3].rot, w2, dw2);
  std::vector<Vec3T<J>> pj;
  std::vector<Mat3T<J>> Rj;
  node_map<J>(r1, R1, r2, R2, pj, Rj);
  const std::size_t nn = nodes_.size();
  pd.resize(nn);
  w.resize(nn);
  if (p) p->resize(nn);
  if (pdd) pdd->resize(nn);
  if (dw) dw->resize(nn);
  for (std::size_t n = 0; n < nn; ++n) {
    for (int i = 0; i < 3; ++i) {
      pd[n](i) = pj[n](i).dx;
      if (p) (*p)[n](i) = pj[n](i).x;
      if (pdd) (*pdd)[n](i) = pj[n](i).ddx;
    }
    Vec3T<S> ww, dww;
    body_rates<S>(Rj[n], ww, dww);
    w[n] = ww;
    if (dw) (*dw)[n] = dww;
  }
}

// Inertia and gravity: r = sum_n Jp_n^T (sum_n' M_nn' a_n' - m_n g) + Jw_n^T (J_n dw_n + w_n x J_n w_n),
// with the Jacobians' columns the node velocities for unit end-section velocities.
template <class S>
void SuperTrussElement::compute_residual(std::span<const SlotState<S>> s, const ElementContext& ctx,
                                         Eigen::Matrix<S, 12, 1>& r) const {
  const std::size_t nn = nodes_.size();
  std::vector<Vec3T<S>> p, pd, pdd, w, dw;
  node_kinematics<S>(s, s[0].vel, s[1].vel, s[2].vel, s[3].vel, s[0].acc, s[1].acc, s[2].acc, s[3].acc, &p, pd, &pdd,
                     w, &dw);
  // Generalized node forces: translational (inertia minus weight) and rotational.
  std::vector<Vec3T<S>> f(nn, Vec3T<S>::Zero()), tau(nn);
  for (std::size_t n = 0; n < nn; ++n) {
    f[n] = -cast_to<S>(Vec3(node_weight_[n] * ctx.gravity));
    const Mat3T<S> Jn = cast_to<S>(node_rotary_[n]);
    tau[n] = Jn * dw[n] + w[n].cross(Jn * w[n]);
  }
  for (const MassPair& mp : mass_pairs_) f[mp.a] += pdd[mp.b] * S(mp.m);
  // Project with the velocity Jacobians (virtual power, 3-97..3-102).
  std::vector<Eigen::Matrix<S, 3, 12>> Jp, Jw;
  node_jacobians<S>(s, Jp, Jw);
  r.setZero();
  for (std::size_t n = 0; n < nn; ++n) r += Jp[n].transpose() * f[n] + Jw[n].transpose() * tau[n];
}

template <class S>
void SuperTrussElement::node_jacobians(std::span<const SlotState<S>> s, std::vector<Eigen::Matrix<S, 3, 12>>& Jp,
                                       std::vector<Eigen::Matrix<S, 3, 12>>& Jw) const {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  using Block = Eigen::Matrix<S, 3, 12>;
  const Mat3T<S>& R1 = s[1].rot;
  const Mat3T<S>& R2 = s[3].rot;
  const Mat3T<S> I = Mat3T<S>::Identity();
  auto skew_s = [](const Vec3T<S>& v) { return skew(v); };
  Jp.assign(nodes_.size(), Block::Zero());
  Jw.assign(nodes_.size(), Block::Zero());
  // End nodes ride on their end frame: pd = v_i + R_i (w_i x s) = v_i - R_i skew(s) w_i.
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    const NodeData& nd = nodes_[n];
    if (nd.end == 0) continue;
    const int c = nd.end == 1 ? 0 : 6;
    const Mat3T<S>& Ri = nd.end == 1 ? R1 : R2;
    Jp[n].template block<3, 3>(0, c) = I;
    Jp[n].template block<3, 3>(0, c + 3) = -Ri * skew_s(cast_to<S>(nd.offset));
    Jw[n].template block<3, 3>(0, c + 3) = I;
  }
  for (const MainBeamData& mb : main_beams_) {
    // Hermite coordinates X0..X3 and their velocity Jacobians.
    const Vec3T<S> a = cast_to<S>(Vec3(mb.direction * mb.length));
    const Mat3T<S> F = cast_to<S>(mb.frame);
    const Vec3T<S> X0 = s[0].pos + R1 * cast_to<S>(nodes_[mb.start].offset);
    const Vec3T<S> X2 = s[2].pos + R2 * cast_to<S>(nodes_[mb.end].offset);
    const Vec3T<S> X1 = R1 * a, X3 = R2 * a;
    Block dX0 = Jp[mb.start], dX2 = Jp[mb.end], dX1 = Block::Zero(), dX3 = Block::Zero();
    dX1.template block<3, 3>(0, 3) = -R1 * skew_s(a);
    dX3.template block<3, 3>(0, 9) = -R2 * skew_s(a);
    const Mat3T<S> A = R1 * F, B = R2 * F;
    const Mat3T<S> C12 = A.transpose() * B;
    // d(phi12)/dq_e from C12' = -skew(wA) C12 + C12 skew(wB), wA = F^T w1, wB = F^T w2.
    const S c21 = C12(2, 1), c22 = C12(2, 2), q = c21 * c21 + c22 * c22;
    Eigen::Matrix<S, 1, 12> dphi12 = Eigen::Matrix<S, 1, 12>::Zero();
    for (int l = 0; l < 3; ++l) {
      const Mat3T<S> Sl = skew_s(Vec3T<S>::Unit(l));
      const Mat3T<S> dA = -Sl * C12, dB = C12 * Sl;  // per unit wA_l, wB_l
      const S gA = (c22 * dA(2, 1) - c21 * dA(2, 2)) / q, gB = (c22 * dB(2, 1) - c21 * dB(2, 2)) / q;
      for (int k = 0; k < 3; ++k) {
        dphi12(3 + k) += gA * F(k, l);  // wA = F^T w1: d/dw1_k = sum_l d/dwA_l F(k, l)
        dphi12(9 + k) += gB * F(k, l);
      }
    }
    const S phi12 = atan2(c21, c22);
    for (int n : mb.internal) {
      const double x = nodes_[n].xi, x2 = x * x, x3 = x2 * x;
      const double h0 = 1 - 3 * x2 + 2 * x3, h1 = x - 2 * x2 + x3, h2 = 3 * x2 - 2 * x3, h3 = x3 - x2;
      const double g0 = -6 * x + 6 * x2, g1 = 1 - 4 * x + 3 * x2, g2 = 6 * x - 6 * x2, g3 = 3 * x2 - 2 * x;
      Jp[n] = dX0 * S(h0) + dX1 * S(h1) + dX2 * S(h2) + dX3 * S(h3);
      const Vec3T<S> rp = X0 * S(g0) + X1 * S(g1) + X2 * S(g2) + X3 * S(g3);
      const Block D = dX0 * S(g0) + dX1 * S(g1) + dX2 * S(g2) + dX3 * S(g3);
      const Vec3T<S> m = A.transpose() * rp;
      // m' = A^T rp' + m x wA.
      Block E1 = Block::Zero();
      E1.template block<3, 3>(0, 3) = F.transpose();
      const Block dm = A.transpose() * D + skew_s(m) * E1;
      const S rho2 = m(0) * m(0) + m(1) * m(1), rho = sqrt(rho2), mm = rho2 + m(2) * m(2);
      const Eigen::Matrix<S, 1, 3> gtheta(-m(1) / rho2, m(0) / rho2, S(0.0));
      const Eigen::Matrix<S, 1, 3> gpsi(m(2) * m(0) / (rho * mm), m(2) * m(1) / (rho * mm), -rho / mm);
      const S psi = atan2(-m(2), rho), theta = atan2(m(1), m(0)), phi = phi12 * x;
      const Eigen::Matrix<S, 1, 12> dtheta = gtheta * dm, dpsi = gpsi * dm, dphi = dphi12 * S(x);
      const Mat3T<S> C = rotation_z<S>(theta) * rotation_y<S>(psi) * rotation_x<S>(phi);
      const S sf = sin(phi), cf = cos(phi), sp = sin(psi), cp = cos(psi);
      Jw[n] = C.transpose() * E1;
      Jw[n].row(0) += dphi - dtheta * sp;
      Jw[n].row(1) += dpsi * cf + dtheta * (sf * cp);
      Jw[n].row(2) += dpsi * (-sf) + dtheta * (cf * cp);
    }
  }
}

}  // namespace latticedyn
