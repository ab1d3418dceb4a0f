// The latticedyn command as a user meets it: exit codes, one-line input errors with file:line and
// key and no output written, results written and readable, solver failures reported with where
// they happened and the results up to then kept, and no hang on several MPI ranks.
#include "command_runner.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <sys/stat.h>
#include <sys/wait.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

namespace {

namespace fs = std::filesystem;

using latticedyn::testing::Outcome;
using latticedyn::testing::slurp;

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("latticedyn_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  Outcome run(const std::string& args, const std::string& launcher = "") {
    return latticedyn::testing::run_in(dir_, LATTICEDYN_EXE, args, launcher, 120);
  }
  fs::path dir_;
};

const char* kPendulum = R"(title: pendulum
gravity: [0, 0, -9.81]
ground:
  joints:
    - {name: pivot, position: [0, 0, 0]}
bodies:
  - name: rod
    type: rigid_body
    mass: 2.0
    centroid: [0, 0, -0.5]
    inertia: [0.17, 0.17, 0.001]
    rotation_deg: [0, 20, 0]
    joints:
      - {name: pivot, position: [0, 0, 0]}
      - {name: tip, position: [0, 0, -1]}
constraints:
  - {name: hinge, type: revolute, axis: y, joints: [ground.pivot, rod.pivot]}
solver:
  dynamics: {t_end: 0.2, time_step: 0.01}
output:
  interval: 0.05
  probes: [rod.tip]
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos) ADD_FAILURE() << "anchor '" << from << "' missing";
  else text.replace(at, from.size(), to);
  return text;
}

