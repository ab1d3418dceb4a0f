// Checkpoints and exact restart (issue 13): a run continued from a checkpoint repeats the rest of
// the uninterrupted run bit for bit (generalized-alpha with Jacobian reuse, on 1 and 2 ranks, and
// the Baumgarte route), an interrupted run leaves a checkpoint that continues, and every
// checkpoint that cannot continue the model (or results file of another format) is an input error
// that says why.
#include "command_runner.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using latticedyn::testing::Outcome;
using latticedyn::testing::slurp;
using latticedyn::testing::dataset;

class Restart : public ::testing::Test {
 public:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("latticedyn_restart_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  Outcome run(const std::string& args, const std::string& launcher = "") {
    return latticedyn::testing::run_in(dir_, LATTICEDYN_EXE, args, launcher, 300);
  }
  fs::path dir_;
};

// The same model as `name`_full and `name`_part, checkpoints every `interval` s.
void write_pair(Restart& t, const std::string& name, const std::string& base, double interval) {
  for (const char* which : {"full", "part"})
    t.write(name + "_" + which + ".yaml", "base: " + base + "\noutput: {directory: out, name: " + name + "_" + which +
                                              ", interval: 0, checkpoint_interval: " + std::to_string(interval) + "}\n");
}

// Run `name`_full to its end; run `name`_part until `stop` s (-ts_max_time), then continue it in
// its own results file from the checkpoint at step `step`: every recorded step, the probes and the
// summary's counts are the same as the uninterrupted run's, to the last bit.
void expect_bit_for_bit(Restart& t, const std::string& name, const std::string& stop, long step,
                        const std::string& launcher) {
  const Outcome full = t.run("run " + name + "_full.yaml", launcher);
  ASSERT_EQ(full.code, 0) << full.out << full.err;
  const Outcome part = t.run("run " + name + "_part.yaml -ts_max_time " + stop, launcher);
  ASSERT_EQ(part.code, 0) << part.out << part.err;
  const Outcome rest = t.run("run " + name + "_part.yaml --restart out/" + name + "_part.h5:" + std::to_string(step),
                             launcher);
  ASSERT_EQ(rest.code, 0) << rest.out << rest.err;
  const fs::path a = t.dir_ / "out" / (name + "_full.h5"), b = t.dir_ / "out" / (name + "_part.h5");
  for (const char* d : {"/time", "/state/coordinates", "/blocks/velocity", "/energy_total"}) {
    const std::vector<double> x = dataset(a, d), y = dataset(b, d);
    ASSERT_FALSE(x.empty()) << d;
    ASSERT_EQ(x.size(), y.size()) << d;
    std::size_t differ = 0;
    for (std::size_t i = 0; i < x.size(); ++i) differ += x[i] != y[i] ? 1 : 0;
    EXPECT_EQ(differ, 0u) << name << ": " << d << " differs in " << differ << " of " << x.size() << " entries";
  }
  EXPECT_EQ(slurp(t.dir_ / "out" / (name + "_full_probes.csv")), slurp(t.dir_ / "out" / (name + "_part_probes.csv")));
  // The summaries count the whole run: steps, Newton iterations, Jacobians.
  const auto counts = [](const std::string& out) { return out.substr(out.find("dynamics completed"), 120); };
  EXPECT_EQ(counts(full.out).substr(0, 90), counts(rest.out).substr(0, 90)) << full.out << rest.out;
}

TEST_F(Restart, TheCraneContinuesBitForBitWithJacobianReuse) {
  // Statics, then 2 s of slewing with h = 0.05 s and a Jacobian kept over up to 50 iterations;
  // checkpoints every 0.5 s; stopped at 1.3 s, continued from the checkpoint at 1.0 s (step 20).
  write_pair(*this, "crane", CRANE_SHORT, 0.5);
  expect_bit_for_bit(*this, "crane", "1.3", 20, "");
}

TEST_F(Restart, TheHangingChainContinuesBitForBitOnTwoRanks) {
  write_pair(*this, "chain", HANGING_CHAIN, 0.25);
  expect_bit_for_bit(*this, "chain", "0.6", 250, latticedyn::testing::mpiexec(MPIEXEC, 2));
}

TEST_F(Restart, TheBaumgarteRouteContinuesBitForBit) {
  write_pair(*this, "dpb", DOUBLE_PENDULUM_BAUMGARTE, 0.25);
  expect_bit_for_bit(*this, "dpb", "0.6", 500, "");
}

// The implicit Runge-Kutta route restarts its method at every checkpoint (ARKIMEX's short start
// step, then one step of 1e-4 h and one back onto the grid), in the run that writes the
// checkpoint as in the one continued from it: the checkpoint at 0.5 s is step 100 + 2.
TEST_F(Restart, TheImplicitRungeKuttaRouteContinuesBitForBit) {
  write_pair(*this, "dpi", DOUBLE_PENDULUM_IMPLICIT_RK, 0.25);
  expect_bit_for_bit(*this, "dpi", "0.6", 102, "");
}

// The minimum-DoF route rebuilds its joint coordinates from the stored poses at every checkpoint,
// as a run continued from it does, and ends its steps on the drives' breakpoints in both: the
// checkpoint at 0.5 s (also where slewing starts) is step 100 of h = 0.005 s.
TEST_F(Restart, TheMinimumDofRouteContinuesBitForBit) {
  write_pair(*this, "fold", FOLDING_BOOM, 0.25);
  expect_bit_for_bit(*this, "fold", "0.6", 100, "");
}

