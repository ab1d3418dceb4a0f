// The steps of `latticedyn control` (thesis chapter 6), each writing its files and its section of
// the report: the quasi-static map's surfaces, the optimal trajectory and its control table, the
// drives file that runs it from a mapped equilibrium, and the verification run of the crane.
#pragma once

#include "control/control_table.hpp"
#include "control/quadratic_regulator.hpp"
#include "control/surface_fit.hpp"
#include "drivers/batch_runner.hpp"
#include "drivers/control_pipeline.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace latticedyn {

/// A step that cannot go on; what() says why. The report keeps the sections done before it.
struct ControlStepFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The mapped equilibria: rope lengths (inputs) and the end point's x and z (outputs) of every
/// case that solved, and the batch case each comes from.
struct MapData {
  std::vector<double> in0, in1, out0, out1;
  std::vector<int> cases;
};

/// Step 1 (6.2): the map and its surfaces both ways.
struct QuasiStaticMap {
  MapData data;
  SurfaceFit x, z;              ///< end point from the rope lengths
  SurfaceFit length0, length1;  ///< rope lengths from the end point
};

/// Steps 2 and 3 (6.3, 6.4): the optimal end point trajectory, the rope lengths along it and the
/// control table resampled from them.
struct ControlPlan {
  QuadraticRegulatorSolution optimal;
  std::vector<double> times, length0, length1;  ///< at the trajectory's N + 1 instants
  bool extrapolated = false;  ///< part of the path lies outside the mapped range
  ControlTable table;
  double maneuver_end = 0.0;  ///< when the table's motion ends
  double t_end = 0.0;         ///< the verification run's end (settling included)
};

/// Columns of equal length as a CSV file with `header`. Throws std::runtime_error when it cannot.
void write_columns_csv(const std::filesystem::path& p, const std::string& header,
                       const std::vector<std::vector<double>>& columns);

/// Step 1: the map's equilibria from the batch, the four surfaces, map_fit.csv. Throws
/// ControlStepFailed with fewer than 9 equilibria.
QuasiStaticMap fit_quasi_static_map(const ControlSpec& spec, const BatchSummary& batch, const std::filesystem::path& dir,
                                    std::string& report);

/// Steps 2 and 3: the quadratic regulator (TAO), the rope lengths through the inverse surfaces, the
/// table; optimal_trajectory.csv, control_table.csv, control_spline.csv. Throws ControlStepFailed
/// when the regulator does not converge.
ControlPlan plan_control(const ControlSpec& spec, const QuasiStaticMap& map, const std::filesystem::path& dir,
                         std::string& report);

/// The drives file control_drives.yaml: the mapped crane with the table as its drives, starting
/// from the equilibrium at the table's first rope lengths (continued from the nearest mapped one,
/// recorded as control_start.h5). Returns its path; throws ControlStepFailed without that start.
std::filesystem::path write_control_drives(const ControlSpec& spec, const QuasiStaticMap& map,
                                           const BatchSummary& batch, const ControlPlan& plan,
                                           const std::filesystem::path& dir, std::string& report);

/// Step 4 (8.4.3): the crane run under the table from its start; tracking.csv, summary.csv, the
/// tracking and sway figures in `summary`. Throws ControlStepFailed when the run fails.
void verify_control(const ControlSpec& spec, const QuasiStaticMap& map, const ControlPlan& plan,
                    const std::filesystem::path& drives_file, const std::filesystem::path& dir, ControlSummary& summary,
                    std::string& report);

}  // namespace latticedyn
