// One case of a batch on its group's ranks: the model read with the case's changes, its static
// equilibrium (from a predicted state when there is one) or its own run, and the measures.
#pragma once

#include "assembly/model_state.hpp"
#include "io/batch_reader.hpp"
#include "io/model_reader.hpp"

#include <petscsys.h>

#include <optional>
#include <string>
#include <vector>

namespace latticedyn {

class SystemAssembler;

/// A measure's joints and body, resolved in the model once.
struct ResolvedMeasure {
  const BatchMeasure* spec;
  std::vector<int> joints;
  int body = -1;
};

/// The measures' joints and bodies in `model`; throws InputError at a measure that names one
/// the model lacks.
std::vector<ResolvedMeasure> resolve_measures(const BatchSpec& spec, const Model& model);
/// The measures' values (BatchMeasure::columns order) in `state`.
std::vector<double> evaluate_measures(const std::vector<ResolvedMeasure>& measures, const ModelState& state);

/// One solved model: its measures and full state (on every rank of the group).
struct Evaluation {
  bool ok = false;
  std::string error;
  int newton = 0;
  std::vector<double> measures;
  std::vector<double> state;
};

/// Solves the cases of one group (collective on its communicator).
class CaseSolver {
 public:
  CaseSolver(const BatchSpec& spec, std::vector<ResolvedMeasure> measures, MPI_Comm comm)
      : spec_(spec), measures_(std::move(measures)), comm_(comm) {}

  /// The model with `overrides`, static equilibrium from `warm` (a state of the same model
  /// shape) or from the model's initial state, then the measures.
  Evaluation statics(const std::vector<KeyOverride>& overrides, const std::vector<double>& warm, bool cold_retry = true);

  /// The model's own run: statics if it asks, then its dynamics; measures at the end.
  Evaluation run(const std::vector<KeyOverride>& overrides);

 private:
  bool read(const std::vector<KeyOverride>& overrides, std::optional<Simulation>* sim, Evaluation* ev);

  // Measures on the group's first rank, shared; the full state on every rank of the group.
  void finish(SystemAssembler& sa, double t, Vec U, Vec V, Evaluation* ev);

  const BatchSpec& spec_;
  std::vector<ResolvedMeasure> measures_;
  MPI_Comm comm_;
};

// Equilibria along a chain, as (coordinate, state): the coordinate is the adjusted value of a
// target, else the chain's parameter. The last two give the secant predictor of the next state.
struct ChainPoint {
  double s = 0.0;
  std::vector<double> state;
};

class ChainHistory {
 public:
  void add(double s, std::vector<double> state) {
    // A point next to the last one (the secant iterations closing in) replaces it, so that the
    // secant keeps a base long enough that solver round-off does not steer the extrapolation.
    const bool close = !points_.empty() &&
                       (points_.back().s == s ||
                        (points_.size() == 2 && std::abs(s - points_[1].s) < 0.1 * std::abs(points_[1].s - points_[0].s)));
    if (close) points_.pop_back();
    points_.push_back({s, std::move(state)});
    if (points_.size() > 2) points_.erase(points_.begin());
  }
  bool empty() const { return points_.empty(); }
  /// The state at s extrapolated along the secant of the last two equilibria: ropes whose rest
  /// length changes come with their stretch already moved, where the neighbour's state alone
  /// would leave a lengthened rope slack (tension only) and Newton without its stiffness.
  std::vector<double> predict(double s) const {
    if (points_.empty()) return {};
    const ChainPoint& p1 = points_.back();
    if (points_.size() < 2 || points_[0].state.size() != p1.state.size() || points_[0].s == p1.s) return p1.state;
    const ChainPoint& p0 = points_[0];
    const double w = (s - p1.s) / (p1.s - p0.s);
    std::vector<double> out(p1.state.size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = p1.state[i] + w * (p1.state[i] - p0.state[i]);
    return out;
  }
  const ChainPoint& last() const { return points_.back(); }
  /// The earlier of the two points, if there are two.
  const ChainPoint* earlier() const { return points_.size() == 2 ? &points_.front() : nullptr; }

 private:
  std::vector<ChainPoint> points_;
};

}  // namespace latticedyn
