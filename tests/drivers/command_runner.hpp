// Running the latticedyn executable from tests: a command line in a folder, its exit code and
// what it printed, optionally under an MPI launcher; and reading what it wrote.
#pragma once

#include <hdf5.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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

/// Newton iterations of the "static equilibrium found: ..." summary line; -1 when there is none.
inline int static_newton_iterations(const std::string& out) {
  int increments = -1, iterations = -1;
  const auto at = out.find("static equilibrium found: ");
  if (at == std::string::npos ||
      std::sscanf(out.c_str() + at, "static equilibrium found: %d load increment(s), %d Newton", &increments,
                  &iterations) != 2)
    return -1;
  return iterations;
}

/// Position of the first probe in the first row of a probe CSV (time, x, y, z, ...); NaN if none.
inline std::array<double, 3> first_probe_position(const std::filesystem::path& csv) {
  const std::string text = slurp(csv);
  const auto row = text.find('\n');
  double t = 0;
  std::array<double, 3> p = {NAN, NAN, NAN};
  if (row == std::string::npos || std::sscanf(text.c_str() + row + 1, "%lf,%lf,%lf,%lf", &t, &p[0], &p[1], &p[2]) != 4)
    return {NAN, NAN, NAN};
  return p;
}

/// A whole dataset of a results file as doubles, row-major (empty if it cannot be read).
inline std::vector<double> dataset(const std::filesystem::path& file, const char* name) {
  std::vector<double> v;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return v;
  const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d >= 0) {
    const hid_t space = H5Dget_space(d);
    v.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0) v.clear();
    H5Sclose(space);
    H5Dclose(d);
  }
  H5Fclose(f);
  return v;
}

/// Two (or n) MPI ranks on any machine, also as root (CI): Open MPI refuses root without these.
inline std::string mpiexec(const std::string& launcher, int ranks) {
  return "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + launcher + " --oversubscribe -n " +
         std::to_string(ranks);
}

}  // namespace latticedyn::testing
