// The batch file of `latticedyn batch`: one model, a grid of parameters or a list of cases that
// change it, what to measure, expanded into numbered cases and checked before anything is solved.
#pragma once

#include "io/input_node.hpp"

#include <optional>
#include <string>
#include <vector>

namespace latticedyn {

/// A model value that follows a grid parameter: value = offset + scale * parameter.
struct LinearSetting {
  std::string path;
  double offset = 0.0;
  double scale = 1.0;
  std::string file;  ///< where it was written, for errors about its path
  int line = 0, column = 0;
};

/// Instead of setting a model value, the parameter is the value a measure must reach: the number
/// at `adjust` is varied (secant iterations of static solves) until it does.
struct BatchTarget {
  std::string measure;
  std::string adjust;        ///< dotted key path of a number in the model
  double start = 0.0;        ///< the model's own value at `adjust`
  double tolerance = 1e-6;   ///< on the measure
  double max_step = 1.0;     ///< largest change of the adjusted value per static solve
  int max_evaluations = 30;  ///< static solves per case
};

struct BatchParameter {
  std::string name;
  std::vector<double> values;
  std::vector<LinearSetting> set;
  std::optional<BatchTarget> target;
};

enum class MeasureKind { position, angle_above_horizontal, axial_force };

/// A quantity recorded for every case from its final state.
struct BatchMeasure {
  std::string name;
  MeasureKind kind = MeasureKind::position;
  std::vector<std::string> joints;  ///< "body.joint": position (1) or angle (2, from -> to)
  std::string body;                 ///< axial_force: mean over the body's elements
  std::string file;                 ///< where it was written, for errors about its names
  int line = 0, column = 0;
  /// Table columns: name_x, name_y, name_z for a position, else name.
  std::vector<std::string> columns() const;
};

struct BatchCase {
  int index = 0;
  int chain = 0;               ///< cases of one chain run in order, each from the previous state
  std::string label;           ///< "boom_angle=45 hoisting_change=3" or the case's name
  std::vector<double> values;  ///< one per BatchSpec::columns entry (NaN: not set)
  std::vector<KeyOverride> overrides;
  std::vector<double> set_values;  ///< the model values the grid sets, in the parameters' order
};

struct BatchSpec {
  std::string source;      ///< the batch file
  std::string model_path;  ///< resolved against the batch file's folder
  bool dynamics = false;   ///< analysis: run (statics if the model asks, then dynamics) or static
  bool warm_start = true;  ///< static grids: chains along the last parameter
  std::vector<BatchParameter> parameters;  ///< grid (empty for a case list)
  std::vector<std::string> columns;        ///< parameter names (grid) or set paths (case list; path[i] per vector component)
  int target_parameter = -1;               ///< index into parameters, or -1
  std::vector<BatchMeasure> measures;
  std::string output_directory;  ///< relative to the working directory, as model outputs
  std::string name;              ///< base name of the table files
  std::vector<BatchCase> cases;
  int chains = 0;
};

/// Throws InputError (file:line:col: key: what was expected) for any problem, including override
/// paths that do not exist in the model and target paths that hold no number.
BatchSpec read_batch(const std::string& path);

/// The measures' columns in order (BatchMeasure::columns of each).
std::vector<std::string> measure_columns(const BatchSpec& spec);

/// The result columns of every case (after the parameter columns): the adjusted value of a
/// target, the model values the grid sets, then the measures' columns.
std::vector<std::string> result_columns(const BatchSpec& spec);

}  // namespace latticedyn
