// Hydraulic co-simulation: the model split into mechanism and circuit, each advanced by its own
// generalized-alpha integrator over a coupling step with the other's state held.
#include "timestepping/hydraulic_cosimulation.hpp"

#include "assembly/block_kinematics.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace latticedyn {

namespace {

/// Per block its first DoF in model order (-1 for fixed blocks), and per constraint its first
/// multiplier's (DofMap: free blocks in the model's order, then multipliers in constraint order).
void model_order_offsets(const Model& m, std::vector<int>* blocks, std::vector<int>* multipliers) {
  int next = 0;
  blocks->assign(m.blocks.size(), -1);
  for (std::size_t b = 0; b < m.blocks.size(); ++b)
    if (!m.blocks[b].fixed) {
      (*blocks)[b] = next;
      next += m.blocks[b].size();
    }
  multipliers->assign(m.constraints.size(), -1);
  for (std::size_t c = 0; c < m.constraints.size(); ++c) {
    (*multipliers)[c] = next;
    next += m.constraints[c].rows();
  }
}

}  // namespace

struct HydraulicCosimulation::Part {
  std::string name;
  Model model;
  std::vector<int> offset, multiplier_offset;
  std::unique_ptr<SystemAssembler> sa;
  Vec U = nullptr, V = nullptr;
  std::unique_ptr<GeneralizedAlphaIntegrator> integrator;
  DynamicReport report;

  ~Part() {
    integrator.reset();
    VecDestroy(&U);
    VecDestroy(&V);
  }
};

HydraulicCosimulation::HydraulicCosimulation(SystemAssembler& sa, DynamicSettings settings)
    : sa_(sa), settings_(settings) {
  const Model& whole = sa.model();
  model_order_offsets(whole, &offset_, &multiplier_offset_);
  auto split = [&](bool circuit) {
    auto part = std::make_unique<Part>();
    part->name = circuit ? "circuit" : "mechanism";
    part->model = whole;
    Model& m = part->model;
    if (circuit) {  // the cylinders' ends move as the mechanism says: no constraints, no loads
      m.constraints.clear();
      m.loads.clear();
    }
    int free = 0;
    for (DofBlock& b : m.blocks) {
      if (b.fixed) continue;
      if (b.first_order != circuit) {
        b.fixed = true;
        b.held = true;
      } else {
        ++free;
      }
    }
    if (free == 0)
      throw ModelError("hydraulic co-simulation: the model has no " + part->name +
                       (circuit ? " (no free hydraulic node)" : " (nothing but hydraulic nodes moves)"));
    model_order_offsets(m, &part->offset, &part->multiplier_offset);
    part->sa = std::make_unique<SystemAssembler>(part->model, PETSC_COMM_SELF);
    PetscCallAbort(PETSC_COMM_SELF, part->sa->create_vector(&part->U));
    PetscCallAbort(PETSC_COMM_SELF, part->sa->create_vector(&part->V));
    return part;
  };
  mechanism_ = split(false);
  circuit_ = split(true);
}

HydraulicCosimulation::~HydraulicCosimulation() = default;

PetscErrorCode HydraulicCosimulation::gather_everywhere(Vec X, std::vector<double>* ordered) {
  PetscFunctionBeginUser;
  PetscCall(sa_.gather_in_model_order(X, ordered));
  const auto n = static_cast<PetscMPIInt>(sa_.dofs().global_size());
  ordered->resize(static_cast<std::size_t>(n));
  PetscCallMPI(MPI_Bcast(ordered->data(), n, MPI_DOUBLE, 0, sa_.comm()));
  PetscFunctionReturn(0);
}

