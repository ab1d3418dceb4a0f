// The latticedyn command line: commands and the options each takes, the help and version texts,
// and a user's slips (an unknown command or option, an option of another command) as errors.
#pragma once

#include "drivers/commands.hpp"

#include <string>
#include <vector>

namespace latticedyn {

struct CommandLine {
  enum class Action {
    execute,  ///< run `command` on `options.model_path`
    print,    ///< print `text` on stdout and exit 0 (help, version)
    fail,     ///< print `text` on stderr and exit 2
    petsc_help  ///< -help without a model: PETSc's and latticedyn's options, then exit 0
  };
  Action action = Action::fail;
  std::string command;
  CommandOptions options;
  std::vector<std::string> petsc_args;  ///< everything for PETSc, in order (options starting with one '-')
  std::string text;
};

/// Reads argv: `latticedyn COMMAND MODEL [--option value ...] [PETSc options]`, `--version`,
/// `--help`, `help [COMMAND]`, `COMMAND --help`. Options with two dashes are latticedyn's: an
/// unknown one, or one that belongs to another command, is an error with a suggestion.
CommandLine parse_command_line(int argc, const char* const* argv);

/// The general usage text.
std::string usage_text();
/// One command's help: what it does, its options, examples; empty for an unknown command.
std::string command_help(const std::string& command);
/// latticedyn's version and the libraries it was built with.
std::string version_text();

/// The candidate closest to `word` by edit distance, if within 2 edits; else "".
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);

/// Registers latticedyn's own PETSc options (-assembly_threads, -progress_*, -dyn_*, -fault_*)
/// with their help texts, so that -help lists them. Collective.
PetscErrorCode register_latticedyn_options(MPI_Comm comm);

/// Options the user gave (`given`: on the command line or in the model's petsc_options, names
/// without the dash) that this run never read (mistyped, or for another command or solver),
/// except those PETSc reads only at start-up or finalization; one line each, "" for none.
std::string unused_options_report(const std::vector<std::string>& given);

/// The option names (without the dash) in a list of arguments or an options string.
std::vector<std::string> option_names(const std::vector<std::string>& words);
std::vector<std::string> option_names(const std::string& options);

}  // namespace latticedyn
