// Solving one case of a batch: reading, static or dynamic solve, measures, full state.
#include "drivers/case_solver.hpp"

#include "drivers/simulation.hpp"

#include <cmath>
#include <limits>

namespace latticedyn {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

std::vector<ResolvedMeasure> resolve_measures(const BatchSpec& spec, const Model& model) {
  std::vector<ResolvedMeasure> out;
  for (const BatchMeasure& m : spec.measures) {
    ResolvedMeasure r{&m, {}, -1};
    for (const std::string& j : m.joints) {
      const int k = model.find_joint(j);
      if (k < 0) throw InputError(m.file, m.line, m.column, "measures." + m.name, "the model has no joint '" + j + "'");
      r.joints.push_back(k);
    }
    if (m.kind == MeasureKind::axial_force) {
      r.body = model.find_body(m.body);
      if (r.body < 0) throw InputError(m.file, m.line, m.column, "measures." + m.name, "the model has no body '" + m.body + "'");
    }
    out.push_back(r);
  }
  return out;
}

std::vector<double> evaluate_measures(const std::vector<ResolvedMeasure>& measures, const ModelState& state) {
  std::vector<double> v;
  for (const ResolvedMeasure& m : measures) {
    switch (m.spec->kind) {
      case MeasureKind::position: {
        const Vec3 p = state.joint_position(m.joints[0]);
        v.insert(v.end(), {p.x(), p.y(), p.z()});
        break;
      }
      case MeasureKind::angle_above_horizontal: {
        const Vec3 d = state.joint_position(m.joints[1]) - state.joint_position(m.joints[0]);
        v.push_back(std::atan2(d.z(), std::hypot(d.x(), d.y())) * 180.0 / M_PI);
        break;
      }
      case MeasureKind::axial_force: {
        double sum = 0;
        int n = 0;
        for (int e : state.model().bodies[m.body].elements)
          if (auto f = state.axial_force(e)) {
            sum += *f;
            ++n;
          }
        v.push_back(n ? sum / n : kNaN);
        break;
      }
    }
  }
  return v;
}


Evaluation CaseSolver::statics(const std::vector<KeyOverride>& overrides, const std::vector<double>& warm, bool cold_retry) {
  Evaluation ev;
  std::optional<Simulation> sim;
  if (!read(overrides, &sim, &ev)) return ev;
  SystemAssembler sa(sim->model, comm_);
  Vec U, V;
  PetscCallAbort(comm_, sa.create_vector(&U));
  PetscCallAbort(comm_, sa.create_vector(&V));
  PetscCallAbort(comm_, initial_state(*sim, sa, U, V));
  PetscInt n = 0;
  PetscCallAbort(comm_, VecGetSize(U, &n));
  const bool warm_start = static_cast<PetscInt>(warm.size()) == n;
  SimulationOutcome outcome;
  if (warm_start) {
    set_state_in_model_order(sa.dofs(), U, warm);
    sim->statics.warm_start = true;  // already loaded: one Newton solve from the neighbour
    PetscCallAbort(comm_, simulate(*sim, sa, U, V, true, false, nullptr, &outcome));
    ev.newton += outcome.statics.newton_iterations;
  }
  if (!warm_start || (!outcome.statics.converged && cold_retry)) {
    PetscCallAbort(comm_, initial_state(*sim, sa, U, V));
    sim->statics.warm_start = false;
    PetscCallAbort(comm_, simulate(*sim, sa, U, V, true, false, nullptr, &outcome));
    ev.newton += outcome.statics.newton_iterations;
  }
  ev.ok = outcome.statics.converged;
  if (!ev.ok) ev.error = outcome.statics.message;
  finish(sa, sim->statics.time, U, V, &ev);
  return ev;
}

Evaluation CaseSolver::run(const std::vector<KeyOverride>& overrides) {
  Evaluation ev;
  std::optional<Simulation> sim;
  if (!read(overrides, &sim, &ev)) return ev;
  if (!sim->run_dynamics) {
    ev.error = spec_.model_path + ": the model has no solver.dynamics section for 'analysis: run'";
    return ev;
  }
  SystemAssembler sa(sim->model, comm_);
  Vec U, V;
  PetscCallAbort(comm_, sa.create_vector(&U));
  PetscCallAbort(comm_, sa.create_vector(&V));
  PetscCallAbort(comm_, initial_state(*sim, sa, U, V));
  SimulationOutcome outcome;
  PetscCallAbort(comm_, simulate(*sim, sa, U, V, sim->run_static, true, nullptr, &outcome));
  ev.newton = outcome.statics.newton_iterations + static_cast<int>(outcome.dynamics.newton_iterations);
  ev.ok = outcome.ok();
  if (!ev.ok) ev.error = outcome.static_run && !outcome.statics.converged ? outcome.statics.message : outcome.dynamics.message;
  const double t = outcome.dynamics_run ? outcome.dynamics.time_reached : sim->statics.time;
  finish(sa, t, U, V, &ev);
  ev.state.clear();  // a dynamic state is no start for another case
  return ev;
}

bool CaseSolver::read(const std::vector<KeyOverride>& overrides, std::optional<Simulation>* sim, Evaluation* ev) {
  try {
    sim->emplace(read_simulation(spec_.model_path, overrides));
    return true;
  } catch (const std::exception& e) {  // a bad value fails this case alone
    ev->error = e.what();
    return false;
  }
}

void CaseSolver::finish(SystemAssembler& sa, double t, Vec U, Vec V, Evaluation* ev) {
  ModelState state(sa.model(), sa.dofs());
  PetscCallAbort(comm_, sa.gather(t, U, V, nullptr, Parametrization::rotation_vector_rates, &state));
  int rank = 0;
  MPI_Comm_rank(comm_, &rank);
  const int count = static_cast<int>(measure_columns(spec_).size());
  ev->measures.assign(count, kNaN);
  if (rank == 0) ev->measures = evaluate_measures(measures_, state);
  MPI_Bcast(ev->measures.data(), count, MPI_DOUBLE, 0, comm_);
  VecScatter to_all;
  Vec all;
  PetscCallAbort(comm_, VecScatterCreateToAll(U, &to_all, &all));
  PetscCallAbort(comm_, VecScatterBegin(to_all, U, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCallAbort(comm_, VecScatterEnd(to_all, U, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscInt n = 0;
  const PetscScalar* a = nullptr;
  PetscCallAbort(comm_, VecGetSize(all, &n));
  PetscCallAbort(comm_, VecGetArrayRead(all, &a));
  // In model order: a chain's states and the batch log mean the same for any group size.
  ev->state = sa.dofs().to_model_order(std::span<const double>(a, static_cast<std::size_t>(n)));
  PetscCallAbort(comm_, VecRestoreArrayRead(all, &a));
  PetscCallAbort(comm_, VecScatterDestroy(&to_all));
  PetscCallAbort(comm_, VecDestroy(&all));
  PetscCallAbort(comm_, VecDestroy(&U));
  PetscCallAbort(comm_, VecDestroy(&V));
}

}  // namespace latticedyn