TEST_F(Cli, RunWritesReadableResults) {
  write("pendulum.yaml", kPendulum);
  const Outcome o = run("run pendulum.yaml --output out");
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  EXPECT_NE(o.out.find("dynamics completed"), std::string::npos) << o.out;
  // 22 unknowns: factored dense, and the summary says so.
  EXPECT_NE(o.out.find("linear solver: dense LU (LAPACK)"), std::string::npos) << o.out;
  for (const char* f : {"out/pendulum.h5", "out/pendulum.xdmf", "out/pendulum_probes.csv"})
    EXPECT_TRUE(fs::exists(dir_ / f)) << f;
  // 0, 0.05, ..., 0.2: five outputs, plus the CSV header.
  const std::string csv = slurp(dir_ / "out/pendulum_probes.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 6) << csv;
}

TEST_F(Cli, ModesGivesThePendulumFrequencyAndWritesTheShapes) {
  write("pendulum.yaml", kPendulum);
  const Outcome o = run("modes pendulum.yaml --modes 1 --output out");
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  // Small swings of a physical pendulum about its hanging equilibrium: omega^2 = m g d / I_O
  // with I_O = I_c + m d^2 (d = 0.5 m, I_c = 0.17 kg m^2 about y, m = 2 kg).
  const double omega2 = 2.0 * 9.81 * 0.5 / (0.17 + 2.0 * 0.25);
  const std::string csv = slurp(dir_ / "out/pendulum_modes.csv");
  std::istringstream lines(csv);
  std::string header, row;
  std::getline(lines, header);
  ASSERT_TRUE(std::getline(lines, row)) << csv;
  int mode = 0;
  double hz = 0.0, w2 = 0.0;
  ASSERT_EQ(std::sscanf(row.c_str(), "%d,%lf,%lf", &mode, &hz, &w2), 3) << row;
  EXPECT_EQ(mode, 1);
  EXPECT_NEAR(w2, omega2, 1e-6 * omega2);
  EXPECT_NEAR(hz, std::sqrt(omega2) / (2.0 * M_PI), 1e-6);
  // Its own files, beside a run's results instead of over them.
  EXPECT_TRUE(fs::exists(dir_ / "out/pendulum_modes.xdmf"));
  EXPECT_FALSE(fs::exists(dir_ / "out/pendulum.h5"));
  EXPECT_NE(o.out.find("modes: wall "), std::string::npos) << o.out;
  EXPECT_EQ(run("modes pendulum.yaml --modes 0").code, 2);
}

// Linearized buckling from the command line: Euler's fixed-free column (Timoshenko & Gere, Theory
// of Elastic Stability, 1961, 2.1), P_cr = pi^2 EI / (4 L^2) with EI of a solid rod of radius
// 0.05 m, 10 m long; 20 elements put it within 0.1 % (shear lowers it by 0.005 %).
TEST_F(Cli, BucklingGivesEulersLoadAndWritesTheModes) {
  write("column.yaml", R"(
gravity: [0, 0, 0]
materials:
  steel: {density: 7800, youngs_modulus: 2.06e11, poisson_ratio: 0.3}
ground:
  joints: [{name: foot}]
bodies:
  - {name: column, type: timoshenko_beam, material: steel, section: {type: round_tube, outer_radius: 0.05},
     ends: [[0, 0, 0], [10, 0, 0]], elements: 20}
constraints:
  - {name: clamp, type: fixed, joints: [ground.foot, column.1]}
loads:
  - {name: head, joint: column.2, force: [-1.0e4, 0, 0]}
)");
  const Outcome o = run("buckling column.yaml --modes 3 --output out");
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  const double pcr = M_PI * M_PI * 2.06e11 * (M_PI * std::pow(0.05, 4) / 4) / (4 * 100.0);
  const std::string csv = slurp(dir_ / "out/column_buckling.csv");
  std::istringstream lines(csv);
  std::string header, row;
  std::getline(lines, header);
  EXPECT_EQ(header, "mode,load_factor");
  for (int k = 1; k <= 2; ++k) {  // the round rod buckles in either plane at the same load
    ASSERT_TRUE(std::getline(lines, row)) << csv;
    int mode = 0;
    double factor = 0.0;
    ASSERT_EQ(std::sscanf(row.c_str(), "%d,%lf", &mode, &factor), 2) << row;
    EXPECT_EQ(mode, k);
    EXPECT_NEAR(factor, pcr / 1e4, 1e-3 * pcr / 1e4);
  }
  EXPECT_NE(o.out.find("critical load factor 2.49"), std::string::npos) << o.out;
  // The equilibrium and three modes, in their own files.
  const std::string xdmf = slurp(dir_ / "out/column_buckling.xdmf");
  EXPECT_NE(xdmf.find("<Time Value=\"3\""), std::string::npos) << xdmf;
  EXPECT_EQ(xdmf.find("<Time Value=\"4\""), std::string::npos) << xdmf;
  EXPECT_FALSE(fs::exists(dir_ / "out/column.h5"));
  EXPECT_EQ(run("buckling column.yaml --modes x").code, 2);
}

// The load-displacement path from the command line: the two-bar truss snaps through (its limit
// load 2960.5 N in closed form, Crisfield 1991, 1.2), the CSV holds the path with the apex's
// displacement, the output names both limit points; bad path settings are an input error.
TEST_F(Cli, PathPassesTheLimitPointsAndWritesTheCurve) {
  const Outcome o = run(std::string("path ") + TWO_BAR_TRUSS + " --output out");
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  EXPECT_NE(o.out.find("limit point: maximum load factor 2.960"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("limit point: minimum load factor -2.960"), std::string::npos) << o.out;
  const std::string csv = slurp(dir_ / "out/path_two_bar_truss_path.csv");
  std::istringstream lines(csv);
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header, "step,load_factor,iterations,arc_length,u_apex.pin.x [m],u_apex.pin.y [m],u_apex.pin.z [m]");
  EXPECT_GT(std::count(csv.begin(), csv.end(), '\n'), 150);
  EXPECT_TRUE(fs::exists(dir_ / "out/path_two_bar_truss_path.xdmf"));
  write("bad.yaml", slurp(TWO_BAR_TRUSS) + "\n");
  std::string text = slurp(dir_ / "bad.yaml");
  text.replace(text.find("max_load_factor: 4"), 18, "max_load_factor: -2e30");
  write("bad.yaml", text);
  const Outcome bad = run("path bad.yaml --output out2");
  EXPECT_EQ(bad.code, 2) << bad.out << bad.err;
  EXPECT_NE(bad.err.find("min_load_factor below max_load_factor"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir_ / "out2"));
}

// The eigenanalyses of a saddle-point lattice on two ranks: MUMPS under SLEPc's "st_" prefix gets
// the working space the other solvers get (it ran out, INFOG(1) = -9, on the full main boom), and
// the load factors and frequencies are those of one rank.
TEST_F(Cli, BucklingAndModesOfTheFullBoomOnTwoRanks) {
  const std::string two = latticedyn::testing::mpiexec(MPIEXEC, 2);
  for (const char* command : {"buckling", "modes"}) {
    const Outcome one = run(std::string(command) + " " + MAIN_BOOM_COLUMN + " --modes 2 --output one");
    const Outcome par = run(std::string(command) + " " + MAIN_BOOM_COLUMN + " --modes 2 --output two", two);
    ASSERT_EQ(one.code, 0) << one.out << one.err;
    ASSERT_EQ(par.code, 0) << par.out << par.err;
    const std::string file = std::string("buckling_main_boom_") + command + ".csv";
    std::istringstream a(slurp(dir_ / "one" / file)), b(slurp(dir_ / "two" / file));
    std::string ra, rb;
    std::getline(a, ra);
    std::getline(b, rb);
    for (int k = 0; k < 2; ++k) {
      ASSERT_TRUE(std::getline(a, ra) && std::getline(b, rb)) << command;
      const double va = std::stod(ra.substr(ra.find(',') + 1)), vb = std::stod(rb.substr(rb.find(',') + 1));
      EXPECT_NEAR(vb, va, 1e-6 * std::abs(va)) << command << " mode " << k + 1;
    }
  }
}

// The command line as PETSc and other simulation codes' users expect it: version and help (nothing
// is run), a suggestion for a mistyped command or option (an error, nothing written), latticedyn's
// own options in PETSc's -help, and options no solver read reported at the end.
TEST_F(Cli, CommandLineHelpVersionAndMistakes) {
  write("pendulum.yaml", kPendulum);
  const Outcome version = run("--version");
  EXPECT_EQ(version.code, 0);
  EXPECT_EQ(version.out.rfind("latticedyn 0.", 0), 0u) << version.out;
  EXPECT_NE(version.out.find("PETSc 3."), std::string::npos) << version.out;
  const Outcome help = run("--help");
  EXPECT_EQ(help.code, 0);
  for (const char* c : {"check", "static", "run", "modes", "batch", "control"})
    EXPECT_NE(help.out.find(std::string("  ") + c + " "), std::string::npos) << c << "\n" << help.out;
  const Outcome run_help = run("run --help");
  EXPECT_EQ(run_help.code, 0);
  EXPECT_NE(run_help.out.find("--restart FILE[:STEP]"), std::string::npos) << run_help.out;
  EXPECT_NE(run("help modes").out.find("--modes N"), std::string::npos);
  // --help after a model: the help, nothing run or written.
  const Outcome static_help = run("static pendulum.yaml --output out --help");
  EXPECT_EQ(static_help.code, 0);
  EXPECT_FALSE(fs::exists(dir_ / "out")) << static_help.out;

  struct Mistake {
    std::string args, message;
  };
  for (const Mistake& m : {Mistake{"rn pendulum.yaml", "unknown command 'rn'; did you mean 'run'?"},
                           Mistake{"run pendulum.yaml --outptu out", "unknown option '--outptu' for 'run'; did you mean '--output'?"},
                           Mistake{"run pendulum.yaml --modes 3", "--modes belongs to 'modes' or 'buckling', not to 'run'"},
                           Mistake{"modes pendulum.yaml --modes 3x", "--modes needs a positive number, not '3x'"},
                           Mistake{"run pendulum.yaml --output", "--output needs a value"}}) {
    const Outcome o = run(m.args);
    EXPECT_EQ(o.code, 2) << m.args;
    EXPECT_NE(o.err.find(m.message), std::string::npos) << m.args << ": " << o.err;
    EXPECT_FALSE(fs::exists(dir_ / "out")) << m.args;
    EXPECT_FALSE(fs::exists(dir_ / "results")) << m.args;
  }

  // PETSc's -help with and without a model lists latticedyn's own options with their help.
  for (const char* args : {"-help", "run -help", "run pendulum.yaml --output out -help"}) {
    const Outcome o = run(args);
    EXPECT_EQ(o.code, 0) << args << o.err;
    EXPECT_NE(o.out.find("-assembly_threads"), std::string::npos) << args << o.out;
    EXPECT_NE(o.out.find("seconds of wall time before the progress line appears"), std::string::npos) << args;
  }

  // Options no solver read are reported; those read are not; a static run ends with its wall time.
  write("opts.yaml", "base: pendulum.yaml\nsolver: {static: {}, dynamics: {t_end: 0.2, time_step: 0.01}, "
                     "petsc_options: '-snes_max_it 50 -ksp_typo gmres'}\n");
  const Outcome o = run("static opts.yaml --output out -snes_typo 1 -snes_rtol 1e-9 -ts_max_time 1");
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.err.find("option -snes_typo 1 was not used"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("option -ksp_typo gmres was not used"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("option -ts_max_time 1 was not used"), std::string::npos) << "no dynamics in static: " << o.err;
  EXPECT_EQ(o.err.find("-snes_max_it"), std::string::npos) << o.err;
  EXPECT_EQ(o.err.find("-snes_rtol"), std::string::npos) << o.err;
  EXPECT_NE(o.out.find("static equilibrium found"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("; wall "), std::string::npos) << o.out;
}

// stdout and stderr in one log keep their order (stdout is line-buffered); the progress line
// counts to -ts_max_time when it ends the run early.
TEST_F(Cli, OneLogKeepsTheOrderOfItsLines) {
  write("pendulum.yaml", kPendulum);
  const Outcome o = latticedyn::testing::run_in(
      dir_, "sh", std::string("-c '") + LATTICEDYN_EXE + " run pendulum.yaml --output out -snes_max_it 1 > log.txt 2>&1'");
  EXPECT_EQ(o.code, 1);
  const std::string log = slurp(dir_ / "log.txt");
  const auto model = log.find("model 'pendulum'"), error = log.find("latticedyn: error: dynamics stopped"),
             summary = log.find("dynamics FAILED");
  ASSERT_NE(model, std::string::npos) << log;
  ASSERT_NE(error, std::string::npos) << log;
  ASSERT_NE(summary, std::string::npos) << log;
  EXPECT_LT(model, error) << log;
  EXPECT_LT(error, summary) << log;
  write("long.yaml", replaced(kPendulum, "t_end: 0.2", "t_end: 1000"));
  const Outcome p = run("run long.yaml --output out2 -ts_max_time 0.1 -progress_after 0 -progress_interval 0");
  EXPECT_EQ(p.code, 0) << p.err;
  EXPECT_NE(p.err.find("t = 0.1 / 0.1 s (100.0%)"), std::string::npos) << p.err;
}

// -static_... options reach the static solver alone, -dyn_... the dynamic one, plain ones both;
// including options read while solving (-ts_view).
TEST_F(Cli, SolverPrefixesSeparateStaticsFromDynamics) {
  write("both.yaml", replaced(kPendulum, "solver:\n", "solver:\n  static: {enabled: true}\n"));
  const Outcome statics = run("run both.yaml --output a -static_snes_max_it 1");
  EXPECT_EQ(statics.code, 1) << statics.out << statics.err;
  EXPECT_NE(statics.err.find("static equilibrium failed"), std::string::npos) << statics.err;
  EXPECT_EQ(statics.err.find("was not used"), std::string::npos) << statics.err;
  // From the equilibrium nothing moves: one Newton iteration a step is enough, statics unharmed.
  const Outcome not_static = run("run both.yaml --output b -dyn_snes_max_it 1");
  EXPECT_EQ(not_static.code, 0) << not_static.out << not_static.err;
  EXPECT_NE(not_static.out.find("static equilibrium found"), std::string::npos) << not_static.out;
  write("pendulum.yaml", kPendulum);  // no statics: the swing needs more than one iteration a step
  const Outcome dynamics = run("run pendulum.yaml --output d -dyn_snes_max_it 1 -dyn_ts_view");
  EXPECT_EQ(dynamics.code, 1) << dynamics.out << dynamics.err;
  EXPECT_NE(dynamics.err.find("dynamics stopped"), std::string::npos) << dynamics.err;
  EXPECT_NE(dynamics.out.find("type: alpha2"), std::string::npos) << dynamics.out;
  const Outcome plain = run("run both.yaml --output c -snes_max_it 1");
  EXPECT_EQ(plain.code, 1) << plain.out << plain.err;
  EXPECT_NE(plain.err.find("static equilibrium failed"), std::string::npos) << plain.err;
}

TEST_F(Cli, CheckDescribesAValidModel) {
  write("pendulum.yaml", kPendulum);
  const Outcome o = run("check pendulum.yaml");
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("the model is valid"), std::string::npos) << o.out;
  EXPECT_FALSE(fs::exists(dir_ / "results")) << "check writes nothing";
}

struct Bad {
  const char* from;
  const char* to;
  const char* where;  // "file:line:" prefix expected on stderr
  const char* key;
};

TEST_F(Cli, BadInputGivesFileLineKeyExitCodeTwoAndNoOutput) {
  const Bad cases[] = {
      {"  - name: rod\n", "  - name: [rod\n", "bad.yaml:8:", "YAML syntax error"},          // syntax
      {"    mass: 2.0\n", "    mass: 2.0\n    mas: 1\n", "bad.yaml:10:", "bodies[0].mas"},  // unknown key
      {"    mass: 2.0\n", "", "bad.yaml:7:", "bodies[0]: missing required key 'mass'"},      // missing field
      {"    mass: 2.0\n", "    mass: -2.0\n", "bad.yaml:9:", "bodies[0].mass"},            // meaningless value
      {"time_step: 0.01", "time_step: -0.01", "bad.yaml:19:", "solver.dynamics.time_step"},  // non-positive step
      {"rod.pivot]", "rod.knee]", "bad.yaml:17:", "constraints[0].joints[1]"},              // dangling reference
      {"rotation_deg: [0, 20, 0]", "axis_angle: {axis: [0, 0, 0], angle_deg: 20}", "bad.yaml:12:",
       "bodies[0].axis_angle.axis"},                                                        // zero-length axis
      {"    mass: 2.0\n    centroid: [0, 0, -0.5]\n    inertia: [0.17, 0.17, 0.001]\n",
       "    section: {type: round_tube, outer_radius: 0.05}\n    material: {density: 7800, youngs_modulus: 2e11, "
       "poisson_ratio: 0.3}\n    length: -1\n",
       "bad.yaml:11:", "bodies[0].length"},                                                 // negative length
  };
  for (const Bad& b : cases) {
    write("bad.yaml", replaced(kPendulum, b.from, b.to));
    for (const char* cmd : {"check", "run"}) {
      const Outcome o = run(std::string(cmd) + " bad.yaml --output out");
      EXPECT_EQ(o.code, 2) << cmd << " " << b.key << ": " << o.err;
      EXPECT_EQ(o.err.rfind(std::string("latticedyn: error: ") + b.where, 0), 0u) << o.err;
      EXPECT_NE(o.err.find(b.key), std::string::npos) << o.err;
      EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << "one line: " << o.err;
      EXPECT_FALSE(fs::exists(dir_ / "out")) << "no output for bad input";
    }
  }
}

TEST_F(Cli, UsageErrorsExitWithTwo) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("fly model.yaml").code, 2);
  EXPECT_EQ(run("run").code, 2);
  const Outcome missing = run("run nowhere.yaml");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("nowhere.yaml"), std::string::npos) << missing.err;
}

