// Energy ledger: power of every element summed, integrated by the trapezoidal rule.
#include "assembly/energy_ledger.hpp"

#include "elements/hydraulic_fluid.hpp"

#include <algorithm>
#include <cmath>

namespace latticedyn {

double EnergyAccount::relative_imbalance() const {
  const double scale = std::max({std::abs(supplied), std::abs(dissipated), std::abs(compression),
                                 std::abs(mechanical_change)});
  return scale > 0 ? imbalance() / scale : 0.0;
}

bool EnergyLedger::applies(const Model& model) {
  return std::any_of(model.blocks.begin(), model.blocks.end(), [](const DofBlock& b) { return b.first_order; });
}

EnergyLedger::EnergyLedger(const Model& model) : model_(model) {
  for (int e = 0; e < static_cast<int>(model.elements.size()); ++e)
    for (const SlotBinding& s : model.elements[e].slots)
      if (model.blocks[s.block].fixed && model.blocks[s.block].first_order) {
        supply_elements_.push_back(e);
        break;
      }
}

std::array<double, 3> EnergyLedger::rates(const ModelState& state) const {
  std::array<double, 3> out{};
  const ElementContext ctx = state.context();
  for (int e = 0; e < static_cast<int>(model_.elements.size()); ++e) {
    const ElementPower p = model_.elements[e].element->power(state.element_slots(e), ctx);
    out[0] += p.supplied;
    out[1] += p.dissipated;
    out[2] += p.compression;
  }
  // A fixed node (a tank, a pressure supply) is outside the model: what the elements take from
  // it, k Q in their rows, brings p Q (nothing from a tank at 0 Pa).
  VecX r;
  for (int e : supply_elements_) {
    const ElementEntry& entry = model_.elements[e];
    const auto slots = state.element_slots(e);
    r.resize(entry.element->num_dofs());
    entry.element->residual(slots, ctx, r);
    const auto kinds = entry.element->slots();
    int offset = 0;
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      const DofBlock& b = model_.blocks[entry.slots[k].block];
      if (b.fixed && b.first_order) out[0] += slots[k].pos(0) * r(offset) / kHydraulicRowScale;
      offset += slot_size(kinds[k]);
    }
  }
  return out;
}

void EnergyLedger::record(const ModelState& state) {
  const std::array<double, 3> now = rates(state);
  const ElementEnergy e = state.energy();
  const double mechanical = e.kinetic + e.gravity_potential + e.strain;
  if (!started_) {
    started_ = true;
    start_mechanical_ = mechanical;
    start_fluid_ = e.fluid;
  } else {
    const double h = state.time() - account_.time;
    account_.supplied += 0.5 * h * (last_rates_[0] + now[0]);
    account_.dissipated += 0.5 * h * (last_rates_[1] + now[1]);
    account_.compression += 0.5 * h * (last_rates_[2] + now[2]);
  }
  last_rates_ = now;
  account_.time = state.time();
  account_.mechanical_change = mechanical - start_mechanical_;
  account_.fluid_change = e.fluid - start_fluid_;
}

}  // namespace latticedyn
