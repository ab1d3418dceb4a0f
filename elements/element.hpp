// The element contract: an element maps the kinematic state of its DoF slots to a local residual
// r = M(q) dq_dot + F(q, dq) and its tangents; it never sees global numbering, PETSc or MPI.
#pragma once

#include "core/types.hpp"
#include "elements/section_stress.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace latticedyn {

/// What a DoF slot of an element is: a point position (3), a frame orientation (3, perturbed
/// on the right by a body-frame rotation vector), one scalar coordinate, or a free 3-vector
/// that is not a point (the slope r' of a rope's absolute nodal coordinates).
enum class SlotKind : std::uint8_t { translation, rotation, scalar, vector };

constexpr int slot_size(SlotKind k) { return k == SlotKind::scalar ? 1 : 3; }

/// Kinematic state of one slot in the thesis's velocity variables dq = [r_dot, B omega]:
///   translation: pos = r, vel = r_dot, acc = r_ddot (inertial frame);
///   rotation:    rot = R (slot frame -> inertial), vel = omega, acc = omega_dot (slot frame);
///   scalar:      pos(0), vel(0), acc(0);
///   vector:      pos = the vector, vel, acc its rates (like a translation, but not a point).
/// Fields a kind does not use are left alone.
template <class S>
struct SlotState {
  Vec3T<S> pos = Vec3T<S>::Zero();
  Mat3T<S> rot = Mat3T<S>::Identity();
  Vec3T<S> vel = Vec3T<S>::Zero();
  Vec3T<S> acc = Vec3T<S>::Zero();
};

/// Global inputs of an element evaluation: gravity (already scaled by any load ramp) and time.
struct ElementContext {
  Vec3 gravity = Vec3::Zero();
  double time = 0.0;
  /// Tangents at rest: every slot's rate is zero and only K is wanted (statics without
  /// regularization). Elements may then skip the terms that need rates and leave C and M zero.
  bool at_rest = false;
};

struct ElementEnergy {
  double kinetic = 0.0;
  double gravity_potential = 0.0;  ///< -integral of rho g . r over the element
  double strain = 0.0;             ///< elastic energy plus any acceleration-like stored energy
  double fluid = 0.0;              ///< compressed oil of hydraulic volumes, V p^2 / (2 beta)
};

/// Power an element exchanges at a state (W), for a run's energy account (EnergyLedger).
struct ElementPower {
  double supplied = 0.0;     ///< brought in from outside the model (a pump's p Q)
  double dissipated = 0.0;   ///< turned into heat (throttling, friction, leakage, end stop damping)
  /// Flowing into compressed oil: p V p_dot / beta over the element's volumes. Integrated over a
  /// run it is the oil's energy change only to O(p / beta): the pressure build-up equation
  /// treats V / beta as constant in the compression term.
  double compression = 0.0;
};

/// What the results record of an element at one output time.
struct ElementOutput {
  ElementEnergy energy;
  std::optional<double> axial_force;           ///< bar-like elements (tension positive)
  std::vector<std::vector<Vec3>> polylines;    ///< axis_polylines
  std::vector<double> polyline_axial_forces;   ///< empty: every polyline drawn with axial_force
  /// Section forces and stresses of each member the element stands for: one for a beam or a bar,
  /// one per polyline of a super truss (in their order); empty for elements that are no member.
  std::vector<MemberStress> members;
};

/// The most elements one batched evaluation takes (the lanes of core/pack.hpp's Pack4).
inline constexpr int kMaxElementBatch = 4;

/// Residual and tangents in the slots' velocity variables, r = M dq_dot + F (thesis C-6, C-87):
/// K = dr/dq (rotations perturbed as R exp(skew(dtheta))), C = dr/d(dq), M = dr/d(dq_dot).
struct ElementTangents {
  VecX residual;
  MatX K, C, M;
  void resize(int n) {
    residual.resize(n);
    K.resize(n, n);
    C.resize(n, n);
    M.resize(n, n);
  }
};

class Element {
 public:
  virtual ~Element() = default;

