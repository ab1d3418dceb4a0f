// The surface of either kind.
#include "control/surface_fit.hpp"

#include <cstdio>

namespace latticedyn {

std::string SurfaceSettings::describe() const {
  char buf[96];
  if (kind == Kind::polynomial)
    std::snprintf(buf, sizeof buf, "polynomial %d-%d", order_x, order_y);
  else
    std::snprintf(buf, sizeof buf, "thin plate spline, smoothing %g", smoothing);
  return buf;
}

SurfaceFit SurfaceFit::fit(const SurfaceSettings& settings, std::span<const double> x, std::span<const double> y,
                           std::span<const double> z) {
  SurfaceFit f;
  if (settings.kind == SurfaceSettings::Kind::polynomial)
    f.s_ = PolynomialSurface::fit(x, y, z, settings.order_x, settings.order_y);
  else
    f.s_ = ThinPlateSpline::fit(x, y, z, settings.smoothing);
  return f;
}

double SurfaceFit::operator()(double x, double y) const {
  return std::visit([&](const auto& s) { return s(x, y); }, s_);
}
std::pair<double, double> SurfaceFit::gradient(double x, double y) const {
  return std::visit([&](const auto& s) { return s.gradient(x, y); }, s_);
}
double SurfaceFit::rms_residual() const {
  return std::visit([](const auto& s) { return s.rms_residual(); }, s_);
}
double SurfaceFit::max_residual() const {
  return std::visit([](const auto& s) { return s.max_residual(); }, s_);
}

}  // namespace latticedyn
