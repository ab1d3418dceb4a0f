// The super truss element (thesis 3.5): a whole lattice section reduced to the 12 coordinates
// of its two rigid end sections; every member's virtual power is projected through the
// kinematic map from the end sections to the lattice nodes.
#pragma once

#include "core/pack.hpp"
#include "elements/super_truss_map.hpp"
#include "elements/timoshenko_beam.hpp"

#include <memory>
#include <vector>

namespace latticedyn {

/// Slots: [translation 1, rotation 1, translation 2, rotation 2], the reference points of the two
/// end sections (on the truss axis at x = 0 and x = L) and the truss frame there (x along the
/// truss); the kinematic map is SuperTrussMap's. Every member is a co-rotational Timoshenko beam
/// rigidly connected to its two nodes.
///
/// Everything in closed form but the second derivatives of the internal nodes' Cardan angles:
/// - elastic force: each member's closed-form force (corotational_force) at its nodes, projected
///   with the node Jacobians, r = sum_n Jp_n^T F_n + Jw_n^T M_n (virtual power);
/// - elastic tangent by the member chain rule: P_m^T K_m P_m per member (P_m its 9 variables'
///   Jacobian in the 12 coordinates) plus the map's second derivatives against the node forces;
/// - translational inertia: the members' consistent mass at the nodes, and since every node
///   position is affine in the end frames (AffinePoint), the whole lattice's translational mass
///   is that of two coupled rigid bodies: its 8 x 8 moment matrix sum m_ab z_a z_b^T (z the
///   points' coefficients) replaces the node pairs, exactly (3-97..3-102);
/// - rotary inertia: the members' lumped rotary inertia at the nodes; rigid on the end sections,
///   through the Cardan angles' rates on the internal nodes.
class SuperTrussElement final : public Element {
 public:
  static constexpr std::array<SlotKind, 4> kSlots = {SlotKind::translation, SlotKind::rotation,
                                                      SlotKind::translation, SlotKind::rotation};

  SuperTrussElement(const TrussSectionSpec& spec, const TrussGeometry& geometry);

