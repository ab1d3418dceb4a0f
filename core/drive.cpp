// Drive: parameter validation, dispatch to the closed-form profiles, and log descriptions.
// Validation is always on: a bad drive in an input file must fail loudly before a run starts.
#include "core/drive.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace latticedyn {
namespace {

// Enough digits to tell apart values a user typed; fewer than round-trip, which would be noise.
std::string fmt(double x) {
  std::ostringstream s;
  s.precision(10);
  s << x;
  return s.str();
}

[[noreturn]] void fail(const char* kind, const std::string& why) {
  throw std::invalid_argument(std::string("Drive ") + kind + ": " + why);
}

void require_finite(const char* kind, const char* name, double v) {
  if (!std::isfinite(v)) fail(kind, std::string(name) + " must be finite, got " + fmt(v));
}

void require_later(const char* kind, const char* late, double t_late, const char* early,
                   double t_early) {
  if (!(t_late > t_early)) {
    fail(kind, std::string(late) + " (" + fmt(t_late) + ") must be greater than " + early + " (" +
                   fmt(t_early) + ")");
  }
}

DriveValue evaluate_kind(const drive::Constant& p, double) { return {p.value, 0.0, 0.0}; }

DriveValue evaluate_kind(const CubicSpline& s, double t) {
  // Hold the end values outside the table instead of extrapolating the end cubics.
  const double t_first = s.x().front();
  const double t_last = s.x().back();
  if (t < t_first) return {s.y().front(), 0.0, 0.0};
  if (t >= t_last) return {s.y().back(), 0.0, 0.0};
  const CubicSpline::Sample v = s.evaluate(t);
  return {v.value, v.d1, v.d2};
}

DriveValue evaluate_kind(const drive::Sum& p, double t) {
  DriveValue total;
  for (const Drive& term : p.terms) {
    const DriveValue v = term.evaluate(t);
    total.value += v.value;
    total.rate += v.rate;
    total.accel += v.accel;
  }
  return total;
}

DriveValue evaluate_kind(const drive::External& p, double t) {
  const drive::ExternalSignal& s = *p.signal;
  const double tau = t - s.t0;
  return {s.value + tau * (s.rate + 0.5 * tau * s.accel), s.rate + tau * s.accel, s.accel};
}

template <class P>
DriveValue evaluate_kind(const P& p, double t) {
  return evaluate_profile(p, t);
}

std::string describe_kind(const drive::Constant& p) { return "constant " + fmt(p.value); }

std::string describe_kind(const drive::External& p) {
  return "external (set by the program running the model), " + fmt(p.signal->value) + " at t = " +
         fmt(p.signal->t0) + " s, rate " + fmt(p.signal->rate) + ", acceleration " + fmt(p.signal->accel);
}

std::string describe_kind(const drive::TrapezoidalVelocity& p) {
  return "trapezoidal velocity from " + fmt(p.initial) + " by " + fmt(p.distance) + " over [" +
         fmt(p.t_start) + ", " + fmt(p.t_start + p.duration) + "] s, accel " +
         fmt(p.accel_time) + " s, decel " + fmt(p.decel_time) + " s, peak rate " +
         fmt(trapezoidal_kinematics(p).peak_rate);
}

// A step from y_start to y_end over [t_start, t_end] (cosine or quintic).
template <class Step>
std::string describe_step(const char* name, const Step& p) {
  return std::string(name) + " step " + fmt(p.y_start) + " -> " + fmt(p.y_end) + " over [" + fmt(p.t_start) +
         ", " + fmt(p.t_end) + "] s";
}

std::string describe_kind(const drive::CosineStep& p) { return describe_step("cosine", p); }
std::string describe_kind(const drive::QuinticStep& p) { return describe_step("quintic", p); }

std::string describe_kind(const drive::CosineFull& p) {
  return "cosine bump " + fmt(p.y1) + " -> " + fmt(p.y2) + " -> " + fmt(p.y1) + " over [" +
         fmt(p.t1) + ", " + fmt(p.t2) + "] s";
}

std::string describe_kind(const drive::TanhStep& p) {
  return "tanh step " + fmt(p.y1) + " -> " + fmt(p.y2) + " over [" + fmt(p.t1) + ", " +
         fmt(p.t2) + "] s, lambda " + fmt(p.lambda);
}

std::string describe_kind(const drive::Sine& p) {
  return "sine " + fmt(p.offset) + " + " + fmt(p.amplitude) + " sin(2 pi " + fmt(p.frequency) +
         " Hz t + " + fmt(p.phase) + ")";
}

std::string describe_kind(const CubicSpline& s) {
  const bool clamped = s.end_condition() == CubicSpline::EndCondition::zero_slope;
  return std::string("table of ") + std::to_string(s.x().size()) + " points over [" +
         fmt(s.x().front()) + ", " + fmt(s.x().back()) + "] s, " +
         (clamped ? "clamped (zero end rates)" : "natural") + " cubic spline";
}

std::string describe_kind(const drive::Sum& p) {
  std::string out = "sum of " + std::to_string(p.terms.size()) + " drives:";
  for (std::size_t i = 0; i < p.terms.size(); ++i) {
    out += (i == 0 ? " [" : " + [") + p.terms[i].describe() + "]";
  }
  return out;
}

template <class Step>
void require_step(const char* kind, const Step& p) {
  require_finite(kind, "t_start", p.t_start);
  require_finite(kind, "t_end", p.t_end);
  require_finite(kind, "y_start", p.y_start);
  require_finite(kind, "y_end", p.y_end);
  require_later(kind, "t_end", p.t_end, "t_start", p.t_start);
}

}  // namespace

