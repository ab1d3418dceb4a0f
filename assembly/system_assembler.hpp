// Global assembly of the constrained equations of motion (4-1) into PETSc: the residual
// [M a + F - f_ext + G^T lambda ; s g] and its Jacobian in a preallocated AIJ matrix whose nonzero
// pattern never changes, evaluated by each rank for its own elements, loads and constraints.
#pragma once

#include "assembly/block_kinematics.hpp"
#include "assembly/dof_map.hpp"
#include "assembly/element_term.hpp"
#include "assembly/evaluation_settings.hpp"
#include "assembly/load_term.hpp"
#include "assembly/constraint_term.hpp"
#include "assembly/local_state.hpp"
#include "assembly/matrix_fill.hpp"
#include "assembly/model_state.hpp"

#include <petscmat.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace latticedyn {

/// Where to evaluate. U holds coordinates and multipliers; V, A their first and second rates in
/// the chosen parametrisation (null = zero). Uc is the state at which the constraint rows are
/// evaluated and from which the multipliers are read (generalized-alpha: the end of the step);
/// null means U.
inline constexpr const char* kMultiplierRows = "latticedyn_multiplier_rows";
inline constexpr const char* kUnstiffenedRows = "latticedyn_unstiffened_rows";

class SystemAssembler {
 public:
  SystemAssembler(const Model& model, MPI_Comm comm);
  ~SystemAssembler();
  SystemAssembler(const SystemAssembler&) = delete;
  SystemAssembler& operator=(const SystemAssembler&) = delete;

  const Model& model() const { return model_; }
  const DofMap& dofs() const { return dofs_; }
  MPI_Comm comm() const { return comm_; }

  /// Takes up new values of the held blocks (DofBlock::held: fixed, moving at velocity0), whose
  /// state is otherwise set once, like every fixed block's. Call after changing them in the model.
  void refresh_held_blocks();
  PetscErrorCode create_vector(Vec* v) const;
  /// AIJ matrix with the exact nonzero pattern; inserting outside it is an error. With
  /// block_size > 1 (only where uniform_blocks(block_size)), a BAIJ matrix of that block size: its
  /// LU works on dense blocks (a 640-bay lattice factors in 0.6 of the time in 3 x 3 blocks, in
  /// 0.9 of that again in each node's 6 x 6).
  PetscErrorCode create_matrix(Mat* m, int block_size = 1) const;
  /// Whether the unknowns fall into aligned groups of block_size DoFs, on every rank, each group
  /// whole blocks coupled to one another (no multipliers): blocks of 3 for 3, a node's translation
  /// and rotation side by side for 6. The condition for create_matrix's BAIJ format.
  bool uniform_blocks(int block_size) const;
  /// Initial coordinates and rates (rotation-vector rates) from the model; multipliers zero.
  PetscErrorCode initial_state(Vec U, Vec V) const;

  /// F = residual; `finite` (collective) is false when any entry is NaN or infinite, which
  /// includes an element evaluated outside its domain (evaluation_error).
  PetscErrorCode residual(const EvaluationPoint& at, const EvaluationSettings& how, Vec F, PetscBool* finite);
  /// What the last residual or Jacobian met outside an element's domain on this rank (a rope's
  /// rest length through zero: the element's std::domain_error), empty if nothing; that
  /// element's entries are NaN then.
  const std::string& evaluation_error() const { return errors_.text(); }
  /// J = cq dF/dU + cv dF/dV + ca dF/dA; multiplier columns enter with uc_per_u.
  PetscErrorCode jacobian(const EvaluationPoint& at, const EvaluationSettings& how, double cq, double cv,
                          double ca, Mat J);

  /// Rescales rotation vectors with |phi| > pi to the same rotation with |phi| <= pi. Rotation-
  /// vector rates in V are mapped so that omega is unchanged; velocity variables need no change
  /// (V may then be null). Collective.
  PetscErrorCode rescale_rotations(Vec U, Vec V, Parametrization param, PetscBool* changed) const;
  /// Converts rotation-vector rates to velocity variables (omega) and back, in place.
  PetscErrorCode rates_to_velocities(Vec U, Vec V) const;
  PetscErrorCode velocities_to_rates(Vec U, Vec V) const;

  /// Largest |g| over all constraints at U and time t, and the constraint where it occurs
  /// (-1 without constraints). Collective; every rank gets the result.
  PetscErrorCode max_constraint_violation(Vec U, double t, double* value, int* constraint);

  /// Constraint values at (U, V, t) into `out`'s multiplier rows, zero on every other row: g, or
  /// with `rates` g_dot = G v + g_t (V in rotation-vector rates). For projecting a state onto the
  /// constraint manifold (implicit Runge-Kutta route). Collective.
  PetscErrorCode constraint_values(Vec U, Vec V, double t, bool rates, Vec out);

