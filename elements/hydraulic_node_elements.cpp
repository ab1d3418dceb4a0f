// One-node hydraulic elements: checks and the stored energy of a node's oil.
#include "elements/hydraulic_node_elements.hpp"

#include <cmath>
#include <stdexcept>

namespace latticedyn {

HydraulicVolume::HydraulicVolume(double volume, const HydraulicFluid& fluid)
    : volume_(volume), bulk_modulus_(fluid.bulk_modulus) {
  if (!(volume > 0)) throw std::invalid_argument("a hydraulic node's volume must be positive");
  if (!(bulk_modulus_ > 0)) throw std::invalid_argument("the fluid's bulk_modulus must be positive");
}

ElementEnergy HydraulicVolume::energy(std::span<const SlotState<double>> s, const ElementContext&) const {
  ElementEnergy e;
  e.fluid = volume_ * s[0].pos(0) * s[0].pos(0) / (2 * bulk_modulus_);
  return e;
}

ElementPower HydraulicVolume::power(std::span<const SlotState<double>> s, const ElementContext&) const {
  ElementPower out;
  out.compression = s[0].pos(0) * volume_ * s[0].vel(0) / bulk_modulus_;
  return out;
}

HydraulicPump::HydraulicPump(double flow, std::optional<Drive> drive) : flow_(flow), drive_(std::move(drive)) {
  if (!std::isfinite(flow)) throw std::invalid_argument("the pump's flow must be finite");
}

}  // namespace latticedyn
