// Thesis 8.1.1: a cantilever bent by an end moment M = K 2 pi EI / L. The exact solution is a
// circular arc of curvature M / EI (the elastica under a pure end moment): with theta = M L / EI
// the tip lies at L sin(theta) / theta along the axis and L (1 - cos(theta)) / theta across it.
#include "verification/study.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>

namespace latticedyn {

std::vector<Verdict> run_end_moment_study(const Study& s) {
  const StudyBeam& b = s.beam();
  const double L = b.length, EI = b.bending_stiffness();
  const auto types = s.values("type"), segments = s.values("segments"), Ks = s.values("K");
  struct Row {
    std::string type, segments;
    double K, error;
    bool converged;
  };
  std::vector<Row> rows;
  CsvTable csv(s.out_dir() / "end_moment.csv",
               {"type", "segments", "K", "converged", "tip_x", "tip_y", "exact_x", "exact_y", "error_over_L"});
  for (const auto& type : types)
    for (const auto& n : segments)
      for (const auto& k : Ks) {
        const double K = std::stod(k);
        const double theta = 2 * std::numbers::pi * K, M = K * 2 * std::numbers::pi * EI / L;
        const Vec3 exact(L * std::sin(theta) / theta, L * (1 - std::cos(theta)) / theta, 0.0);
        SimulationOutcome outcome;
        const std::string tag = "end_moment_" + type_label(type) + n + "_K" + k;
        const Trajectory tr = s.run(tag, {{"type", type}, {"segments", n}, {"moment", CsvTable::number(M)}}, &outcome);
        const int tip = tr.simulation->model.find_joint("beam.2");
        const Vec3 r = tr.joints.back()[tip];
        const bool ok = outcome.ok();
        const double err = ok ? (r - exact).norm() / L : NAN;
        rows.push_back({type, n, K, err, ok});
        csv.row({type, n, k, ok ? "1" : "0", CsvTable::number(r.x()), CsvTable::number(r.y()), CsvTable::number(exact.x()),
                 CsvTable::number(exact.y()), CsvTable::number(err)});
        std::printf("end moment  %s%-3s K = %-5s  tip (%8.4f, %8.4f)  exact (%8.4f, %8.4f)  error %s\n",
                    type_label(type).c_str(), n.c_str(), k.c_str(), r.x(), r.y(), exact.x(), exact.y(),
                    ok ? (CsvTable::number(100 * err) + " % of L").c_str() : ("no equilibrium: " + outcome.statics.message).c_str());
      }
  // The error table of the report: one row per model, one column per K.
  std::ofstream md(s.out_dir() / "end_moment.md");
  md << "| model |";
  for (const auto& k : Ks) md << " K = " << k << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < Ks.size(); ++i) md << "---|";
  md << "\n";
  for (std::size_t i = 0; i < rows.size(); i += Ks.size()) {
    md << "| " << type_label(rows[i].type) << "-beam, " << rows[i].segments << " seg. |";
    for (std::size_t j = i; j < i + Ks.size(); ++j) {
      char cell[32];
      std::snprintf(cell, sizeof cell, " %.3g |", 100 * rows[j].error);
      md << (rows[j].converged ? cell : " fails |");
    }
    md << "\n";
  }
  std::vector<Verdict> verdicts;
  for (const InputNode& a : s.root()["acceptance"].items()) {
    a.allow_only({"type", "segments", "K_max", "max_error"});
    const std::string type = a["type"].as_string(), n = a["segments"].as_string();
    const double K_max = a["K_max"].as_positive(), max_error = a["max_error"].as_positive();
    double worst = 0.0;
    int checked = 0;
    for (const Row& r : rows)
      if (r.type == type && r.segments == n && r.K <= K_max + 1e-12) {
        worst = std::max(worst, r.converged ? r.error : INFINITY);
        ++checked;
      }
    char what[200];
    std::snprintf(what, sizeof what, "%s-beam %s segments, K <= %g: max tip error %.4g %% of L (limit %.3g %%)",
                  type_label(type).c_str(), n.c_str(), K_max, 100 * worst, 100 * max_error);
    verdicts.push_back({what, checked > 0 && worst <= max_error});
  }
  return verdicts;
}

}  // namespace latticedyn
