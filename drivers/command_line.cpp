// Parsing and texts of the latticedyn command line; latticedyn's own PETSc options for -help.
#include "drivers/command_line.hpp"

#include "drivers/observers.hpp"
#include "timestepping/generalized_alpha.hpp"

#include <H5public.h>
#include <slepcversion.h>

#include <Eigen/Core>

#include <algorithm>
#include <cstdio>
#include <string_view>

#ifndef LATTICEDYN_VERSION
#error "LATTICEDYN_VERSION comes from CMake's project(VERSION)"
#endif

namespace latticedyn {

namespace {

struct OptionSpec {
  const char* name;
  const char* value;  // nullptr: a flag
  const char* help;
};

const OptionSpec kOptions[] = {
    {"--output", "DIR", "results folder (replaces output.directory)"},
    {"--modes", "N", "how many of the lowest natural or buckling modes (default 6)"},
    {"--groups", "G", "MPI rank groups solving cases side by side (default: one per rank)"},
    {"--retry-failed", nullptr, "solve the cases a resumed batch recorded as failed again"},
    {"--restart", "FILE[:STEP]", "continue a run from the last checkpoint of FILE, or the one at STEP, exactly"},
    {"--help", nullptr, "this command's help (nothing is run)"},
};

struct CommandSpec {
  const char* name;
  const char* summary;
  std::vector<std::string> options;
  const char* details;
};

const std::vector<CommandSpec>& commands() {
  static const std::vector<CommandSpec> list = {
      {"check", "validate the model and describe it; writes nothing", {"--output"},
       "Reads MODEL.yaml, prints a summary (bodies, joints, constraints, DoFs), the largest constraint violation of\n"
       "the initial state, the solver plan and where results would go. Exit 0 for a valid model, 2 with\n"
       "file:line:col and key for any input error. Model petsc_options are validated, not applied.\n"
       "  latticedyn check examples/crane/lifting.yaml\n"},
      {"static", "find the static equilibrium and write it", {"--output"},
       "Solves the static equilibrium with solver.static's settings (load steps, cuts, regularization) and writes\n"
       "it as one output step. PETSc's -snes_*, -ksp_*, -pc_* options change the solver.\n"
       "  latticedyn static examples/main_boom.yaml --output results/boom\n"},
      {"run", "static equilibrium if the model asks for it, then the dynamics", {"--output", "--restart"},
       "Statics if solver.static is enabled, then the dynamics of solver.dynamics (its integrator:\n"
       "generalized_alpha, baumgarte, implicit_rk or minimum_dof); results every output.interval, checkpoints\n"
       "every output.checkpoint_interval, at the end and on SIGINT/SIGTERM. --restart continues a run from a\n"
       "checkpoint (docs/model-format.md).\n"
       "  latticedyn run examples/crane/lifting.yaml\n"
       "  latticedyn run examples/crane/lifting.yaml --restart results/crane/lifting.h5\n"
       "  mpiexec -n 2 latticedyn run examples/crane/lifting_full.yaml -ts_max_time 5\n"},
      {"modes", "static equilibrium, then the lowest natural frequencies and mode shapes", {"--output", "--modes"},
       "The equilibrium, then the lowest natural modes about it (SLEPc); writes <name>_modes.h5/.xdmf (step 0 the\n"
       "equilibrium, step k mode k) and <name>_modes.csv (frequencies), beside a run's results, not over them.\n"
       "  latticedyn modes examples/main_boom.yaml --modes 10\n"},
      {"buckling", "static equilibrium under the loads, then the smallest load factors of linearized buckling",
       {"--output", "--modes"},
       "The equilibrium under the model's gravity and loads, then the load factors lambda at which lambda times\n"
       "those loads buckle the model (linearized buckling, SLEPc; docs/theory.md); writes <name>_buckling.h5/.xdmf\n"
       "(step 0 the equilibrium, step k buckling mode k) and <name>_buckling.csv (factors).\n"
       "  latticedyn buckling verification/cases/buckling_column_fixed_free.yaml --modes 4\n"},
      {"path", "the static load-displacement path through limit points (arc length), for limit loads", {"--output"},
       "From the unloaded start, the equilibria under lambda times the model's gravity and loads, traced by\n"
       "Crisfield's arc-length method through limit points and snap-through (solver.path: arc_length, max_steps,\n"
       "max_load_factor, ...); writes <name>_path.h5/.xdmf (step k: path point k) and <name>_path.csv (load\n"
       "factor and the probe joints' displacements), and names the limit points it passed.\n"
       "  latticedyn path verification/cases/path_two_bar_truss.yaml\n"},
      {"batch", "the cases of a batch file (a grid or list of model changes) over MPI rank groups",
       {"--output", "--groups", "--retry-failed"},
       "Solves every case of BATCH.yaml (docs/batch.md) and writes one table; run again into the same folder to\n"
       "resume after an interruption.\n"
       "  mpiexec -n 2 latticedyn batch examples/control/map_coarse.yaml --groups 2\n"},
      {"control", "quasi-static optimal control of the crane: map, surfaces, trajectory, table, verification",
       {"--output", "--groups"},
       "The pipeline of a control file (docs/control.md): mapping batch, response surfaces, optimal trajectory\n"
       "(TAO), control table, verification run and report.\n"
       "  latticedyn control examples/control/control_coarse.yaml\n"},
  };
  return list;
}

const CommandSpec* find_command(const std::string& name) {
  for (const CommandSpec& c : commands())
    if (name == c.name) return &c;
  return nullptr;
}

const OptionSpec* find_option(const std::string& name) {
  for (const OptionSpec& o : kOptions)
    if (name == o.name) return &o;
  return nullptr;
}

bool takes(const CommandSpec& c, const std::string& option) {
  return option == "--help" || std::find(c.options.begin(), c.options.end(), option) != c.options.end();
}

std::vector<std::string> command_names() {
  std::vector<std::string> names;
  for (const CommandSpec& c : commands()) names.emplace_back(c.name);
  return names;
}

// A positive integer of digits only (atoi would take "3x" and "-1" silently).
bool positive_int(const char* text, int* value) {
  const std::string_view s(text);
  if (s.empty() || s.size() > 9 || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return false;
  *value = std::stoi(std::string(s));
  return *value > 0;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

CommandLine failure(const std::string& text) {
  CommandLine c;
  c.action = CommandLine::Action::fail;
  c.text = "latticedyn: error: " + text + "\n";
  return c;
}

CommandLine printed(const std::string& text) {
  CommandLine c;
  c.action = CommandLine::Action::print;
  c.text = text;
  return c;
}

}  // namespace

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = 3;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

std::string usage_text() {
  std::string text =
      "usage: latticedyn COMMAND MODEL.yaml [--option value ...] [PETSc options]\n"
      "       latticedyn COMMAND --help | latticedyn --help | latticedyn --version | latticedyn -help\n"
      "commands:\n";
  for (const CommandSpec& c : commands()) {
    char line[200];
    std::snprintf(line, sizeof line, "  %-8s %s\n", c.name, c.summary);
    text += line;
  }
  text +=
      "Every option with one dash goes to PETSc (-ts_*, -snes_*, -ksp_*, -pc_*, -log_view) or is one of\n"
      "latticedyn's own (-assembly_threads, -progress_*, -dyn_*: `latticedyn -help` lists them). Results go to\n"
      "the model's output.directory (default results/<model name>). Exit codes: 0 done, 1 a solver failed,\n"
      "2 bad input or usage, 3 internal error, 130/143 stopped by SIGINT/SIGTERM.\n";
  return text;
}

std::string command_help(const std::string& command) {
  const CommandSpec* c = find_command(command);
  if (!c) return "";
  std::string text = "usage: latticedyn " + command + " " + (command == "batch" ? "BATCH.yaml" : command == "control" ? "CONTROL.yaml" : "MODEL.yaml");
  for (const std::string& o : c->options) {
    const OptionSpec* spec = find_option(o);
    text += " [" + o + (spec->value ? std::string(" ") + spec->value : "") + "]";
  }
  text += " [PETSc options]\n" + std::string(c->summary) + ".\n\n" + c->details;
  if (!c->options.empty()) text += "options:\n";
  for (const std::string& o : c->options) {
    const OptionSpec* spec = find_option(o);
    char line[256];
    std::snprintf(line, sizeof line, "  %-26s %s\n", (o + (spec->value ? std::string(" ") + spec->value : "")).c_str(),
                  spec->help);
    text += line;
  }
  return text;
}

std::string version_text() {
  char buf[512];
  char mpi[MPI_MAX_LIBRARY_VERSION_STRING] = "";
  int length = 0;
  MPI_Get_library_version(mpi, &length);  // allowed before MPI_Init
  std::string mpi_line(mpi, static_cast<std::size_t>(std::max(length, 0)));
  mpi_line = mpi_line.substr(0, mpi_line.find_first_of(",\n"));
  std::snprintf(buf, sizeof buf,
                "latticedyn %s\nbuilt with PETSc %d.%d.%d, SLEPc %d.%d.%d, HDF5 %d.%d.%d, Eigen %d.%d.%d, %s\n",
                LATTICEDYN_VERSION, PETSC_VERSION_MAJOR, PETSC_VERSION_MINOR, PETSC_VERSION_SUBMINOR, SLEPC_VERSION_MAJOR,
                SLEPC_VERSION_MINOR, SLEPC_VERSION_SUBMINOR, H5_VERS_MAJOR, H5_VERS_MINOR, H5_VERS_RELEASE,
                EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION, mpi_line.c_str());
  return buf;
}

CommandLine parse_command_line(int argc, const char* const* argv) {
  if (argc < 2) return failure("no command\n" + usage_text());
  const std::string first = argv[1];
  if (first == "--version" || first == "-V" || first == "version") return printed(version_text());
  if (first == "--help" || first == "-h" || first == "help") {
    if (argc > 2) {
      const std::string help = command_help(argv[2]);
      if (help.empty()) return failure(std::string("unknown command '") + argv[2] + "'");
      return printed(help);
    }
    return printed(usage_text());
  }
  CommandLine cl;
  cl.action = CommandLine::Action::execute;
  bool petsc_help = false;
  int i = 2;
  if (first == "-help") {  // PETSc's help without a command
    petsc_help = true;
    i = 1;
  } else if (!find_command(first)) {
    const std::string guess = closest_match(first, command_names());
    return failure("unknown " + std::string(first[0] == '-' ? "option" : "command") + " '" + first + "'" +
                   (guess.empty() ? "" : "; did you mean '" + guess + "'?") + " (latticedyn --help lists the commands)");
  } else {
    cl.command = first;
  }
  const CommandSpec* spec = find_command(cl.command);
  for (; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") return printed(spec ? command_help(cl.command) : usage_text());
    if (arg.rfind("--", 0) == 0) {
      const OptionSpec* option = find_option(arg);
      if (!option) {
        std::vector<std::string> names;
        for (const OptionSpec& o : kOptions)
          if (spec && takes(*spec, o.name)) names.emplace_back(o.name);
        const std::string guess = closest_match(arg, names);
        return failure("unknown option '" + arg + "'" + (spec ? " for '" + cl.command + "'" : "") +
                       (guess.empty() ? "" : "; did you mean '" + guess + "'?") + " (latticedyn " + cl.command +
                       " --help lists its options)");
      }
      if (!spec || !takes(*spec, arg)) {
        std::vector<const char*> names;
        for (const CommandSpec& c : commands())
          if (takes(c, arg)) names.push_back(c.name);
        std::string owners;
        for (std::size_t k = 0; k < names.size(); ++k) {
          if (k > 0) owners.append(k + 1 == names.size() ? " or " : ", ");
          owners.append("'").append(names[k]).append("'");
        }
        return failure(arg + " belongs to " + owners + ", not to '" + cl.command + "'");
      }
      const char* value = nullptr;
      if (option->value) {
        if (i + 1 >= argc) return failure(arg + " needs a value: " + arg + " " + option->value);
        value = argv[++i];
      }
      if (arg == "--output") {
        cl.options.output_directory = value;
      } else if (arg == "--modes" || arg == "--groups") {
        int n = 0;
        if (!positive_int(value, &n)) return failure(arg + " needs a positive number, not '" + value + "'");
        (arg == "--modes" ? cl.options.modes : cl.options.groups) = n;
      } else if (arg == "--restart") {
        cl.options.restart = value;
      } else if (arg == "--retry-failed") {
        cl.options.retry_failed = true;
      }
      continue;
    }
    if (i == 2 && arg[0] != '-') {
      cl.options.model_path = arg;  // right after the command, so option values are never taken for it
      continue;
    }
    if (arg == "-help") petsc_help = true;
    cl.petsc_args.push_back(arg);
  }
  if (cl.options.model_path.empty()) {
    if (petsc_help) {
      cl.action = CommandLine::Action::petsc_help;
      return cl;
    }
    return failure("'" + cl.command + "' needs a " + (cl.command == "batch" ? "batch" : cl.command == "control" ? "control" : "model") +
                   " file right after it (latticedyn " + cl.command + " --help)");
  }
  return cl;
}

PetscErrorCode register_latticedyn_options(MPI_Comm comm) {
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "latticedyn's own options", "latticedyn");
  PetscInt threads = 0, dense = GeneralizedAlphaIntegrator::kDenseBelow, rank = -1, block_size = 6;
  PetscReal after = ProgressObserver::kDefaultAfter, interval = ProgressObserver::kDefaultInterval, slow = 0.0;
  PetscBool blocks = PETSC_TRUE, predictor = PETSC_TRUE, collective = PETSC_TRUE;
  PetscCall(PetscOptionsInt("-assembly_threads", "threads evaluating elements per rank (default: OMP_NUM_THREADS on 1 rank, 1 on several)",
                            "latticedyn", threads, &threads, nullptr));
  PetscCall(PetscOptionsReal("-progress_after", "seconds of wall time before the progress line appears", "latticedyn",
                             after, &after, nullptr));
  PetscCall(PetscOptionsReal("-progress_interval", "seconds between progress lines (default 0.5 on a terminal, 5 in a log)",
                             "latticedyn", interval, &interval, nullptr));
  PetscCall(PetscOptionsInt("-dyn_dense_below", "generalized-alpha: systems of at most this many unknowns are factored dense (0: never)",
                            "latticedyn", dense, &dense, nullptr));
  PetscCall(PetscOptionsBool("-dyn_block_matrix", "generalized-alpha: 3 x 3 block matrices where every unknown is in a block of three",
                             "latticedyn", blocks, &blocks, nullptr));
  PetscCall(PetscOptionsInt("-dyn_block_size", "generalized-alpha: the largest block: 6 (a node's translation and rotation, where they lie side by side), 3, or 1 (none)",
                            "latticedyn", block_size, &block_size, nullptr));
  PetscCall(PetscOptionsBool("-dyn_predictor", "generalized-alpha: Newton starts from a Taylor guess", "latticedyn",
                             predictor, &predictor, nullptr));
  PetscCall(PetscOptionsBool("-output_collective", "on several ranks: every rank writes its part of the results (MPI-IO); 0: rank 0 writes all",
                             "latticedyn", collective, &collective, nullptr));
  PetscCall(PetscOptionsInt("-fault_injection_rank", "testing aid: an error on this rank at the first step", "latticedyn",
                            rank, &rank, nullptr));
  PetscCall(PetscOptionsReal("-fault_slow_steps", "testing aid: seconds of sleep after each step", "latticedyn", slow,
                             &slow, nullptr));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

std::vector<std::string> option_names(const std::vector<std::string>& words) {
  std::vector<std::string> names;
  for (const std::string& w : words)
    if (w.size() > 1 && w[0] == '-' && !(w[1] >= '0' && w[1] <= '9') && w[1] != '.') names.push_back(w.substr(1));
  return names;
}

std::vector<std::string> option_names(const std::string& options) {
  std::vector<std::string> words;
  std::size_t i = 0;
  while (i < options.size()) {
    const std::size_t start = options.find_first_not_of(" \t\n", i);
    if (start == std::string::npos) break;
    const std::size_t end = options.find_first_of(" \t\n", start);
    words.push_back(options.substr(start, end - start));
    i = end == std::string::npos ? options.size() : end;
  }
  return option_names(words);
}

std::string unused_options_report(const std::vector<std::string>& given) {
  PetscInt n = 0;
  char** names = nullptr;
  char** values = nullptr;
  if (PetscOptionsLeftGet(nullptr, &n, &names, &values) != 0) return "";
  // Read by PETSc at start-up or at PetscFinalize, after this report: not unused.
  static const char* const kLate[] = {"log",     "malloc", "memory_view", "options_", "objects_dump", "checkstack",
                                      "no_signal_handler", "on_error", "fp_trap", "info", "history", "help",
                                      "version", "nox",    "display",     "skip_petscrc", "vecscatter_mpi1", "saws"};
  std::string report;
  for (PetscInt k = 0; k < n; ++k) {
    const std::string name = names[k];
    if (std::find(given.begin(), given.end(), name) == given.end()) continue;  // set by latticedyn itself
    if (std::any_of(std::begin(kLate), std::end(kLate), [&](const char* p) { return name.rfind(p, 0) == 0; })) continue;
    report += "latticedyn: warning: option -" + name + (values[k] ? std::string(" ") + values[k] : "") +
              " was not used (mistyped, or not for this command or solver)\n";
  }
  PetscOptionsLeftRestore(nullptr, &n, &names, &values);
  return report;
}

}  // namespace latticedyn
