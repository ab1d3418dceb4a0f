// Global residual and Jacobian assembly. Each rank gathers the coordinates its elements, loads and
// constraints read (one VecScatter), sets the blocks' states and chain maps, lets each term
// (ElementTerm, LoadTerm, ConstraintTerm) add its part, maps rotation rows to the stored
// coordinates, and adds the result into the global vector (reverse scatter) and matrix.
#include "assembly/system_assembler.hpp"

#include "assembly/log_events.hpp"
#include "core/rotation.hpp"

#include <petscvec.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <stdexcept>

namespace latticedyn {

namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

}  // namespace

SystemAssembler::SystemAssembler(const Model& model, MPI_Comm comm)
    : model_(model), comm_(comm), dofs_(model, [&] {
        int r = 0;
        MPI_Comm_rank(comm, &r);
        return r;
      }(), [&] {
        int s = 1;
        MPI_Comm_size(comm, &s);
        return s;
      }()),
      elements_(model_, dofs_, comm_),
      loads_(model_, dofs_),
      constraints_(model_, dofs_) {
  const int nb = static_cast<int>(model_.blocks.size());
  const int nc = static_cast<int>(model_.constraints.size());
  local_.block_offset.assign(nb, -1);
  local_.multiplier_offset.assign(nc, -1);
  std::vector<PetscInt> global_index;
  for (int b : dofs_.needed_blocks()) {
    local_.block_offset[b] = static_cast<int>(global_index.size());
    for (int i = 0; i < model_.blocks[b].size(); ++i) global_index.push_back(dofs_.block_dof(b) + i);
  }
  for (int c : dofs_.local_constraints()) {
    local_.multiplier_offset[c] = static_cast<int>(global_index.size());
    for (int i = 0; i < model_.constraints[c].rows(); ++i) global_index.push_back(dofs_.multiplier_dof(c) + i);
  }
  local_size_ = static_cast<int>(global_index.size());
  PetscCallAbort(comm_, VecCreateMPI(comm_, dofs_.owned_size(), dofs_.global_size(), &global_template_));
  for (Vec* v : {&u_loc_, &v_loc_, &a_loc_, &uc_loc_, &r_loc_})
    PetscCallAbort(PETSC_COMM_SELF, VecCreateSeq(PETSC_COMM_SELF, local_size_, v));
  IS from;
  PetscCallAbort(PETSC_COMM_SELF, ISCreateGeneral(PETSC_COMM_SELF, local_size_, global_index.data(), PETSC_COPY_VALUES, &from));
  PetscCallAbort(comm_, VecScatterCreate(global_template_, from, u_loc_, nullptr, &to_local_));
  PetscCallAbort(PETSC_COMM_SELF, ISDestroy(&from));

  // Fixed blocks never change: their state is set once.
  local_.state.resize(nb);
  local_.state_c.resize(nb);
  local_.chain.resize(nb);
  local_.chain_c.resize(nb);
  rows_T_.assign(nb, Mat3::Identity());
  phi_.assign(nb, Vec3::Zero());
  for (int b = 0; b < nb; ++b) {
    block_kinematics(model_.blocks[b], nullptr, nullptr, nullptr, Parametrization::rotation_vector_rates, local_.state[b]);
    local_.state_c[b] = local_.state[b];
  }
  constrained_.assign(nb, 0);
  for (int c : dofs_.local_constraints())
    for (int b : dofs_.constraint_blocks()[c]) constrained_[b] = 1;
  for (int b = 0; b < nb; ++b)
    if (constrained_[b]) constraint_blocks_.push_back(b);
  estimate_scales();
}

void SystemAssembler::refresh_held_blocks() {
  for (std::size_t b = 0; b < model_.blocks.size(); ++b) {
    if (!model_.blocks[b].fixed || !model_.blocks[b].held) continue;
    block_kinematics(model_.blocks[b], nullptr, nullptr, nullptr, Parametrization::rotation_vector_rates, local_.state[b]);
    local_.state_c[b] = local_.state[b];
  }
}

SystemAssembler::~SystemAssembler() {
  VecScatterDestroy(&to_local_);
  VecScatterDestroy(&to_root_);
  VecScatterDestroy(&to_all_);
  for (Vec* v : {&global_template_, &u_loc_, &v_loc_, &a_loc_, &uc_loc_, &r_loc_, &root_seq_, &all_seq_}) VecDestroy(v);
}

