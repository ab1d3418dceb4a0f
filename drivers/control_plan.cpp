// Steps 2 and 3 of the control pipeline: the optimal end point trajectory (thesis 6.3, quadratic
// regulator with TAO), the rope lengths along it through the inverse surfaces and the control
// table resampled from them (6.4).
#include "drivers/control_steps.hpp"

#include "core/drive.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace latticedyn {

ControlPlan plan_control(const ControlSpec& spec, const QuasiStaticMap& map, const std::filesystem::path& dir,
                         std::string& report) {
  ControlPlan plan;
  char buf[1024];
  QuadraticRegulatorSolution& opt = plan.optimal;
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
  if (!opt.converged) throw ControlStepFailed("the optimal trajectory did not converge: " + opt.message);

  // The rope lengths along it through the inverse surfaces, then the table.
  std::vector<double>&t = plan.times, &l0 = plan.length0, &l1 = plan.length1;
  t.resize(N + 1);
  l0.resize(N + 1);
  l1.resize(N + 1);
  bool& outside = plan.extrapolated;
  const auto [x_lo, x_hi] = std::minmax_element(map.data.out0.begin(), map.data.out0.end());
  const auto [z_lo, z_hi] = std::minmax_element(map.data.out1.begin(), map.data.out1.end());
  for (int k = 0; k <= N; ++k) {
    t[k] = k * p.sample_time;
    const double x = opt.states(k, 0), z = opt.states(k, 1);
    l0[k] = map.length0(x, z);
    l1[k] = map.length1(x, z);
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
    write_columns_csv(dir / "optimal_trajectory.csv", "t,x,z,vx,vz,ax,az," + spec.drives[0] + "," + spec.drives[1], cols);
  }
  plan.table = make_control_table(t, {l0, l1}, spec.samples, spec.steady_points);
  const ControlTable& table = plan.table;
  {
    std::vector<std::vector<double>> cols{table.times, table.values[0], table.values[1]};
    write_columns_csv(dir / "control_table.csv", "t," + spec.drives[0] + "," + spec.drives[1], cols);
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
    write_columns_csv(dir / "control_spline.csv",
              "t," + spec.drives[0] + "," + spec.drives[1] + "," + spec.drives[0] + "_rate," + spec.drives[1] + "_rate", dense);
  }
  plan.maneuver_end = table.lead_time + t.back();
  plan.t_end = table.times.back() + spec.settle;
  return plan;
}

}  // namespace latticedyn
