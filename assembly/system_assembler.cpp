// Global residual and Jacobian assembly. Each rank gathers the coordinates its elements, loads and
// constraints read (one VecScatter), evaluates them in the blocks' velocity variables, maps the
// results to the stored coordinates through the rotation chain rule, and adds them into the
// global vector (reverse scatter) and matrix (MatSetValues, ADD_VALUES).
#include "assembly/system_assembler.hpp"

#include "assembly/element_loop.hpp"
#include "assembly/log_events.hpp"
#include "assembly/matrix_fill.hpp"
#include "assembly/nodal_load.hpp"
#include "core/rotation.hpp"

#include <petscvec.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <new>
#include <string>
#include <stdexcept>
#include <typeinfo>

namespace latticedyn {

namespace {

// The exception being handled, for the failure message that ends a run if cutting the step does
// not help: an element outside its domain says so; anything else names where it came from.
std::string describe_current_exception(const std::string& where) {
  try {
    throw;
  } catch (const std::domain_error& e) {
    return std::string("an element was evaluated outside its domain: ") + e.what();
  } catch (const std::bad_alloc&) {
    return "evaluating " + where + " ran out of memory";
  } catch (const std::exception& e) {
    return "evaluating " + where + " failed: " + e.what();
  } catch (...) {
    return "evaluating " + where + " failed with an exception that is not a std::exception";
  }
}

std::string describe_current_exception(const Element& e) {
  return describe_current_exception("a " + std::string(e.type_name()) + " element");
}

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
      }()) {
  const int nb = static_cast<int>(model_.blocks.size());
  const int nc = static_cast<int>(model_.constraints.size());
  local_block_offset_.assign(nb, -1);
  local_multiplier_offset_.assign(nc, -1);
  std::vector<PetscInt> global_index;
  for (int b : dofs_.needed_blocks()) {
    local_block_offset_[b] = static_cast<int>(global_index.size());
    for (int i = 0; i < model_.blocks[b].size(); ++i) global_index.push_back(dofs_.block_dof(b) + i);
  }
  for (int c : dofs_.local_constraints()) {
    local_multiplier_offset_[c] = static_cast<int>(global_index.size());
    for (int i = 0; i < model_.constraints[c].rows(); ++i) global_index.push_back(dofs_.multiplier_dof(c) + i);
  }
  local_size_ = static_cast<int>(global_index.size());
  threads_ = element_threads(comm_);
  const std::vector<int>& elements = dofs_.local_elements();
  buffer_of_.assign(elements.size(), -1);
  for (std::size_t i = 0; i < elements.size(); ++i)
    if (threads_ > 1 && model_.elements[elements[i]].element->expensive()) {
      buffer_of_[i] = static_cast<int>(threaded_.size());
      threaded_.push_back(static_cast<int>(i));
    }
  if (threaded_.size() < 2) {  // nothing to share out
    threaded_.clear();
    buffer_of_.assign(elements.size(), -1);
  }
  element_residuals_.resize(threaded_.size());
  element_tangents_.resize(threaded_.size());
  run_first_.assign(elements.size(), -1);
  run_length_.assign(elements.size(), 0);
  for (std::size_t i = 0; i < elements.size();) {
    const Element& e = *model_.elements[elements[i]].element;
    const std::size_t width = static_cast<std::size_t>(std::clamp(e.batch_size(), 1, kMaxElementBatch));
    std::size_t n = 1;
    while (n < width && i + n < elements.size() &&
           typeid(*model_.elements[elements[i + n]].element) == typeid(e) &&
           (buffer_of_[i + n] < 0) == (buffer_of_[i] < 0))
      ++n;
    for (std::size_t k = 0; k < n; ++k) run_first_[i + k] = static_cast<int>(i);
    run_length_[i] = static_cast<int>(n);
    if (buffer_of_[i] >= 0) threaded_runs_.push_back(static_cast<int>(i));  // buffers i..i+n-1 are consecutive
    i += n;
  }

  PetscCallAbort(comm_, VecCreateMPI(comm_, dofs_.owned_size(), dofs_.global_size(), &global_template_));
  for (Vec* v : {&u_loc_, &v_loc_, &a_loc_, &uc_loc_, &r_loc_})
    PetscCallAbort(PETSC_COMM_SELF, VecCreateSeq(PETSC_COMM_SELF, local_size_, v));
  IS from;
  PetscCallAbort(PETSC_COMM_SELF, ISCreateGeneral(PETSC_COMM_SELF, local_size_, global_index.data(), PETSC_COPY_VALUES, &from));
  PetscCallAbort(comm_, VecScatterCreate(global_template_, from, u_loc_, nullptr, &to_local_));
  PetscCallAbort(PETSC_COMM_SELF, ISDestroy(&from));

  // Fixed blocks never change: their state is set once.
  state_.resize(nb);
  state_c_.resize(nb);
  chain_.resize(nb);
  chain_c_.resize(nb);
  rows_T_.assign(nb, Mat3::Identity());
  phi_.assign(nb, Vec3::Zero());
  for (int b = 0; b < nb; ++b) {
    block_kinematics(model_.blocks[b], nullptr, nullptr, nullptr, Parametrization::rotation_vector_rates, state_[b]);
    state_c_[b] = state_[b];
  }
  constrained_.assign(nb, 0);
  for (int c : dofs_.local_constraints())
    for (int b : dofs_.constraint_blocks()[c]) constrained_[b] = 1;
  estimate_scales();
}

