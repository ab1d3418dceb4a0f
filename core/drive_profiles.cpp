// Closed-form drive profiles of thesis Appendix E and eq. (8-3), each with its two derivatives.
// Cosine forms are rewritten with the positive span T = t_end - t_start; they equal the thesis's.
#include "core/drive_profiles.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace latticedyn {

TrapezoidalKinematics trapezoidal_kinematics(const drive::TrapezoidalVelocity& p) {
  const double t0 = p.duration;
  const double t1 = p.accel_time;
  const double t3 = p.decel_time;
  const double denom = 2.0 * t0 - t1 - t3;  // > 0 whenever t1 + t3 <= t0
  TrapezoidalKinematics k;
  k.accel = 2.0 * p.distance / (t1 * denom);
  k.decel = -2.0 * p.distance / (t3 * denom);
  k.peak_rate = k.accel * t1;
  return k;
}

DriveValue evaluate_profile(const drive::TrapezoidalVelocity& p, double t) {
  const double tau = t - p.t_start;
  if (tau < 0.0) return {p.initial, 0.0, 0.0};
  if (tau >= p.duration) return {p.initial + p.distance, 0.0, 0.0};
  const TrapezoidalKinematics k = trapezoidal_kinematics(p);
  const double t1 = p.accel_time;
  const double decel_begin = p.duration - p.decel_time;  // t1 + t2
  if (tau < t1) {
    return {p.initial + 0.5 * k.accel * tau * tau, k.accel * tau, k.accel};
  }
  if (tau < decel_begin) {
    // (8-3) prints s1 + v_max (t - t2) here; only (t - t1) is continuous with the first phase.
    const double s1 = 0.5 * k.accel * t1 * t1;
    return {p.initial + s1 + k.peak_rate * (tau - t1), k.peak_rate, 0.0};
  }
  // Last phase of (8-3), s1 + v_max (t - t1) + a3/2 (t - t1 - t2)^2, written backwards from the
  // end (equal by E-3/E-4) so the end value s0 is hit without cancellation error.
  const double to_end = p.duration - tau;
  return {p.initial + p.distance + 0.5 * k.decel * to_end * to_end, -k.decel * to_end, k.decel};
}

DriveValue evaluate_profile(const drive::CosineStep& p, double t) {
  if (t < p.t_start) return {p.y_start, 0.0, 0.0};
  if (t >= p.t_end) return {p.y_end, 0.0, 0.0};
  const double span = p.t_end - p.t_start;
  const double omega = std::numbers::pi / span;
  const double phi = omega * (t - p.t_start);
  const double half_jump = 0.5 * (p.y_end - p.y_start);
  return {p.y_start + half_jump * (1.0 - std::cos(phi)), half_jump * omega * std::sin(phi),
          half_jump * omega * omega * std::cos(phi)};
}

DriveValue evaluate_profile(const drive::QuinticStep& p, double t) {
  if (t < p.t_start) return {p.y_start, 0.0, 0.0};
  if (t >= p.t_end) return {p.y_end, 0.0, 0.0};
  const double span = p.t_end - p.t_start;
  const double s = (t - p.t_start) / span;
  const double jump = p.y_end - p.y_start;
  return {p.y_start + jump * s * s * s * (10.0 + s * (-15.0 + 6.0 * s)), jump / span * 30.0 * s * s * (1.0 - s) * (1.0 - s),
          jump / (span * span) * 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s)};
}

DriveValue evaluate_profile(const drive::CosineFull& p, double t) {
  if (t < p.t1 || t >= p.t2) return {p.y1, 0.0, 0.0};
  const double span = p.t2 - p.t1;
  const double omega = 2.0 * std::numbers::pi / span;
  const double phi = omega * (t - p.t1);
  const double half_jump = 0.5 * (p.y2 - p.y1);
  return {p.y1 + half_jump * (1.0 - std::cos(phi)), half_jump * omega * std::sin(phi),
          half_jump * omega * omega * std::cos(phi)};
}

DriveValue evaluate_profile(const drive::TanhStep& p, double t) {
  const double span = p.t2 - p.t1;
  const double th = std::tanh(p.lambda * (2.0 * t - (p.t1 + p.t2)) / span);
  const double sech2 = 1.0 - th * th;
  const double rate = p.lambda * (p.y2 - p.y1) / span * sech2;
  return {0.5 * (p.y1 + p.y2) + 0.5 * (p.y2 - p.y1) * th, rate,
          -4.0 * p.lambda / span * th * rate};
}

DriveValue evaluate_profile(const drive::Sine& p, double t) {
  const double omega = 2.0 * std::numbers::pi * p.frequency;
  const double phi = omega * t + p.phase;
  const double s = p.amplitude * std::sin(phi);
  return {p.offset + s, p.amplitude * omega * std::cos(phi), -omega * omega * s};
}

double tanh_confidence_coefficient(double confidence) {
  struct Row {
    double confidence;
    double lambda;
  };
  // Thesis Table E-1 as printed. The values are close to, but not exactly, atanh(c)
  // (atanh(0.9) = 1.4722 vs 1.4765, atanh(0.999) = 3.8002 vs 3.8088); kept as printed so
  // results match the thesis's.
  static constexpr std::array<Row, 5> table{{{0.9, 1.4765},
                                             {0.95, 1.8368},
                                             {0.99, 2.6476},
                                             {0.995, 2.9980},
                                             {0.999, 3.8088}}};
  for (const Row& row : table) {
    if (std::abs(confidence - row.confidence) <= 1e-9) return row.lambda;
  }
  std::ostringstream msg;
  msg << "tanh_confidence_coefficient: confidence " << confidence
      << " is not tabulated (thesis Table E-1); allowed values are";
  for (const Row& row : table) msg << ' ' << row.confidence;
  throw std::invalid_argument(msg.str());
}

}  // namespace latticedyn
