// Co-simulation of a hydraulic circuit and the mechanism it drives (thesis Fig. 5-3): two models
// stepped apart by their own generalized-alpha integrators, exchanging pressures and motion.
#pragma once

#include "timestepping/dynamic_settings.hpp"
#include "timestepping/generalized_alpha.hpp"
#include "timestepping/solver_setup.hpp"

#include <memory>

namespace latticedyn {

/// The option beside the monolithic solve: the model is split into the mechanism (every block but
/// the pressures, which it holds at the circuit's last values) and the circuit (the pressures,
/// with the mechanism's blocks held at their last positions and velocities, no constraints). Every
/// coupling step H the mechanism advances first with the pressures held (zero-order hold), then the
/// circuit advances with the cylinders' ends held at the mechanism's new state (Gauss-Seidel),
/// each on generalized-alpha with the model's time step. Explicit coupling: first order in H, and
/// stable only while H resolves the oil's stiffness on the mechanism (docs/hydraulics.md).
/// Both parts run replicated on every rank (circuits are small); the observer sees the whole
/// model's state after every coupling step.
class HydraulicCosimulation {
 public:
  /// Throws ModelError for a model without a circuit or without a mechanism.
  HydraulicCosimulation(SystemAssembler& assembler, DynamicSettings settings);
  ~HydraulicCosimulation();
  HydraulicCosimulation(const HydraulicCosimulation&) = delete;
  HydraulicCosimulation& operator=(const HydraulicCosimulation&) = delete;

  /// U, V (rotation-vector rates) of the whole model at t_start in, at the end out. The report
  /// counts coupling steps as steps and both parts' Newton iterations; its linear_solver line
  /// names the coupling and each part's steps.
  PetscErrorCode run(Vec U, Vec V, StepObserver* observer, DynamicReport* report);

 private:
  /// One part of the split: its model (a copy of the whole with the other part's blocks fixed
  /// and held), assembler on PETSC_COMM_SELF, state and integrator.
  struct Part;
  /// The whole model's U, V in model order, on every rank.
  PetscErrorCode gather_everywhere(Vec X, std::vector<double>* ordered);
  /// Copies the free blocks of `from` (model order of the whole) into the part's vectors.
  PetscErrorCode load_part(Part& part, const std::vector<double>& u, const std::vector<double>& v);
  /// Writes the part's free blocks (and multipliers) into the whole model's model-order arrays.
  PetscErrorCode store_part(Part& part, std::vector<double>& u, std::vector<double>& v);
  /// Holds the blocks `part` does not integrate at the whole model's state (u, v).
  void hold(Part& part, const std::vector<double>& u, const std::vector<double>& v);
  /// The whole model's distributed U, V from model-order arrays.
  PetscErrorCode scatter_whole(const std::vector<double>& u, const std::vector<double>& v, Vec U, Vec V);

  SystemAssembler& sa_;
  DynamicSettings settings_;
  std::vector<int> offset_;             // per block of the whole model: first DoF in model order, -1 fixed
  std::vector<int> multiplier_offset_;  // per constraint
  std::unique_ptr<Part> mechanism_, circuit_;
};

}  // namespace latticedyn