// The last step's n rows of three of a (T, n, 3) dataset of a results file.
std::vector<double> last_rows(const fs::path& file, const char* name, std::size_t n) {
  const std::vector<double> all = latticedyn::testing::dataset(file, name);
  if (all.size() < 3 * n) return {};
  return {all.end() - static_cast<std::ptrdiff_t>(3 * n), all.end()};
}

// Constraint reactions in the results, against statics by hand: a rod clamped at one end carries
// its weight m g and the moment m g c about the clamp (c the centroid's distance); a bob hung from
// a ball joint, its weight and no moment.
TEST_F(Cli, StaticReactionsCarryTheWeights) {
  write("reactions.yaml", R"(title: reactions
gravity: [0, 0, -9.81]
ground:
  joints:
    - {name: wall, position: [0, 0, 0]}
    - {name: pivot, position: [5, 0, 0]}
bodies:
  - {name: arm, type: rigid_body, mass: 3.0, centroid: [1.2, 0, 0], inertia: [0.1, 0.5, 0.5],
     joints: [{name: root, position: [0, 0, 0]}]}
  - {name: bob, type: rigid_body, mass: 2.0, centroid: [5, 0, -1], inertia: [0.01, 0.01, 0.01],
     joints: [{name: top, position: [5, 0, 0]}]}
constraints:
  - {name: clamp, type: fixed, joints: [ground.wall, arm.root]}
  - {name: hinge, type: spherical, joints: [ground.pivot, bob.top]}
)");
  const Outcome o = run("static reactions.yaml --output out");
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  const fs::path h5 = dir_ / "out/reactions.h5";
  const std::vector<double> force = last_rows(h5, "/constraints/reaction_force", 2);
  const std::vector<double> moment = last_rows(h5, "/constraints/reaction_moment", 2);
  const std::vector<double> point = last_rows(h5, "/constraints/position", 2);
  const std::vector<double> weight{0, 0, 3.0 * 9.81, 0, 0, 2.0 * 9.81};
  const std::vector<double> clamp_moment{0, -3.0 * 9.81 * 1.2, 0, 0, 0, 0};  // c x (-m g e_z), reversed
  const std::vector<double> at{0, 0, 0, 5, 0, 0};
  ASSERT_EQ(force.size(), 6u);
  ASSERT_EQ(moment.size(), 6u);
  ASSERT_EQ(point.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(force[i], weight[i], 1e-9) << i;
    EXPECT_NEAR(moment[i], clamp_moment[i], 1e-9) << i;
    EXPECT_NEAR(point[i], at[i], 1e-12) << i;
  }
  const std::string xdmf = slurp(dir_ / "out/reactions.xdmf");
  EXPECT_NE(xdmf.find("<Attribute Name=\"reaction_force [N]\""), std::string::npos);
}

