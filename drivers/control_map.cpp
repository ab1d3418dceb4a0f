// Step 1 of the control pipeline (thesis 6.2): the mapped equilibria and the surfaces fitted to
// them both ways, rope lengths -> end point and end point -> rope lengths.
#include "drivers/control_steps.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

namespace latticedyn {

namespace {

MapData map_data(const ControlSpec& spec, const BatchSummary& batch) {
  auto column = [&](const std::string& name) -> std::pair<bool, int> {
    const auto r = result_columns(spec.mapping);
    const auto it = std::find(r.begin(), r.end(), name);
    if (it != r.end()) return {true, static_cast<int>(it - r.begin())};
    const auto p = std::find(spec.mapping.columns.begin(), spec.mapping.columns.end(), name);
    return {false, static_cast<int>(p - spec.mapping.columns.begin())};
  };
  const std::pair<bool, int> cols[4] = {column(spec.inputs[0]), column(spec.inputs[1]), column(spec.outputs[0]),
                                        column(spec.outputs[1])};
  MapData d;
  std::vector<double>* lists[4] = {&d.in0, &d.in1, &d.out0, &d.out1};
  for (const BatchCase& bc : spec.mapping.cases) {
    const auto it = batch.records.find(bc.index);
    if (it == batch.records.end() || !it->second.ok) continue;
    for (int k = 0; k < 4; ++k)
      lists[k]->push_back(cols[k].first ? it->second.values.at(cols[k].second) : bc.values.at(cols[k].second));
    d.cases.push_back(bc.index);
  }
  return d;
}

}  // namespace

void write_columns_csv(const std::filesystem::path& p, const std::string& header,
                       const std::vector<std::vector<double>>& columns) {
  std::ofstream f(p);
  f << header << "\n";
  char buf[40];
  const std::size_t n = columns.empty() ? 0 : columns[0].size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      std::snprintf(buf, sizeof buf, "%s%.10g", c ? "," : "", columns[c][i]);
      f << buf;
    }
    f << "\n";
  }
  if (!f) throw std::runtime_error("cannot write " + p.string());
}

QuasiStaticMap fit_quasi_static_map(const ControlSpec& spec, const BatchSummary& batch, const std::filesystem::path& dir,
                                    std::string& report) {
  const MapData d = map_data(spec, batch);
  if (d.in0.size() < 9)
    throw ControlStepFailed("the mapping has " + std::to_string(d.in0.size()) + " equilibria; the surfaces need at least 9");
  char buf[1024];
  const SurfaceFit fx = SurfaceFit::fit(spec.surface, d.in0, d.in1, d.out0);
  const SurfaceFit fz = SurfaceFit::fit(spec.surface, d.in0, d.in1, d.out1);
  const SurfaceFit g0 = SurfaceFit::fit(spec.surface, d.out0, d.out1, d.in0);
  const SurfaceFit g1 = SurfaceFit::fit(spec.surface, d.out0, d.out1, d.in1);
  {
    std::vector<std::vector<double>> cols(8);
    for (std::size_t k = 0; k < d.in0.size(); ++k) {
      const double v[8] = {d.in0[k], d.in1[k], d.out0[k], d.out1[k], fx(d.in0[k], d.in1[k]), fz(d.in0[k], d.in1[k]),
                           g0(d.out0[k], d.out1[k]), g1(d.out0[k], d.out1[k])};
      for (int c = 0; c < 8; ++c) cols[c].push_back(v[c]);
    }
    write_columns_csv(dir / "map_fit.csv",
              spec.drives[0] + "," + spec.drives[1] + ",x,z,x_fit,z_fit," + spec.drives[0] + "_fit," + spec.drives[1] + "_fit",
              cols);
  }
  std::snprintf(buf, sizeof buf,
                "## Quasi-static map (thesis 6.2)\n\n%zu equilibria of %d cases; surfaces: %s.\n\n"
                "| surface | RMS residual | largest residual |\n|---|---|---|\n"
                "| x(%s, %s) | %.3g m | %.3g m |\n| z(%s, %s) | %.3g m | %.3g m |\n"
                "| %s(x, z) | %.3g m | %.3g m |\n| %s(x, z) | %.3g m | %.3g m |\n\n",
                d.in0.size(), batch.cases, spec.surface.describe().c_str(), spec.drives[0].c_str(), spec.drives[1].c_str(),
                fx.rms_residual(), fx.max_residual(), spec.drives[0].c_str(), spec.drives[1].c_str(), fz.rms_residual(),
                fz.max_residual(), spec.drives[0].c_str(), g0.rms_residual(), g0.max_residual(), spec.drives[1].c_str(),
                g1.rms_residual(), g1.max_residual());
  report += buf;
  return QuasiStaticMap{d, fx, fz, g0, g1};
}

}  // namespace latticedyn
