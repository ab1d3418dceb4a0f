// Options for one solver alone: while a PrefixedOptions is alive, -static_snes_rtol 1e-9 stands in
// PETSc's options database as -snes_rtol 1e-9, over a plain -snes_rtol that reaches every solver.
#pragma once

#include <petscsys.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace latticedyn {

/// The prefixes: the static solver's and the dynamic one's (-dyn_ts_adapt_type basic,
/// -dyn_snes_monitor, -dyn_pc_factor_mat_solver_type mumps).
inline constexpr const char* kStaticPrefix = "static_";
inline constexpr const char* kDynamicPrefix = "dyn_";

/// Scoped: every option -<prefix>NAME [VALUE] in the database is copied to -NAME [VALUE] (the
/// plain option's own value saved), and on destruction the plain options are restored. Solvers
/// keep no prefix, so options read while they set up or solve (-snes_view, -ksp_converged_reason,
/// subdomain solvers created at the first solve) see the prefixed values too. latticedyn's own
/// -dyn_dense_below, -dyn_block_matrix, -dyn_block_size and -dyn_predictor are left alone. Not nestable for one
/// name; the static and dynamic solvers never run at the same time.
class PrefixedOptions {
 public:
  explicit PrefixedOptions(const char* prefix);
  ~PrefixedOptions();
  PrefixedOptions(const PrefixedOptions&) = delete;
  PrefixedOptions& operator=(const PrefixedOptions&) = delete;

 private:
  std::vector<std::pair<std::string, std::optional<std::string>>> saved_;  // -NAME, its value before
};

}  // namespace latticedyn