PetscErrorCode HydraulicCosimulation::load_part(Part& part, const std::vector<double>& u, const std::vector<double>& v) {
  PetscFunctionBeginUser;
  const auto n = static_cast<std::size_t>(part.sa->dofs().global_size());
  std::vector<double> pu(n, 0.0), pv(n, 0.0);
  const Model& whole = sa_.model();
  for (std::size_t b = 0; b < whole.blocks.size(); ++b) {
    if (part.offset[b] < 0) continue;
    for (int i = 0; i < whole.blocks[b].size(); ++i) {
      pu[part.offset[b] + i] = u[offset_[b] + i];
      pv[part.offset[b] + i] = v[offset_[b] + i];
    }
  }
  for (std::size_t c = 0; c < part.model.constraints.size(); ++c)
    for (int i = 0; i < part.model.constraints[c].rows(); ++i)
      pu[part.multiplier_offset[c] + i] = u[multiplier_offset_[c] + i];
  const std::vector<double> gu = part.sa->dofs().from_model_order(pu), gv = part.sa->dofs().from_model_order(pv);
  PetscScalar *xu, *xv;
  PetscCall(VecGetArray(part.U, &xu));
  PetscCall(VecGetArray(part.V, &xv));
  std::copy(gu.begin(), gu.end(), xu);
  std::copy(gv.begin(), gv.end(), xv);
  PetscCall(VecRestoreArray(part.U, &xu));
  PetscCall(VecRestoreArray(part.V, &xv));
  PetscFunctionReturn(0);
}

PetscErrorCode HydraulicCosimulation::store_part(Part& part, std::vector<double>& u, std::vector<double>& v) {
  std::vector<double> pu, pv;
  PetscFunctionBeginUser;
  PetscCall(part.sa->gather_in_model_order(part.U, &pu));
  PetscCall(part.sa->gather_in_model_order(part.V, &pv));
  const Model& whole = sa_.model();
  for (std::size_t b = 0; b < whole.blocks.size(); ++b) {
    if (part.offset[b] < 0) continue;
    for (int i = 0; i < whole.blocks[b].size(); ++i) {
      u[offset_[b] + i] = pu[part.offset[b] + i];
      v[offset_[b] + i] = pv[part.offset[b] + i];
    }
  }
  for (std::size_t c = 0; c < part.model.constraints.size(); ++c)
    for (int i = 0; i < part.model.constraints[c].rows(); ++i)
      u[multiplier_offset_[c] + i] = pu[part.multiplier_offset[c] + i];
  PetscFunctionReturn(0);
}

void HydraulicCosimulation::hold(Part& part, const std::vector<double>& u, const std::vector<double>& v) {
  const Model& whole = sa_.model();
  for (std::size_t b = 0; b < whole.blocks.size(); ++b) {
    if (offset_[b] < 0 || part.offset[b] >= 0) continue;  // fixed in both, or the part's own
    BlockState s;
    block_kinematics(whole.blocks[b], u.data() + offset_[b], v.data() + offset_[b], nullptr,
                     Parametrization::rotation_vector_rates, s);
    DofBlock& held = part.model.blocks[b];
    held.position0 = s.pos;
    held.orientation0 = s.rot;
    held.velocity0 = s.vel;  // the slot's velocity variables: r_dot, body omega, p_dot
  }
  part.sa->refresh_held_blocks();
}

PetscErrorCode HydraulicCosimulation::scatter_whole(const std::vector<double>& u, const std::vector<double>& v, Vec U,
                                                    Vec V) {
  PetscFunctionBeginUser;
  const int lo = sa_.dofs().owned_begin(), hi = sa_.dofs().owned_end();
  const std::vector<double> gu = sa_.dofs().from_model_order(u), gv = sa_.dofs().from_model_order(v);
  PetscScalar *xu, *xv;
  PetscCall(VecGetArray(U, &xu));
  PetscCall(VecGetArray(V, &xv));
  for (int i = lo; i < hi; ++i) {
    xu[i - lo] = gu[i];
    xv[i - lo] = gv[i];
  }
  PetscCall(VecRestoreArray(U, &xu));
  PetscCall(VecRestoreArray(V, &xv));
  PetscFunctionReturn(0);
}

