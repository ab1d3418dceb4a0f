// Thin plate spline surfaces z(x, y) through scattered samples: the spline option of the
// quasi-static map (thesis 6.2), exact at the samples or smoothed, beside the polynomial surfaces.
#pragma once

#include <span>
#include <utility>
#include <vector>

namespace latticedyn {

/// z = a0 + a1 u + a2 v + sum_k w_k phi(|(u, v) - (u_k, v_k)|), phi(r) = r^2 log r, with u, v the
/// inputs mapped onto [-1, 1] over the samples' range (the two inputs may be metres of rope and
/// degrees). `smoothing` lambda >= 0 adds lambda to the kernel's diagonal: 0 interpolates the
/// samples exactly (and follows their noise, the thesis's warning about spline surfaces); larger
/// values trade fidelity for smoothness. Solved densely (Eigen LU): meant for up to a few
/// thousand samples.
class ThinPlateSpline {
 public:
  /// Throws std::invalid_argument for lists of different lengths, fewer than 3 samples,
  /// non-finite values, coincident samples, samples on one line, or a negative smoothing.
  static ThinPlateSpline fit(std::span<const double> x, std::span<const double> y, std::span<const double> z,
                             double smoothing = 0.0);

  double operator()(double x, double y) const;
  /// dz/dx and dz/dy at (x, y).
  std::pair<double, double> gradient(double x, double y) const;

  double smoothing() const { return smoothing_; }
  /// Residuals over the fitted samples: root mean square and largest magnitude.
  double rms_residual() const { return rms_; }
  double max_residual() const { return max_; }

 private:
  double scale_x(double x) const { return (2.0 * x - (x_lo_ + x_hi_)) / (x_hi_ - x_lo_); }
  double scale_y(double y) const { return (2.0 * y - (y_lo_ + y_hi_)) / (y_hi_ - y_lo_); }

  double x_lo_ = -1, x_hi_ = 1, y_lo_ = -1, y_hi_ = 1;
  std::vector<double> u_, v_, w_;
  double a_[3] = {0, 0, 0};
  double smoothing_ = 0.0;
  double rms_ = 0.0, max_ = 0.0;
};

}  // namespace latticedyn
