// The pipeline: map (batch) -> surfaces -> optimal end point trajectory -> control table ->
// verification run -> report files (CSV, YAML drives, markdown; PNGs by scripts/control_report.py).
#include "drivers/control_pipeline.hpp"

#include "control/control_table.hpp"
#include "core/drive.hpp"
#include "drivers/batch_runner.hpp"
#include "drivers/case_solver.hpp"
#include "drivers/observers.hpp"
#include "drivers/simulation.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

namespace latticedyn {

namespace {

namespace fs = std::filesystem;

struct MapData {
  std::vector<double> in0, in1, out0, out1;  // rope lengths, end point x and z
  std::vector<int> cases;                    // the batch case of each equilibrium
};

MapData map_data(const ControlSpec& spec, const BatchSummary& batch) {
  auto column = [&](const std::string& name) -> std::pair<bool, int> {
    const auto r = result_columns(spec.mapping);
    const auto it = std::find(r.begin(), r.end(), name);
    if (it != r.end()) return {true, static_cast<int>(it - r.begin())};
    const auto p = std::find(spec.mapping.columns.begin(), spec.mapping.columns.end(), name);
    return {false, static_cast<int>(p - spec.mapping.columns.begin())};
  };
  const std::pair<bool, int> cols[4] = {column(spec.inputs[0]), column(spec.inputs[1]), column(spec.outputs[0]),
                                        column(spec.outputs[1])};
  MapData d;
  std::vector<double>* lists[4] = {&d.in0, &d.in1, &d.out0, &d.out1};
  for (const BatchCase& bc : spec.mapping.cases) {
    const auto it = batch.records.find(bc.index);
    if (it == batch.records.end() || !it->second.ok) continue;
    for (int k = 0; k < 4; ++k)
      lists[k]->push_back(cols[k].first ? it->second.values.at(cols[k].second) : bc.values.at(cols[k].second));
    d.cases.push_back(bc.index);
  }
  return d;
}

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

void write_csv(const fs::path& p, const std::string& header, const std::vector<std::vector<double>>& columns) {
  std::ofstream f(p);
  f << header << "\n";
  char buf[40];
  const std::size_t n = columns.empty() ? 0 : columns[0].size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      std::snprintf(buf, sizeof buf, "%s%.10g", c ? "," : "", columns[c][i]);
      f << buf;
    }
    f << "\n";
  }
  if (!f) throw std::runtime_error("cannot write " + p.string());
}

// The model with the control table as its drives, a dynamics section and its own output folder.
fs::path write_verification_model(const ControlSpec& spec, const ControlTable& table, double t_end, const fs::path& dir,
                                  const std::string& start_file) {
  const InputNode merged = InputNode::load_file(spec.mapping.model_path);  // with its bases
  YAML::Node drives = YAML::Clone(merged["drives"].yaml());
  for (int c = 0; c < 2; ++c) {
    YAML::Node d;
    d["type"] = "table";
    d["times"] = table.times;
    d["values"] = table.values[c];
    d["zero_end_rates"] = true;
    drives[spec.drives[c]] = d;
  }
  YAML::Emitter out;
  out.SetDoublePrecision(12);
  out << YAML::BeginMap;
  out << YAML::Key << "base" << YAML::Value << fs::absolute(spec.mapping.model_path).lexically_normal().string();
  out << YAML::Key << "title" << YAML::Value << "quasi-static optimal control: verification run";
  out << YAML::Key << "drives" << YAML::Value << drives;
  YAML::Node solver = merged.has("solver") ? YAML::Clone(merged["solver"].yaml()) : YAML::Node(YAML::NodeType::Map);
  YAML::Node dyn;
  dyn["t_end"] = t_end;
  dyn["time_step"] = spec.time_step;
  dyn["rho_infinity"] = spec.rho_infinity;
  dyn["jacobian_reuse"] = spec.jacobian_reuse;
  solver["dynamics"] = dyn;
  if (!solver["static"]) solver["static"] = YAML::Node(YAML::NodeType::Map);
  out << YAML::Key << "solver" << YAML::Value << solver;
  YAML::Node output;
  output["directory"] = fs::absolute(dir / "verification").lexically_normal().string();
  output["interval"] = 0.1;
  output["probes"].push_back(spec.end_point_joint);
  out << YAML::Key << "output" << YAML::Value << output;
  if (!start_file.empty()) {
    YAML::Node start;
    start["file"] = start_file;
    out << YAML::Key << "start_state" << YAML::Value << start;
  }
  out << YAML::EndMap;
  const fs::path p = dir / "control_drives.yaml";
  std::ofstream f(p);
  f << "# Generated by latticedyn control from " << spec.source << ": the crane of the mapping batch with\n"
    << "# the control table (thesis 6.4) as spline drives, starting from the static equilibrium at the\n"
    << "# table's first rope lengths (start_state, recorded beside this file). Run it with\n"
    << "# latticedyn run control_drives.yaml\n"
    << out.c_str() << "\n";
  if (!f) throw std::runtime_error("cannot write " + p.string());
  return p;
}

