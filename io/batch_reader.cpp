// Reads and expands a batch file; see docs/batch.md for the format.
#include "io/batch_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <set>

namespace latticedyn {

std::vector<std::string> BatchMeasure::columns() const {
  if (kind == MeasureKind::position) return {name + "_x", name + "_y", name + "_z"};
  return {name};
}

namespace {

KeyOverride number_override(const LinearSetting& s, double value) {
  KeyOverride o;
  o.path = s.path;
  o.value = YAML::Node(value);
  o.origin_file = s.file;
  o.origin_line = s.line;
  o.origin_column = s.column;
  return o;
}

// The table columns a set value fills: a number its key, a list of numbers key[0], key[1], ...,
// anything else its key with NaN.
std::vector<std::pair<std::string, double>> value_columns(const std::string& key, const YAML::Node& value) {
  double v = 0;
  if (value.IsScalar() && YAML::convert<double>::decode(value, v)) return {{key, v}};
  if (value.IsSequence() && value.size() > 0) {
    std::vector<std::pair<std::string, double>> out;
    for (std::size_t i = 0; i < value.size(); ++i) {
      if (!value[i].IsScalar() || !YAML::convert<double>::decode(value[i], v)) return {{key, std::numeric_limits<double>::quiet_NaN()}};
      out.emplace_back(key + "[" + std::to_string(i) + "]", v);
    }
    return out;
  }
  return {{key, std::numeric_limits<double>::quiet_NaN()}};
}

std::vector<double> read_values(const InputNode& n) {
  if (n.is_sequence()) {
    auto v = n.as_doubles();
    if (v.empty()) n.fail("expected at least one value");
    return v;
  }
  n.allow_only({"from", "to", "step"});
  const double from = n["from"].as_double(), to = n["to"].as_double(), step = n["step"].as_double();
  if (step == 0 || (to - from) / step < -1e-12) n["step"].fail("the step must lead from 'from' to 'to'");
  const double count = (to - from) / step;
  const long steps = std::lround(count);
  if (std::abs(count - steps) > 1e-9 * std::max(1.0, std::abs(count)))
    n.fail("'to' is not reached in whole steps from 'from'");
  if (steps > 1000000) n.fail("more than a million values");
  std::vector<double> v;
  // From the ends inwards by index, so that no rounding accumulates (85 - 40 x 1 is exactly 45).
  for (long k = 0; k <= steps; ++k) v.push_back(k == steps ? to : from + static_cast<double>(k) * step);
  return v;
}

std::vector<LinearSetting> read_settings(const InputNode& n) {
  std::vector<LinearSetting> out;
  for (const auto& [path, value] : n.entries()) {
    LinearSetting s;
    s.path = path;
    s.file = value.file();
    s.line = value.line();
    s.column = value.column();
    if (value.is_map()) {
      value.allow_only({"offset", "scale"});
      s.offset = value.get_double("offset", 0.0);
      s.scale = value.get_double("scale", 1.0);
    } else if (!value.is_scalar() || value.as_string() != "value") {
      value.fail("expected 'value' (the model value is the parameter) or {offset: a, scale: b} (a + b x parameter)");
    }
    out.push_back(s);
  }
  return out;
}

BatchTarget read_target(const InputNode& n, const InputNode& model_root) {
  n.allow_only({"measure", "adjust", "tolerance", "max_step", "max_evaluations"});
  BatchTarget t;
  t.measure = n["measure"].as_string();
  t.adjust = n["adjust"].as_string();
  const auto at = model_root.at_path(t.adjust);
  if (!at || !at->is_scalar()) n["adjust"].fail("the model has no number at '" + t.adjust + "'");
  t.start = at->as_double();
  t.tolerance = n.get_positive("tolerance", t.tolerance);
  t.max_step = n.get_positive("max_step", t.max_step);
  t.max_evaluations = n.get_int("max_evaluations", t.max_evaluations);
  if (t.max_evaluations < 2) n["max_evaluations"].fail("expected at least 2");
  return t;
}

BatchMeasure read_measure(const InputNode& n) {
  n.allow_only({"name", "position_of", "angle_above_horizontal", "axial_force_of"});
  BatchMeasure m;
  m.name = n["name"].as_string();
  m.file = n.file();
  m.line = n.line();
  m.column = n.column();
  int kinds = 0;
  if (auto p = n.get("position_of")) {
    m.kind = MeasureKind::position;
    m.joints = {p->as_string()};
    ++kinds;
  }
  if (auto a = n.get("angle_above_horizontal")) {
    m.kind = MeasureKind::angle_above_horizontal;
    for (const InputNode& j : a->items()) m.joints.push_back(j.as_string());
    if (m.joints.size() != 2) a->fail("expected two joints [from, to]");
    ++kinds;
  }
  if (auto f = n.get("axial_force_of")) {
    m.kind = MeasureKind::axial_force;
    m.body = f->as_string();
    ++kinds;
  }
  if (kinds != 1) n.fail("expected exactly one of position_of, angle_above_horizontal, axial_force_of");
  return m;
}

void expand_grid(BatchSpec& spec, const InputNode& where) {
  std::size_t total = 1;
  for (const auto& p : spec.parameters) total *= p.values.size();
  if (total > 10000000) where.fail("the grid has more than 10 million cases");
  const std::size_t inner = spec.parameters.back().values.size();
  std::vector<std::size_t> idx(spec.parameters.size(), 0);
  for (std::size_t c = 0; c < total; ++c) {
    // The last parameter varies fastest: its runs are the chains.
    std::size_t rest = c;
    for (std::size_t k = spec.parameters.size(); k-- > 0;) {
      idx[k] = rest % spec.parameters[k].values.size();
      rest /= spec.parameters[k].values.size();
    }
    BatchCase bc;
    bc.index = static_cast<int>(c);
    bc.chain = spec.warm_start ? static_cast<int>(c / inner) : static_cast<int>(c);
    for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
      const BatchParameter& p = spec.parameters[k];
      const double v = p.values[idx[k]];
      bc.values.push_back(v);
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s%s=%g", bc.label.empty() ? "" : " ", p.name.c_str(), v);
      bc.label += buf;
      for (const LinearSetting& s : p.set) {
        bc.overrides.push_back(number_override(s, s.offset + s.scale * v));
        bc.set_values.push_back(s.offset + s.scale * v);
      }
    }
    spec.cases.push_back(std::move(bc));
  }
  spec.chains = spec.cases.empty() ? 0 : spec.cases.back().chain + 1;
}

}  // namespace

