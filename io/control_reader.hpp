// The control file of `latticedyn control` (thesis chapter 6): which mapping batch, which drives and
// end point, the surfaces, the QR problem of Table 8-2, the control table and the verification run.
#pragma once

#include "control/surface_fit.hpp"
#include "io/batch_reader.hpp"
#include "control/quadratic_regulator.hpp"

#include <array>
#include <string>

namespace latticedyn {

struct ControlSpec {
  std::string source;
  BatchSpec mapping;                       ///< the static map, run (or resumed) by the pipeline
  std::array<std::string, 2> drives;       ///< the model's drives the map varies (rope lengths)
  std::array<std::string, 2> inputs;       ///< their table columns: drives.<name>.value
  std::string end_point;                   ///< a position measure of the mapping batch
  std::string end_point_joint;             ///< its joint, for the verification run
  std::array<std::string, 2> outputs;      ///< its horizontal and vertical columns: <name>_x, <name>_z
  SurfaceSettings surface;
  QuadraticRegulatorProblem problem;       ///< states [x, z, vx, vz], controls [ax, az]
  int horizon = 0;                         ///< 0: the whole horizon as one QP; else MPC steps
  int samples = 20, steady_points = 5;     ///< the control table (6.4)
  bool verify = true;
  double time_step = 0.05, settle = 20.0, rho_infinity = 0.8;
  int jacobian_reuse = 50;
  std::string output_directory;
};

/// Throws InputError (file:line:col: key: what was expected) for any problem, including drives
/// or measures the mapping batch does not have.
ControlSpec read_control(const std::string& path);

}  // namespace latticedyn