// SIGINT: the run stops after a step with a checkpoint there, which continues the run to its end.
TEST_F(Restart, AnInterruptedRunContinuesFromItsCheckpoint) {
  write("long.yaml", "base: " + std::string(DOUBLE_PENDULUM_BAUMGARTE) +
                         "\nsolver: {dynamics: {integrator: generalized_alpha, t_end: 100000, time_step: 0.001}}\n"
                         "output: {directory: out, name: long, interval: 1}\n");
  const Outcome o = run("run long.yaml", "timeout --preserve-status -s INT 3");
  ASSERT_EQ(o.code, 130) << o.out << o.err;
  long step = -1;
  double t = -1;
  const auto at = o.out.find("checkpoint: step ");
  ASSERT_NE(at, std::string::npos) << o.out;
  ASSERT_EQ(std::sscanf(o.out.c_str() + at, "checkpoint: step %ld, t = %lf s", &step, &t), 2) << o.out;
  const Outcome rest = run("run long.yaml --restart out/long.h5 -ts_max_time " + std::to_string(t + 0.5));
  ASSERT_EQ(rest.code, 0) << rest.out << rest.err;
  EXPECT_NE(rest.out.find("dynamics completed: " + std::to_string(step + 500) + " steps"), std::string::npos)
      << rest.out;
  // The results file goes on from the checkpoint: the last time is the new end.
  const std::vector<double> times = dataset(dir_ / "out/long.h5", "/time");
  ASSERT_FALSE(times.empty());
  EXPECT_NEAR(times.back(), t + 0.5, 1e-9);
  for (std::size_t i = 1; i < times.size(); ++i) ASSERT_LT(times[i - 1], times[i]) << "step " << i;
}

TEST_F(Restart, CheckpointsThatCannotContinueTheModelAreInputErrors) {
  write_pair(*this, "dpb", DOUBLE_PENDULUM_BAUMGARTE, 0.25);
  ASSERT_EQ(run("run dpb_part.yaml -ts_max_time 0.3").code, 0);
  ASSERT_EQ(run("static " + std::string(CRANE_SHORT) + " --output statics").code, 0);
  write("ga.yaml", "base: dpb_part.yaml\nsolver: {dynamics: {integrator: generalized_alpha, t_end: 1, time_step: 0.001}}\n");
  write("short.yaml", "base: dpb_part.yaml\nsolver: {dynamics: {integrator: baumgarte, t_end: 0.2, time_step: 0.001}}\n");
  write("crane.yaml", "base: " + std::string(CRANE_SHORT) + "\n");
  write("ga_own.yaml", "base: ga.yaml\noutput: {directory: out, name: ga}\n");
  ASSERT_EQ(run("run ga_own.yaml -ts_max_time 0.01").code, 0);
  struct Case {
    std::string args, message;
  };
  const Case cases[] = {
      {"run dpb_part.yaml --restart out/none.h5", "'out/none.h5': no such file"},
      {"run dpb_part.yaml --restart dpb_part.yaml", "not an HDF5 file"},
      {"run dpb_part.yaml --restart out/dpb_part.h5:7", "no checkpoint at step 7 (checkpoints at steps 250, 300)"},
      {"run dpb_part.yaml --restart statics/crane_short.h5", "no checkpoint: the run that wrote it"},
      {"run ga.yaml --restart out/dpb_part.h5", "written by the baumgarte integrator, the model asks for generalized_alpha"},
      {"run short.yaml --restart out/dpb_part.h5", "is not before the model's t_end = 0.2 s"},
      {"run crane.yaml --restart out/ga.h5 --output c", "it was written for another model"},
      {"static dpb_part.yaml --restart out/dpb_part.h5", "--restart belongs to 'run'"},
  };
  for (const Case& c : cases) {
    const Outcome o = run(c.args);
    EXPECT_EQ(o.code, 2) << c.args << "\n" << o.out << o.err;
    EXPECT_NE(o.err.find(c.message), std::string::npos) << c.args << "\n" << o.err;
  }
  // A results file of an earlier format (3: the members' values per drawn segment) cannot be
  // extended by this one; it is left as it was.
  write("old.yaml", "base: dpb_part.yaml\noutput: {directory: out, name: old, interval: 0, checkpoint_interval: 0.25}\n");
  fs::copy_file(dir_ / "out/dpb_part.h5", dir_ / "out/old.h5");
  {
    const hid_t f = H5Fopen((dir_ / "out/old.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const hid_t a = H5Aopen(f, "format_version", H5P_DEFAULT);
    const int three = 3;
    ASSERT_GE(H5Awrite(a, H5T_NATIVE_INT, &three), 0);
    H5Aclose(a);
    H5Fclose(f);
  }
  const std::size_t steps = dataset(dir_ / "out/old.h5", "/time").size();
  const Outcome old = run("run old.yaml --restart out/old.h5");
  EXPECT_EQ(old.code, 2) << old.out << old.err;
  EXPECT_NE(old.err.find("it is of results format 3, this latticedyn writes format 4"), std::string::npos) << old.err;
  EXPECT_EQ(dataset(dir_ / "out/old.h5", "/time").size(), steps);
}

// start_state is a pose, not a restart, and says so.
TEST_F(Restart, StartStateWarnsThatItIsNotARestart) {
  write_pair(*this, "dpb", DOUBLE_PENDULUM_BAUMGARTE, 0.25);
  ASSERT_EQ(run("run dpb_part.yaml -ts_max_time 0.1").code, 0);
  write("pose.yaml", "base: dpb_full.yaml\nstart_state: {file: out/dpb_part.h5}\n");
  const Outcome o = run("run pose.yaml -ts_max_time 0.01");
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  EXPECT_NE(o.err.find("start_state sets the coordinates only (velocities zero, time from the model); it is not a "
                       "restart: --restart RESULTS.h5 continues a run exactly"),
            std::string::npos)
      << o.err;
}

}  // namespace
