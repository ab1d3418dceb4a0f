// Parameter studies of the verification suite (thesis chapter 8): a study file holds a model
// template, the parameter grid, the beam data and the acceptance limits; the study kinds compute
// the closed forms, run every instance, write CSV and markdown, and judge.
#pragma once

#include "io/input_node.hpp"
#include "verification/trajectory.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace latticedyn {

/// The beam of Table 8-1 (solid round section) as the study file gives it.
struct StudyBeam {
  double length = 0, radius = 0, youngs_modulus = 0, poisson_ratio = 0, density = 0;
  double area() const;
  double second_moment() const;  ///< I = pi r^4 / 4
  double bending_stiffness() const { return youngs_modulus * second_moment(); }
  double mass_per_length() const { return density * area(); }
};

/// One parameter combination of a study: name -> value text, in the grid's order.
using StudyPoint = std::vector<std::pair<std::string, std::string>>;

class Study {
 public:
  Study(const std::string& path, std::filesystem::path out_dir, bool quick);

  const InputNode& root() const { return root_; }
  const StudyBeam& beam() const { return beam_; }
  const std::filesystem::path& out_dir() const { return out_dir_; }
  /// Values of one grid parameter (the `quick` lists when quick mode is on and they exist).
  std::vector<std::string> values(const std::string& parameter) const;

  /// Writes the model template with ${name} replaced by the beam data and `substitutions` to
  /// out_dir/models/<tag>.yaml, runs it (results for ParaView in out_dir/results/<tag>/) and
  /// returns its trajectory. A failed run is recorded in `outcome` (the trajectory holds what was
  /// computed up to the failure).
  Trajectory run(const std::string& tag, const std::map<std::string, std::string>& substitutions,
                 SimulationOutcome* outcome) const;
  /// Only writes the instantiated model; returns its path.
  std::string instantiate(const std::string& tag, const std::map<std::string, std::string>& substitutions) const;
  std::filesystem::path model_path(const std::string& tag) const;

 private:
  InputNode root_;
  StudyBeam beam_;
  bool has_beam_ = false;
  std::filesystem::path out_dir_;
  bool quick_;
};

/// A CSV file with a header row; numbers written with 10 significant digits.
class CsvTable {
 public:
  CsvTable(const std::filesystem::path& path, const std::vector<std::string>& columns);
  void row(const std::vector<std::string>& cells);
  static std::string number(double x);

 private:
  std::FILE* file_ = nullptr;
  std::size_t columns_;

 public:
  ~CsvTable();
  CsvTable(const CsvTable&) = delete;
  CsvTable& operator=(const CsvTable&) = delete;
};

/// One acceptance check's verdict, printed and collected for the exit code.
struct Verdict {
  std::string what;
  bool pass = false;
};

/// Centred moving average of w(t) over `window` (NaN where the window leaves the record).
std::vector<double> moving_average(const std::vector<double>& t, const std::vector<double>& w, double window);
/// Mean frequency of the oscillation of w about `mean`: upward crossings per second.
double oscillation_frequency(const std::vector<double>& t, const std::vector<double>& w, const std::vector<double>& mean);

/// Short element-type label of the thesis: "C" (cubic spline) or "T" (Timoshenko).
std::string type_label(const std::string& type);

/// The study kinds; each returns its verdicts.
std::vector<Verdict> run_end_moment_study(const Study& s);
std::vector<Verdict> run_self_weight_study(const Study& s);
std::vector<Verdict> run_fixed_axis_rotation_study(const Study& s);
std::vector<Verdict> run_lattice_reduction_study(const Study& s);

}  // namespace latticedyn
