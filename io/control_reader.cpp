// Reads the control file; the format is in docs/control.md.
#include "io/control_reader.hpp"

#include <algorithm>
#include <filesystem>

namespace latticedyn {

namespace {

Eigen::VectorXd read_vector(const InputNode& n, int size) {
  const auto v = n.as_doubles();
  if (static_cast<int>(v.size()) != size) n.fail("expected a list of " + std::to_string(size) + " numbers");
  return Eigen::Map<const Eigen::VectorXd>(v.data(), size);
}

Eigen::MatrixXd read_diagonal(const InputNode& n, int size) {
  const Eigen::VectorXd d = read_vector(n, size);
  for (int i = 0; i < size; ++i)
    if (d(i) < 0) n.fail("the weights must be >= 0");
  return d.asDiagonal();
}

void read_trajectory(const InputNode& n, ControlSpec& spec) {
  n.allow_only({"start", "target", "state_min", "state_max", "control_min", "control_max", "Q", "R", "P_end", "steps",
                "sample_time", "horizon"});
  const double ts = n["sample_time"].as_positive();
  QuadraticRegulatorProblem p = double_integrator_problem(2, ts);
  p.steps = n["steps"].as_int();
  if (p.steps < 1) n["steps"].fail("expected at least 1 step");
  p.x0 = read_vector(n["start"], 4);
  p.x_target = read_vector(n["target"], 4);
  if (auto v = n.get("state_min")) p.x_min = read_vector(*v, 4);
  if (auto v = n.get("state_max")) p.x_max = read_vector(*v, 4);
  if (auto v = n.get("control_min")) p.u_min = read_vector(*v, 2);
  if (auto v = n.get("control_max")) p.u_max = read_vector(*v, 2);
  p.Q = read_diagonal(n["Q"], 4);
  p.R = read_diagonal(n["R"], 2);
  p.P_end = read_diagonal(n["P_end"], 4);
  for (int i = 0; i < 2; ++i)
    if (!(p.R(i, i) > 0)) n["R"].fail("the control weights must be positive");
  const std::string problem = validate_quadratic_regulator(p);
  if (!problem.empty()) n.fail(problem);
  for (int i = 0; i < 4; ++i)
    if (p.x0(i) < p.x_min(i) || p.x0(i) > p.x_max(i)) n["start"].fail("the start lies outside state_min..state_max");
  spec.horizon = n.get_int("horizon", 0);
  if (spec.horizon < 0) n["horizon"].fail("expected 0 (whole horizon) or a positive number of steps");
  spec.problem = p;
}

}  // namespace

ControlSpec read_control(const std::string& path) {
  const InputNode root = InputNode::load_file(path);
  root.allow_only({"title", "mapping", "map", "trajectory", "control_table", "verification", "output"});
  ControlSpec spec;
  spec.source = path;
  const InputNode mapping = root["mapping"];
  const auto batch = std::filesystem::path(path).parent_path() / mapping.as_string();
  if (!std::filesystem::is_regular_file(batch)) mapping.fail("no batch file '" + batch.string() + "'");
  spec.mapping = read_batch(batch.lexically_normal().string());
  if (spec.mapping.dynamics) mapping.fail("the mapping batch must be a static analysis");

  const InputNode map = root["map"];
  map.allow_only({"drives", "end_point", "surface"});
  const auto drives = map["drives"].items();
  if (drives.size() != 2) map["drives"].fail("expected two drives [luffing, hoisting]");
  const auto results = result_columns(spec.mapping);
  auto has_column = [&](const std::string& c) {
    return std::find(results.begin(), results.end(), c) != results.end() ||
           std::find(spec.mapping.columns.begin(), spec.mapping.columns.end(), c) != spec.mapping.columns.end();
  };
  for (int i = 0; i < 2; ++i) {
    spec.drives[i] = drives[i].as_string();
    spec.inputs[i] = "drives." + spec.drives[i] + ".value";
    if (!has_column(spec.inputs[i]))
      drives[i].fail("the mapping batch's table has no column '" + spec.inputs[i] + "' (it must set or adjust the drive's value)");
  }
  spec.end_point = map["end_point"].as_string();
  const auto m = std::find_if(spec.mapping.measures.begin(), spec.mapping.measures.end(),
                              [&](const BatchMeasure& b) { return b.name == spec.end_point && b.kind == MeasureKind::position; });
  if (m == spec.mapping.measures.end()) map["end_point"].fail("the mapping batch has no position measure '" + spec.end_point + "'");
  spec.end_point_joint = m->joints[0];
  spec.outputs = {spec.end_point + "_x", spec.end_point + "_z"};
  if (auto s = map.get("surface")) {
    s->allow_only({"type", "orders", "smoothing"});
    const std::string type = s->has("type") ? (*s)["type"].as_choice({"polynomial", "thin_plate"}) : "polynomial";
    if (type == "polynomial") {
      spec.surface.kind = SurfaceSettings::Kind::polynomial;
      if (auto o = s->get("orders")) {
        const auto items = o->items();
        if (items.size() != 2) o->fail("expected two orders [in x, in y]");
        spec.surface.order_x = items[0].as_int();
        spec.surface.order_y = items[1].as_int();
        for (const auto& it : items)
          if (it.as_int() < 0 || it.as_int() > PolynomialSurface::kMaxOrder) it.fail("expected an order in 0..5");
      }
      if (s->has("smoothing")) (*s)["smoothing"].fail("smoothing belongs to type thin_plate");
    } else {
      spec.surface.kind = SurfaceSettings::Kind::thin_plate;
      spec.surface.smoothing = s->get_non_negative("smoothing", 0.0);
      if (s->has("orders")) (*s)["orders"].fail("orders belong to type polynomial");
    }
  }
  read_trajectory(root["trajectory"], spec);
  if (auto t = root.get("control_table")) {
    t->allow_only({"samples", "steady_points"});
    spec.samples = t->get_int("samples", spec.samples);
    spec.steady_points = t->get_int("steady_points", spec.steady_points);
    if (spec.samples < 2) (*t)["samples"].fail("expected at least 2");
    if (spec.steady_points < 0) (*t)["steady_points"].fail("expected 0 or more");
  }
  if (auto v = root.get("verification")) {
    v->allow_only({"run", "time_step", "settle", "rho_infinity", "jacobian_reuse"});
    spec.verify = v->get_bool("run", true);
    spec.time_step = v->get_positive("time_step", spec.time_step);
    spec.settle = v->get_non_negative("settle", spec.settle);
    spec.rho_infinity = v->get_non_negative("rho_infinity", spec.rho_infinity);
    spec.jacobian_reuse = v->get_int("jacobian_reuse", spec.jacobian_reuse);
  }
  spec.output_directory = "results/" + std::filesystem::path(path).stem().string();
  if (auto o = root.get("output")) {
    o->allow_only({"directory"});
    spec.output_directory = o->get_string("directory", spec.output_directory);
  }
  return spec;
}

}  // namespace latticedyn
