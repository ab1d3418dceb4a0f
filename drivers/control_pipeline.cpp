// `latticedyn control`, end to end: the mapping batch on every rank, then its steps on rank 0
// (drivers/control_steps.hpp): surfaces -> optimal end point trajectory -> control table ->
// drives file -> verification run -> report (CSV, YAML drives, markdown; PNGs by
// scripts/control_report.py).
#include "drivers/control_pipeline.hpp"

#include "drivers/control_steps.hpp"

#include <exception>
#include <filesystem>
#include <fstream>

namespace latticedyn {

namespace {

namespace fs = std::filesystem;

// Everything after the map, on one process. A failed step leaves the report of the steps before it.
ControlSummary solve_control(const ControlSpec& spec, const BatchSummary& batch, const fs::path& dir) {
  ControlSummary summary;
  std::string report;
  try {
    const QuasiStaticMap map = fit_quasi_static_map(spec, batch, dir, report);
    const ControlPlan plan = plan_control(spec, map, dir, report);
    const fs::path drives_file = write_control_drives(spec, map, batch, plan, dir, report);
    if (spec.verify) verify_control(spec, map, plan, drives_file, dir, summary, report);
  } catch (const ControlStepFailed& e) {
    summary.message = e.what();
    std::ofstream(dir / "control_report.md") << "# Quasi-static optimal control\n\n" << report;
    return summary;
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
