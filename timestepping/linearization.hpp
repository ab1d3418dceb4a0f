// The model linearised about a state: M dq'' + C dq' + K dq + G^T dlambda = B_f du, G dq = E du,
// reduced to independent coordinates (the null space of G) as a state-space model (A, B, C, D).
#pragma once

#include "assembly/system_assembler.hpp"
#include "timestepping/linear_model.hpp"

#include <vector>

namespace latticedyn {

/// Linearises about U, V (rotation-vector rates), A (their acceleration) at time t, the inputs
/// being the model's external drives `input_drives` (indices; perturbed through their signals),
/// the outputs the joints `output_joints`. Dense: for models up to a few thousand unknowns, on
/// one process. Throws std::invalid_argument for an input drive that is not external, and
/// std::runtime_error when M reduced to the null space is singular (a mass-less mechanism).
LinearModel linearize(SystemAssembler& sa, Vec U, Vec V, Vec A, double t, const std::vector<int>& input_drives,
                      const std::vector<int>& output_joints);

}  // namespace latticedyn
