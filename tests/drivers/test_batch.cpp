// `latticedyn batch` from the outside: a grid with a target, a list with a failing case that does
// not stop the others, resume after an interruption with bit-identical results, the same table on
// 1 and 2 MPI ranks, and input errors that name the batch file's line.
#include "command_runner.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using latticedyn::testing::Outcome;
using latticedyn::testing::slurp;

// The table as rows of column -> text.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::string cell;
    bool quoted = false;
    for (char c : s) {
      if (c == '"') {
        quoted = !quoted;
      } else if (c == ',' && !quoted) {
        out.push_back(cell);
        cell.clear();
      } else {
        cell += c;
      }
    }
    out.push_back(cell);
    return out;
  };
  while (std::getline(in, line)) {
    const auto cells = split(line);
    if (header.empty()) {
      header = cells;
      continue;
    }
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < header.size() && k < cells.size(); ++k) row[header[k]] = cells[k];
    rows.push_back(row);
  }
  return rows;
}

class Batch : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("latticedyn_batch_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(BATCH_MODEL, dir_ / "truss.yaml");
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  Outcome run(const std::string& args, const std::string& launcher = "") {
    return latticedyn::testing::run_in(dir_, LATTICEDYN_EXE, args, launcher, 300);
  }
  static std::string mpiexec(int n) { return latticedyn::testing::mpiexec(MPIEXEC, n); }
  fs::path dir_;
};

// Bar 4 joins the two loaded nodes; node B hangs on bars 4, 5 and 6 alone, so bar 4's force
// follows B's load: its vertical part is adjusted until bar 4 carries the case's axial force. Two
// chains (B's load along x) of four targets each.
const char* kTargetGrid = R"(model: truss.yaml
parameters:
  - name: load_b_x
    values: {from: 0, to: 2000, step: 2000}
    set: {loads.load_B.force.0: value}
  - name: bar4_force
    values: [1000, 2000, 4000, 8000]
    target: {measure: bar4, adjust: loads.load_B.force.2, tolerance: 1.0e-6, max_step: 1.0e+5}
measures:
  - {name: bar4, axial_force_of: bar4}
  - {name: node_b, position_of: bar4.2}
output: {directory: grid}
)";

TEST_F(Batch, GridWithTargetReachesEveryTarget) {
  write("grid.yaml", kTargetGrid);
  const Outcome o = run("batch grid.yaml");
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  EXPECT_NE(o.out.find("8 cases, 8 ok, 0 failed"), std::string::npos) << o.out;
  const auto rows = read_csv(dir_ / "grid" / "grid.csv");
  ASSERT_EQ(rows.size(), 8u);
  for (const auto& r : rows) {
    EXPECT_EQ(r.at("status"), "ok");
    EXPECT_NEAR(std::stod(r.at("bar4")), std::stod(r.at("bar4_force")), 1e-6) << r.at("label");
    EXPECT_DOUBLE_EQ(std::stod(r.at("loads.load_B.force.0")), std::stod(r.at("load_b_x")));
    EXPECT_TRUE(std::isfinite(std::stod(r.at("loads.load_B.force.2"))));
  }
  // The truss is linear up to small rotations: the adjusted load is affine in the target, so the
  // secant iterations need few solves (the first case of each chain probes the slope).
  EXPECT_LE(std::stoi(rows[3].at("evaluations")), 3);
  EXPECT_TRUE(fs::exists(dir_ / "grid" / "grid.h5"));
}

