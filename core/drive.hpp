// Drive: a validated, copyable prescribed function of time (thesis Appendix E, eq. 8-3).
// Used for rope lengths, slewing angles and other imposed motions; one type, no inheritance.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "core/cubic_spline.hpp"
#include "core/drive_params.hpp"
#include "core/drive_profiles.hpp"

namespace latticedyn {

/// A prescribed function of time with its first two derivatives. Built from one parameter set of
/// namespace drive (also reachable as Drive::Constant etc.); each constructor validates its
/// parameters, so every Drive that exists can be evaluated at any t. Constructors are implicit
/// so parameter sets can be listed directly, e.g. Drive::Sum{{stage1, stage2}}.
/// Value and rate are continuous in t for every kind except a natural-spline Table at its ends;
/// where the acceleration jumps, evaluate() returns the one of the phase starting at t.
class Drive {
 public:
  using Constant = drive::Constant;
  using TrapezoidalVelocity = drive::TrapezoidalVelocity;
  using CosineStep = drive::CosineStep;
  using QuinticStep = drive::QuinticStep;
  using CosineFull = drive::CosineFull;
  using TanhStep = drive::TanhStep;
  using Sine = drive::Sine;
  using Table = drive::Table;
  using Sum = drive::Sum;
  using External = drive::External;

  /// The zero drive, Constant{0}.
  Drive();
  /// @throws std::invalid_argument if the value is not finite.
  Drive(Constant p);
  /// Thesis eq. 8-3 / E-1..E-5.
  /// @throws std::invalid_argument unless accel_time > 0, decel_time > 0,
  /// accel_time + decel_time <= duration and all fields are finite.
  Drive(TrapezoidalVelocity p);
  /// Thesis eq. E-6..E-8. @throws std::invalid_argument unless t_end > t_start, all finite.
  Drive(CosineStep p);
  /// @throws std::invalid_argument unless t_end > t_start, all finite.
  Drive(QuinticStep p);
  /// Thesis eq. E-9..E-11. @throws std::invalid_argument unless t2 > t1, all finite.
  Drive(CosineFull p);
  /// Thesis eq. E-13..E-15. @throws std::invalid_argument unless t2 > t1, lambda > 0, finite.
  Drive(TanhStep p);
  /// @throws std::invalid_argument unless frequency >= 0 and all fields are finite.
  Drive(Sine p);
  /// @throws std::invalid_argument unless there are >= 2 points, times and values have the same
  /// length, times strictly increase and everything is finite.
  Drive(const Table& p);
  /// @throws std::invalid_argument if there are no terms.
  Drive(Sum p);
  /// @throws std::invalid_argument without a signal or with a signal not finite.
  Drive(External p);

  /// The signal of an External drive, nullptr for every other kind.
  [[nodiscard]] drive::ExternalSignal* external_signal() const;

  /// Value, rate and acceleration at time t.
  [[nodiscard]] DriveValue evaluate(double t) const;

  /// Times where the motion is not smooth (the acceleration or a higher derivative jumps: the
  /// phases of a trapezoidal profile, the knots of a table), ascending. An integrator that ends
  /// its steps there keeps its order; one that steps across them loses it.
  [[nodiscard]] std::vector<double> breakpoints() const;

  /// One-line human-readable description with all parameters, for logs.
  [[nodiscard]] std::string describe() const;

 private:
  // A table is kept as its spline (which keeps the points), so the system is solved only once.
  std::variant<Constant, TrapezoidalVelocity, CosineStep, QuinticStep, CosineFull, TanhStep, Sine, CubicSpline,
               Sum, External>
      kind_;
};

}  // namespace latticedyn