// The equilibrium at rope lengths `to`, continued from the mapped equilibrium nearest to them.
Continuation start_equilibrium(const ControlSpec& spec, const MapData& d, const BatchSummary& batch,
                               const std::array<double, 2>& to, int* from_case) {
  const double s0 = *std::max_element(d.in0.begin(), d.in0.end()) - *std::min_element(d.in0.begin(), d.in0.end());
  const double s1 = *std::max_element(d.in1.begin(), d.in1.end()) - *std::min_element(d.in1.begin(), d.in1.end());
  std::size_t near = 0;
  double best = 1e300;
  for (std::size_t k = 0; k < d.in0.size(); ++k) {
    const double dist = std::hypot((d.in0[k] - to[0]) / s0, (d.in1[k] - to[1]) / s1);
    if (dist < best) best = dist, near = k;
  }
  *from_case = d.cases[near];
  const CaseRecord& r = batch.records.at(d.cases[near]);
  return continue_equilibrium(spec.mapping.model_path, {spec.inputs[0], spec.inputs[1]}, {d.in0[near], d.in1[near]},
                              {to[0], to[1]}, r.state, 10, PETSC_COMM_SELF);
}

// One output step holding `state` (global numbering, at rest) as a results file of the model.
void write_start_state(const fs::path& model_file, const std::vector<double>& state, const fs::path& dir,
                       const std::string& name) {
  const Simulation sim = read_simulation(model_file.string());
  SystemAssembler sa(sim.model, PETSC_COMM_SELF);
  if (state.size() != static_cast<std::size_t>(sa.dofs().global_size()))
    throw std::runtime_error("the mapped states do not fit the verification model");
  ModelState st(sim.model, sa.dofs());
  st.set(sim.run_dynamics ? sim.dynamics.t_start : sim.statics.time, sa.dofs().from_model_order(state), {}, {},
         Parametrization::rotation_vector_rates);
  ResultWriterOptions wo;
  wo.directory = dir;
  wo.base_name = name;
  ResultWriter writer(sim.model, wo);
  writer.append(st);
  writer.close();
}