TEST_F(Batch, FailingCaseIsRecordedAndTheOthersFinish) {
  write("list.yaml", R"(model: truss.yaml
set: {loads.load_B.force: [0, 0, 0]}
cases:
  - {name: light, set: {loads.load_A.force: [0, 0, -5000]}}
  - {name: broken, set: {materials.steel.youngs_modulus: -1}}
  - {name: heavy, set: {loads.load_A.force: [0, 0, -20000]}}
  - {name: stalls, set: {loads.load_A.force: [0, 0, -5000], solver.static: {max_iterations: 1, max_cuts: 0}}}
measures:
  - {name: node_a, position_of: bar1.2}
output: {directory: list}
)");
  const Outcome o = run("batch list.yaml");
  EXPECT_EQ(o.code, 1) << o.out << o.err;  // a failed case makes the batch's exit code 1
  EXPECT_NE(o.out.find("4 cases, 2 ok, 2 failed"), std::string::npos) << o.out;
  EXPECT_NE(o.err.find("broken"), std::string::npos) << o.err;
  const auto rows = read_csv(dir_ / "list" / "list.csv");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].at("status"), "ok");
  EXPECT_EQ(rows[1].at("status"), "failed");
  EXPECT_NE(rows[1].at("error").find("youngs_modulus"), std::string::npos) << rows[1].at("error");
  EXPECT_EQ(rows[2].at("status"), "ok");
  // A solver failure (Newton stopped after one iteration) is recorded the same way.
  EXPECT_EQ(rows[3].at("status"), "failed");
  EXPECT_NE(rows[3].at("error").find("static equilibrium failed"), std::string::npos) << rows[3].at("error");
  EXPECT_NE(rows[3].at("error").find("DIVERGED_MAX_IT"), std::string::npos) << rows[3].at("error");
  // A vector value fills one column per component.
  EXPECT_EQ(std::stod(rows[0].at("loads.load_A.force[2]")), -5000.0);
  EXPECT_EQ(std::stod(rows[2].at("loads.load_A.force[2]")), -20000.0);
  EXPECT_EQ(std::stod(rows[2].at("loads.load_A.force[0]")), 0.0);
  // Four times the load, four times the (linear) deflection of node A below its unloaded height 3.
  const double d_light = 3.0 - std::stod(rows[0].at("node_a_z"));
  const double d_heavy = 3.0 - std::stod(rows[2].at("node_a_z"));
  EXPECT_GT(d_light, 0.0);
  EXPECT_NEAR(d_heavy / d_light, 4.0, 0.02);
}

// analysis: run: each case runs the model's statics, then its dynamics (a section the batch adds),
// and the measures come from the last state. From its equilibrium the truss stays put, so the
// run's final positions are the static batch's.
TEST_F(Batch, DynamicRunsEndWhereTheStaticsPutTheTruss) {
  const std::string cases = R"(cases:
  - {name: light, set: {loads.load_A.force: [0, 0, -5000]}}
  - {name: heavy, set: {loads.load_A.force: [0, 0, -20000]}}
measures:
  - {name: node_a, position_of: bar1.2}
)";
  write("static.yaml", "model: truss.yaml\n" + cases + "output: {directory: static}\n");
  write("run.yaml", "model: truss.yaml\nanalysis: run\nset: {solver.dynamics: {t_end: 0.02, time_step: 0.001}}\n" +
                        cases + "output: {directory: run}\n");
  ASSERT_EQ(run("batch static.yaml").code, 0);
  const Outcome o = run("batch run.yaml");
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  EXPECT_NE(o.out.find("dynamic analysis"), std::string::npos) << o.out;
  const auto a = read_csv(dir_ / "static" / "static.csv"), b = read_csv(dir_ / "run" / "run.csv");
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(b[i].at("status"), "ok");
    // The dynamics start at the equilibrium: the predictor meets the Newton tolerance there, so
    // the steps may need no iteration beyond the statics'.
    EXPECT_GE(std::stod(b[i].at("newton_iterations")), std::stod(a[i].at("newton_iterations")));
    EXPECT_NEAR(std::stod(a[i].at("node_a_z")), std::stod(b[i].at("node_a_z")), 1e-7);
  }
  EXPECT_LT(std::stod(b[1].at("node_a_z")), std::stod(b[0].at("node_a_z")));
}

