// The energy account of a run with a hydraulic circuit: the pumps' work, the heat of valves,
// friction and leakage, the oil's compression and the mechanism's energy, integrated step by step.
#pragma once

#include "assembly/model_state.hpp"

#include <array>

namespace latticedyn {

/// Works since the account's first state, J. The balance supplied = mechanical_change +
/// dissipated + compression holds for the circuit and every mechanism it drives; what is left,
/// imbalance(), is the work of what the account does not itemize (drives, external loads,
/// mechanical damping, the integrator's numerical damping) plus the time integration's error.
struct EnergyAccount {
  double time = 0.0;               ///< s, of the last state recorded
  double supplied = 0.0;           ///< pumps' p Q and pressure supplies' (fixed nodes above 0 Pa)
  double dissipated = 0.0;         ///< throttling dp Q, friction, leakage, end stop damping
  double compression = 0.0;        ///< into compressed oil, the integral of p V p_dot / beta
  double mechanical_change = 0.0;  ///< change of kinetic, gravity and strain energy
  /// Change of the oil's V p^2 / (2 beta): equal to `compression` only to O(p / beta), because the
  /// pressure build-up equation takes V / beta as constant (for a fixed volume it is exact).
  double fluid_change = 0.0;
  double imbalance() const { return supplied - dissipated - compression - mechanical_change; }
  /// imbalance() over the largest itemized work (0 when nothing moved).
  double relative_imbalance() const;
};

class EnergyLedger {
 public:
  explicit EnergyLedger(const Model& model);
  /// Whether the model has elements that exchange power with a circuit (first-order blocks).
  static bool applies(const Model& model);
  /// Adds the interval from the last state recorded to this one by the trapezoidal rule (second
  /// order in the step: record every accepted step); the first call sets the starting energies.
  void record(const ModelState& state);
  bool started() const { return started_; }
  const EnergyAccount& account() const { return account_; }

 private:
  /// Supplied, dissipated and compression power, W.
  std::array<double, 3> rates(const ModelState& state) const;

  const Model& model_;
  std::vector<int> supply_elements_;  // elements with a slot on a fixed first-order block
  bool started_ = false;
  std::array<double, 3> last_rates_{};
  double start_mechanical_ = 0.0, start_fluid_ = 0.0;
  EnergyAccount account_;
};

}  // namespace latticedyn
