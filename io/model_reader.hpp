// Reads a latticedyn model file (YAML, format in docs/model-format.md) into a Model and the run
// settings; every input problem is an InputError with file:line:col and key, before any solve.
#pragma once

#include "assembly/model.hpp"
#include "io/input_node.hpp"
#include "timestepping/dynamic_settings.hpp"
#include "timestepping/arc_length.hpp"
#include "timestepping/static_solver.hpp"

#include <string>
#include <vector>

namespace latticedyn {

struct OutputSettings {
  std::string directory;          ///< results folder (created by the run)
  std::string name;               ///< base name of the files in it
  double interval = 0.0;          ///< simulated seconds between outputs, 0 = every step
  std::vector<int> probe_joints;  ///< joints written to the probe CSV
  bool body_blocks = false;       ///< the XDMF draws each body as a block named after it
};

struct Simulation {
  std::string source;  ///< the model file
  Model model;
  bool run_static = false;    ///< find the static equilibrium before dynamics
  StaticSettings statics;
  bool run_dynamics = false;  ///< a dynamics section is present
  DynamicSettings dynamics;
  PathSettings path;  ///< solver.path: the arc-length continuation of `latticedyn path`
  OutputSettings output;
  std::string petsc_options;  ///< inserted into the options database before the command line
  /// A recorded state to start from (start_state), in model order (DofMap::to_model_order);
  /// empty: the model's own.
  std::vector<double> start_coordinates;
  /// Wall seconds of reading it: the YAML parse, then the model built from it (nodes, elements,
  /// joints, constraints, node sharing) and the parsed document released.
  double parse_seconds = 0.0, build_seconds = 0.0;
};

/// Throws InputError for any bad input (syntax, unknown key, missing field, meaningless value,
/// dangling reference, inconsistent shared connection).
Simulation read_simulation(const std::string& path);
/// The model with values replaced at dotted key paths first (see KeyOverride).
Simulation read_simulation(const std::string& path, const std::vector<KeyOverride>& overrides);
Simulation read_simulation_from_string(const std::string& yaml, const std::string& name);
Simulation read_simulation_from_string(const std::string& yaml, const std::string& name,
                                       const std::vector<KeyOverride>& overrides);

}  // namespace latticedyn