SystemAssembler::~SystemAssembler() {
  VecScatterDestroy(&to_local_);
  VecScatterDestroy(&to_root_);
  for (Vec* v : {&global_template_, &u_loc_, &v_loc_, &a_loc_, &uc_loc_, &r_loc_, &root_seq_}) VecDestroy(v);
}

void SystemAssembler::estimate_scales() {
  // Mean diagonal mass and stiffness of the translational DoFs at the initial state (state_ holds
  // every block's initial state here), over all elements: the same numbers on every rank.
  double mass = 0.0, stiffness = 0.0, load2 = 0.0;
  int count = 0;
  const ElementContext ctx{model_.gravity, 0.0};
  ElementTangents t;
  for (std::size_t e = 0; e < model_.elements.size(); ++e) {
    const ElementEntry& entry = model_.elements[e];
    const auto kinds = entry.element->slots();
    std::vector<SlotState<double>> s;
    gather_slots(entry, state_, s);
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

void SystemAssembler::record_evaluation_error(const std::string& what) {
  static std::mutex guard;  // element evaluations may run on several threads
  std::lock_guard<std::mutex> lock(guard);
  if (evaluation_error_.empty()) evaluation_error_ = what;
}

bool SystemAssembler::uniform_blocks(int block_size) const {
  if (dofs_.num_multipliers() > 0) return false;
  for (const DofBlock& b : model_.blocks)
    if (!b.fixed && b.size() != block_size) return false;
  return true;
}

PetscErrorCode SystemAssembler::create_matrix(Mat* m, int block_size) const {
  PetscFunctionBeginUser;
  PetscCheck(block_size == 1 || uniform_blocks(block_size), comm_, PETSC_ERR_ARG_WRONG,
             "create_matrix: not every unknown is in a block of %d DoFs", block_size);
  std::vector<int> d, o;
  dofs_.count_nonzeros(d, o);
  // Per block row (every row of a block has its pattern): the nonzero blocks of its first row.
  std::vector<PetscInt> dn, on;
  for (std::size_t i = 0; i < d.size(); i += block_size) {
    dn.push_back(d[i] / block_size);
    on.push_back(o[i] / block_size);
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
                                               double ca) {
  const PetscScalar *u, *v = nullptr, *a = nullptr, *uc = nullptr;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(u_loc_, &u));
  if (have_v_) PetscCall(VecGetArrayRead(v_loc_, &v));
  if (have_a_) PetscCall(VecGetArrayRead(a_loc_, &a));
  if (separate_uc_) PetscCall(VecGetArrayRead(uc_loc_, &uc));
  const bool rates = how.param == Parametrization::rotation_vector_rates;
  for (int b : dofs_.needed_blocks()) {
    const int o = local_offset(b);
    const DofBlock& blk = model_.blocks[b];
    block_kinematics(blk, u + o, v ? v + o : nullptr, a ? a + o : nullptr, how.param, state_[b],
                     with_chain ? &chain_[b] : nullptr, cq, cv, ca);
    if (blk.kind == SlotKind::rotation) {
      phi_[b] = Vec3(u[o], u[o + 1], u[o + 2]);
      rows_T_[b] = rates ? Mat3(tangent_operator(phi_[b]).transpose()) : Mat3::Identity();
    }
    if (!constrained_[b]) continue;  // the end-of-step state only enters constraint rows
    if (separate_uc_) {
      block_kinematics(blk, uc + o, nullptr, nullptr, how.param, state_c_[b], with_chain ? &chain_c_[b] : nullptr, cq, cv, ca);
    } else {
      state_c_[b] = state_[b];
      if (with_chain) chain_c_[b] = chain_[b];
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
  PetscCall(scatter_in(at));
  PetscCall(compute_states(how, false, 1.0, 0.0, 0.0));

  const PetscScalar* uc;
  PetscCall(VecGetArrayRead(separate_uc_ ? uc_loc_ : u_loc_, &uc));
  PetscScalar* r;
  PetscCall(VecZeroEntries(r_loc_));
  PetscCall(VecGetArray(r_loc_, &r));

  const ElementContext ctx{how.load_scale * model_.gravity, at.t};
  const std::vector<int>& elements = dofs_.local_elements();
  const LogEvents& events = log_events();
  PetscCall(PetscLogEventBegin(events.element_residual, 0, 0, 0, 0));
  evaluation_error_.clear();
  auto evaluate = [&](int first, VecX* out) {
    const ElementRun run = gather_run(model_, elements, first, run_length_[first], state_);
    try {
      if (run.count == 1) {
        out[0].resize(run.elements[0]->num_dofs());
        run.elements[0]->residual(run.states[0], ctx, out[0]);
      } else {
        run.elements[0]->residual_batch(run.element_span(), run.state_span(), ctx, {out, run.size()});
      }
    } catch (...) {
      // Outside an element's domain (a rope's rest length through zero), or any other failure of
      // its evaluation: NaN marks the residual not finite, so the integrator cuts the step (a
      // domain error) instead of an exception unwinding through PETSc.
      record_evaluation_error(describe_current_exception(*run.elements[0]));
      for (int k = 0; k < run.count; ++k) out[k].setConstant(run.elements[k]->num_dofs(), std::nan(""));
    }
  };
  parallel_for_each(static_cast<int>(threaded_runs_.size()), threads_, [&](int k) {
    evaluate(threaded_runs_[k], &element_residuals_[buffer_of_[threaded_runs_[k]]]);
  });
  thread_local std::array<VecX, kMaxElementBatch> inline_re;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const ElementEntry& entry = model_.elements[elements[i]];
    const auto kinds = entry.element->slots();
    if (buffer_of_[i] < 0 && run_first_[i] == static_cast<int>(i)) evaluate(static_cast<int>(i), inline_re.data());
    const VecX& re = buffer_of_[i] < 0 ? inline_re[i - run_first_[i]] : element_residuals_[buffer_of_[i]];
    int o = 0;
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      const int n = slot_size(kinds[k]);
      const int lo = local_offset(entry.slots[k].block);
      if (lo >= 0) {
        if (kinds[k] == SlotKind::rotation) {
          const Vec3 rb = entry.slots[k].offset * re.segment<3>(o);
          for (int i = 0; i < 3; ++i) r[lo + i] += rb(i);
        } else {
          for (int i = 0; i < n; ++i) r[lo + i] += re(o + i);
        }
      }
      o += n;
    }
  }
  PetscCall(PetscLogEventEnd(events.element_residual, 0, 0, 0, 0));

  PetscCall(PetscLogEventBegin(events.constraints, 0, 0, 0, 0));
  auto state_of = [this](int b) -> const BlockState& { return state_[b]; };
  auto state_c_of = [this](int b) -> const BlockState& { return state_c_[b]; };
  // Loads and constraints evaluated without an exception leaving (it would unwind through PETSc):
  // a failure there marks the residual not finite, as an element's does.
  bool failed = false;
  try {
    for (int l : dofs_.local_loads()) {
      const NodalLoad& load = model_.loads[l];
      const double scale = how.load_scale * (load.drive >= 0 ? model_.drives[load.drive].evaluate(at.t).value : 1.0);
      const LoadEval le = evaluate_load(model_, load, state_of, scale, false);
      for (int k = 0; k < 2; ++k)
        if (le.blocks[k] >= 0) {
          const int lo = local_offset(le.blocks[k]);
          for (int i = 0; i < 3; ++i) r[lo + i] -= le.f(3 * k + i);
        }
    }

    for (int c : dofs_.local_constraints()) {
      const Constraint& con = model_.constraints[c];
      const int mo = local_multiplier_offset_[c];
      ConstraintInputs in;
      in.model = &model_;
      in.constraint = &con;
      in.block_state = state_of;
      in.drive = con.drive >= 0 ? model_.drives[con.drive].evaluate(at.t) : DriveValue{};
      in.with_velocity_terms = how.rows == ConstraintRows::acceleration;
      const ConstraintEval ce = evaluate_constraint(in);
      for (int k = 0; k < 4 && ce.blocks[k] >= 0; ++k) {
        const int lo = local_offset(ce.blocks[k]);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < ce.rows; ++j) r[lo + i] += ce.G(j, 3 * k + i) * uc[mo + j];
      }
      if (how.rows == ConstraintRows::acceleration) {
        const double al = how.baumgarte_alpha, be = how.baumgarte_beta;
        // G a + Gamma* = 0 (4-3, 4-27): the second time derivative of g, stabilised.
        for (int j = 0; j < ce.rows; ++j) {
          double ga = 0.0;
          for (int k = 0; k < 4 && ce.blocks[k] >= 0; ++k) ga += ce.G.block<1, 3>(j, 3 * k).dot(state_[ce.blocks[k]].acc);
          r[mo + j] = ga + ce.gamma(j) + 2 * al * be * ce.g_dot(j) + al * al * ce.g(j);
        }
      } else {
        ConstraintInputs inc = in;
        inc.block_state = state_c_of;
        inc.drive = con.drive >= 0 ? model_.drives[con.drive].evaluate(at.tc) : DriveValue{};
        inc.with_velocity_terms = false;
        const ConstraintEval cc = separate_uc_ || at.tc != at.t ? evaluate_constraint(inc) : ce;
        for (int j = 0; j < ce.rows; ++j) r[mo + j] = how.constraint_scale * cc.g(j);
      }
    }
  } catch (...) {
    record_evaluation_error(describe_current_exception("loads and constraints"));
    failed = true;
  }
  PetscCall(PetscLogEventEnd(events.constraints, 0, 0, 0, 0));

  // Rows of rotation blocks: from omega-variables to phi via T^T (identity for velocity variables).
  if (how.param == Parametrization::rotation_vector_rates)
    for (int b : dofs_.needed_blocks())
      if (model_.blocks[b].kind == SlotKind::rotation) {
        const int lo = local_offset(b);
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
  PetscCall(scatter_in(at));
  PetscCall(compute_states(how, true, cq, cv, ca));
  const bool rates = how.param == Parametrization::rotation_vector_rates;
  const PetscScalar* uc;
  PetscCall(VecGetArrayRead(separate_uc_ ? uc_loc_ : u_loc_, &uc));
  PetscCall(MatZeroEntries(J));

  // y: the residual in omega-variables per rotation block, for the derivative of T^T(phi) y.
  std::vector<Vec3> y(model_.blocks.size(), Vec3::Zero());
  const ElementContext ctx{how.load_scale * model_.gravity, at.t, !have_v_ && !have_a_ && cv == 0.0 && ca == 0.0};

  // rows_I (cq K col_K_J + C col_C_J + M col_M_J) on 3x3 blocks (a scalar block uses the top-left
  // entry, the rest stays zero): fixed sizes, no allocation in the element loop.
  auto chain_block = [&](int bi, int bj, const Mat3& K, const Mat3& C, const Mat3& M) -> Mat3 {
    const BlockChain& ci = chain_[bi];
    const BlockChain& cj = chain_[bj];
    return ci.rows * (cq * K * cj.col_K + C * cj.col_C + M * cj.col_M);
  };

  const std::vector<int>& elements = dofs_.local_elements();
  const LogEvents& events = log_events();
  PetscCall(PetscLogEventBegin(events.element_jacobian, 0, 0, 0, 0));
  evaluation_error_.clear();
  auto evaluate = [&](int first, ElementTangents* out) {
    const ElementRun run = gather_run(model_, elements, first, run_length_[first], state_);
    try {
      if (run.count == 1)
        run.elements[0]->tangents(run.states[0], ctx, out[0]);
      else
        run.elements[0]->tangents_batch(run.element_span(), run.state_span(), ctx, {out, run.size()});
    } catch (...) {
      record_evaluation_error(describe_current_exception(*run.elements[0]));
      for (int k = 0; k < run.count; ++k) {
        out[k].resize(run.elements[k]->num_dofs());
        for (auto* m : {&out[k].K, &out[k].C, &out[k].M}) m->setConstant(std::nan(""));
        out[k].residual.setConstant(std::nan(""));
      }
    }
  };
  parallel_for_each(static_cast<int>(threaded_runs_.size()), threads_, [&](int k) {
    evaluate(threaded_runs_[k], &element_tangents_[buffer_of_[threaded_runs_[k]]]);
  });
  // Elements' tangents go straight into the matrix's value arrays where the plan knows the
  // positions (every Jacobian after the first, on rows this rank owns), else through MatSetValues.
  const bool direct = fill_.ready_for(J);
  if (direct) PetscCall(fill_.begin(J));
  thread_local std::array<ElementTangents, kMaxElementBatch> inline_t;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const ElementEntry& entry = model_.elements[elements[i]];
    if (buffer_of_[i] < 0 && run_first_[i] == static_cast<int>(i)) evaluate(static_cast<int>(i), inline_t.data());
    const ElementTangents& t = buffer_of_[i] < 0 ? inline_t[i - run_first_[i]] : element_tangents_[buffer_of_[i]];
    PetscCall(add_element_jacobian(static_cast<int>(i), entry, t, cq, cv, ca, direct, J, y));
  }
  if (direct) PetscCall(fill_.end(J));
  PetscCall(PetscLogEventEnd(events.element_jacobian, 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(events.constraints, 0, 0, 0, 0));

  auto state_of = [this](int b) -> const BlockState& { return state_[b]; };
  auto state_c_of = [this](int b) -> const BlockState& { return state_c_[b]; };
  const Eigen::Matrix3d zero3 = Eigen::Matrix3d::Zero();
  try {  // a failure marks the Jacobian unusable (evaluation_error), as an element's does
    for (int l : dofs_.local_loads()) {
      const NodalLoad& load = model_.loads[l];
      const double scale = how.load_scale * (load.drive >= 0 ? model_.drives[load.drive].evaluate(at.t).value : 1.0);
      const LoadEval le = evaluate_load(model_, load, state_of, scale, true);
      if (le.blocks[1] >= 0) y[le.blocks[1]] -= le.f.tail<3>();
      for (int ki = 0; ki < 2; ++ki)
        for (int kj = 0; kj < 2; ++kj) {
          if (le.blocks[ki] < 0 || le.blocks[kj] < 0) continue;
          const Eigen::Matrix3d K = -le.K.block<3, 3>(3 * ki, 3 * kj);
          if (K.isZero(0.0)) continue;
          const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> blk = chain_block(le.blocks[ki], le.blocks[kj], K, zero3, zero3);
          PetscInt ri = dofs_.block_dof(le.blocks[ki]), cj = dofs_.block_dof(le.blocks[kj]);
          PetscInt rows[3] = {ri, ri + 1, ri + 2}, cols[3] = {cj, cj + 1, cj + 2};
          PetscCall(MatSetValues(J, 3, rows, 3, cols, blk.data(), ADD_VALUES));
        }
    }

    for (int c : dofs_.local_constraints()) {
      const Constraint& con = model_.constraints[c];
      const int mo = local_multiplier_offset_[c];
      const int m = con.rows();
      ConstraintInputs in;
      in.model = &model_;
      in.constraint = &con;
      in.block_state = state_of;
      in.drive = con.drive >= 0 ? model_.drives[con.drive].evaluate(at.t) : DriveValue{};
      in.lambda = uc + mo;
      const ConstraintEval ce = evaluate_constraint(in);
      const int nblk = ce.cols / 3;
      std::vector<PetscInt> mult(m);
      for (int j = 0; j < m; ++j) mult[j] = dofs_.multiplier_dof(c) + j;

      for (int ki = 0; ki < nblk; ++ki) {
        const int bi = ce.blocks[ki];
        y[bi] += (ce.G.block(0, 3 * ki, m, 3).transpose() * Eigen::Map<const Eigen::VectorXd>(uc + mo, m)).eval();
        PetscInt ri = dofs_.block_dof(bi);
        PetscInt rows[3] = {ri, ri + 1, ri + 2};
        // Geometric stiffness d(G^T lambda)/dq.
        for (int kj = 0; kj < nblk; ++kj) {
          const int bj = ce.blocks[kj];
          const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> blk = chain_block(bi, bj, ce.H.block<3, 3>(3 * ki, 3 * kj), zero3, zero3);
          PetscInt cj = dofs_.block_dof(bj);
          PetscInt cols[3] = {cj, cj + 1, cj + 2};
          PetscCall(MatSetValues(J, 3, rows, 3, cols, blk.data(), ADD_VALUES));
        }
        // Multiplier columns: rows_I G^T, times dUc/dU since lambda is read from Uc.
        RowMajor gt = how.uc_per_u * chain_[bi].rows * ce.G.block(0, 3 * ki, m, 3).transpose();
        PetscCall(MatSetValues(J, 3, rows, m, mult.data(), gt.data(), ADD_VALUES));
      }

      // Constraint rows.
      RowMajor grow;
      if (how.rows == ConstraintRows::acceleration) {
        for (int kj = 0; kj < nblk; ++kj) {
          const int bj = ce.blocks[kj];
          grow = ca * ce.G.block(0, 3 * kj, m, 3);
          PetscInt cj = dofs_.block_dof(bj);
          PetscInt cols[3] = {cj, cj + 1, cj + 2};
          PetscCall(MatSetValues(J, m, mult.data(), 3, cols, grow.data(), ADD_VALUES));
        }
      } else {
        ConstraintInputs inc = in;
        inc.block_state = state_c_of;
        inc.lambda = nullptr;
        inc.drive = con.drive >= 0 ? model_.drives[con.drive].evaluate(at.tc) : DriveValue{};
        const ConstraintEval cc = evaluate_constraint(inc);
        for (int kj = 0; kj < cc.cols / 3; ++kj) {
          const int bj = cc.blocks[kj];
          grow = (cq * how.constraint_scale * how.uc_per_u) * cc.G.block(0, 3 * kj, m, 3) * chain_c_[bj].col_K;
          PetscInt cj = dofs_.block_dof(bj);
          PetscInt cols[3] = {cj, cj + 1, cj + 2};
          PetscCall(MatSetValues(J, m, mult.data(), 3, cols, grow.data(), ADD_VALUES));
        }
      }
      for (int j = 0; j < m; ++j) PetscCall(MatSetValue(J, mult[j], mult[j], 0.0, ADD_VALUES));
    }
  } catch (...) {
    record_evaluation_error(describe_current_exception("loads and constraints"));
  }

  PetscCall(PetscLogEventEnd(events.constraints, 0, 0, 0, 0));

  // d(T^T y)/dphi on the diagonal blocks of rotation coordinates.
  if (rates && cq != 0.0)
    for (int b : dofs_.needed_blocks()) {
      if (model_.blocks[b].kind != SlotKind::rotation || y[b].isZero(0.0)) continue;
      RowMajor Y = cq * tangent_transpose_derivative(phi_[b], y[b]);
      PetscInt g = dofs_.block_dof(b);
      PetscInt rows[3] = {g, g + 1, g + 2};
      PetscCall(MatSetValues(J, 3, rows, 3, rows, Y.data(), ADD_VALUES));
    }

  PetscCall(VecRestoreArrayRead(separate_uc_ ? uc_loc_ : u_loc_, &uc));
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  if (!direct) PetscCall(plan_element_fill(J));
  PetscFunctionReturn(0);
}

// One element's tangents (K, C, M in its slots' frames) as J blocks rows_I (cq K col_K_J + C col_C_J
// + M col_M_J) of the blocks' chain maps, the slots' frame offsets O folded into them (a rotation
// slot sees R O: rows O, columns O^T), in fixed 3 x 3 sizes; a block of a translation, vector or
// scalar slot has the plain chain (I, I, cv I, ca I).
PetscErrorCode SystemAssembler::add_element_jacobian(int local, const ElementEntry& entry, const ElementTangents& t,
                                                     double cq, double cv, double ca, bool direct, Mat J,
                                                     std::vector<Vec3>& y) {
  struct SlotMap {
    int block, n, offset;
    bool free, plain;
    Mat3 rows, colK, colC, colM;
  };
  PetscFunctionBeginUser;
  const auto kinds = entry.element->slots();
  const int ns = static_cast<int>(kinds.size());
  std::array<SlotMap, 8> maps;
  if (ns > static_cast<int>(maps.size())) throw std::logic_error("add_element_jacobian: more than 8 slots");
  int o = 0;
  for (int k = 0; k < ns; ++k) {
    SlotMap& m = maps[k];
    m.block = entry.slots[k].block;
    m.n = slot_size(kinds[k]);
    m.offset = o;
    m.free = !model_.blocks[m.block].fixed;
    m.plain = kinds[k] != SlotKind::rotation;
    if (!m.plain) {
      const BlockChain& c = chain_[m.block];
      const Mat3& O = entry.slots[k].offset;
      m.rows = c.rows * O;
      m.colK = O.transpose() * c.col_K;
      m.colC = O.transpose() * c.col_C;
      m.colM = O.transpose() * c.col_M;
      y[m.block] += O * t.residual.segment<3>(o);
    }
    o += m.n;
  }
  const int n = o;
  // The element's block of J: columns through the column blocks' chain maps, then rows through
  // the row blocks'. Fixed 12 x 12 for the elements of two frames (beams, super trusses), else a
  // fixed maximum size: no heap traffic either way.
  using Local = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor, 36, 36>;
  if (n > 36) throw std::logic_error("add_element_jacobian: more than 36 DoFs");
  auto combine = [&](auto& out, const auto& K, const auto& C, const auto& M) {
    for (int kj = 0; kj < ns; ++kj) {
      const SlotMap& mj = maps[kj];
      if (!mj.free) continue;
      const int oj = mj.offset;
      if (mj.plain) {
        out.middleCols(oj, mj.n) = cq * K.middleCols(oj, mj.n);
        if (cv != 0.0) out.middleCols(oj, mj.n) += cv * C.middleCols(oj, mj.n);
        if (ca != 0.0) out.middleCols(oj, mj.n) += ca * M.middleCols(oj, mj.n);
      } else {
        const Mat3 colK = cq * mj.colK;
        out.template middleCols<3>(oj).noalias() = K.template middleCols<3>(oj).lazyProduct(colK);
        out.template middleCols<3>(oj).noalias() += C.template middleCols<3>(oj).lazyProduct(mj.colC);
        out.template middleCols<3>(oj).noalias() += M.template middleCols<3>(oj).lazyProduct(mj.colM);
      }
    }
    for (int ki = 0; ki < ns; ++ki) {
      const SlotMap& mi = maps[ki];
      if (!mi.free || mi.plain) continue;
      const Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 36> rowsi = out.middleRows(mi.offset, 3);
      out.middleRows(mi.offset, 3).noalias() = mi.rows.lazyProduct(rowsi);
    }
  };
  // Into the matrix: through MatSetValues, or straight into its value arrays at the planned
  // positions (the plan lists, row by row of each free slot i, one position per slot j; -1: fixed
  // column or a row of another rank).
  auto insert = [&](const auto& A) -> PetscErrorCode {
    PetscFunctionBeginUser;
    if (!direct) {
      thread_local std::vector<PetscInt> idx;
      idx.assign(n, -1);
      for (int k = 0; k < ns; ++k)
        if (maps[k].free)
          for (int i = 0; i < maps[k].n; ++i) idx[maps[k].offset + i] = dofs_.block_dof(maps[k].block) + i;
      // Fixed rows and columns go in as -1 indices, which MatSetValues skips.
      PetscCall(MatSetValues(J, n, idx.data(), n, idx.data(), A.data(), ADD_VALUES));  // A row-major here
      PetscFunctionReturn(0);
    }
    const PetscInt* plan = fill_.element_offsets(local);
    const PetscInt stride = fill_.column_stride();
    if (stride == 3) {
      // BAIJ's 3 x 3 blocks are column-major and contiguous: the first row's position is the block's.
      // Every slot has three DoFs (uniform_blocks); rows of another rank go through MatSetValues.
      for (int ki = 0; ki < ns; ++ki) {
        const SlotMap& mi = maps[ki];
        if (!mi.free) continue;
        const PetscInt* row0 = plan;
        plan += 3 * ns;
        for (int kj = 0; kj < ns; ++kj) {
          const SlotMap& mj = maps[kj];
          if (!mj.free) continue;
          if (row0[kj] >= 0) {
            Eigen::Map<Mat3>(fill_.values(row0[kj])) += A.template block<3, 3>(mi.offset, mj.offset);
          } else {
            const PetscInt ri = dofs_.block_dof(mi.block), cj = dofs_.block_dof(mj.block);
            const PetscInt rows[3] = {ri, ri + 1, ri + 2}, cols[3] = {cj, cj + 1, cj + 2};
            const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> block = A.template block<3, 3>(mi.offset, mj.offset);
            PetscCall(MatSetValues(J, 3, rows, 3, cols, block.data(), ADD_VALUES));
          }
        }
      }
      PetscFunctionReturn(0);
    }
    for (int ki = 0; ki < ns; ++ki) {
      const SlotMap& mi = maps[ki];
      if (!mi.free) continue;
      for (int r = 0; r < mi.n; ++r, plan += ns) {
        const int ar = mi.offset + r;
        for (int kj = 0; kj < ns; ++kj) {
          const SlotMap& mj = maps[kj];
          if (!mj.free) continue;
          const PetscInt at = plan[kj];
          if (at >= 0) {
            double* v = fill_.values(at);
            for (int c = 0; c < mj.n; ++c) v[c * stride] += A(ar, mj.offset + c);
          } else {
            const PetscInt row = dofs_.block_dof(mi.block) + r, col = dofs_.block_dof(mj.block);
            const PetscInt cols[3] = {col, col + 1, col + 2};
            double vals[3];
            for (int c = 0; c < mj.n; ++c) vals[c] = A(ar, mj.offset + c);
            PetscCall(MatSetValues(J, 1, &row, mj.n, cols, vals, ADD_VALUES));
          }
        }
      }
    }
    PetscFunctionReturn(0);
  };
  if (n == 12 && ns == 4) {
    using Map12 = Eigen::Map<const Mat12>;
    Mat12 A12;  // column-major: the column maps write whole columns
    combine(A12, Map12(t.K.data()), Map12(t.C.data()), Map12(t.M.data()));
    if (direct) {
      PetscCall(insert(A12));
    } else {
      const Eigen::Matrix<double, 12, 12, Eigen::RowMajor> rows = A12;  // MatSetValues reads rows
      PetscCall(insert(rows));
    }
  } else {
    thread_local Local A;
    A.resize(n, n);
    combine(A, t.K, t.C, t.M);
    PetscCall(insert(A));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::plan_element_fill(Mat J) {
  PetscFunctionBeginUser;
  PetscCall(fill_.open(J));
  const std::vector<int>& elements = dofs_.local_elements();
  try {
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const ElementEntry& entry = model_.elements[elements[i]];
    const auto kinds = entry.element->slots();
    fill_.start_element();
    for (std::size_t ki = 0; ki < kinds.size(); ++ki) {
      const int bi = entry.slots[ki].block;
      if (model_.blocks[bi].fixed) continue;
      for (int r = 0; r < slot_size(kinds[ki]); ++r)
        for (std::size_t kj = 0; kj < kinds.size(); ++kj) {
          const int bj = entry.slots[kj].block;
          fill_.add_position(dofs_.block_dof(bi) + r, model_.blocks[bj].fixed ? -1 : dofs_.block_dof(bj));
        }
    }
  }
  } catch (const std::exception& e) {
    SETERRQ(comm_, PETSC_ERR_PLIB, "%s", e.what());  // no exception crosses into PETSc
  }
  PetscCall(fill_.close());
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

PetscErrorCode SystemAssembler::max_constraint_violation(Vec U, double t, double* value, int* constraint) {
  PetscFunctionBeginUser;
  PetscCall(scatter_in(EvaluationPoint{U, nullptr, nullptr, nullptr, t, t}));
  EvaluationSettings how;
  PetscCall(compute_states(how, false, 1.0, 0.0, 0.0));
  struct {
    double value;
    int index;
  } local{-1.0, -1}, global{-1.0, -1};
  auto state_of = [this](int b) -> const BlockState& { return state_[b]; };
  for (int c : dofs_.local_constraints()) {
    const Constraint& con = model_.constraints[c];
    ConstraintInputs in;
    in.model = &model_;
    in.constraint = &con;
    in.block_state = state_of;
    in.drive = con.drive >= 0 ? model_.drives[con.drive].evaluate(t) : DriveValue{};
    const ConstraintEval ce = evaluate_constraint(in);
    const double v = ce.g.head(ce.rows).cwiseAbs().maxCoeff();
    if (v > local.value) local = {v, c};
  }
  PetscCallMPI(MPI_Allreduce(&local, &global, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm_));
  *value = std::max(global.value, 0.0);
  *constraint = global.index;
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::gather(double t, Vec U, Vec V, Vec A, Parametrization param, ModelState* state) {
  PetscFunctionBeginUser;
  std::vector<double> full[3];
  const Vec in[3] = {U, V, A};
  // U, V and A share one layout: one scatter to rank 0, made on first use.
  if (!to_root_) PetscCall(VecScatterCreateToZero(global_template_, &to_root_, &root_seq_));
  for (int k = 0; k < 3; ++k) {
    if (!in[k]) continue;
    PetscCall(VecScatterBegin(to_root_, in[k], root_seq_, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(to_root_, in[k], root_seq_, INSERT_VALUES, SCATTER_FORWARD));
    if (dofs_.rank() == 0) {
      const PetscScalar* x;
      PetscInt n;
      PetscCall(VecGetLocalSize(root_seq_, &n));
      PetscCall(VecGetArrayRead(root_seq_, &x));
      full[k].assign(x, x + n);
      PetscCall(VecRestoreArrayRead(root_seq_, &x));
    }
  }
  if (dofs_.rank() == 0 && state) state->set(t, full[0], full[1], full[2], param);
  PetscFunctionReturn(0);
}

PetscErrorCode SystemAssembler::gather_in_model_order(Vec X, std::vector<double>* ordered) {
  PetscFunctionBeginUser;
  ordered->clear();
  if (!to_root_) PetscCall(VecScatterCreateToZero(global_template_, &to_root_, &root_seq_));
  PetscCall(VecScatterBegin(to_root_, X, root_seq_, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(to_root_, X, root_seq_, INSERT_VALUES, SCATTER_FORWARD));
  if (dofs_.rank() == 0) {
    const PetscScalar* x;
    PetscInt n;
    PetscCall(VecGetLocalSize(root_seq_, &n));
    PetscCall(VecGetArrayRead(root_seq_, &x));
    *ordered = dofs_.to_model_order(std::span<const double>(x, static_cast<std::size_t>(n)));
    PetscCall(VecRestoreArrayRead(root_seq_, &x));
  }
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
