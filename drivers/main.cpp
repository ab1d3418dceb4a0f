// latticedyn: command line entry point. Parses the command and model file, hands every other
// argument to PETSc (so any -ts_/-snes_/-ksp_/-pc_ option and -log_view work) and maps errors
// to exit codes: 0 success, 1 solver failure, 2 bad input or usage, 3 internal error.
#include "drivers/commands.hpp"
#include "io/input_node.hpp"

#include <slepcsys.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

const char* kUsage =
    "usage: latticedyn <command> MODEL.yaml [--output DIR] [--restart FILE[:STEP]] [PETSc options]\n"
    "commands:\n"
    "  check    validate the model and describe it\n"
    "  static   find the static equilibrium and write it\n"
    "  run      static equilibrium if the model asks for it, then the dynamics (--restart RESULTS.h5[:STEP]\n"
    "           continues a run from its last checkpoint, or the one at step STEP, exactly)\n"
    "  modes    static equilibrium, then the lowest natural frequencies and mode shapes (--modes N, default 6)\n"
    "  batch    the cases of a batch file (a grid or list of model changes) over MPI rank groups\n"
    "           (--groups G, default one per rank; resumes in its output folder; --retry-failed)\n"
    "  control  quasi-static optimal control: mapping batch, surfaces, optimal trajectory (TAO), control\n"
    "           table, verification run and report (--groups G for the batch)\n"
    "  help     this text\n"
    "Every other option goes to PETSc, e.g. -ts_adapt_type basic, -snes_monitor, -pc_factor_mat_solver_type\n"
    "umfpack, -log_view. Results go to the model's output.directory (default results/<model name>).\n";

}  // namespace

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
  if (argc < 2 || !std::strcmp(argv[1], "help") || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    std::fputs(kUsage, argc < 2 ? stderr : stdout);
    return argc < 2 ? kInputError : kSuccess;
  }
  const std::string command = argv[1];
  if (command != "check" && command != "static" && command != "run" && command != "modes" && command != "batch" &&
      command != "control") {
    std::fprintf(stderr, "latticedyn: error: unknown command '%s'\n%s", command.c_str(), kUsage);
    return kInputError;
  }
  CommandOptions options;
  std::vector<char*> petsc_args{argv[0]};
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--output")) {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "latticedyn: error: --output needs a directory\n");
        return kInputError;
      }
      options.output_directory = argv[++i];
    } else if (!std::strcmp(argv[i], "--modes")) {
      if (i + 1 >= argc || std::atoi(argv[i + 1]) < 1) {
        std::fprintf(stderr, "latticedyn: error: --modes needs a positive number\n");
        return kInputError;
      }
      options.modes = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--groups")) {
      if (i + 1 >= argc || std::atoi(argv[i + 1]) < 1) {
        std::fprintf(stderr, "latticedyn: error: --groups needs a positive number\n");
        return kInputError;
      }
      options.groups = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--restart")) {
      if (command != "run" || i + 1 >= argc) {
        std::fprintf(stderr, "latticedyn: error: --restart belongs to 'run' and needs a results file (FILE or FILE:STEP)\n");
        return kInputError;
      }
      options.restart = argv[++i];
    } else if (!std::strcmp(argv[i], "--retry-failed")) {
      options.retry_failed = true;
    } else if (i == 2 && argv[i][0] != '-') {
      options.model_path = argv[i];  // right after the command, so option values are never taken for it
    } else {
      petsc_args.push_back(argv[i]);
    }
  }
  if (options.model_path.empty()) {
    std::fprintf(stderr, "latticedyn: error: '%s' needs a model file\n%s", command.c_str(), kUsage);
    return kInputError;
  }

  int pargc = static_cast<int>(petsc_args.size());
  petsc_args.push_back(nullptr);
  char** pargv = petsc_args.data();
  if (SlepcInitialize(&pargc, &pargv, nullptr, nullptr) != 0) return kInternalError;
  PetscMPIInt size = 1, rank = 0;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  // An error on one rank must end the run on all ranks with its message, never hang the others.
  if (size > 1) PetscPushErrorHandler(PetscMPIAbortErrorHandler, nullptr);

  int code = kSuccess;
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
    if (!sim.petsc_options.empty() && command != "check") {
      PetscCallAbort(PETSC_COMM_WORLD, PetscOptionsInsertString(nullptr, sim.petsc_options.c_str()));
      PetscCallAbort(PETSC_COMM_WORLD, PetscOptionsInsert(nullptr, &pargc, &pargv, nullptr));
    }
    if (command == "check") code = command_check(sim, PETSC_COMM_WORLD);
    if (command == "static") code = command_static(sim, options, PETSC_COMM_WORLD);
    if (command == "run") code = command_run(sim, options, PETSC_COMM_WORLD);
    if (command == "modes") code = command_modes(sim, options, PETSC_COMM_WORLD);
  } catch (const InputError& e) {
    if (rank == 0) std::fprintf(stderr, "latticedyn: error: %s\n", e.what());
    code = kInputError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "latticedyn: internal error on rank %d: %s\n", rank, e.what());
    if (size > 1) MPI_Abort(PETSC_COMM_WORLD, kInternalError);
    code = kInternalError;
  }
  SlepcFinalize();
  return code;
}