BatchSpec read_batch(const std::string& path) {
  const InputNode root = InputNode::load_file(path);
  root.allow_only({"title", "model", "analysis", "parameters", "cases", "set", "measures", "warm_start", "output"});
  BatchSpec spec;
  spec.source = path;
  const InputNode model = root["model"];
  spec.model_path = (std::filesystem::path(path).parent_path() / model.as_string()).lexically_normal().string();
  if (!std::filesystem::is_regular_file(spec.model_path)) model.fail("no model file '" + spec.model_path + "'");
  spec.dynamics = root.has("analysis") && root["analysis"].as_choice({"static", "run"}) == "run";
  const InputNode model_root = InputNode::load_file(spec.model_path);

  std::vector<KeyOverride> common;
  if (auto s = root.get("set"))
    for (const auto& [key, value] : s->entries()) common.push_back(make_key_override(key, value.yaml(), value));

  if (root.has("parameters") == root.has("cases")) root.fail("expected either 'parameters' (a grid) or 'cases' (a list)");
  std::set<std::string> names;
  if (auto params = root.get("parameters")) {
    for (const InputNode& n : params->items()) {
      n.allow_only({"name", "values", "set", "target"});
      BatchParameter p;
      p.name = n["name"].as_string();
      if (!names.insert(p.name).second) n["name"].fail("a second parameter named '" + p.name + "'");
      p.values = read_values(n["values"]);
      if (auto s = n.get("set")) p.set = read_settings(*s);
      if (auto t = n.get("target")) {
        if (spec.dynamics) t->fail("a target needs static analysis");
        if (spec.target_parameter >= 0) t->fail("only one parameter may have a target");
        p.target = read_target(*t, model_root);
        spec.target_parameter = static_cast<int>(spec.parameters.size());
      }
      if (p.set.empty() && !p.target) n.fail("the parameter changes nothing: give 'set' or 'target'");
      spec.columns.push_back(p.name);
      spec.parameters.push_back(std::move(p));
    }
    if (spec.parameters.empty()) params->fail("expected at least one parameter");
  }
  spec.warm_start = root.get_bool("warm_start", !spec.dynamics) && !spec.dynamics;
  if (!spec.parameters.empty()) {
    expand_grid(spec, *root.get("parameters"));
  } else {
    const InputNode cases = root["cases"];
    std::set<std::string> labels;
    for (const InputNode& n : cases.items()) {
      n.allow_only({"name", "set"});
      BatchCase bc;
      bc.index = static_cast<int>(spec.cases.size());
      bc.chain = bc.index;
      bc.label = n.get_string("name", "case " + std::to_string(bc.index));
      if (!labels.insert(bc.label).second) n.fail("a second case named '" + bc.label + "'");
      for (const auto& [key, value] : n["set"].entries()) {
        bc.overrides.push_back(make_key_override(key, value.yaml(), value));
        for (const auto& [column, v] : value_columns(key, value.yaml()))
          if (std::find(spec.columns.begin(), spec.columns.end(), column) == spec.columns.end()) spec.columns.push_back(column);
      }
      spec.cases.push_back(std::move(bc));
    }
    if (spec.cases.empty()) cases.fail("expected at least one case");
    // Numeric set values become columns, a vector one column per component (NaN where a case
    // leaves the key alone or sets a text or a map).
    for (BatchCase& bc : spec.cases) {
      bc.values.assign(spec.columns.size(), std::numeric_limits<double>::quiet_NaN());
      for (const KeyOverride& o : bc.overrides)
        for (const auto& [column, v] : value_columns(o.path, o.value))
          bc.values[std::find(spec.columns.begin(), spec.columns.end(), column) - spec.columns.begin()] = v;
    }
    spec.chains = static_cast<int>(spec.cases.size());
  }
  for (BatchCase& bc : spec.cases) bc.overrides.insert(bc.overrides.begin(), common.begin(), common.end());

  if (auto ms = root.get("measures")) {
    std::set<std::string> mnames;
    for (const InputNode& n : ms->items()) {
      spec.measures.push_back(read_measure(n));
      if (!mnames.insert(spec.measures.back().name).second) n["name"].fail("a second measure with this name");
    }
  }
  for (const BatchMeasure& m : spec.measures)
    for (const std::string& c : m.columns())
      if (std::find(spec.columns.begin(), spec.columns.end(), c) != spec.columns.end())
        throw InputError(m.file, m.line, m.column, "measures." + m.name,
                         "the table column '" + c + "' would be both a parameter and a measure; rename the measure");
  if (spec.target_parameter >= 0) {
    const BatchTarget& t = *spec.parameters[spec.target_parameter].target;
    const bool found = std::any_of(spec.measures.begin(), spec.measures.end(), [&](const BatchMeasure& m) {
      return m.name == t.measure && m.kind != MeasureKind::position;
    });
    if (!found)
      root["parameters"].fail("the target's measure '" + t.measure + "' is not a scalar measure (angle or force) in 'measures'");
  }

  // Every path must lead somewhere in the model (values are checked when a case is read, so that
  // a bad value fails its case alone).
  std::set<std::string> checked;
  for (const BatchCase& bc : spec.cases) {
    std::string key;
    for (const KeyOverride& o : bc.overrides) key += o.path + "\n";
    if (checked.insert(key).second) (void)InputNode::load_file(spec.model_path, bc.overrides);
  }

  const std::string stem = std::filesystem::path(path).stem().string();
  spec.output_directory = "results/" + stem;
  spec.name = stem;
  if (auto o = root.get("output")) {
    o->allow_only({"directory", "name"});
    spec.output_directory = o->get_string("directory", spec.output_directory);
    spec.name = o->get_string("name", spec.name);
  }
  return spec;
}

std::vector<std::string> measure_columns(const BatchSpec& spec) {
  std::vector<std::string> cols;
  for (const BatchMeasure& m : spec.measures)
    for (const std::string& c : m.columns()) cols.push_back(c);
  return cols;
}

std::vector<std::string> result_columns(const BatchSpec& spec) {
  std::vector<std::string> cols;
  if (spec.target_parameter >= 0) cols.push_back(spec.parameters[spec.target_parameter].target->adjust);
  for (const BatchParameter& p : spec.parameters)
    for (const LinearSetting& s : p.set) cols.push_back(s.path);
  const auto measured = measure_columns(spec);
  cols.insert(cols.end(), measured.begin(), measured.end());
  return cols;
}

}  // namespace latticedyn
