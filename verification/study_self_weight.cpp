// Thesis 8.1.2: a cantilever released undeformed under its own weight swings about its static
// deflection. Euler-Bernoulli: first period 2 pi / ((beta1 L)^2 sqrt(EI / (rho A L^4))) with
// beta1 L = 1.875104069 (e.g. Meirovitch, Fundamentals of Vibrations, 7.8); static tip
// deflection w L^4 / (8 EI), about which the undamped tip swings, from 0 to about twice that
// (the higher modes the release excites widen the swing by a few per cent).
#include "verification/study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>

namespace latticedyn {

std::vector<Verdict> run_self_weight_study(const Study& s) {
  const StudyBeam& b = s.beam();
  const double L = b.length, EI = b.bending_stiffness(), rhoA = b.mass_per_length();
  const double g = 9.81;
  const double beta1L = 1.875104069;
  const double period = 2 * std::numbers::pi / (beta1L * beta1L * std::sqrt(EI / (rhoA * std::pow(L, 4))));
  const double w_static = rhoA * g * std::pow(L, 4) / (8 * EI);
  const auto types = s.values("type"), segments = s.values("segments");
  CsvTable csv(s.out_dir() / "self_weight.csv", {"type", "segments", "completed", "period", "period_exact",
                                                  "period_error", "tip_z_min", "tip_z_max", "swing_exact", "center_error",
                                                  "energy_drift"});
  CsvTable series(s.out_dir() / "self_weight_series.csv", {"model", "time", "tip_z"});
  struct Row {
    std::string type, segments;
    double period_error, swing_error, center_error, drift;
    bool ok;
  };
  std::vector<Row> rows;
  std::printf("self weight: Euler-Bernoulli period %.6f s, tip swing 0 .. %.6f m\n", period, 2 * w_static);
  for (const auto& type : types)
    for (const auto& n : segments) {
      SimulationOutcome outcome;
      const std::string model = type_label(type) + n;
      const Trajectory tr = s.run("self_weight_" + model, {{"type", type}, {"segments", n}}, &outcome);
      const int tip = tr.simulation->model.find_joint("beam.2");
      double lo = 1e300, hi = -1e300;
      for (std::size_t k = 0; k < tr.time.size(); ++k) {
        const double z = tr.joints[k][tip].z() - tr.joints0[tip].z();
        lo = std::min(lo, z);
        hi = std::max(hi, z);
        series.row({model, CsvTable::number(tr.time[k]), CsvTable::number(z)});
      }
      const double T = tr.period(tip, 2);
      const double perr = (T - period) / period, serr = ((hi - lo) - 2 * w_static) / (2 * w_static);
      const double cerr = (-0.5 * (hi + lo) - w_static) / w_static;
      rows.push_back({type, n, perr, serr, cerr, tr.energy_drift(), outcome.ok()});
      csv.row({type, n, outcome.ok() ? "1" : "0", CsvTable::number(T), CsvTable::number(period), CsvTable::number(perr),
               CsvTable::number(lo), CsvTable::number(hi), CsvTable::number(2 * w_static), CsvTable::number(cerr),
               CsvTable::number(tr.energy_drift())});
      std::printf("self weight %-4s period %.5f s (%+.3f %%)  tip z %.4f .. %.4f m (swing %+.2f %%, centre %+.2f %%)  "
                  "energy drift %.2e%s\n",
                  model.c_str(), T, 100 * perr, lo, hi, 100 * serr, 100 * cerr, tr.energy_drift(),
                  outcome.ok() ? "" : ("  FAILED: " + outcome.dynamics.message).c_str());
    }
  std::ofstream md(s.out_dir() / "self_weight.md");
  md << "Euler-Bernoulli first period " << CsvTable::number(period) << " s; tip swing 0 .. "
     << CsvTable::number(2 * w_static) << " m about the static deflection " << CsvTable::number(w_static)
     << " m.\n\n| model | period error | swing error | swing centre error | energy drift |\n|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    char line[160];
    std::snprintf(line, sizeof line, "| %s-beam, %s seg. | %+.3f %% | %+.2f %% | %+.2f %% | %.2e |\n",
                  type_label(r.type).c_str(), r.segments.c_str(), 100 * r.period_error, 100 * r.swing_error,
                  100 * r.center_error, r.drift);
    md << line;
  }
  std::vector<Verdict> verdicts;
  for (const InputNode& a : s.root()["acceptance"].items()) {
    a.allow_only({"type", "segments", "period_tol", "swing_tol", "center_tol", "energy_drift"});
    const std::string type = a["type"].as_string(), n = a["segments"].as_string();
    for (const Row& r : rows) {
      if (r.type != type || r.segments != n) continue;
      const std::string m = type_label(type) + "-beam " + n + " segments: ";
      char what[200];
      std::snprintf(what, sizeof what, "%speriod error %+.3f %% (limit %.3g %%)", m.c_str(), 100 * r.period_error,
                    100 * a["period_tol"].as_positive());
      verdicts.push_back({what, r.ok && std::abs(r.period_error) <= a["period_tol"].as_positive()});
      if (a.has("swing_tol")) {
        std::snprintf(what, sizeof what, "%sswing error %+.2f %% (limit %.3g %%)", m.c_str(), 100 * r.swing_error,
                      100 * a["swing_tol"].as_positive());
        verdicts.push_back({what, r.ok && std::abs(r.swing_error) <= a["swing_tol"].as_positive()});
      }
      if (a.has("center_tol")) {
        std::snprintf(what, sizeof what, "%sswing centre vs static deflection %+.2f %% (limit %.3g %%)", m.c_str(),
                      100 * r.center_error, 100 * a["center_tol"].as_positive());
        verdicts.push_back({what, r.ok && std::abs(r.center_error) <= a["center_tol"].as_positive()});
      }
      if (a.has("energy_drift")) {
        std::snprintf(what, sizeof what, "%senergy drift %.2e of the kinetic energy (limit %.2e)", m.c_str(), r.drift,
                      a["energy_drift"].as_positive());
        verdicts.push_back({what, r.ok && r.drift <= a["energy_drift"].as_positive()});
      }
    }
  }
  return verdicts;
}

}  // namespace latticedyn
