// Parabolic rope shapes parametrised by arc length.
#include "io/rope_shape.hpp"

#include <algorithm>
#include <cmath>

namespace latticedyn {

namespace {

// Parabola y(x) = 4 f x (D - x) / D^2 across a chord of length D: arc length from 0 to x
// (closed form of the integral of sqrt(1 + y'^2)).
double parabola_arc(double f, double D, double x) {
  if (f <= 0) return x;
  const double a = 4 * f / (D * D);  // y' = a (D - 2x)
  auto F = [&](double u) { return 0.5 * (u * std::sqrt(1 + u * u) + std::asinh(u)) / (2 * a); };  // integral in u = y'
  return F(a * D) - F(a * (D - 2 * x));
}

// Sag of the parabola whose arc length is `length` (> D), by bisection.
double sag_for_length(double D, double length) {
  double lo = 0.0, hi = length;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (parabola_arc(mid, D, D) < length ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

RopeShape rope_initial_shape(const Vec3& start, const Vec3& end, double L0, int n, const Vec3& across,
                             double weight_per_length, double axial_stiffness, std::optional<double> sag) {
  const double D = (end - start).norm();
  const Vec3 chord = (end - start) / D;
  RopeShape s;
  double f = 0.0, stretch = D / L0;
  if (sag) {
    f = *sag;
  } else if (L0 > D) {
    // Fixed point: the strain sets the arc length, the arc length the sag, the sag the pull.
    double strain = 0.0;
    for (int it = 0; it < 50; ++it) {
      f = sag_for_length(D, L0 * (1 + strain));
      const double next = std::clamp(weight_per_length * D * D / (8 * f * axial_stiffness), 1e-9, 1e-2);
      if (std::abs(next - strain) <= 1e-6 * next) break;
      strain = next;
    }
  }
  const double total = parabola_arc(f, D, D);
  if (f > 0) stretch = total / L0;
  for (int k = 0; k <= n; ++k) {
    // The point at arc length k/n of the total, by bisection on x.
    const double target = total * k / n;
    double lo = 0.0, hi = D;
    for (int i = 0; i < 200 && f > 0; ++i) {
      const double mid = 0.5 * (lo + hi);
      (parabola_arc(f, D, mid) < target ? lo : hi) = mid;
    }
    const double x = f > 0 ? 0.5 * (lo + hi) : D * k / n;
    const double y = 4 * f * x * (D - x) / (D * D), dy = 4 * f * (D - 2 * x) / (D * D);
    s.positions.push_back(start + chord * x + across * y);
    s.slopes.push_back((chord + across * dy).normalized() * stretch);
  }
  return s;
}

}  // namespace latticedyn
