// `latticedyn control` end to end on the coarse map (examples/control/control_coarse.yaml): the
// pipeline runs on 1 and 2 MPI ranks with identical files, the optimal trajectory meets Table
// 8-2, and the crane under the control table follows it within the bounds of docs/control.md.
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

// A CSV of numbers as columns by name.
std::map<std::string, std::vector<double>> read_columns(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> header;
  std::map<std::string, std::vector<double>> cols;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (header.empty()) {
      header = cells;
      continue;
    }
    for (std::size_t k = 0; k < header.size() && k < cells.size(); ++k) cols[header[k]].push_back(std::stod(cells[k]));
  }
  return cols;
}

// One test: the pipeline is the expensive part (a minute per run), its checks are cheap.
TEST(Control, PipelineOnOneAndTwoRanks) {
  const fs::path dir = fs::temp_directory_path() / ("latticedyn_control_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto run = [&](const std::string& args, const std::string& launcher) {
    return latticedyn::testing::run_in(dir, LATTICEDYN_EXE, args, launcher, 900);
  };
  const Outcome one = run("control " + std::string(CONTROL_FILE) + " --output one", "");
  ASSERT_EQ(one.code, 0) << one.out << one.err;
  const Outcome two =
      run("control " + std::string(CONTROL_FILE) + " --output two", latticedyn::testing::mpiexec(MPIEXEC, 2));
  ASSERT_EQ(two.code, 0) << two.out << two.err;

  // Identical results on 1 and 2 ranks.
  for (const char* f : {"map_fit.csv", "optimal_trajectory.csv", "control_table.csv", "control_spline.csv",
                        "tracking.csv", "summary.csv"})
    EXPECT_EQ(slurp(dir / "one" / f), slurp(dir / "two" / f)) << f << " differs between 1 and 2 ranks";
  EXPECT_TRUE(fs::exists(dir / "two" / "mapping" / "mapping_coarse_records" / "group1of2.log"));
  EXPECT_TRUE(fs::exists(dir / "one" / "verification"));
  EXPECT_TRUE(fs::exists(dir / "one" / "control_report.md"));
  EXPECT_TRUE(fs::exists(dir / "one" / "control_drives.yaml"));

  // Table 8-2 and Figure 8-15: the end point reaches the target, accelerates at the bound of
  // 0.2 m/s^2 and cruises at the speed bound of 1 m/s.
  auto o = read_columns(dir / "one" / "optimal_trajectory.csv");
  ASSERT_EQ(o["t"].size(), 401u);
  EXPECT_NEAR(o["x"].front(), -10.0, 1e-12);
  EXPECT_NEAR(o["x"].back(), -35.0, 1e-3);
  EXPECT_NEAR(o["z"].back(), 10.0, 1e-3);
  double vmax = 0, amax = 0;
  for (std::size_t k = 0; k < o["t"].size(); ++k) {
    vmax = std::max({vmax, std::abs(o["vx"][k]), std::abs(o["vz"][k])});
    amax = std::max({amax, std::abs(o["ax"][k]), std::abs(o["az"][k])});
  }
  EXPECT_NEAR(vmax, 1.0, 1e-6);
  EXPECT_NEAR(amax, 0.2, 1e-6);

  // The crane under the control table. Measured on this coarse map (docs/control.md): largest
  // tracking error 1.97 m, RMS 1.21 m, mostly the load's pendulum sway (period 12 s on 35 m of
  // rope) that the open-loop control does not damp; the sway's centre 4 cm from the target.
  const std::string summary = slurp(dir / "one" / "summary.csv");
  auto value = [&](const std::string& key) {
    const auto at = summary.find(key + ",");
    EXPECT_NE(at, std::string::npos) << key;
    return at == std::string::npos ? 1e300 : std::stod(summary.substr(at + key.size() + 1));
  };
  EXPECT_LT(value("tracking_max"), 2.5);
  EXPECT_LT(value("tracking_rms"), 1.5);
  EXPECT_LT(value("final_offset"), 0.1);
  EXPECT_LT(value("residual_sway"), 2.0);
  // The start: the load at rest where the map puts the table's first rope lengths (within the
  // surfaces' residual, 0.1 m RMS on this map); no slewing, so the load stays in the boom's plane.
  auto tr = read_columns(dir / "one" / "tracking.csv");
  EXPECT_NEAR(tr["x"].front(), -10.0, 0.25);
  EXPECT_NEAR(tr["z"].front(), 0.0, 0.25);
  EXPECT_NEAR(tr["y"].front(), 0.0, 1e-3);

  // The exported drives file runs on its own: it starts from the recorded start equilibrium, so
  // its static solve has nothing left to do and finds the load where the verification run began.
  const Outcome alone = run("static one/control_drives.yaml --output alone", "");
  ASSERT_EQ(alone.code, 0) << alone.out << alone.err;
  const int iterations = latticedyn::testing::static_newton_iterations(alone.out);
  EXPECT_GE(iterations, 0) << alone.out;
  EXPECT_LE(iterations, 2) << alone.out;
  auto probe = read_columns(dir / "alone" / "control_drives_probes.csv");
  ASSERT_FALSE(probe.empty());
  std::string joint;
  // The probe table's header names its columns with their units: "load.1.x [m]".
  EXPECT_EQ(probe.count("time [s]"), 1u);
  for (const auto& [name, column] : probe)
    if (name.ends_with(".x [m]")) joint = name.substr(0, name.size() - 6);
  ASSERT_FALSE(joint.empty());
  EXPECT_NEAR(probe[joint + ".x [m]"].back(), tr["x"].front(), 1e-3);
  EXPECT_NEAR(probe[joint + ".z [m]"].back(), tr["z"].front(), 1e-3);

  // The report's plots (the PNG half of scripts/control.sh).
  const Outcome plots = latticedyn::testing::run_in(dir, "/usr/bin/python3", std::string(CONTROL_REPORT) + " one", "", 300);
  ASSERT_EQ(plots.code, 0) << plots.out << plots.err;
  for (const char* f : {"control_map.png", "control_optimal.png", "control_trajectory.png", "control_table.png",
                        "control_tracking.png"})
    EXPECT_GT(fs::exists(dir / "one" / f) ? fs::file_size(dir / "one" / f) : 0u, 10000u) << f;
  fs::remove_all(dir);
}

