// Resampling with steady points.
#include "control/control_table.hpp"

#include <algorithm>
#include <stdexcept>

namespace latticedyn {

double interpolate_linear(std::span<const double> t, std::span<const double> v, double at) {
  const auto it = std::upper_bound(t.begin(), t.end(), at);
  if (it == t.begin()) return v.front();
  if (it == t.end()) return v.back();
  const std::size_t k = static_cast<std::size_t>(it - t.begin());
  const double w = (at - t[k - 1]) / (t[k] - t[k - 1]);
  return (1.0 - w) * v[k - 1] + w * v[k];
}

ControlTable make_control_table(std::span<const double> times, const std::vector<std::vector<double>>& channels,
                                int samples, int steady) {
  if (samples < 2) throw std::invalid_argument("control table: at least 2 samples");
  if (steady < 0) throw std::invalid_argument("control table: the number of steady points must be >= 0");
  if (times.size() < 2) throw std::invalid_argument("control table: the trajectory needs at least 2 instants");
  for (std::size_t k = 1; k < times.size(); ++k)
    if (!(times[k] > times[k - 1])) throw std::invalid_argument("control table: the times must increase");
  for (const auto& c : channels)
    if (c.size() != times.size()) throw std::invalid_argument("control table: a channel has not one value per time");
  ControlTable table;
  const double t0 = times.front(), t1 = times.back();
  table.spacing = (t1 - t0) / (samples - 1);
  table.lead_time = steady * table.spacing;
  table.values.resize(channels.size());
  const int total = samples + 2 * steady;
  for (int i = 0; i < total; ++i) {
    table.times.push_back(i * table.spacing);
    const int s = std::clamp(i - steady, 0, samples - 1);
    const double at = s == samples - 1 ? t1 : t0 + s * table.spacing;
    for (std::size_t c = 0; c < channels.size(); ++c) table.values[c].push_back(interpolate_linear(times, channels[c], at));
  }
  return table;
}

}  // namespace latticedyn
