// Interpolating C2 cubic spline through tabulated points, with clamped or natural end conditions.
// Backs the tabulated drive; kept separate because it is plain numerics with no thesis tie.
#pragma once

#include <vector>

namespace latticedyn {

/// A twice continuously differentiable piecewise cubic through (x_i, y_i) with strictly
/// increasing x_i. Built once (O(n) tridiagonal solve for the knot second derivatives),
/// evaluated in O(log n).
class CubicSpline {
 public:
  /// How the two missing equations of the spline system are closed.
  enum class EndCondition {
    zero_slope,  ///< clamped: first derivative 0 at both ends
    natural,     ///< second derivative 0 at both ends
  };

  /// Value and first two derivatives at one abscissa.
  struct Sample {
    double value = 0.0;
    double d1 = 0.0;
    double d2 = 0.0;
  };

  /// @throws std::invalid_argument if fewer than 2 points, sizes differ, values are not finite
  /// or x is not strictly increasing.
  CubicSpline(std::vector<double> x, std::vector<double> y, EndCondition end);

  /// Value and derivatives at x. Outside [x.front(), x.back()] the end pieces are extrapolated;
  /// callers wanting another behaviour there (e.g. hold the end value) handle it themselves.
  /// At a knot the value is y_i exactly, not up to rounding.
  [[nodiscard]] Sample evaluate(double x) const;

  [[nodiscard]] const std::vector<double>& x() const noexcept { return x_; }
  [[nodiscard]] const std::vector<double>& y() const noexcept { return y_; }
  [[nodiscard]] EndCondition end_condition() const noexcept { return end_; }

 private:
  std::vector<double> x_;
  std::vector<double> y_;
  std::vector<double> m_;  // second derivative at each knot ("moments")
  EndCondition end_;
};

}  // namespace latticedyn