Drive::Drive() : kind_(Constant{0.0}) {}

Drive::Drive(Constant p) : kind_(p) { require_finite("Constant", "value", p.value); }

Drive::Drive(TrapezoidalVelocity p) : kind_(p) {
  const char* kind = "TrapezoidalVelocity";
  require_finite(kind, "t_start", p.t_start);
  require_finite(kind, "duration", p.duration);
  require_finite(kind, "accel_time", p.accel_time);
  require_finite(kind, "decel_time", p.decel_time);
  require_finite(kind, "distance", p.distance);
  require_finite(kind, "initial", p.initial);
  if (!(p.accel_time > 0.0)) fail(kind, "accel_time must be > 0, got " + fmt(p.accel_time));
  if (!(p.decel_time > 0.0)) fail(kind, "decel_time must be > 0, got " + fmt(p.decel_time));
  if (!(p.accel_time + p.decel_time <= p.duration)) {
    fail(kind, "accel_time + decel_time (" + fmt(p.accel_time) + " + " + fmt(p.decel_time) +
                   ") must not exceed duration (" + fmt(p.duration) + ")");
  }
}

Drive::Drive(CosineStep p) : kind_(p) { require_step("CosineStep", p); }

Drive::Drive(QuinticStep p) : kind_(p) { require_step("QuinticStep", p); }

Drive::Drive(CosineFull p) : kind_(p) {
  const char* kind = "CosineFull";
  require_finite(kind, "t1", p.t1);
  require_finite(kind, "t2", p.t2);
  require_finite(kind, "y1", p.y1);
  require_finite(kind, "y2", p.y2);
  require_later(kind, "t2", p.t2, "t1", p.t1);
}

Drive::Drive(TanhStep p) : kind_(p) {
  const char* kind = "TanhStep";
  require_finite(kind, "t1", p.t1);
  require_finite(kind, "t2", p.t2);
  require_finite(kind, "y1", p.y1);
  require_finite(kind, "y2", p.y2);
  require_finite(kind, "lambda", p.lambda);
  require_later(kind, "t2", p.t2, "t1", p.t1);
  if (!(p.lambda > 0.0)) fail(kind, "lambda must be > 0, got " + fmt(p.lambda));
}

Drive::Drive(Sine p) : kind_(p) {
  const char* kind = "Sine";
  require_finite(kind, "amplitude", p.amplitude);
  require_finite(kind, "frequency", p.frequency);
  require_finite(kind, "phase", p.phase);
  require_finite(kind, "offset", p.offset);
  if (p.frequency < 0.0) fail(kind, "frequency must be >= 0 Hz, got " + fmt(p.frequency));
}

// CubicSpline's constructor does the validation; its messages are rethrown under this kind.
Drive::Drive(const Table& p)
    : kind_([&p] {
        try {
          return CubicSpline(p.times, p.values,
                             p.zero_end_rates ? CubicSpline::EndCondition::zero_slope
                                              : CubicSpline::EndCondition::natural);
        } catch (const std::invalid_argument& e) {
          fail("Table", e.what());
        }
      }()) {}

Drive::Drive(Sum p) : kind_(std::move(p)) {
  if (std::get<Sum>(kind_).terms.empty()) fail("Sum", "needs at least one term");
}

Drive::Drive(External p) : kind_(p) {
  if (!p.signal) fail("External", "needs a signal");
  for (const double v : {p.signal->t0, p.signal->value, p.signal->rate, p.signal->accel})
    require_finite("External", "every field of its signal", v);
}

drive::ExternalSignal* Drive::external_signal() const {
  const auto* e = std::get_if<External>(&kind_);
  return e ? e->signal.get() : nullptr;
}

DriveValue Drive::evaluate(double t) const {
  return std::visit([t](const auto& k) { return evaluate_kind(k, t); }, kind_);
}

namespace {

std::vector<double> breakpoints_of(const drive::Constant&) { return {}; }
std::vector<double> breakpoints_of(const drive::TrapezoidalVelocity& p) {
  return {p.t_start, p.t_start + p.accel_time, p.t_start + p.duration - p.decel_time, p.t_start + p.duration};
}
std::vector<double> breakpoints_of(const drive::CosineStep& p) { return {p.t_start, p.t_end}; }
std::vector<double> breakpoints_of(const drive::QuinticStep& p) { return {p.t_start, p.t_end}; }
std::vector<double> breakpoints_of(const drive::CosineFull& p) { return {p.t1, p.t2}; }
std::vector<double> breakpoints_of(const drive::TanhStep& p) { return {p.t1, p.t2}; }
std::vector<double> breakpoints_of(const drive::Sine&) { return {}; }
std::vector<double> breakpoints_of(const CubicSpline& s) { return s.x(); }
std::vector<double> breakpoints_of(const drive::Sum& p) {
  std::vector<double> all;
  for (const Drive& d : p.terms) {
    const std::vector<double> b = d.breakpoints();
    all.insert(all.end(), b.begin(), b.end());
  }
  return all;
}
std::vector<double> breakpoints_of(const drive::External&) { return {}; }

}  // namespace

std::vector<double> Drive::breakpoints() const {
  std::vector<double> b = std::visit([](const auto& k) { return breakpoints_of(k); }, kind_);
  std::sort(b.begin(), b.end());
  b.erase(std::unique(b.begin(), b.end()), b.end());
  return b;
}

std::string Drive::describe() const {
  return std::visit([](const auto& k) { return describe_kind(k); }, kind_);
}

}  // namespace latticedyn