TEST_F(Batch, ResumeAfterInterruptionSkipsFinishedCasesAndGivesTheSameTable) {
  write("grid.yaml", kTargetGrid);
  ASSERT_EQ(run("batch grid.yaml --output first").code, 0);
  const auto a = read_csv(dir_ / "first" / "grid.csv");
  // A run killed after k cases, in the middle of a chain (two chains of four) or between chains:
  // the records of the first k cases and half a line of the next.
  const fs::path log = dir_ / "first" / "grid_records" / "group0of1.log";
  for (int k = 1; k < 8; ++k) {
    const std::string second = "second" + std::to_string(k);
    std::istringstream lines(slurp(log));
    std::string line, kept;
    for (int i = 0; i <= k && std::getline(lines, line); ++i) kept += line + "\n";  // header + k cases
    std::getline(lines, line);
    kept += line.substr(0, line.size() / 2);
    fs::create_directories(dir_ / second / "grid_records");
    std::ofstream(dir_ / second / "grid_records" / "group0of1.log") << kept;
    const Outcome o = run("batch grid.yaml --output " + second);
    ASSERT_EQ(o.code, 0) << o.out << o.err;
    EXPECT_NE(o.out.find(std::to_string(k) + " taken from an earlier run"), std::string::npos) << o.out;
    EXPECT_EQ(o.err.find("case 0 "), std::string::npos) << "case 0 was solved again:\n" << o.err;
    EXPECT_NE(o.err.find("case " + std::to_string(k) + " "), std::string::npos) << o.err;
    // Every number but the wall times is bit-identical: a chain goes on from its cases' recorded
    // (17-digit) equilibria alone, so the resumed one predicts its next start the same way. (Before
    // the chains' history held the secant's probes, which no record keeps: cut after 1 or 5
    // cases, 12 and 16 numbers differed at round-off.)
    const auto b = read_csv(dir_ / second / "grid.csv");
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i)
      for (const auto& [key, value] : a[i])
        if (key != "wall_seconds") {
          EXPECT_EQ(value, b[i].at(key)) << "cut after " << k << " cases: case " << i << ", " << key;
        }
  }
  // A folder that holds another batch (the file changed) is refused, not mixed.
  write("grid.yaml", std::string(kTargetGrid) + "warm_start: false\n");
  const Outcome mixed = run("batch grid.yaml --output second1");
  EXPECT_EQ(mixed.code, 2) << mixed.out << mixed.err;
  EXPECT_NE(mixed.err.find("another batch"), std::string::npos) << mixed.err;
}

TEST_F(Batch, OneAndTwoRanksGiveTheSameTable) {
  write("grid.yaml", kTargetGrid);
  ASSERT_EQ(run("batch grid.yaml --output one").code, 0);
  const Outcome o = run("batch grid.yaml --output two", mpiexec(2));
  ASSERT_EQ(o.code, 0) << o.out << o.err;
  EXPECT_NE(o.err.find("group 2/2"), std::string::npos) << o.err;
  EXPECT_TRUE(fs::exists(dir_ / "two" / "grid_records" / "group1of2.log"));
  const auto a = read_csv(dir_ / "one" / "grid.csv"), b = read_csv(dir_ / "two" / "grid.csv");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    for (const auto& [key, value] : a[i])
      if (key != "wall_seconds") {
        EXPECT_EQ(value, b[i].at(key)) << "case " << i << ", " << key;
      }
  // One group of two ranks: each case solved by both ranks together (a distributed solve).
  const Outcome g = run("batch grid.yaml --output grouped --groups 1", mpiexec(2));
  ASSERT_EQ(g.code, 0) << g.out << g.err;
  const auto c = read_csv(dir_ / "grouped" / "grid.csv");
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_NEAR(std::stod(a[i].at("loads.load_B.force.2")), std::stod(c[i].at("loads.load_B.force.2")),
                1e-6 * std::abs(std::stod(a[i].at("loads.load_B.force.2"))));
}

TEST_F(Batch, BadInputNamesTheBatchFileLine) {
  write("typo.yaml", R"(model: truss.yaml
parameters:
  - name: fz
    values: [1, 2]
    set: {loads.load_A.forse.2: value}
output: {directory: typo}
)");
  Outcome o = run("batch typo.yaml");
  EXPECT_EQ(o.code, 2) << o.out << o.err;
  EXPECT_NE(o.err.find("typo.yaml:5:"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("no key 'forse'"), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(dir_ / "typo"));

  write("measure.yaml", R"(model: truss.yaml
parameters:
  - name: fz
    values: [1, 2]
    set: {loads.load_A.force.2: value}
measures:
  - {name: tip, position_of: bar9.2}
output: {directory: measure}
)");
  o = run("batch measure.yaml");
  EXPECT_EQ(o.code, 2) << o.out << o.err;
  EXPECT_NE(o.err.find("measure.yaml:7:"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("no joint 'bar9.2'"), std::string::npos) << o.err;

  const Outcome groups = run("batch measure.yaml --groups 3", mpiexec(2));
  EXPECT_EQ(groups.code, 2) << groups.out << groups.err;
}

}  // namespace
