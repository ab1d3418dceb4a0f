// Closed-form drive profiles of thesis Appendix E and eq. (8-3): value, rate and acceleration.
// Pure functions of validated parameters; Drive (core/drive.hpp) checks the parameters first.
#pragma once

// Where the acceleration jumps (phase boundaries), every profile returns the value from the right,
// i.e. that of the phase starting there, as eq. 8-3's half-open intervals do: a motion starting
// at t_start has its start-up acceleration at t_start, and one ending at t_end is at rest there.

#include "core/drive_params.hpp"

namespace latticedyn {

/// Accelerations and peak speed of a trapezoidal velocity profile (thesis eq. E-1, E-5).
struct TrapezoidalKinematics {
  double accel = 0.0;      ///< a1 = 2 s0 / (t1 (2 t0 - t1 - t3))
  double decel = 0.0;      ///< a3 = -2 s0 / (t3 (2 t0 - t1 - t3)), opposite sign to a1
  double peak_rate = 0.0;  ///< v_max = a1 t1
};

/// a1, a3 and v_max of a trapezoidal profile (thesis eq. E-1, E-5). Precondition: valid p.
TrapezoidalKinematics trapezoidal_kinematics(const drive::TrapezoidalVelocity& p);

/// Trapezoidal velocity profile (thesis eq. 8-3 with the middle phase corrected to
/// s1 + v_max (t - t1)). C1 in time; the acceleration is piecewise constant.
DriveValue evaluate_profile(const drive::TrapezoidalVelocity& p, double t);

/// Half-cosine step (thesis eq. E-6..E-8). C1 in time; the acceleration jumps at the ends.
DriveValue evaluate_profile(const drive::CosineStep& p, double t);
DriveValue evaluate_profile(const drive::QuinticStep& p, double t);

/// Full-cosine bump (thesis eq. E-9..E-11). C1 in time; the acceleration jumps at the ends.
DriveValue evaluate_profile(const drive::CosineFull& p, double t);

/// Hyperbolic-tangent step (thesis eq. E-13..E-15), applied for all t (never clipped at t1, t2,
/// which would make the value jump), so it only approaches y1 and y2 asymptotically.
DriveValue evaluate_profile(const drive::TanhStep& p, double t);

/// Sine oscillation.
DriveValue evaluate_profile(const drive::Sine& p, double t);

/// The coefficient lambda(c) of thesis Table E-1 for confidence c in {0.9, 0.95, 0.99, 0.995,
/// 0.999}: with it a fraction of about c of the tanh step's change happens inside [t1, t2].
/// @throws std::invalid_argument for any other c, listing the allowed values.
double tanh_confidence_coefficient(double confidence);

}  // namespace latticedyn
