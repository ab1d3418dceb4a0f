// A linearised model (timestepping/linear_model.hpp) as an HDF5 file: A, B, C, D and the names
// of its inputs and outputs, for Python, MATLAB or any control design tool.
#pragma once

#include "timestepping/linear_model.hpp"

#include <filesystem>

namespace latticedyn::io {

/// Writes (replacing) `path`: datasets /A (nx x nx), /B (nx x nu), /C (ny x nx), /D (ny x nu),
/// row-major doubles; /inputs, /outputs (strings: drive names, "joint.x" ... "joint.vz");
/// attributes time (s), independent (dim z), states ("z, z', u, u'"). Throws std::runtime_error
/// naming the file and HDF5's reason.
void write_linear_model(const std::filesystem::path& path, const LinearModel& model);

}  // namespace latticedyn::io
