// Orifice: parameter checks and the flow for output and tests.
#include "elements/hydraulic_orifice.hpp"

#include <stdexcept>

namespace latticedyn {

void HydraulicOrificeProperties::validate() const {
  if (!(area > 0)) throw std::invalid_argument("area must be positive");
  if (!(discharge_coefficient > 0 && discharge_coefficient <= 1)) throw std::invalid_argument("discharge_coefficient must lie in (0, 1]");
  if (!(transition_pressure > 0)) throw std::invalid_argument("transition_pressure must be positive");
  if (!(fluid.density > 0)) throw std::invalid_argument("the fluid's density must be positive");
  const bool driven = opening == OrificeOpening::drive || opening == OrificeOpening::spool_positive ||
                      opening == OrificeOpening::spool_negative;
  if (driven && !drive) throw std::invalid_argument("a drive (or spool) opening needs a drive");
  if (opening == OrificeOpening::relief && !(full_open_pressure > cracking_pressure && cracking_pressure >= 0))
    throw std::invalid_argument("a relief valve needs 0 <= cracking_pressure < full_open_pressure");
}

HydraulicOrifice::HydraulicOrifice(HydraulicOrificeProperties p) : props_(std::move(p)) { props_.validate(); }

ElementPower HydraulicOrifice::power(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  ElementPower out;
  out.dissipated = (s[0].pos(0) - s[1].pos(0)) * flow(s[0].pos(0), s[1].pos(0), ctx.time);
  return out;
}

double HydraulicOrifice::flow(double p1, double p2, double t) const {
  std::array<SlotState<double>, 2> s;
  s[0].pos(0) = p1;
  s[1].pos(0) = p2;
  Eigen::Matrix<double, 2, 1> r;
  ElementContext ctx;
  ctx.time = t;
  compute_residual<double>(std::span<const SlotState<double>>(s), ctx, r);
  return r(0) / kHydraulicRowScale;
}

}  // namespace latticedyn
