// One fitted surface z(x, y) of the quasi-static map, polynomial or thin plate spline (thesis 6.2),
// behind one interface so that the control pipeline and its report need not care which.
#pragma once

#include "control/polynomial_surface.hpp"
#include "control/thin_plate_spline.hpp"

#include <span>
#include <string>
#include <variant>

namespace latticedyn {

struct SurfaceSettings {
  enum class Kind { polynomial, thin_plate } kind = Kind::polynomial;
  int order_x = 2, order_y = 2;  ///< polynomial (the thesis recommends 2-2)
  double smoothing = 0.0;        ///< thin plate spline
  std::string describe() const;  ///< "polynomial 2-2" or "thin plate spline, smoothing 0"
};

class SurfaceFit {
 public:
  /// Throws std::invalid_argument as the underlying fit does.
  static SurfaceFit fit(const SurfaceSettings& settings, std::span<const double> x, std::span<const double> y,
                        std::span<const double> z);
  double operator()(double x, double y) const;
  std::pair<double, double> gradient(double x, double y) const;
  double rms_residual() const;
  double max_residual() const;

 private:
  std::variant<PolynomialSurface, ThinPlateSpline> s_;
};

}  // namespace latticedyn