  /// Gathers the state to rank 0 and loads it into `state` there (other ranks: untouched), or
  /// with `everywhere` to every rank (a results writer shared by the ranks). Collective.
  PetscErrorCode gather(double t, Vec U, Vec V, Vec A, Parametrization param, ModelState* state,
                        bool everywhere = false);
  /// Gathers X (a vector of the system's layout) to rank 0 in model order (DofMap::to_model_order),
  /// the same on any number of ranks; other ranks get an empty vector unless `everywhere`.
  /// Collective.
  PetscErrorCode gather_in_model_order(Vec X, std::vector<double>* ordered, bool everywhere = false);

  /// Typical diagonal mass and stiffness at the initial state, for scaling constraint rows.
  double characteristic_mass() const { return mass_scale_; }
  double characteristic_stiffness() const { return stiffness_scale_; }
  /// The model's loads as one force: the 2-norm of its weight, node by node, and its nodal forces
  /// (at full scale); without either, the characteristic mass times 1 m/s^2.
  double characteristic_load() const { return load_scale_; }
  /// Size of the model: the diagonal of the box around its initial translation coordinates.
  double characteristic_length() const { return length_scale_; }
  /// The residual's round-off floor, as an absolute force: a stiffness k moves forces by about
  /// k eps L when coordinates of size L carry round-off eps, and n such rows add in quadrature to
  /// a norm sqrt(n) times that (lattice-bays, observed: 2e-5 N at 240 unknowns, 1.3e-2 N at
  /// 15,360); at least 100 k eps L, which covers the sums over elements of a small model.
  double residual_floor() const {
    return std::max(100.0, 2.0 * std::sqrt(static_cast<double>(dofs_.global_size()))) *
           std::numeric_limits<double>::epsilon() * stiffness_scale_ * length_scale_;
  }

 private:
  PetscErrorCode scatter_in(const EvaluationPoint& at);
  /// Constraint c's inputs at time t on the block states of the last compute_states.
  ConstraintInputs local_constraint_inputs(int c, double t) const;
  /// The block states (and, with_chain, chain maps) of `blocks`, by default every block the rank's
  /// terms read, from the local vectors of the last scatter_in.
  PetscErrorCode compute_states(const EvaluationSettings& how, bool with_chain, double cq, double cv, double ca,
                                const std::vector<int>* blocks = nullptr);
  /// cq d(T^T y)/dphi on the diagonal block of every rotation block (y: its rows' residual in
  /// omega-variables), into J's values where rotation_fill_ knows the places, else by MatSetValues.
  PetscErrorCode add_rotation_row_derivatives(Mat J, const std::vector<Vec3>& y, double cq);
  /// Plans rotation_fill_ for J (assembled): one entry per needed rotation block, its three rows.
  PetscErrorCode plan_rotation_fill(Mat J);
  void estimate_scales();

  const Model& model_;
  MPI_Comm comm_;
  DofMap dofs_;
  int local_size_ = 0;
  Vec global_template_ = nullptr;
  Vec u_loc_ = nullptr, v_loc_ = nullptr, a_loc_ = nullptr, uc_loc_ = nullptr, r_loc_ = nullptr;
  VecScatter to_local_ = nullptr;
  VecScatter to_root_ = nullptr;  // gather() to rank 0
  Vec root_seq_ = nullptr;
  VecScatter to_all_ = nullptr;  // gather() to every rank
  Vec all_seq_ = nullptr;
  /// The scatter of gather() (made on first use) and its target.
  PetscErrorCode gather_scatter(bool everywhere, VecScatter* scatter, Vec* target);
  bool have_v_ = false, have_a_ = false, separate_uc_ = false;
  // The terms read the rank's blocks and multipliers from here; its states and chain maps are set
  // per evaluation by compute_states.
  LocalState local_;
  ElementTerm elements_;
  LoadTerm loads_;
  ConstraintTerm constraints_;
  FirstError errors_;
  std::vector<char> constrained_;  // blocks of this rank's constraints: the only users of state_c_
  std::vector<int> constraint_blocks_;  // the same as a list, for what reads constraints alone
  std::vector<Mat3> rows_T_;  // T(phi)^T per block (rotation-vector rates), identity otherwise
  std::vector<Vec3> phi_;     // rotation vectors of needed rotation blocks
  MatrixFill rotation_fill_;  // places of the rotation blocks' diagonal blocks in the Jacobian
  double mass_scale_ = 1.0;
  double stiffness_scale_ = 1.0;
  double length_scale_ = 1.0;
  double load_scale_ = 1.0;
};

}  // namespace latticedyn