// Bad control files stop before any computation: one line with file:line and the key, exit
// code 2, no output folder.
TEST(Control, BadControlFilesNameFileLineAndKey) {
  const fs::path dir = fs::temp_directory_path() / ("latticedyn_control_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string good = slurp(CONTROL_FILE);
  const std::string mapping = (fs::path(CONTROL_FILE).parent_path() / "mapping_coarse.yaml").string();
  struct Bad {
    const char* from;
    const char* to;
    const char* key;
  };
  const Bad cases[] = {
      {"mapping: mapping_coarse.yaml", "mapping: nowhere.yaml", "mapping"},
      {"drives: [luffing, hoisting]", "drives: [luffing]", "map.drives"},
      {"drives: [luffing, hoisting]", "drives: [luffing, slewing]", "map.drives[1]"},
      {"end_point: load", "end_point: hook", "map.end_point"},
      {"orders: [2, 2]", "orders: [2, 6]", "map.surface.orders[1]"},
      {"start: [-10, 0, 0, 0]", "start: [-10, 0, 0]", "trajectory.start"},
      {"start: [-10, 0, 0, 0]", "start: [-60, 0, 0, 0]", "trajectory.start"},
      {"R: [1, 1]", "R: [1, 0]", "trajectory.R"},
      {"steps: 400", "steps: 0", "trajectory.steps"},
      {"horizon: 0", "horizon: -3", "trajectory.horizon"},
      {"samples: 20", "samples: 1", "control_table.samples"},
  };
  for (const Bad& b : cases) {
    std::string text = good;
    const auto at = text.find(b.from);
    ASSERT_NE(at, std::string::npos) << b.from;
    text.replace(at, std::string(b.from).size(), b.to);
    // The mapping batch stays where it is; only the control file moves.
    const auto m = text.find("mapping: mapping_coarse.yaml");
    if (m != std::string::npos) text.replace(m, std::string("mapping: mapping_coarse.yaml").size(), "mapping: " + mapping);
    std::ofstream(dir / "bad.yaml") << text;
    const Outcome o = latticedyn::testing::run_in(dir, LATTICEDYN_EXE, "control bad.yaml --output out", "", 120);
    EXPECT_EQ(o.code, 2) << b.key << ": " << o.out << o.err;
    EXPECT_EQ(o.err.rfind("latticedyn: error: bad.yaml:", 0), 0u) << b.key << ": " << o.err;
    EXPECT_NE(o.err.find(std::string(" ") + b.key + ":"), std::string::npos) << b.key << ": " << o.err;
    EXPECT_FALSE(fs::exists(dir / "out")) << b.key;
  }
  fs::remove_all(dir);
}

}  // namespace
