// Running the latticedyn executable from tests: a command line in a folder, its exit code and
// what it printed, optionally under an MPI launcher.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace latticedyn::testing {

struct Outcome {
  int code = -1;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// `launcher exe args` in `dir` with a time limit; stdout and stderr land in dir/out.txt, err.txt.
inline Outcome run_in(const std::filesystem::path& dir, const std::string& exe, const std::string& args,
                      const std::string& launcher = "", int timeout_seconds = 120) {
  const std::string cmd = "cd " + dir.string() + " && OMP_NUM_THREADS=1 timeout " + std::to_string(timeout_seconds) +
                          " " + launcher + " " + exe + " " + args + " > out.txt 2> err.txt";
  const int status = std::system(cmd.c_str());
  Outcome o;
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  o.out = slurp(dir / "out.txt");
  o.err = slurp(dir / "err.txt");
  return o;
}

/// Two (or n) MPI ranks on any machine, also as root (CI): Open MPI refuses root without these.
inline std::string mpiexec(const std::string& launcher, int ranks) {
  return "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + launcher + " --oversubscribe -n " +
         std::to_string(ranks);
}

}  // namespace latticedyn::testing
