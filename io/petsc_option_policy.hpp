// What PETSc options a model file may carry: solver behaviour yes, files and processes no. A model
// is untrusted input; the command line is the user's own and stays unrestricted.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace latticedyn {

/// The options of a PETSc option string as PETSc's PetscOptionsInsertString reads it: tokens split
/// at white space, quotes grouping; a token that starts with '-' and not with a number is a name,
/// the next token its value unless it is a name too.
struct PetscOptionToken {
  std::string name;   ///< without its leading dashes
  std::string value;  ///< empty: none
};
std::vector<PetscOptionToken> split_petsc_options(const std::string& options);

/// Why an option from a model file is refused, or nothing when it may be applied. Refused: options
/// that read, write or name files or start processes (-options_file, -log_trace, -history,
/// debuggers, trajectories on disk), viewers and monitors that go anywhere but the terminal
/// (`-log_view :FILE`, `-ksp_view_mat binary:FILE`, draw, socket, HDF5, VTK, ...), and any value
/// that holds a path ('/'); and options PETSc reads only when it starts (-log_view, -fp_trap),
/// which would fail from a model.
std::optional<std::string> refused_model_option(const PetscOptionToken& option);

}  // namespace latticedyn