TEST_F(Cli, DynamicFailureSaysWhereAndKeepsResults) {
  write("pendulum.yaml", kPendulum);
  // One Newton iteration per step cannot converge: the run must stop and say so.
  const Outcome o = run("run pendulum.yaml --output out -snes_max_it 1");
  EXPECT_EQ(o.code, 1) << o.out << o.err;
  EXPECT_NE(o.err.find("latticedyn: error: dynamics stopped at t = "), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("Newton"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("largest violation"), std::string::npos) << o.err;
  EXPECT_NE(o.out.find("results: "), std::string::npos) << o.out;
  // The results written so far (the initial state) are readable.
  const hid_t f = H5Fopen((dir_ / "out/pendulum.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, "/time", H5P_DEFAULT);
  ASSERT_GE(d, 0);
  const hid_t s = H5Dget_space(d);
  hsize_t n = 0;
  H5Sget_simple_extent_dims(s, &n, nullptr);
  EXPECT_GE(n, 1u);
  H5Sclose(s);
  H5Dclose(d);
  H5Fclose(f);
}

TEST_F(Cli, StaticFailureOfAnUnsupportedBodyIsReported) {
  // A free body under gravity has no equilibrium: the static solver must say so, not crash.
  write("free.yaml", replaced(kPendulum, "constraints:\n  - {name: hinge, type: revolute, axis: y, joints: [ground.pivot, rod.pivot]}\n", ""));
  const Outcome o = run("static free.yaml --output out");
  EXPECT_EQ(o.code, 1) << o.out << o.err;
  EXPECT_NE(o.err.find("latticedyn: error: static equilibrium failed"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("singular"), std::string::npos) << o.err;
}

// Bad input that once escaped as "internal error" (exit 3) or blocked: each is exit 2 with where.
TEST_F(Cli, InputThatIsNotAModelIsExitTwo) {
  write("pendulum.yaml", kPendulum);
  const std::string long_name(300, 'x');
  struct Case {
    std::string args, text, expected;
  } cases[] = {
      {"check " + dir_.string(), "", "must be a regular file"},                               // a directory
      {"check listkey.yaml", "[a, b]: 1\n", "listkey.yaml:1:1: a key must be a plain name"},  // a list as a key
      {"check nested.yaml", "title: t\nbodies:\n  - {? {a: 1} : 2}\n", "nested.yaml:3:"},  // a map as a key, deeper
      {"check longbase.yaml", "base: " + long_name + ".yaml\n", "longbase.yaml:1:7: base: no model file"},
      {"check steps.yaml", "base: pendulum.yaml\nsolver:\n  static: {load_steps: 2000000000}\n",
       "steps.yaml:3:24: solver.static.load_steps: expected 1 to 10000"},  // a static solve without end
  };
  for (const Case& c : cases) {
    if (!c.text.empty()) write(c.args.substr(6), c.text);
    const Outcome o = run(c.args);
    EXPECT_EQ(o.code, 2) << c.args << ": " << o.err;
    EXPECT_NE(o.err.find(c.expected), std::string::npos) << c.args << ": " << o.err;
  }
  ASSERT_EQ(::mkfifo((dir_ / "fifo.yaml").c_str(), 0600), 0);
  const Outcome fifo = run("check fifo.yaml");  // would block for ever in the YAML reader
  EXPECT_EQ(fifo.code, 2) << fifo.err;
  EXPECT_NE(fifo.err.find("regular file"), std::string::npos) << fifo.err;
}

// A model file is untrusted: its PETSc options may steer the solvers but not reach files; check
// applies none of them; output names stay in their folder.
TEST_F(Cli, ModelOptionsCannotReachFiles) {
  const std::string stolen = (dir_ / "written_by_the_model.txt").string();
  const std::string refused[] = {"-log_view :" + stolen, "-options_file /etc/passwd", "-ksp_view_mat binary:J.bin",
                                 "-snes_monitor_lg_residualnorm", "-ts_save_trajectory", "-info", "-log_view"};
  for (const std::string& options : refused) {
    write("opts.yaml", replaced(kPendulum, "solver:\n", "solver:\n  petsc_options: \"" + options + "\"\n"));
    for (const char* cmd : {"check", "run"}) {
      const Outcome o = run(std::string(cmd) + " opts.yaml --output out");
      EXPECT_EQ(o.code, 2) << options << ": " << o.err;
      EXPECT_NE(o.err.find("solver.petsc_options"), std::string::npos) << o.err;
      EXPECT_FALSE(fs::exists(stolen));
      EXPECT_FALSE(fs::exists(dir_ / "out"));
    }
  }
  // Allowed: solver settings and monitors on the terminal. check applies none: -options_left
  // from the model would report the unused -no_such_option at the end of a run, not of a check.
  write("opts.yaml", replaced(kPendulum, "solver:\n",
                              "solver:\n  petsc_options: \"-snes_monitor ascii -options_left -no_such_option 1\"\n"));
  const Outcome checked = run("check opts.yaml");
  EXPECT_EQ(checked.code, 0) << checked.err;
  EXPECT_EQ((checked.out + checked.err).find("no_such_option"), std::string::npos) << checked.out << checked.err;
  const Outcome ran = run("run opts.yaml --output out");
  EXPECT_EQ(ran.code, 0) << ran.err;
  EXPECT_NE((ran.out + ran.err).find("no_such_option"), std::string::npos) << ran.out << ran.err;
  EXPECT_NE(ran.out.find("SNES Function norm"), std::string::npos);
  // The command line is the user's own: a file there is fine.
  write("pendulum.yaml", kPendulum);
  EXPECT_EQ(run("run pendulum.yaml --output out2 -log_view :" + stolen).code, 0);
  EXPECT_TRUE(fs::exists(stolen));
  for (const char* name : {"..", ".", ".hidden", "a:b", "back\\\\slash"}) {
    write("named.yaml", replaced(kPendulum, "output:\n", std::string("output:\n  name: \"") + name + "\"\n"));
    const Outcome o = run("run named.yaml --output out3");
    EXPECT_EQ(o.code, 2) << name << ": " << o.err;
    EXPECT_NE(o.err.find("output.name"), std::string::npos) << o.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "out3"));
}

// Results never follow a symbolic link: a link at a result's name is replaced, its target kept.
TEST_F(Cli, ResultsReplaceSymbolicLinksInsteadOfWritingThroughThem) {
  write("pendulum.yaml", kPendulum);
  const fs::path target = write("precious.txt", "keep me\n");
  fs::create_directories(dir_ / "out");
  for (const char* name : {"pendulum.h5", "pendulum.xdmf", "pendulum_probes.csv", "pendulum.xdmf.tmp"})
    fs::create_symlink(target, dir_ / "out" / name);
  const Outcome o = run("run pendulum.yaml --output out");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_EQ(slurp(target), "keep me\n");
  for (const char* name : {"pendulum.h5", "pendulum.xdmf", "pendulum_probes.csv"})
    EXPECT_FALSE(fs::is_symlink(dir_ / "out" / name)) << name;
}

// Exit codes are 0, 1, 2, 3 only: a solver type PETSc does not know is bad input, found before
// anything is written; on two ranks too.
TEST_F(Cli, UnknownSolverTypesAreExitTwoWithNothingWritten) {
  write("pendulum.yaml", kPendulum);
  for (const char* option : {"-ts_type nonexistent", "-snes_type nonexistent", "-ksp_type nonexistent",
                             "-pc_type nonexistent", "-snes_linesearch_type nonexistent"}) {
    const Outcome o = run(std::string("run pendulum.yaml --output out ") + option);
    EXPECT_EQ(o.code, 2) << option << ": " << o.err;
    EXPECT_NE(o.err.find("unknown solver type 'nonexistent'"), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(dir_ / "out" / "pendulum.h5")) << option;
  }
  // latticedyn's own block size: 6, 3 or 1, said in one line.
  for (const char* option : {"-dyn_block_size 4", "-dyn_block_size six"}) {
    const Outcome o = run(std::string("run pendulum.yaml --output out ") + option);
    EXPECT_EQ(o.code, 2) << option << ": " << o.err;
    EXPECT_NE(o.err.find("-dyn_block_size"), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("expected 6"), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(dir_ / "out" / "pendulum.h5")) << option;
  }
  const Outcome two = run("run pendulum.yaml --output out -ts_type nonexistent", latticedyn::testing::mpiexec(MPIEXEC, 2));
  EXPECT_EQ(two.code, 2) << two.err;
  // A PETSc error past the checks (here an unknown sub-solver's type, met when the
  // preconditioner is set up) still ends with one of the four codes, PETSc's message kept.
  const Outcome deep = run("run pendulum.yaml --output out -pc_factor_mat_ordering_type nonexistent -dyn_dense_below 0");
  EXPECT_EQ(deep.code, 2) << deep.out << deep.err;
  EXPECT_NE(deep.err.find("PETSC ERROR"), std::string::npos) << deep.err;
  EXPECT_NE(deep.err.find("exit code 2"), std::string::npos) << deep.err;
}

// A rope paid in through zero length: check finds it at the drive's key; a run taken past the
// checked span (-ts_max_time) meets it as a domain error, cuts its step, and ends as a solver
// failure (exit 1) that names it, with its summary and the results up to then.
TEST_F(Cli, RopeRestLengthThroughZeroIsFoundByCheckOrEndsTheRunCleanly) {
  const std::string shortened = std::string("base: ") + ROPE_LOWERING +
                                "\ndrives:\n  pay_out: {type: trapezoidal, t_start: 1, duration: 10, accel_time: 2, "
                                "decel_time: 2, distance: -12, initial: 10}\n";
  write("through_zero.yaml", shortened + "solver:\n  static: {enabled: true}\n  dynamics: {t_end: 12, time_step: 0.005}\n");
  const Outcome checked = run("check through_zero.yaml");
  EXPECT_EQ(checked.code, 2) << checked.err;
  EXPECT_NE(checked.err.find("rest_length_drive: the drive takes the rope's rest length to"), std::string::npos)
      << checked.err;
  write("until_8.yaml", shortened + "solver:\n  static: {enabled: true}\n  dynamics: {t_end: 8, time_step: 0.005}\n");
  ASSERT_EQ(run("check until_8.yaml").code, 0);
  const Outcome o = run("run until_8.yaml --output out -ts_max_time 12");
  EXPECT_EQ(o.code, 1) << o.out << o.err;
  EXPECT_NE(o.err.find("outside its domain: rope rest length"), std::string::npos) << o.err;
  EXPECT_NE(o.out.find("dynamics FAILED"), std::string::npos) << o.out;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "until_8.h5"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "until_8.xdmf"));
}

// SIGINT or SIGTERM during a run: the step ends, the results and the summary are written, and the
// exit code says which signal (130, 143); on two ranks both stop after the same step.
TEST_F(Cli, SignalsEndTheRunWithResultsAndSummary) {
  write("long.yaml", replaced(replaced(kPendulum, "t_end: 0.2", "t_end: 100000"), "interval: 0.05", "interval: 10"));
  for (const auto& [signal, code] : {std::pair<std::string, int>{"INT", 130}, {"TERM", 143}}) {
    const std::string out = "out_" + signal;
    const Outcome o = run("run long.yaml --output " + out, "timeout --preserve-status -s " + signal + " 3");
    EXPECT_EQ(o.code, code) << signal << ": " << o.out << o.err;
    EXPECT_NE(o.out.find("dynamics INTERRUPTED"), std::string::npos) << o.out;
    EXPECT_NE(o.err.find("by SIG" + signal + "; results written up to there"), std::string::npos) << o.err;
    EXPECT_TRUE(fs::exists(dir_ / out / "long.xdmf"));
    const hid_t f = H5Fopen((dir_ / out / "long.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(f, 0) << "the results must be readable";
    const hid_t d = H5Dopen2(f, "/time", H5P_DEFAULT);
    const hid_t space = H5Dget_space(d);
    hsize_t n = 0;
    H5Sget_simple_extent_dims(space, &n, nullptr);
    EXPECT_GE(n, 2u) << "the first state and the one the run stopped at";
    H5Sclose(space);
    H5Dclose(d);
    H5Fclose(f);
  }
  // On two ranks mpiexec passes SIGTERM on to the ranks, stops forwarding their output and kills
  // them about a second later (Open MPI's odls_base_sigkill_timeout): the ranks stop together and
  // nothing hangs; what reaches the disk before the kill depends on the machine's load.
  const Outcome two = run("run long.yaml --output out_mpi",
                          "timeout --preserve-status -s TERM 4 " + latticedyn::testing::mpiexec(MPIEXEC, 2));
  EXPECT_NE(two.code, 124) << "the run hung: " << two.err;
  EXPECT_NE(two.code, 0) << two.out << two.err;
}

// A second SIGINT while the first waits for the step to end stops the run at once: steps of 8 s
// (-fault_slow_steps), the first signal a second after the setup line (the handler is in place
// then), which alone would end the run after the step (about 7 s later); the second 2.5 s after
// the first ends it there, killed by the signal (status 130 from the shell). The script times
// from the first signal: a slow start (the sanitizer build on a loaded machine takes seconds) must
// neither send the first signal before the handler exists nor count as the run's reaction, and
// the 2.5 s gap stays clear of the handler's one second in which a repeat counts as the same
// request.
TEST_F(Cli, ASecondSignalStopsTheRunAtOnce) {
  write("long.yaml", replaced(kPendulum, "t_end: 0.2", "t_end: 100000"));
  write("twice.sh", std::string(LATTICEDYN_EXE) +
                        " run long.yaml --output out -fault_slow_steps 8 > ld_out.txt 2> ld_err.txt &\n"
                        "pid=$!\n"
                        "i=0\n"
                        "while ! grep -q '^setup:' ld_out.txt 2>/dev/null && [ $i -lt 600 ]; do sleep 0.1; i=$((i+1)); done\n"
                        "sleep 1\n"
                        "date +%s.%N > first_signal.txt\n"
                        "kill -INT $pid\nsleep 2.5\nkill -INT $pid\nwait $pid\nstatus=$?\n"
                        "date +%s.%N > ended.txt\n"
                        "exit $status\n");
  const Outcome o = latticedyn::testing::run_in(dir_, "sh", "twice.sh", "", 90);
  const std::string out = slurp(dir_ / "ld_out.txt"), err = slurp(dir_ / "ld_err.txt");
  EXPECT_EQ(o.code, 130) << out << err;
  ASSERT_TRUE(fs::exists(dir_ / "first_signal.txt") && fs::exists(dir_ / "ended.txt")) << out << err;
  const double seconds = std::stod(slurp(dir_ / "ended.txt")) - std::stod(slurp(dir_ / "first_signal.txt"));
  EXPECT_LT(seconds, 5.0) << "from the first signal to the end; " << out << err;
  EXPECT_NE(err.find("again to stop at once"), std::string::npos) << err;
  EXPECT_EQ(out.find("dynamics INTERRUPTED"), std::string::npos) << "no summary after the second signal: " << out;
}

TEST_F(Cli, InputErrorOnTwoRanksEndsBothWithoutHanging) {
  write("bad.yaml", replaced(kPendulum, "    mass: 2.0\n", "    mass: -2.0\n"));
  // Open MPI refuses root without these (CI runs as root); 2 ranks on any machine.
  const Outcome o = run("run bad.yaml --output out", latticedyn::testing::mpiexec(MPIEXEC, 2));
  EXPECT_EQ(o.code, 2) << o.out << o.err;
  EXPECT_NE(o.err.find("bad.yaml:9:"), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(Cli, ErrorOnOneRankEndsTheRunOnAllRanks) {
  write("pendulum.yaml", kPendulum);
  // Rank 1 fails at its first step while rank 0 goes on into the next step's collective solve:
  // without the abort it would wait there for ever (the time limit would end it with 124).
  const Outcome o = run("run pendulum.yaml --output out -fault_injection_rank 1",
                        latticedyn::testing::mpiexec(MPIEXEC, 2));
  EXPECT_NE(o.code, 0) << o.out << o.err;
  EXPECT_NE(o.code, 124) << "the run hung: " << o.err;
  EXPECT_NE(o.err.find("fault injected on this rank"), std::string::npos) << o.err;
}

TEST_F(Cli, ProgressLineShowsTimeStepsAndEta) {
  write("pendulum.yaml", kPendulum);
  // From the first step on (instead of after a second of wall time), one line per step.
  const Outcome o = run("run pendulum.yaml --output out -progress_after 0 -progress_interval 0");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.err.find("t = 0.2 / 0.2 s (100.0%)  step 20"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("ETA"), std::string::npos) << o.err;
  EXPECT_GE(std::count(o.err.begin(), o.err.end(), '\n'), 20) << o.err;
  // Runs shorter than the default second show none.
  const Outcome quiet = run("run pendulum.yaml --output out2");
  EXPECT_EQ(quiet.err.find("ETA"), std::string::npos) << quiet.err;
  // Statics say so: the load level, increments, Newton iterations and residual.
  const Outcome statics = run("static pendulum.yaml --output out3 -progress_after 0 -progress_interval 0");
  ASSERT_EQ(statics.code, 0) << statics.err;
  EXPECT_NE(statics.err.find("statics: load 1 of 1 (0 increments in equilibrium, up to 0), Newton 1, residual"),
            std::string::npos)
      << statics.err;
}

TEST_F(Cli, StartsFromARecordedState) {
  write("pendulum.yaml", kPendulum);
  ASSERT_EQ(run("static pendulum.yaml --output out").code, 0);
  write("again.yaml", "base: pendulum.yaml\nstart_state: {file: out/pendulum.h5}\n");
  const Outcome o = run("static again.yaml --output out2");
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  // Already in equilibrium: no Newton iteration, or one that only polishes round-off.
  const int iterations = latticedyn::testing::static_newton_iterations(o.out);
  EXPECT_GE(iterations, 0) << o.out;
  EXPECT_LE(iterations, 1) << o.out;
  // The start is the recorded one: the hanging rod's tip straight below the pivot.
  const auto tip = latticedyn::testing::first_probe_position(dir_ / "out2/again_probes.csv");
  EXPECT_NEAR(tip[0], 0.0, 1e-9);
  EXPECT_NEAR(tip[2], -1.0, 1e-9);
}

TEST_F(Cli, BadStartStateGivesFileLineKeyExitCodeTwoAndNoOutput) {
  write("pendulum.yaml", kPendulum);
  ASSERT_EQ(run("static pendulum.yaml --output rec").code, 0);
  // A spherical hinge has 3 multipliers instead of 5: the recorded state does not fit.
  write("other.yaml", replaced(kPendulum, "type: revolute, axis: y,", "type: spherical,"));
  const Bad cases[] = {
      {"", "start_state: {file: rec/none.h5}\n", "bad.yaml:2:", "start_state.file: '"},
      {"", "start_state: {file: pendulum.yaml}\n", "bad.yaml:2:", "not an HDF5 file"},
      {"", "start_state: {file: rec/pendulum.h5, step: 3}\n", "bad.yaml:2:", "start_state.step"},
      {"", "start_state: {path: rec/pendulum.h5}\n", "bad.yaml:2:", "start_state.path"},
  };
  for (const Bad& b : cases) {
    write("bad.yaml", std::string("base: pendulum.yaml\n") + b.to);
    const Outcome o = run("run bad.yaml --output out");
    EXPECT_EQ(o.code, 2) << b.key << ": " << o.err;
    EXPECT_EQ(o.err.rfind(std::string("latticedyn: error: ") + b.where, 0), 0u) << o.err;
    EXPECT_NE(o.err.find(b.key), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(dir_ / "out")) << "no output for bad input";
  }
  write("bad.yaml", "base: other.yaml\nstart_state: {file: rec/pendulum.h5}\n");
  const Outcome o = run("static bad.yaml --output out");
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("bad.yaml:2:"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("written by another model"), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(Cli, StaticLineSearchesAreOptions) {
  // Full Newton steps by default (docs/decisions/0002); every SNES line search by option, with
  // the same equilibrium: the rod hanging straight down.
  write("pendulum.yaml", kPendulum);
  for (const char* search : {"basic", "bt", "l2", "cp"}) {
    const std::string out = std::string("out_") + search;
    const Outcome o = run("static pendulum.yaml --output " + out + " -snes_linesearch_type " + search +
                          " -snes_view -options_left 0");
    ASSERT_EQ(o.code, 0) << search << ": " << o.out << o.err;
    EXPECT_NE(o.out.find(std::string("type: ") + search), std::string::npos) << search << ": " << o.out;
    const auto tip = latticedyn::testing::first_probe_position(dir_ / out / "pendulum_probes.csv");
    EXPECT_NEAR(tip[0], 0.0, 1e-8) << search;
    EXPECT_NEAR(tip[2], -1.0, 1e-8) << search;
  }
}

TEST_F(Cli, PetscOptionsReachTheSolvers) {
  write("pendulum.yaml", kPendulum);
  // The integrator, the direct solver chosen by option, and PETSc's performance log.
  const Outcome o = run("run pendulum.yaml --output out -ts_view -pc_factor_mat_solver_type klu -log_view -options_left 0");
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  EXPECT_NE(o.out.find("type: alpha2"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("klu"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("Performance Summary"), std::string::npos) << o.out;
  // An option nobody reads is reported by PETSc (-options_left), not silently dropped.
  const Outcome left = run("run pendulum.yaml --output out2 -ts_no_such_option 3 -options_left");
  EXPECT_EQ(left.code, 0) << left.err;
  EXPECT_NE((left.out + left.err).find("ts_no_such_option"), std::string::npos) << left.out << left.err;
}

// Four links in a chain: enough blocks for METIS to split them over two ranks, so the global
// numbering differs between 1 and 2 ranks.
const char* kChain = R"(title: chain
gravity: [0, 0, -9.81]
ground:
  joints: [{name: pivot}]
bodies:
  - {name: a, type: rigid_body, mass: 1, centroid: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1], rotation_deg: [0, 30, 0],
     joints: [{name: "1", position: [0, 0, 0]}, {name: "2", position: [1, 0, 0]}]}
  - {name: b, type: rigid_body, mass: 1, centroid: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1], position: [0.8660254037844387, 0, -0.5],
     rotation_deg: [0, 30, 0], joints: [{name: "1", position: [0, 0, 0]}, {name: "2", position: [1, 0, 0]}]}
  - {name: c, type: rigid_body, mass: 1, centroid: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1], position: [1.7320508075688772, 0, -1],
     rotation_deg: [0, 30, 0], joints: [{name: "1", position: [0, 0, 0]}, {name: "2", position: [1, 0, 0]}]}
  - {name: d, type: rigid_body, mass: 1, centroid: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1], position: [2.598076211353316, 0, -1.5],
     rotation_deg: [0, 30, 0], joints: [{name: "1", position: [0, 0, 0]}, {name: "2", position: [1, 0, 0]}]}
constraints:
  - {type: revolute, axis: y, joints: [ground.pivot, a.1]}
  - {type: revolute, axis: y, joints: [a.2, b.1]}
  - {type: revolute, axis: y, joints: [b.2, c.1]}
  - {type: revolute, axis: y, joints: [c.2, d.1]}
output:
  probes: [d.2]
)";

TEST_F(Cli, RecordedStatesMeanTheSameOnAnyNumberOfRanks) {
  write("chain.yaml", kChain);
  const std::string two = latticedyn::testing::mpiexec(MPIEXEC, 2);
  ASSERT_EQ(run("static chain.yaml --output rec1").code, 0);
  const Outcome o2 = run("static chain.yaml --output rec2", two);
  ASSERT_EQ(o2.code, 0) << o2.out << o2.err;
  // A state recorded on 2 ranks starts 1 rank at its equilibrium, and one recorded on 1 rank
  // starts 2 ranks there: no Newton iteration beyond a polish.
  write("from2.yaml", "base: chain.yaml\nstart_state: {file: rec2/chain.h5}\n");
  write("from1.yaml", "base: chain.yaml\nstart_state: {file: rec1/chain.h5}\n");
  const Outcome a = run("static from2.yaml --output a");
  ASSERT_EQ(a.code, 0) << a.out << a.err;
  EXPECT_LE(latticedyn::testing::static_newton_iterations(a.out), 1) << a.out;
  EXPECT_GE(latticedyn::testing::static_newton_iterations(a.out), 0) << a.out;
  const Outcome b = run("static from1.yaml --output b", two);
  ASSERT_EQ(b.code, 0) << b.out << b.err;
  EXPECT_LE(latticedyn::testing::static_newton_iterations(b.out), 1) << b.out;
  EXPECT_GE(latticedyn::testing::static_newton_iterations(b.out), 0) << b.out;
  // Both start where the 1-rank solve ended (Newton finds the equilibrium nearest the start).
  const auto ref = latticedyn::testing::first_probe_position(dir_ / "rec1/chain_probes.csv");
  for (const char* f : {"rec2/chain_probes.csv", "a/from2_probes.csv", "b/from1_probes.csv"}) {
    const auto p = latticedyn::testing::first_probe_position(dir_ / f);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(p[i], ref[i], 1e-8) << f << " component " << i;
  }
}

}  // namespace