// Everything after the map, on one process.
ControlSummary solve_control(const ControlSpec& spec, const BatchSummary& batch, const fs::path& dir) {
  ControlSummary summary;
  std::string report;
  char buf[1024];
  // On a failure the report keeps what was done up to it.
  auto write_partial_report = [&] {
    std::ofstream(dir / "control_report.md") << "# Quasi-static optimal control\n\n" << report;
  };
  const MapData d = map_data(spec, batch);
  if (d.in0.size() < 9) {
    summary.message = "the mapping has " + std::to_string(d.in0.size()) + " equilibria; the surfaces need at least 9";
    return summary;
  }
  // 1. Surfaces both ways (thesis 6.2): rope lengths -> end point, end point -> rope lengths.
  const SurfaceFit fx = SurfaceFit::fit(spec.surface, d.in0, d.in1, d.out0);
  const SurfaceFit fz = SurfaceFit::fit(spec.surface, d.in0, d.in1, d.out1);
  const SurfaceFit g0 = SurfaceFit::fit(spec.surface, d.out0, d.out1, d.in0);
  const SurfaceFit g1 = SurfaceFit::fit(spec.surface, d.out0, d.out1, d.in1);
  {
    std::vector<std::vector<double>> cols(8);
    for (std::size_t k = 0; k < d.in0.size(); ++k) {
      const double v[8] = {d.in0[k], d.in1[k], d.out0[k], d.out1[k], fx(d.in0[k], d.in1[k]), fz(d.in0[k], d.in1[k]),
                           g0(d.out0[k], d.out1[k]), g1(d.out0[k], d.out1[k])};
      for (int c = 0; c < 8; ++c) cols[c].push_back(v[c]);
    }
    write_csv(dir / "map_fit.csv",
              spec.drives[0] + "," + spec.drives[1] + ",x,z,x_fit,z_fit," + spec.drives[0] + "_fit," + spec.drives[1] + "_fit",
              cols);
  }
  std::snprintf(buf, sizeof buf,
                "## Quasi-static map (thesis 6.2)\n\n%zu equilibria of %d cases; surfaces: %s.\n\n"
                "| surface | RMS residual | largest residual |\n|---|---|---|\n"
                "| x(%s, %s) | %.3g m | %.3g m |\n| z(%s, %s) | %.3g m | %.3g m |\n"
                "| %s(x, z) | %.3g m | %.3g m |\n| %s(x, z) | %.3g m | %.3g m |\n\n",
                d.in0.size(), batch.cases, spec.surface.describe().c_str(), spec.drives[0].c_str(), spec.drives[1].c_str(),
                fx.rms_residual(), fx.max_residual(), spec.drives[0].c_str(), spec.drives[1].c_str(), fz.rms_residual(),
                fz.max_residual(), spec.drives[0].c_str(), g0.rms_residual(), g0.max_residual(), spec.drives[1].c_str(),
                g1.rms_residual(), g1.max_residual());
  report += buf;

  // 2. The optimal end point trajectory (6.3).
  QuadraticRegulatorSolution opt;
  const auto t_qp = std::chrono::steady_clock::now();
  PetscCallAbort(PETSC_COMM_SELF, spec.horizon > 0 ? solve_receding_horizon(spec.problem, spec.horizon, &opt)
                                                   : solve_quadratic_regulator(spec.problem, &opt));
  const double qp_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_qp).count();
  const QuadraticRegulatorProblem& p = spec.problem;
  const int N = p.steps;
  std::snprintf(buf, sizeof buf,
                "## Optimal end point trajectory (thesis 6.3, eq. %s)\n\nStates [x, z, vx, vz] of the end point (%s), "
                "controls [ax, az]; N = %d, ts = %g s; %s in %d iterations, %.3g s; cost J = %.6g.\n"
                "Start [%g, %g, %g, %g], target [%g, %g, %g, %g]; reached [%.4f, %.4f, %.4f, %.4f].\n\n",
                spec.horizon > 0 ? "6-2, receding horizon" : "6-1, whole horizon", spec.end_point_joint.c_str(), N,
                p.sample_time, opt.converged ? "converged" : "NOT converged", opt.iterations, qp_seconds, opt.cost,
                p.x0(0), p.x0(1), p.x0(2), p.x0(3), p.x_target(0), p.x_target(1), p.x_target(2), p.x_target(3),
                opt.states(N, 0), opt.states(N, 1), opt.states(N, 2), opt.states(N, 3));
  report += buf;
  if (!opt.converged) {
    summary.message = "the optimal trajectory did not converge: " + opt.message;
    write_partial_report();
    return summary;
  }

  // 3. Rope lengths along it through the inverse surfaces (6.4), then the table.
  std::vector<double> t(N + 1), l0(N + 1), l1(N + 1);
  bool outside = false;
  const auto [x_lo, x_hi] = std::minmax_element(d.out0.begin(), d.out0.end());
  const auto [z_lo, z_hi] = std::minmax_element(d.out1.begin(), d.out1.end());
  for (int k = 0; k <= N; ++k) {
    t[k] = k * p.sample_time;
    const double x = opt.states(k, 0), z = opt.states(k, 1);
    l0[k] = g0(x, z);
    l1[k] = g1(x, z);
    outside = outside || x < *x_lo || x > *x_hi || z < *z_lo || z > *z_hi;
  }
  {
    std::vector<std::vector<double>> cols{t};
    for (int c = 0; c < 4; ++c) cols.push_back(std::vector<double>(opt.states.col(c).data(), opt.states.col(c).data() + N + 1));
    for (int c = 0; c < 2; ++c) {
      std::vector<double> u(N + 1, 0.0);
      for (int k = 0; k < N; ++k) u[k] = opt.controls(k, c);
      cols.push_back(u);
    }
    cols.push_back(l0);
    cols.push_back(l1);
    write_csv(dir / "optimal_trajectory.csv", "t,x,z,vx,vz,ax,az," + spec.drives[0] + "," + spec.drives[1], cols);
  }
  const ControlTable table = make_control_table(t, {l0, l1}, spec.samples, spec.steady_points);
  {
    std::vector<std::vector<double>> cols{table.times, table.values[0], table.values[1]};
    write_csv(dir / "control_table.csv", "t," + spec.drives[0] + "," + spec.drives[1], cols);
    // The spline drives as the verification run will see them, densely, for the plots.
    const Drive d0 = Drive::Table{table.times, table.values[0], true}, d1 = Drive::Table{table.times, table.values[1], true};
    std::vector<std::vector<double>> dense(5);
    for (int i = 0; i <= 600; ++i) {
      const double tt = table.times.back() * i / 600.0;
      const DriveValue a = d0.evaluate(tt), b = d1.evaluate(tt);
      for (auto [c, v] : {std::pair{0, tt}, std::pair{1, a.value}, std::pair{2, b.value}, std::pair{3, a.rate},
                          std::pair{4, b.rate}})
        dense[c].push_back(v);
    }
    write_csv(dir / "control_spline.csv",
              "t," + spec.drives[0] + "," + spec.drives[1] + "," + spec.drives[0] + "_rate," + spec.drives[1] + "_rate", dense);
  }
  const double maneuver_end = table.lead_time + t.back();
  const double t_end = table.times.back() + spec.settle;
  // The start: the model's own pose may be degrees of boom angle away, too far for Newton. Walk
  // from the nearest mapped equilibrium to the table's first rope lengths instead, and record that
  // equilibrium as the drives file's start_state, so the file also runs on its own.
  const fs::path model_file = write_verification_model(spec, table, t_end, dir, "");
  int start_case = -1;
  const Continuation start = start_equilibrium(spec, d, batch, {table.values[0].front(), table.values[1].front()}, &start_case);
  if (!start.ok) {
    summary.message = "no equilibrium at the start of the control table (from mapped case " + std::to_string(start_case) +
                      "): " + start.error;
    write_partial_report();
    return summary;
  }
  write_start_state(model_file, start.state, dir, "control_start");
  write_verification_model(spec, table, t_end, dir, "control_start.h5");
  std::snprintf(buf, sizeof buf,
                "## Control trajectory (thesis 6.4)\n\n%s and %s from the inverse surfaces at the %d instants%s; "
                "resampled at %d points, %d steady points at each end (spacing %.4g s), spline drives with zero end "
                "rates: `%s` (table start %.4g / %.4g m, end %.4g / %.4g m). It starts from the static equilibrium at "
                "the table's first rope lengths, reached from mapped case %d in %d static solves and recorded in "
                "`control_start.h5` (its start_state): `latticedyn run %s` runs it alone.\n\n",
                spec.drives[0].c_str(), spec.drives[1].c_str(), N + 1,
                outside ? " (part of the path lies outside the mapped range: the surfaces extrapolate there)" : "",
                spec.samples, spec.steady_points, table.spacing, model_file.filename().c_str(), table.values[0].front(),
                table.values[1].front(), table.values[0].back(), table.values[1].back(), start_case, start.solves,
                model_file.filename().c_str());
  report += buf;

  // 4. Verification run of the crane under the control table (8.4.3).
  if (spec.verify) {
    Simulation sim = read_simulation(model_file.string());
    SystemAssembler sa(sim.model, PETSC_COMM_SELF);
    Vec U, V;
    PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(&U));
    PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(&V));
    PetscCallAbort(PETSC_COMM_SELF, initial_state(sim, sa, U, V));  // the recorded start
    ResultWriterOptions wo;
    wo.directory = sim.output.directory;
    wo.base_name = sim.output.name;
    wo.probe_joints = sim.output.probe_joints;
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
    if (!outcome.ok()) {
      summary.message = "the verification run failed: " +
                        (outcome.statics.converged ? outcome.dynamics.message : outcome.statics.message);
      write_partial_report();
      return summary;
    }
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
    write_csv(dir / "tracking.csv", "t,x,y,z,x_optimal,z_optimal,error", cols);
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
                                       << "qr_cost," << opt.cost << ",\n"
                                       << "map_equilibria," << d.in0.size() << ",\n";
  }
  std::ofstream(dir / "control_report.md")
      << "# Quasi-static optimal control\n\nFrom `" << spec.source << "` (mapping batch `" << spec.mapping.source
      << "`). Plots: `scripts/control_report.py " << dir.string() << "`.\n\n"
      << report;
  summary.ok = true;
  summary.message = (dir / "control_report.md").string();
  return summary;
}

}  // namespace

