// latticedyn: command line entry point. Parses the command and model file, hands every other
// argument to PETSc (so any -ts_/-snes_/-ksp_/-pc_ option and -log_view work) and maps errors
// to exit codes: 0 success, 1 solver failure, 2 bad input or usage, 3 internal error.
#include "drivers/command_line.hpp"
#include "drivers/commands.hpp"
#include "io/input_node.hpp"

#include <slepcsys.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

// Every way out of a run ends with a documented exit code. PETSc's PetscCallAbort and its
// error handler on several ranks end a run with MPI_Abort(comm, PETSc error code) after printing
// the error; through MPI's profiling interface that code becomes one of latticedyn's on its way
// to PMPI_Abort (drivers/exit_codes.hpp).
extern "C" int MPI_Abort(MPI_Comm comm, int errorcode) {
  const latticedyn::ExitCode code = latticedyn::exit_code_for(errorcode);
  if (errorcode > PETSC_ERR_MIN_VALUE)
    std::fprintf(stderr, "latticedyn: stopped by PETSc error %d (its message above): exit code %d\n", errorcode,
                 static_cast<int>(code));
  return PMPI_Abort(comm, code);
}

int main(int argc, char** argv) {
  using namespace latticedyn;
  // Line by line, so that stdout and stderr keep their order when both go to one log.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const CommandLine cl = parse_command_line(argc, argv);
  if (cl.action == CommandLine::Action::print) {
    std::fputs(cl.text.c_str(), stdout);
    return kSuccess;
  }
  if (cl.action == CommandLine::Action::fail) {
    std::fputs(cl.text.c_str(), stderr);
    return kInputError;
  }
  const std::string& command = cl.command;
  const CommandOptions& options = cl.options;
  std::vector<char*> petsc_args{argv[0]};
  for (const std::string& a : cl.petsc_args) petsc_args.push_back(const_cast<char*>(a.c_str()));
  int pargc = static_cast<int>(petsc_args.size());
  petsc_args.push_back(nullptr);
  char** pargv = petsc_args.data();
  if (SlepcInitialize(&pargc, &pargv, nullptr, nullptr) != 0) return kInternalError;
  PetscMPIInt size = 1, rank = 0;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  // An error on one rank must end the run on all ranks with its message, never hang the others.
  if (size > 1) PetscPushErrorHandler(PetscMPIAbortErrorHandler, nullptr);
  PetscBool help = PETSC_FALSE;
  PetscOptionsHasName(nullptr, nullptr, "-help", &help);
  if (help) {
    // PETSc has printed its own options; latticedyn's follow, with their help texts.
    if (rank == 0) std::fputs(usage_text().c_str(), stdout);
    PetscCallAbort(PETSC_COMM_WORLD, register_latticedyn_options(PETSC_COMM_WORLD));
    if (cl.action == CommandLine::Action::petsc_help) {
      SlepcFinalize();
      return kSuccess;
    }
  }

  int code = kSuccess;
  std::vector<std::string> given = option_names(cl.petsc_args);  // and the model's, below
  try {
    if (command == "batch" || command == "control") {
      code = command == "batch" ? command_batch(options, PETSC_COMM_WORLD) : command_control(options, PETSC_COMM_WORLD);
      SlepcFinalize();
      return code;
    }
    // Every rank reads the model; an input error is the same on all of them.
    Simulation sim = read_simulation(options.model_path);
    // Options from the model first, then the command line again so that it wins; `check` applies
    // none (they are only validated: io/petsc_option_policy.hpp).
    for (const std::string& name : option_names(sim.petsc_options)) given.push_back(name);
    if (!sim.petsc_options.empty() && command != "check") {
      PetscCallAbort(PETSC_COMM_WORLD, PetscOptionsInsertString(nullptr, sim.petsc_options.c_str()));
      PetscCallAbort(PETSC_COMM_WORLD, PetscOptionsInsert(nullptr, &pargc, &pargv, nullptr));
    }
    if (!options.output_directory.empty()) sim.output.directory = options.output_directory;
    if (command == "check") code = command_check(sim, PETSC_COMM_WORLD);
    if (command == "static") code = command_static(sim, options, PETSC_COMM_WORLD);
    if (command == "run") code = command_run(sim, options, PETSC_COMM_WORLD);
    if (command == "modes") code = command_modes(sim, options, PETSC_COMM_WORLD);
    if (command == "buckling") code = command_buckling(sim, options, PETSC_COMM_WORLD);
    if (command == "path") code = command_path(sim, options, PETSC_COMM_WORLD);
  } catch (const InputError& e) {
    if (rank == 0) std::fprintf(stderr, "latticedyn: error: %s\n", e.what());
    code = kInputError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "latticedyn: internal error on rank %d: %s\n", rank, e.what());
    if (size > 1) MPI_Abort(PETSC_COMM_WORLD, kInternalError);
    code = kInternalError;
  }
  // `check` applies no solver options: nothing to report.
  if (code != kInternalError && command != "check" && rank == 0) std::fputs(unused_options_report(given).c_str(), stderr);
  SlepcFinalize();
  return code;
}
