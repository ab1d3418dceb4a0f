// The table of a batch, one row per case, as CSV and HDF5; each file is written under a temporary
// name and renamed, so that a reader never sees half a table.
#pragma once

#include "drivers/batch_log.hpp"
#include "io/batch_reader.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace latticedyn {

/// Columns: case, label, status, the spec's columns, `results` (result_columns), evaluations,
/// newton_iterations, wall_seconds, error. Throws std::runtime_error when a file cannot be written.
void write_batch_table(const BatchSpec& spec, const std::vector<std::string>& results,
                       const std::map<int, CaseRecord>& records, const std::filesystem::path& csv,
                       const std::filesystem::path& h5);

}  // namespace latticedyn