ControlSummary run_control(const ControlSpec& spec, const ControlOptions& options, MPI_Comm world) {
  int rank = 0;
  MPI_Comm_rank(world, &rank);
  const fs::path dir = options.output_directory.empty() ? spec.output_directory : options.output_directory;
  BatchOptions bo;
  bo.output_directory = (dir / "mapping").string();
  bo.groups = options.groups;
  const BatchSummary batch = run_batch(spec.mapping, bo, world);
  ControlSummary summary;
  if (rank == 0) {
    try {
      summary = solve_control(spec, batch, dir);
    } catch (const std::exception& e) {
      summary.ok = false;
      summary.message = e.what();
    }
  }
  // Share the outcome: every rank returns the same summary.
  double numbers[5] = {summary.ok ? 1.0 : 0.0, summary.tracking_max, summary.tracking_rms, summary.residual_sway,
                       summary.final_offset};
  MPI_Bcast(numbers, 5, MPI_DOUBLE, 0, world);
  int length = static_cast<int>(summary.message.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, world);
  summary.message.resize(length);
  MPI_Bcast(summary.message.data(), length, MPI_CHAR, 0, world);
  summary.ok = numbers[0] > 0.5;
  summary.tracking_max = numbers[1];
  summary.tracking_rms = numbers[2];
  summary.residual_sway = numbers[3];
  summary.final_offset = numbers[4];
  return summary;
}

}  // namespace latticedyn
