// Parameter sets of the prescribed-motion drive functions (thesis Appendix E and eq. 8-3).
// Plain aggregates; Drive (core/drive.hpp) validates them and is what the rest of the code uses.
#pragma once

#include <memory>
#include <vector>

namespace latticedyn {

class Drive;

/// A prescribed quantity and its first two time derivatives at one instant.
struct DriveValue {
  double value = 0.0;
  double rate = 0.0;   ///< d value / dt
  double accel = 0.0;  ///< d^2 value / dt^2
};

namespace drive {

/// y(t) = value for all t.
struct Constant {
  double value = 0.0;
};

/// Three-phase trapezoidal velocity profile (thesis eq. 8-3, E-1..E-5): constant acceleration for
/// accel_time, constant speed, constant deceleration for decel_time, covering `distance` in
/// `duration` starting at t_start. Holds `initial` before and initial + distance after.
/// Requires accel_time > 0, decel_time > 0, accel_time + decel_time <= duration.
struct TrapezoidalVelocity {
  double t_start = 0.0;
  double duration = 0.0;    ///< t0, total motion time
  double accel_time = 0.0;  ///< t1
  double decel_time = 0.0;  ///< t3
  double distance = 0.0;    ///< s0, may be negative
  double initial = 0.0;     ///< value before t_start
};

/// Half-cosine transition from y_start to y_end over [t_start, t_end] (thesis eq. E-6..E-8).
struct CosineStep {
  double t_start = 0.0;
  double t_end = 0.0;
  double y_start = 0.0;
  double y_end = 0.0;
};

/// Quintic (minimum-jerk) step from y_start to y_end over [t_start, t_end]:
/// y = y_start + (y_end - y_start)(10 s^3 - 15 s^4 + 6 s^5), s = (t - t_start)/(t_end - t_start);
/// rate and acceleration are zero at both ends (the cosine step's acceleration jumps there), so
/// a prescribed motion starting from rest excites a flexible body's stiff modes only through the
/// jerk (Flash & Hogan 1985; Biagiotti & Melchiorri 2008, 2.1.5).
struct QuinticStep {
  double t_start = 0.0;
  double t_end = 0.0;
  double y_start = 0.0;
  double y_end = 0.0;
};

/// Full-cosine bump y1 -> y2 at (t1 + t2)/2 -> back to y1 at t2 (thesis eq. E-9..E-11).
struct CosineFull {
  double t1 = 0.0;
  double t2 = 0.0;
  double y1 = 0.0;
  double y2 = 0.0;
};

/// Hyperbolic-tangent transition from y1 to y2 centred on (t1 + t2)/2 (thesis eq. E-13..E-15).
/// lambda sets how much of the change falls inside [t1, t2]: a fraction tanh(lambda) of it;
/// see tanh_confidence_coefficient() for the thesis's Table E-1 values.
struct TanhStep {
  double t1 = 0.0;
  double t2 = 0.0;
  double y1 = 0.0;
  double y2 = 0.0;
  double lambda = 0.0;
};

/// y(t) = offset + amplitude * sin(2 pi frequency t + phase).
struct Sine {
  double amplitude = 0.0;
  double frequency = 0.0;  ///< Hz
  double phase = 0.0;      ///< rad
  double offset = 0.0;
};

/// C2 cubic spline through (times[i], values[i]), holding the end values outside the table.
/// zero_end_rates: clamped spline with zero slope at both ends (smooth start and stop);
/// otherwise a natural spline (zero curvature at the ends, so the rate jumps there).
struct Table {
  std::vector<double> times;
  std::vector<double> values;
  bool zero_end_rates = true;
};

/// A drive set from outside the model, by the program that runs it (a controller, a learning
/// agent: api/simulator.hpp): from time t0 on, value + rate (t - t0) + accel (t - t0)^2 / 2, so
/// that a new rate or acceleration, set at the current time, keeps the value (and with an
/// acceleration the rate) continuous. Shared by every copy of the drive (a rope keeps its own
/// copy), which all follow the one signal.
struct ExternalSignal {
  double t0 = 0.0;
  double value = 0.0;
  double rate = 0.0;
  double accel = 0.0;
};

/// The drive of an ExternalSignal; until the program sets it, it holds `signal->value`.
struct External {
  std::shared_ptr<ExternalSignal> signal;
};

/// Sum of several drives, e.g. the successive trapezoidal stages of a combined crane motion
/// (thesis section 8.3.2).
struct Sum {
  std::vector<Drive> terms;
};

}  // namespace drive
}  // namespace latticedyn