  virtual std::string_view type_name() const = 0;
  /// Whether one evaluation takes microseconds or more (AD tangents of beams, the super truss's
  /// member loop): such elements are worth handing to another thread; strut ties are not.
  virtual bool expensive() const { return false; }
  /// Kinds of the DoF slots, in the order of the local residual.
  virtual std::span<const SlotKind> slots() const = 0;
  int num_dofs() const;

  virtual void residual(std::span<const SlotState<double>> state, const ElementContext& ctx,
                        Eigen::Ref<VecX> r) const = 0;
  virtual void tangents(std::span<const SlotState<double>> state, const ElementContext& ctx,
                        ElementTangents& out) const = 0;
  virtual ElementEnergy energy(std::span<const SlotState<double>> state,
                               const ElementContext& ctx) const = 0;

  /// Up to how many elements of this type one *_batch call evaluates together (one kernel on
  /// SIMD lanes); 1: none. The assembler hands consecutive elements of one type to the first's
  /// residual_batch / tangents_batch, at most batch_size() and kMaxElementBatch of them.
  virtual int batch_size() const { return 1; }
  /// residual / tangents of elements[k] (each of this element's dynamic type) at states[k] into
  /// out[k], the same as the single evaluations up to round-off; by default one by one.
  virtual void residual_batch(std::span<const Element* const> elements,
                              std::span<const std::span<const SlotState<double>>> states, const ElementContext& ctx,
                              std::span<VecX> out) const;
  virtual void tangents_batch(std::span<const Element* const> elements,
                              std::span<const std::span<const SlotState<double>>> states, const ElementContext& ctx,
                              std::span<ElementTangents> out) const;

  /// Axial force of a bar-like element (tension positive), for output; none by default.
  virtual std::optional<double> axial_force(std::span<const SlotState<double>> /*state*/,
                                            const ElementContext& /*ctx*/) const {
    return std::nullopt;
  }
  /// Power the element exchanges with the outside, heat and compressed oil (hydraulic elements).
  /// None by default: inertia, gravity and elasticity only store energy, which energy() counts;
  /// mechanical damping and drives are not itemized (they show as a ledger's imbalance).
  virtual ElementPower power(std::span<const SlotState<double>> /*state*/, const ElementContext& /*ctx*/) const {
    return {};
  }
  /// Names of the volume flows the element passes, for the results' flow columns; none by default.
  virtual std::span<const std::string> flow_names() const { return {}; }
  /// The flows named by flow_names() at a state (m^3/s, in their order) into `out`, which has
  /// their size.
  virtual void flows(std::span<const SlotState<double>> /*state*/, const ElementContext& /*ctx*/,
                     std::span<double> /*out*/) const {}
  /// Points along the element's axis for drawing it as a polyline; rigid bodies return none
  /// (they are drawn through their joints).
  virtual std::vector<Vec3> axis_points(std::span<const SlotState<double>> state, const ElementContext& ctx) const;
  /// Several polylines for elements that stand for many members (a super truss); by default the
  /// one polyline of axis_points.
  virtual std::vector<std::vector<Vec3>> axis_polylines(std::span<const SlotState<double>> state,
                                                        const ElementContext& ctx) const {
    return {axis_points(state, ctx)};
  }
  /// Axial force of each polyline of axis_polylines (tension positive), for elements that stand
  /// for many bars; empty (the default) draws every polyline with axial_force.
  virtual std::vector<double> polyline_axial_forces(std::span<const SlotState<double>> /*state*/,
                                                    const ElementContext& /*ctx*/) const {
    return {};
  }
  /// All of ElementOutput in one evaluation, into `out` (its vectors keep their capacity from call
  /// to call). By default from energy(), axial_force(), axis_polylines() and
  /// polyline_axial_forces(); elements whose outputs share costly work (the co-rotational frame,
  /// a super truss's node poses) compute it once.
  virtual void output(std::span<const SlotState<double>> state, const ElementContext& ctx, ElementOutput& out) const;
};

}  // namespace latticedyn