void SystemAssembler::estimate_scales() {
  // Mean diagonal mass and stiffness of the translational DoFs at the initial state (local_.state holds
  // every block's initial state here), over all elements: the same numbers on every rank. Each rank
  // sums a contiguous share of the elements and the shares are added up: this is setup work that
  // falls with ranks (at 1e6 unknowns half of the numbering stage was these element tangents,
  // computed in full by every rank). One rank sums in the element order as before, to the bit.
  const std::size_t ne = model_.elements.size(), rank = dofs_.rank(), ranks = dofs_.size();
  const std::size_t first = ne * rank / ranks, last = ne * (rank + 1) / ranks;
  double sums[4] = {0.0, 0.0, 0.0, 0.0};  // mass, stiffness, squared weights, translational DoFs
  double &mass = sums[0], &stiffness = sums[1], &load2 = sums[2], &count = sums[3];
  const ElementContext ctx{model_.gravity, 0.0};
  ElementTangents t;
  std::vector<SlotState<double>> s;
  for (std::size_t e = first; e < last; ++e) {
    const ElementEntry& entry = model_.elements[e];
    const auto kinds = entry.element->slots();
    gather_slots(entry, local_.state, s);
    entry.element->tangents(s, ctx, t);
    int o = 0;
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      if (kinds[k] == SlotKind::translation) {
        for (int i = 0; i < 3; ++i) {
          mass += std::abs(t.M(o + i, o + i));
          stiffness += std::abs(t.K(o + i, o + i));
          ++count;
        }
        // This slot's share of the element's weight: its rows of M times gravity on every
        // translation slot.
        Vec3 weight = Vec3::Zero();
        int oj = 0;
        for (std::size_t kj = 0; kj < kinds.size(); ++kj) {
          if (kinds[kj] == SlotKind::translation) weight += t.M.block<3, 3>(o, oj) * model_.gravity;
          oj += slot_size(kinds[kj]);
        }
        load2 += weight.squaredNorm();
      }
      o += slot_size(kinds[k]);
    }
  }
  PetscCallAbort(comm_, MPI_Allreduce(MPI_IN_PLACE, sums, 4, MPI_DOUBLE, MPI_SUM, comm_));
  for (const NodalLoad& l : model_.loads) load2 += l.force.squaredNorm();
  if (count > 0) {
    mass_scale_ = mass / count;
    stiffness_scale_ = stiffness / count;
  }
  Eigen::AlignedBox3d box;
  for (const DofBlock& b : model_.blocks)
    if (b.kind == SlotKind::translation) box.extend(b.position0);
  length_scale_ = box.isEmpty() ? 1.0 : std::max(box.diagonal().norm(), 1e-3);
  if (!(mass_scale_ > 0)) mass_scale_ = 1.0;
  load_scale_ = std::sqrt(load2);
  if (!(load_scale_ > 0)) load_scale_ = mass_scale_;  // no weight, no loads: the force of 1 m/s^2
  if (!(stiffness_scale_ > 0)) stiffness_scale_ = mass_scale_ * std::max(model_.gravity.norm(), 1.0);
}

PetscErrorCode SystemAssembler::create_vector(Vec* v) const {
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(global_template_, v));
  PetscFunctionReturn(0);
}

bool SystemAssembler::uniform_blocks(int block_size) const {
  if (block_size < 1 || dofs_.num_multipliers() > 0) return false;
  for (int p = 0; p <= dofs_.size(); ++p)
    if ((p < dofs_.size() ? dofs_.begin(p) : dofs_.global_size()) % block_size != 0) return false;
  // Each group of block_size DoFs made of whole blocks coupled to one another (a node's translation
  // and rotation for 6): else the stored blocks would carry zeros the LU works through.
  const auto& graph = dofs_.block_graph();
  for (std::size_t b = 0; b < model_.blocks.size(); ++b) {
    const DofBlock& block = model_.blocks[b];
    if (block.fixed) continue;
    const int size = block.size(), group = dofs_.block_dof(static_cast<int>(b)) / block_size;
    if (block_size % size != 0) return false;
    int partners = 0;  // blocks of its group it is coupled to, itself included
    for (int c : graph[b])
      if (dofs_.block_dof(c) / block_size == group) {
        if (model_.blocks[c].size() != size) return false;
        ++partners;
      }
    if (partners != block_size / size) return false;
  }
  return true;
}

