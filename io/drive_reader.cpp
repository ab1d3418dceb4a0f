// Drive functions from YAML; parameter checks of core/drive become located input errors.
#include "io/drive_reader.hpp"

#include <stdexcept>
#include <string>

namespace latticedyn {

namespace {

// Sums of sums through YAML aliases grow geometrically (30 references to a sum of 1,000 constants
// in 5 kB: every evaluation, and the rope checks take thousands, adds 30,000 terms); no drive a
// crane needs comes near this many functions.
constexpr int kMaxDriveFunctions = 1000;

Drive read_counted(const InputNode& n, int* functions);

Drive make(const InputNode& n, int* functions) {
  const std::string type = n["type"].as_choice(
      {"constant", "trapezoidal", "cosine_step", "quintic_step", "cosine_full", "tanh", "sine", "table", "sum", "external"});
  if (type == "external") {
    // Set by the program running the model (api/simulator.hpp); the command line holds it.
    if (*functions > 1) n.fail("an external drive of its own, not a term of a sum (a program sets it by its name)");
    n.allow_only({"type", "initial"});
    return Drive::External{std::make_shared<drive::ExternalSignal>(drive::ExternalSignal{0.0, n.get_double("initial", 0.0), 0.0, 0.0})};
  }
  if (type == "constant") {
    n.allow_only({"type", "value"});
    return Drive::Constant{n["value"].as_double()};
  }
  if (type == "trapezoidal") {
    n.allow_only({"type", "t_start", "duration", "accel_time", "decel_time", "distance", "initial"});
    Drive::TrapezoidalVelocity p;
    p.t_start = n.get_double("t_start", 0.0);
    p.duration = n["duration"].as_positive();
    p.accel_time = n["accel_time"].as_positive();
    p.decel_time = n["decel_time"].as_positive();
    p.distance = n["distance"].as_double();
    p.initial = n.get_double("initial", 0.0);
    return p;
  }
  if (type == "cosine_step") {
    n.allow_only({"type", "t_start", "t_end", "y_start", "y_end"});
    return Drive::CosineStep{n["t_start"].as_double(), n["t_end"].as_double(), n["y_start"].as_double(), n["y_end"].as_double()};
  }
  if (type == "quintic_step") {
    n.allow_only({"type", "t_start", "t_end", "y_start", "y_end"});
    return Drive::QuinticStep{n["t_start"].as_double(), n["t_end"].as_double(), n["y_start"].as_double(), n["y_end"].as_double()};
  }
  if (type == "cosine_full") {
    n.allow_only({"type", "t1", "t2", "y1", "y2"});
    return Drive::CosineFull{n["t1"].as_double(), n["t2"].as_double(), n["y1"].as_double(), n["y2"].as_double()};
  }
  if (type == "tanh") {
    n.allow_only({"type", "t1", "t2", "y1", "y2", "confidence", "lambda"});
    if (n.has("confidence") == n.has("lambda")) n.fail("give exactly one of 'confidence' (Table E-1) or 'lambda'");
    double lambda = 0.0;
    if (auto c = n.get("confidence")) {
      try {
        lambda = tanh_confidence_coefficient(c->as_double());
      } catch (const std::invalid_argument& e) {
        c->fail(e.what());
      }
    } else {
      lambda = n["lambda"].as_positive();
    }
    return Drive::TanhStep{n["t1"].as_double(), n["t2"].as_double(), n["y1"].as_double(), n["y2"].as_double(), lambda};
  }
  if (type == "sine") {
    n.allow_only({"type", "amplitude", "frequency", "phase", "offset"});
    return Drive::Sine{n["amplitude"].as_double(), n["frequency"].as_non_negative(), n.get_double("phase", 0.0),
                       n.get_double("offset", 0.0)};
  }
  if (type == "table") {
    n.allow_only({"type", "times", "values", "zero_end_rates"});
    return Drive::Table{n["times"].as_doubles(), n["values"].as_doubles(), n.get_bool("zero_end_rates", true)};
  }
  n.allow_only({"type", "terms"});
  Drive::Sum sum;
  for (const InputNode& t : n["terms"].items()) sum.terms.push_back(read_counted(t, functions));
  return sum;
}

Drive read_counted(const InputNode& n, int* functions) {
  if (++*functions > kMaxDriveFunctions)
    n.fail("a drive of at most " + std::to_string(kMaxDriveFunctions) +
           " functions in all (sums of sums counted through their aliases)");
  try {
    return make(n, functions);
  } catch (const std::invalid_argument& e) {
    n.fail(e.what());
  }
}

}  // namespace

Drive read_drive(const InputNode& n) {
  int functions = 0;
  return read_counted(n, &functions);
}

}  // namespace latticedyn
