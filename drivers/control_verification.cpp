// Step 4 of the control pipeline (thesis 8.4.3): the crane run under the control table from its
// recorded start, the load tracked against the optimal trajectory, the sway left when the drives stop.
#include "drivers/control_steps.hpp"

#include "drivers/observers.hpp"
#include "drivers/simulation.hpp"
#include "io/result_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace latticedyn {

namespace {

// The load's position at every step of the verification run.
class EndPointTracker final : public StepObserver {
 public:
  EndPointTracker(SystemAssembler& sa, int joint) : sa_(sa), joint_(joint), state_(sa.model(), sa.dofs()) {}
  PetscErrorCode on_step(const StepInfo& info) override {
    PetscFunctionBeginUser;
    PetscCall(sa_.gather(info.time, info.U, info.V, nullptr, info.param, &state_));
    times.push_back(info.time);
    positions.push_back(state_.joint_position(joint_));
    PetscFunctionReturn(0);
  }
  std::vector<double> times;
  std::vector<Vec3> positions;

 private:
  SystemAssembler& sa_;
  int joint_;
  ModelState state_;
};

}  // namespace

void verify_control(const ControlSpec& spec, const QuasiStaticMap& map, const ControlPlan& plan,
                    const std::filesystem::path& drives_file, const std::filesystem::path& dir, ControlSummary& summary,
                    std::string& report) {
  const QuadraticRegulatorProblem& p = spec.problem;
  const QuadraticRegulatorSolution& opt = plan.optimal;
  const int N = p.steps;
  const std::vector<double>& t = plan.times;
  const ControlTable& table = plan.table;
  const double t_end = plan.t_end, maneuver_end = plan.maneuver_end;
  char buf[1024];
  Simulation sim = read_simulation(drives_file.string());
  SystemAssembler sa(sim.model, PETSC_COMM_SELF);
  Vec U, V;
  PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(&U));
  PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(&V));
  PetscCallAbort(PETSC_COMM_SELF, initial_state(sim, sa, U, V));  // the recorded start
  ResultWriterOptions wo;
  wo.directory = sim.output.directory;
  wo.base_name = sim.output.name;
  wo.probe_joints = sim.output.probe_joints;
  wo.body_blocks = sim.output.body_blocks;
  ResultWriter writer(sim.model, wo);
  OutputObserver out(sa, &writer, sim.output.interval, sim.dynamics.t_end);
  ProgressObserver progress(PETSC_COMM_SELF, sim.dynamics.t_start, sim.dynamics.t_end);
  const int joint = sim.model.find_joint(spec.end_point_joint);
  EndPointTracker tracker(sa, joint);
  ObserverList observers;
  observers.add(&out);
  observers.add(&progress);
  observers.add(&tracker);
  SimulationOutcome outcome;
  PetscCallAbort(PETSC_COMM_SELF, simulate(sim, sa, U, V, true, true, &observers, &outcome));
  progress.done();
  PetscCallAbort(PETSC_COMM_SELF, out.finish(outcome.dynamics_run ? outcome.dynamics.time_reached : 0.0, U, V,
                                             Parametrization::rotation_vector_rates));
  VecDestroy(&U);
  VecDestroy(&V);
  if (!outcome.ok())
    throw ControlStepFailed("the verification run failed: " +
                            (outcome.statics.converged ? outcome.dynamics.message : outcome.statics.message));
  // Tracking: the load against the optimal trajectory shifted by the table's lead time.
  std::vector<double> ox(N + 1), oz(N + 1);
  for (int k = 0; k <= N; ++k) ox[k] = opt.states(k, 0), oz[k] = opt.states(k, 1);
  std::vector<std::vector<double>> cols(7);
  double sum2 = 0, worst = 0;
  int inside = 0;
  double settle_lo[2] = {1e300, 1e300}, settle_hi[2] = {-1e300, -1e300};
  int settled = 0;
  for (std::size_t i = 0; i < tracker.times.size(); ++i) {
    const double tt = tracker.times[i], tau = tt - table.lead_time;
    const Vec3& q = tracker.positions[i];
    const double xo = interpolate_linear(t, ox, tau), zo = interpolate_linear(t, oz, tau);
    const double e = std::hypot(q.x() - xo, q.z() - zo);
    for (auto [c, v] : {std::pair{0, tt}, std::pair{1, q.x()}, std::pair{2, q.y()}, std::pair{3, q.z()},
                        std::pair{4, xo}, std::pair{5, zo}, std::pair{6, e}})
      cols[c].push_back(v);
    if (tau >= 0 && tau <= t.back()) {
      sum2 += e * e;
      worst = std::max(worst, e);
      ++inside;
    }
    if (tt >= table.times.back()) {  // the drives at rest again: what remains is sway
      const double v[2] = {q.x(), q.z()};
      for (int c = 0; c < 2; ++c) {
        settle_lo[c] = std::min(settle_lo[c], v[c]);
        settle_hi[c] = std::max(settle_hi[c], v[c]);
      }
      ++settled;
    }
  }
  write_columns_csv(dir / "tracking.csv", "t,x,y,z,x_optimal,z_optimal,error", cols);
  summary.tracking_max = worst;
  summary.tracking_rms = inside ? std::sqrt(sum2 / inside) : 0.0;
  if (settled > 0) {
    summary.residual_sway = 0.5 * std::max(settle_hi[0] - settle_lo[0], settle_hi[1] - settle_lo[1]);
    // The centre of the sway, not its mean: the window holds no whole number of periods.
    summary.final_offset = std::hypot(0.5 * (settle_lo[0] + settle_hi[0]) - p.x_target(0),
                                      0.5 * (settle_lo[1] + settle_hi[1]) - p.x_target(1));
  }
  const DynamicReport& r = outcome.dynamics;
  std::snprintf(buf, sizeof buf,
                "## Verification run (thesis 8.4.3)\n\nThe crane of `%s` under the control table from its static "
                "equilibrium, %g s (maneuver %.4g..%.4g s, drives at rest from %.4g s), generalized-alpha "
                "h = %g s: %ld steps, %ld Newton iterations, wall %.3g s.\n\n"
                "| quantity | value |\n|---|---|\n"
                "| tracking error during the maneuver, largest | %.4g m |\n"
                "| tracking error during the maneuver, RMS | %.4g m |\n"
                "| residual sway after the drives stop (half peak-to-peak, x or z) | %.4g m |\n"
                "| centre of the sway after the drives stop, distance to the target | %.4g m |\n\n",
                spec.mapping.model_path.c_str(), t_end, table.lead_time, maneuver_end, table.times.back(),
                spec.time_step, r.steps, r.newton_iterations, r.wall_seconds, summary.tracking_max,
                summary.tracking_rms, summary.residual_sway, summary.final_offset);
  report += buf;
  std::ofstream(dir / "summary.csv") << "quantity,value,unit\n"
                                     << "tracking_max," << summary.tracking_max << ",m\n"
                                     << "tracking_rms," << summary.tracking_rms << ",m\n"
                                     << "residual_sway," << summary.residual_sway << ",m\n"
                                     << "final_offset," << summary.final_offset << ",m\n"
                                     << "qr_cost," << plan.optimal.cost << ",\n"
                                     << "map_equilibria," << map.data.in0.size() << ",\n";
}

}  // namespace latticedyn