  std::string_view type_name() const override { return "super_truss"; }
  bool expensive() const override { return true; }
  std::span<const SlotKind> slots() const override { return kSlots; }
  void residual(std::span<const SlotState<double>> state, const ElementContext& ctx,
                Eigen::Ref<VecX> r) const override;
  void tangents(std::span<const SlotState<double>> state, const ElementContext& ctx,
                ElementTangents& out) const override;
  ElementEnergy energy(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  /// The truss axis (the members are drawn by axis_polylines).
  std::vector<Vec3> axis_points(std::span<const SlotState<double>> state, const ElementContext& ctx) const override;
  std::vector<double> polyline_axial_forces(std::span<const SlotState<double>> state,
                                            const ElementContext&) const override {
    return member_axial_forces(state);
  }
  std::vector<std::vector<Vec3>> axis_polylines(std::span<const SlotState<double>> state,
                                                const ElementContext& ctx) const override;
  /// Energy, the members' axes and axial forces from one evaluation of the node poses and of each
  /// member's co-rotational frame.
  void output(std::span<const SlotState<double>> state, const ElementContext& ctx, ElementOutput& out) const override;

  const SuperTrussMap& map() const { return map_; }
  int num_nodes() const { return map_.num_nodes(); }
  /// The lattice this element stands for (members in the order of member_axial_forces).
  const TrussGeometry& geometry() const { return geometry_; }
  const TrussSectionSpec& spec() const { return spec_; }
  int num_members() const { return static_cast<int>(members_.size()); }
  /// Positions and orientations of the lattice nodes for end-section states (for tests, drawing
  /// and the comparison with the full model).
  void node_poses(std::span<const SlotState<double>> state, std::vector<Vec3>& p, std::vector<Mat3>& R) const;
  /// The axial force of every member (Timoshenko: E A (l - L0) / L0) at a state.
  std::vector<double> member_axial_forces(std::span<const SlotState<double>> state) const;
  /// Velocities of the lattice nodes for the end sections' velocities in `state`.
  std::vector<Vec3> node_velocities(std::span<const SlotState<double>> state) const;

  /// The lumped mass of the lattice nodes, as the members give it: translational couplings
  /// (a, b, m) (consistent mass, symmetric: both (a, b) and (b, a)), rotary inertia per node in
  /// the node's frame, and the mass whose weight acts at each node.
  struct LumpedMass {
    struct Pair {
      int a, b;
      double m;
    };
    std::vector<Pair> pairs;
    std::vector<Mat3> rotary;
    std::vector<double> weight;
  };
  const LumpedMass& lumped_mass() const { return lumped_; }
  /// A member: its nodes, its frame in the node frames (rigid connection) and its beam.
  struct Member {
    int a = -1, b = -1;
    Mat3 offset_a, offset_b;
    std::shared_ptr<TimoshenkoBeam> beam;
  };
  const std::vector<Member>& members() const { return members_; }

 private:
  struct Evaluation;
  struct MemberLoads;
  void evaluate(std::span<const SlotState<double>> s, const ElementContext& ctx, Vec12& r, ElementTangents* t) const;
  /// The material's Rayleigh damping: beta as Kelvin-Voigt damping of every member's co-rotated
  /// deformation, alpha times M(q) v as the derivative of alpha times the kinetic energy's
  /// quadratic forms (kinetic_form_), the rates through the map (node poses by automatic
  /// differentiation in the 12 coordinates: exact, but a damped super truss costs several times
  /// an undamped one).
  void add_damping(std::span<const SlotState<double>> s, const ElementContext& ctx, Vec12& r, ElementTangents* t) const;
  /// Hands each set of damped measures (as numbers of Seeds, seeded once) with its damping
  /// matrix to add(e, Cd).
  template <class Seeds, class Add>
  void damping_measures(std::span<const SlotState<double>> s, Seeds& ad, Add&& add) const;
  /// The members of batches [first, last), four at a time: their forces on the nodes and, with
  /// tangent, their stiffness projected with the node Jacobians.
  void add_members(const Evaluation& kinematics, int first, int last, MemberLoads& out, bool tangent) const;
  struct LocalTangents {
    Mat12 K, C, M;
  };
  void add_translational_inertia(std::span<const SlotState<double>> s, const ElementContext& ctx, Vec12& r,
                                 LocalTangents* t) const;

  TrussSectionSpec spec_;
  TrussGeometry geometry_;
  SuperTrussMap map_;
  std::vector<Member> members_;
  /// Members in fours, evaluated together (the last batch padded with stiffless copies of its first).
  struct MemberBatch {
    int count = 0;
    int a[Pack4::kLanes], b[Pack4::kLanes];
    CorotationalStiffnessT<Pack4> stiffness;
    Mat3T<Pack4> offset_a, offset_b;
  };
  std::vector<MemberBatch> batches_;
  /// A batch's first ends r1, chords d = r_b - r_a and member end frames from node poses.
  static void gather(const std::vector<Vec3>& p, const std::vector<Mat3>& R, const MemberBatch& bt, Vec3T<Pack4>& r1,
                     Vec3T<Pack4>& d, Mat3T<Pack4>& R1, Mat3T<Pack4>& R2);
  LumpedMass lumped_;
  // Translational mass as 8 point pairs (unit point k, row k of the moment matrix) and the weight
  // as one point; rotary inertia of each end section's nodes, in the end frame.
  std::vector<std::pair<AffinePoint, AffinePoint>> mass_points_;
  AffinePoint weight_point_;
  Mat3 end_rotary_[2] = {Mat3::Zero(), Mat3::Zero()};
  /// The kinetic energy's quadratic forms (add_damping): over the 8 basis points' rates (24), and
  /// over each internal node frame's columns (9), in map_.internal_nodes() order.
  MatX kinetic_form_;
  std::vector<MatX> internal_kinetic_form_;
};

}  // namespace latticedyn