PetscErrorCode HydraulicCosimulation::run(Vec U, Vec V, StepObserver* observer, DynamicReport* report) {
  PetscFunctionBeginUser;
  const auto start = std::chrono::steady_clock::now();
  start_report(nullptr, report);
  const double H = settings_.coupling_step > 0 ? settings_.coupling_step : settings_.time_step;
  double t = settings_.t_start;
  PetscCall(consistent_first_order_rates(sa_, t, U, V));
  std::vector<double> u, v;
  PetscCall(gather_everywhere(U, &u));
  PetscCall(gather_everywhere(V, &v));
  PetscCall(load_part(*mechanism_, u, v));
  PetscCall(load_part(*circuit_, u, v));
  PetscCall(record_step(sa_, StepInfo{0, t, 0.0, U, V, nullptr, Parametrization::rotation_vector_rates}, report, observer));

  // Advances a part to t1 with the other part held (the first call starts its integrator) and
  // takes its state into the whole model's; false, with the report's message, when it failed.
  bool failed = false;
  auto advance = [&](Part& part, double t1, std::vector<double>& u, std::vector<double>& v) -> PetscErrorCode {
    PetscFunctionBeginUser;
    hold(part, u, v);
    if (!part.integrator) {
      DynamicSettings s = settings_;
      s.t_end = t1;
      s.checkpoint_interval = 0.0;
      part.integrator = std::make_unique<GeneralizedAlphaIntegrator>(*part.sa, s);
      part.integrator->set_open_end(true);
      PetscCall(part.integrator->run(part.U, part.V, nullptr, &part.report));
    } else {
      PetscCall(part.integrator->continue_to(t1, part.U, part.V, nullptr, &part.report));
    }
    if (!part.report.completed) {
      failed = true;
      char where[128];
      std::snprintf(where, sizeof where, " failed between t = %.9g and %.9g s: ", t, t1);
      report->message = "co-simulation: the " + part.name + where + part.report.message;
      PetscFunctionReturn(0);
    }
    PetscCall(store_part(part, u, v));
    PetscFunctionReturn(0);
  };

  long k = 0;
  const double end = settings_.t_end, eps = 1e-9 * H;
  while (t < end - eps && !report->interrupted) {
    double t1 = std::min(t + H, end);
    if (end - t1 < eps) t1 = end;
    // The mechanism with the pressures of t (zero-order hold), then the circuit with the cylinders'
    // ends at the mechanism's new state (Gauss-Seidel).
    PetscCall(advance(*mechanism_, t1, u, v));
    if (!failed) PetscCall(advance(*circuit_, t1, u, v));
    if (failed) break;
    PetscCall(scatter_whole(u, v, U, V));
    t = t1;
    ++k;
    StepInfo info{static_cast<int>(k), t, H, U, V, nullptr, Parametrization::rotation_vector_rates,
                  mechanism_->report.newton_iterations + circuit_->report.newton_iterations,
                  mechanism_->report.rejected_steps + circuit_->report.rejected_steps};
    PetscCall(record_step(sa_, info, report, observer));
  }
  report->jacobians = mechanism_->report.jacobians + circuit_->report.jacobians;
  report->rotation_rescales = mechanism_->report.rotation_rescales;
  report->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report->completed = !failed && !report->interrupted;
  if (report->completed) report->message = "reached t = " + std::to_string(t) + " s";
  else if (report->interrupted) report->message = "stopped at t = " + std::to_string(t) + " s";
  char line[512];
  std::snprintf(line, sizeof line,
                "co-simulation (Gauss-Seidel, mechanism first, coupling step %g s): mechanism %ld steps, %ld Newton "
                "iterations; circuit %ld steps, %ld Newton iterations; %s",
                H, mechanism_->report.steps, mechanism_->report.newton_iterations, circuit_->report.steps,
                circuit_->report.newton_iterations, mechanism_->report.linear_solver.c_str());
  report->linear_solver = line;
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