PetscErrorCode SystemAssembler::create_matrix(Mat* m, int block_size) const {
  PetscFunctionBeginUser;
  PetscCheck(block_size == 1 || uniform_blocks(block_size), comm_, PETSC_ERR_ARG_WRONG,
             "create_matrix: the unknowns do not form coupled groups of %d DoFs", block_size);
  std::vector<PetscInt> dn, on;
  if (block_size == 1) {
    std::vector<int> d, o;
    dofs_.count_nonzeros(d, o);
    dn.assign(d.begin(), d.end());
    on.assign(o.begin(), o.end());
  } else {
    // Per block row: the block columns its blocks' couplings reach (no multipliers here).
    const int lo = dofs_.owned_begin(), hi = dofs_.owned_end();
    std::vector<std::vector<int>> columns((hi - lo) / block_size);
    const auto& graph = dofs_.block_graph();
    for (std::size_t b = 0; b < model_.blocks.size(); ++b) {
      const int g = dofs_.block_dof(static_cast<int>(b));
      if (model_.blocks[b].fixed || g < lo || g >= hi) continue;
      for (int c : graph[b]) columns[(g - lo) / block_size].push_back(dofs_.block_dof(c) / block_size);
    }
    for (auto& row : columns) {
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
      const auto own = std::count_if(row.begin(), row.end(), [&](int k) { return k * block_size >= lo && k * block_size < hi; });
      dn.push_back(static_cast<PetscInt>(own));
      on.push_back(static_cast<PetscInt>(row.size() - own));
    }
  }
  PetscCall(MatCreate(comm_, m));
  PetscCall(MatSetSizes(*m, dofs_.owned_size(), dofs_.owned_size(), dofs_.global_size(), dofs_.global_size()));
  PetscCall(MatSetType(*m, block_size > 1 ? MATBAIJ : MATAIJ));
  PetscCall(MatSetFromOptions(*m));
  PetscCall(MatXAIJSetPreallocation(*m, block_size, dn.data(), on.data(), nullptr, nullptr));
  PetscCall(MatSetOption(*m, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  std::vector<char> stiffened(model_.blocks.size(), 0);
  for (const ElementEntry& e : model_.elements)
    for (const SlotBinding& s : e.slots) stiffened[s.block] = 1;
  std::vector<PetscInt> frames, multipliers;
  for (std::size_t b = 0; b < model_.blocks.size(); ++b) {
    const int g = dofs_.block_dof(static_cast<int>(b));
    if (stiffened[b] || g < dofs_.owned_begin() || g >= dofs_.owned_end()) continue;
    for (int i = 0; i < model_.blocks[b].size(); ++i) frames.push_back(g + i);
  }
  for (std::size_t c = 0; c < model_.constraints.size(); ++c) {
    const int g = dofs_.multiplier_dof(static_cast<int>(c));
    if (g < dofs_.owned_begin() || g >= dofs_.owned_end()) continue;
    for (int i = 0; i < model_.constraints[c].rows(); ++i) multipliers.push_back(g + i);
  }
  for (const auto& [name, rows] : {std::pair{kUnstiffenedRows, &frames}, std::pair{kMultiplierRows, &multipliers}}) {
    IS is;
    PetscCall(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(rows->size()), rows->data(), PETSC_COPY_VALUES, &is));
    PetscCall(PetscObjectCompose((PetscObject)*m, name, (PetscObject)is));
    PetscCall(ISDestroy(&is));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::initial_state(Vec U, Vec V) const {
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(U));
  PetscCall(VecZeroEntries(V));
  PetscScalar *u, *v;
  PetscCall(VecGetArray(U, &u));
  PetscCall(VecGetArray(V, &v));
  const int lo = dofs_.owned_begin();
  for (std::size_t b = 0; b < model_.blocks.size(); ++b) {
    const DofBlock& blk = model_.blocks[b];
    if (blk.fixed || dofs_.block_owner(static_cast<int>(b)) != dofs_.rank()) continue;
    const int g = dofs_.block_dof(static_cast<int>(b)) - lo;
    for (int i = 0; i < blk.size(); ++i) {
      // Rotation coordinates start at phi = 0, where phi_dot = T(0)^{-1} omega = omega.
      u[g + i] = blk.kind == SlotKind::rotation ? 0.0 : blk.position0(i);
      v[g + i] = blk.velocity0(i);
    }
  }
  PetscCall(VecRestoreArray(U, &u));
  PetscCall(VecRestoreArray(V, &v));
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::scatter_in(const EvaluationPoint& at) {
  PetscFunctionBeginUser;
  have_v_ = at.V != nullptr;
  have_a_ = at.A != nullptr;
  separate_uc_ = at.Uc != nullptr && at.Uc != at.U;
  const std::pair<Vec, Vec> pairs[] = {{at.U, u_loc_}, {at.V, v_loc_}, {at.A, a_loc_}, {separate_uc_ ? at.Uc : nullptr, uc_loc_}};
  for (const auto& [global, local] : pairs) {
    if (!global) continue;
    PetscCall(VecScatterBegin(to_local_, global, local, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(to_local_, global, local, INSERT_VALUES, SCATTER_FORWARD));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::compute_states(const EvaluationSettings& how, bool with_chain, double cq, double cv,
                                               double ca, const std::vector<int>* blocks) {
  const PetscScalar *u, *v = nullptr, *a = nullptr, *uc = nullptr;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(u_loc_, &u));
  if (have_v_) PetscCall(VecGetArrayRead(v_loc_, &v));
  if (have_a_) PetscCall(VecGetArrayRead(a_loc_, &a));
  if (separate_uc_) PetscCall(VecGetArrayRead(uc_loc_, &uc));
  const bool rates = how.param == Parametrization::rotation_vector_rates;
  for (int b : blocks ? *blocks : dofs_.needed_blocks()) {
    const int o = local_.offset(b);
    const DofBlock& blk = model_.blocks[b];
    block_kinematics(blk, u + o, v ? v + o : nullptr, a ? a + o : nullptr, how.param, local_.state[b],
                     with_chain ? &local_.chain[b] : nullptr, cq, cv, ca);
    // T(phi) evaluated apart from the rotation chain: taking the chain's (equal to round-off) moved
    // the static solve of the control pipeline's exported drives from 2 to 3 Newton iterations under
    // the sanitizer build, for 8 % of these states' instructions.
    if (blk.kind == SlotKind::rotation) {
      phi_[b] = Vec3(u[o], u[o + 1], u[o + 2]);
      rows_T_[b] = rates ? Mat3(tangent_operator(phi_[b]).transpose()) : Mat3::Identity();
    }
    if (!constrained_[b]) continue;  // the end-of-step state only enters constraint rows
    if (separate_uc_) {
      block_kinematics(blk, uc + o, nullptr, nullptr, how.param, local_.state_c[b], with_chain ? &local_.chain_c[b] : nullptr, cq, cv, ca);
    } else {
      local_.state_c[b] = local_.state[b];
      if (with_chain) local_.chain_c[b] = local_.chain[b];
    }
  }
  PetscCall(VecRestoreArrayRead(u_loc_, &u));
  if (have_v_) PetscCall(VecRestoreArrayRead(v_loc_, &v));
  if (have_a_) PetscCall(VecRestoreArrayRead(a_loc_, &a));
  if (separate_uc_) PetscCall(VecRestoreArrayRead(uc_loc_, &uc));
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::residual(const EvaluationPoint& at, const EvaluationSettings& how, Vec F, PetscBool* finite) {
  PetscFunctionBeginUser;
  const LogEvents& events = log_events();
  PetscCall(PetscLogEventBegin(events.block_states, 0, 0, 0, 0));
  PetscCall(scatter_in(at));
  PetscCall(compute_states(how, false, 1.0, 0.0, 0.0));
  PetscCall(PetscLogEventEnd(events.block_states, 0, 0, 0, 0));

  const PetscScalar* uc;
  PetscCall(VecGetArrayRead(separate_uc_ ? uc_loc_ : u_loc_, &uc));
  PetscScalar* r;
  PetscCall(VecZeroEntries(r_loc_));
  PetscCall(VecGetArray(r_loc_, &r));

  errors_.clear();
  PetscCall(PetscLogEventBegin(events.element_residual, 0, 0, 0, 0));
  elements_.add_residual(local_, ElementContext{how.load_scale * model_.gravity, at.t}, r, errors_);
  PetscCall(PetscLogEventEnd(events.element_residual, 0, 0, 0, 0));

  // Loads and constraints evaluated without an exception leaving (it would unwind through PETSc):
  // a failure there marks the residual not finite, as an element's does.
  PetscCall(PetscLogEventBegin(events.constraints, 0, 0, 0, 0));
  bool failed = false;
  try {
    loads_.add_residual(local_, at.t, how.load_scale, r);
    constraints_.add_residual(local_, at, how, uc, separate_uc_, r);
  } catch (...) {
    errors_.record_current_exception("loads and constraints");
    failed = true;
  }
  PetscCall(PetscLogEventEnd(events.constraints, 0, 0, 0, 0));

  // Rows of rotation blocks: from omega-variables to phi via T^T (identity for velocity variables).
  if (how.param == Parametrization::rotation_vector_rates)
    for (int b : dofs_.needed_blocks())
      if (model_.blocks[b].kind == SlotKind::rotation) {
        const int lo = local_.offset(b);
        const Vec3 rb = rows_T_[b] * Vec3(r[lo], r[lo + 1], r[lo + 2]);
        for (int i = 0; i < 3; ++i) r[lo + i] = rb(i);
      }

  PetscBool ok = failed ? PETSC_FALSE : PETSC_TRUE;
  for (int i = 0; i < local_size_ && ok; ++i)
    if (!std::isfinite(r[i])) {
      ok = PETSC_FALSE;
      break;
    }
  PetscCall(VecRestoreArray(r_loc_, &r));
  PetscCall(VecRestoreArrayRead(separate_uc_ ? uc_loc_ : u_loc_, &uc));
  PetscCall(VecZeroEntries(F));
  PetscCall(VecScatterBegin(to_local_, r_loc_, F, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(to_local_, r_loc_, F, ADD_VALUES, SCATTER_REVERSE));
  if (finite) PetscCall(MPIU_Allreduce(&ok, finite, 1, MPIU_BOOL, MPI_LAND, comm_));
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::jacobian(const EvaluationPoint& at, const EvaluationSettings& how, double cq, double cv,
                                         double ca, Mat J) {
  PetscFunctionBeginUser;
  const LogEvents& events = log_events();
  PetscCall(PetscLogEventBegin(events.block_states, 0, 0, 0, 0));
  PetscCall(scatter_in(at));
  PetscCall(compute_states(how, true, cq, cv, ca));
  PetscCall(PetscLogEventEnd(events.block_states, 0, 0, 0, 0));
  const bool rates = how.param == Parametrization::rotation_vector_rates;
  const PetscScalar* uc;
  PetscCall(VecGetArrayRead(separate_uc_ ? uc_loc_ : u_loc_, &uc));
  PetscCall(MatZeroEntries(J));

  // y: the residual in omega-variables per rotation block, for the derivative of T^T(phi) y.
  std::vector<Vec3> y(model_.blocks.size(), Vec3::Zero());
  const ElementContext ctx{how.load_scale * model_.gravity, at.t, !have_v_ && !have_a_ && cv == 0.0 && ca == 0.0};

  errors_.clear();
  PetscCall(PetscLogEventBegin(events.element_jacobian, 0, 0, 0, 0));
  // Elements' tangents go straight into the matrix's value arrays where the plan knows the
  // positions (every Jacobian after the first, on rows this rank owns), else through MatSetValues.
  const bool direct = elements_.fill_ready(J);
  PetscCall(elements_.add_jacobian(local_, ctx, cq, cv, ca, direct, J, y, errors_));
  PetscCall(PetscLogEventEnd(events.element_jacobian, 0, 0, 0, 0));

  PetscCall(PetscLogEventBegin(events.constraints, 0, 0, 0, 0));
  try {  // a failure marks the Jacobian unusable (evaluation_error), as an element's does
    PetscCall(loads_.add_jacobian(local_, at.t, how.load_scale, cq, J, y));
    PetscCall(constraints_.add_jacobian(local_, at, how, uc, cq, cv, J, y));
  } catch (...) {
    errors_.record_current_exception("loads and constraints");
  }
  PetscCall(PetscLogEventEnd(events.constraints, 0, 0, 0, 0));

  const bool rotation_rows = rates && cq != 0.0;
  PetscCall(PetscLogEventBegin(events.rotation_rows, 0, 0, 0, 0));
  if (rotation_rows) PetscCall(add_rotation_row_derivatives(J, y, cq));
  PetscCall(PetscLogEventEnd(events.rotation_rows, 0, 0, 0, 0));

  PetscCall(VecRestoreArrayRead(separate_uc_ ? uc_loc_ : u_loc_, &uc));
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  if (!direct) PetscCall(elements_.plan_fill(J));
  if (rotation_rows && !rotation_fill_.ready_for(J)) PetscCall(plan_rotation_fill(J));
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::add_rotation_row_derivatives(Mat J, const std::vector<Vec3>& y, double cq) {
  PetscFunctionBeginUser;
  // Through MatSetValues (a search per entry) these blocks took 9.4 ms of a 245,760-unknown
  // lattice's Jacobian, at the planned places 4.4 ms, the derivatives alone (-log_view LdRotationRows).
  const bool direct = rotation_fill_.ready_for(J);
  if (direct) PetscCall(rotation_fill_.begin(J));
  const PetscInt stride = rotation_fill_.column_stride();
  int entry = 0;  // the plan's entries: the needed rotation blocks in order
  for (int b : dofs_.needed_blocks()) {
    if (model_.blocks[b].kind != SlotKind::rotation) continue;
    const PetscInt* at = direct ? rotation_fill_.element_offsets(entry) : nullptr;
    ++entry;
    if (y[b].isZero(0.0)) continue;
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Y = cq * tangent_transpose_derivative(phi_[b], y[b]);
    if (at && at[0] >= 0) {
      // Entry (r, c) of the block lies `stride` per column past its row's first entry.
      for (int r = 0; r < 3; ++r) {
        double* row = rotation_fill_.values(at[r]);
        for (int c = 0; c < 3; ++c) row[stride * c] += Y(r, c);
      }
      continue;
    }
    const PetscInt g = dofs_.block_dof(b);
    const PetscInt rows[3] = {g, g + 1, g + 2};
    PetscCall(MatSetValues(J, 3, rows, 3, rows, Y.data(), ADD_VALUES));
  }
  if (direct) PetscCall(rotation_fill_.end(J));
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::plan_rotation_fill(Mat J) {
  PetscFunctionBeginUser;
  PetscCall(rotation_fill_.open(J));
  try {
    for (int b : dofs_.needed_blocks()) {
      if (model_.blocks[b].kind != SlotKind::rotation) continue;
      rotation_fill_.start_element();
      const PetscInt g = dofs_.block_dof(b);
      for (int r = 0; r < 3; ++r) rotation_fill_.add_position(g + r, g);
    }
  } catch (const std::logic_error&) {
    // A rotation block without its diagonal block in the pattern: it stays with MatSetValues,
    // which reports the missing entry if it is ever written.
    PetscCall(rotation_fill_.close());
    rotation_fill_ = MatrixFill{};
    PetscFunctionReturn(0);
  }
  PetscCall(rotation_fill_.close());
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::rescale_rotations(Vec U, Vec V, Parametrization param, PetscBool* changed) const {
  PetscFunctionBeginUser;
  const bool rates = param == Parametrization::rotation_vector_rates;
  const int lo = dofs_.owned_begin();
  std::vector<int> due;  // local offsets of rotation blocks beyond pi
  {
    const PetscScalar* ur;
    PetscCall(VecGetArrayRead(U, &ur));
    for (std::size_t b = 0; b < model_.blocks.size(); ++b) {
      const DofBlock& blk = model_.blocks[b];
      if (blk.fixed || blk.kind != SlotKind::rotation || dofs_.block_owner(static_cast<int>(b)) != dofs_.rank()) continue;
      const int g = dofs_.block_dof(static_cast<int>(b)) - lo;
      if (Vec3(ur[g], ur[g + 1], ur[g + 2]).norm() > std::numbers::pi) due.push_back(g);
    }
    PetscCall(VecRestoreArrayRead(U, &ur));
  }
  // Write access only when something changes: TS restarts the step whenever the state of the
  // solution vector changes in a post-step hook.
  PetscBool any = due.empty() ? PETSC_FALSE : PETSC_TRUE;
  PetscScalar *u = nullptr, *v = nullptr;
  if (any) {
    PetscCall(VecGetArray(U, &u));
    if (rates) PetscCall(VecGetArray(V, &v));
  }
  for (int g : due) {
    const Vec3 phi(u[g], u[g + 1], u[g + 2]);
    const Vec3 phi_new = rescaled_rotation_vector(phi);
    for (int i = 0; i < 3; ++i) u[g + i] = phi_new(i);
    if (rates) {
      const Vec3 omega = tangent_operator(phi) * Vec3(v[g], v[g + 1], v[g + 2]);
      const Vec3 rate_new = tangent_operator_inverse(phi_new) * omega;
      for (int i = 0; i < 3; ++i) v[g + i] = rate_new(i);
    }
  }
  if (any) {
    PetscCall(VecRestoreArray(U, &u));
    if (rates) PetscCall(VecRestoreArray(V, &v));
  }
  PetscCall(MPIU_Allreduce(&any, changed, 1, MPIU_BOOL, MPI_LOR, comm_));
  PetscFunctionReturn(0);
}

namespace {
template <class F>
PetscErrorCode map_rotation_rates(const Model& model, const DofMap& dofs, Vec U, Vec V, F&& f) {
  PetscFunctionBeginUser;
  const PetscScalar* u;
  PetscScalar* v;
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArray(V, &v));
  const int lo = dofs.owned_begin();
  for (std::size_t b = 0; b < model.blocks.size(); ++b) {
    const DofBlock& blk = model.blocks[b];
    if (blk.fixed || blk.kind != SlotKind::rotation || dofs.block_owner(static_cast<int>(b)) != dofs.rank()) continue;
    const int g = dofs.block_dof(static_cast<int>(b)) - lo;
    const Vec3 w = f(Vec3(u[g], u[g + 1], u[g + 2]), Vec3(v[g], v[g + 1], v[g + 2]));
    for (int i = 0; i < 3; ++i) v[g + i] = w(i);
  }
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(VecRestoreArray(V, &v));
  PetscFunctionReturn(0);
}
}  // namespace

PetscErrorCode SystemAssembler::rates_to_velocities(Vec U, Vec V) const {
  return map_rotation_rates(model_, dofs_, U, V, [](const Vec3& phi, const Vec3& rate) { return Vec3(tangent_operator(phi) * rate); });
}

PetscErrorCode SystemAssembler::velocities_to_rates(Vec U, Vec V) const {
  return map_rotation_rates(model_, dofs_, U, V, [](const Vec3& phi, const Vec3& w) { return Vec3(tangent_operator_inverse(phi) * w); });
}

ConstraintInputs SystemAssembler::local_constraint_inputs(int c, double t) const {
  const Constraint& con = model_.constraints[c];
  ConstraintInputs in;
  in.model = &model_;
  in.constraint = &con;
  in.block_state = [this](int b) -> const BlockState& { return local_.state[b]; };
  in.drive = con.drive >= 0 ? model_.drives[con.drive].evaluate(t) : DriveValue{};
  return in;
}

PetscErrorCode SystemAssembler::max_constraint_violation(Vec U, double t, double* value, int* constraint) {
  PetscFunctionBeginUser;
  *value = 0.0;
  *constraint = -1;
  // Called after every step: a model without constraints (the same on every rank, so no rank
  // leaves a collective call alone) skips the scatter and the block states, and one with
  // constraints computes only its constraints' blocks (3 % of lattice-bays' run at 640 bays).
  if (model_.constraints.empty()) PetscFunctionReturn(0);
  PetscCall(scatter_in(EvaluationPoint{U, nullptr, nullptr, nullptr, t, t}));
  EvaluationSettings how;
  PetscCall(compute_states(how, false, 1.0, 0.0, 0.0, &constraint_blocks_));
  struct {
    double value;
    int index;
  } local{-1.0, -1}, global{-1.0, -1};
  for (int c : dofs_.local_constraints()) {
    const ConstraintEval ce = evaluate_constraint(local_constraint_inputs(c, t));
    const double v = ce.g.head(ce.rows).cwiseAbs().maxCoeff();
    if (v > local.value) local = {v, c};
  }
  PetscCallMPI(MPI_Allreduce(&local, &global, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm_));
  *value = std::max(global.value, 0.0);
  *constraint = global.index;
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::constraint_values(Vec U, Vec V, double t, bool rates, Vec out) {
  PetscFunctionBeginUser;
  PetscCall(scatter_in(EvaluationPoint{U, rates ? V : nullptr, nullptr, nullptr, t, t}));
  EvaluationSettings how;
  how.param = Parametrization::rotation_vector_rates;
  PetscCall(compute_states(how, false, 1.0, 0.0, 0.0));
  PetscCall(VecZeroEntries(out));
  std::vector<PetscInt> rows;
  std::vector<PetscScalar> values;
  for (int c : dofs_.local_constraints()) {
    ConstraintInputs in = local_constraint_inputs(c, t);
    in.with_velocity_terms = rates;
    const ConstraintEval ce = evaluate_constraint(in);
    for (int j = 0; j < ce.rows; ++j) {
      rows.push_back(dofs_.multiplier_dof(c) + j);
      values.push_back(rates ? ce.g_dot(j) : ce.g(j));
    }
  }
  PetscCall(VecSetValues(out, static_cast<PetscInt>(rows.size()), rows.data(), values.data(), INSERT_VALUES));
  PetscCall(VecAssemblyBegin(out));
  PetscCall(VecAssemblyEnd(out));
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::gather_scatter(bool everywhere, VecScatter* scatter, Vec* target) {
  PetscFunctionBeginUser;
  // U, V and A share one layout: one scatter each way, made on first use.
  if (everywhere) {
    if (!to_all_) PetscCall(VecScatterCreateToAll(global_template_, &to_all_, &all_seq_));
    *scatter = to_all_;
    *target = all_seq_;
  } else {
    if (!to_root_) PetscCall(VecScatterCreateToZero(global_template_, &to_root_, &root_seq_));
    *scatter = to_root_;
    *target = root_seq_;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::gather(double t, Vec U, Vec V, Vec A, Parametrization param, ModelState* state,
                                       bool everywhere) {
  PetscFunctionBeginUser;
  std::vector<double> full[3];
  const Vec in[3] = {U, V, A};
  VecScatter scatter;
  Vec seq;
  PetscCall(gather_scatter(everywhere, &scatter, &seq));
  const bool here = everywhere || dofs_.rank() == 0;
  for (int k = 0; k < 3; ++k) {
    if (!in[k]) continue;
    PetscCall(VecScatterBegin(scatter, in[k], seq, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(scatter, in[k], seq, INSERT_VALUES, SCATTER_FORWARD));
    if (here) {
      const PetscScalar* x;
      PetscInt n;
      PetscCall(VecGetLocalSize(seq, &n));
      PetscCall(VecGetArrayRead(seq, &x));
      full[k].assign(x, x + n);
      PetscCall(VecRestoreArrayRead(seq, &x));
    }
  }
  if (here && state) state->set(t, full[0], full[1], full[2], param);
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::gather_in_model_order(Vec X, std::vector<double>* ordered, bool everywhere) {
  PetscFunctionBeginUser;
  ordered->clear();
  VecScatter scatter;
  Vec seq;
  PetscCall(gather_scatter(everywhere, &scatter, &seq));
  PetscCall(VecScatterBegin(scatter, X, seq, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(scatter, X, seq, INSERT_VALUES, SCATTER_FORWARD));
  if (everywhere || dofs_.rank() == 0) {
    const PetscScalar* x;
    PetscInt n;
    PetscCall(VecGetLocalSize(seq, &n));
    PetscCall(VecGetArrayRead(seq, &x));
    *ordered = dofs_.to_model_order(std::span<const double>(x, static_cast<std::size_t>(n)));
    PetscCall(VecRestoreArrayRead(seq, &x));
  }
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
