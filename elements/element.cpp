// Defaults of the element contract shared by all element types.
#include "elements/element.hpp"

namespace latticedyn {

int Element::num_dofs() const {
  int n = 0;
  for (SlotKind k : slots()) n += slot_size(k);
  return n;
}

std::vector<Vec3> Element::axis_points(std::span<const SlotState<double>> state, const ElementContext&) const {
  std::vector<Vec3> pts;
  const auto kinds = slots();
  for (std::size_t k = 0; k < kinds.size(); ++k)
    if (kinds[k] == SlotKind::translation) pts.push_back(state[k].pos);
  return pts;
}

void Element::residual_batch(std::span<const Element* const> elements,
                             std::span<const std::span<const SlotState<double>>> states, const ElementContext& ctx,
                             std::span<VecX> out) const {
  for (std::size_t k = 0; k < elements.size(); ++k) {
    out[k].resize(elements[k]->num_dofs());
    elements[k]->residual(states[k], ctx, out[k]);
  }
}

void Element::tangents_batch(std::span<const Element* const> elements,
                             std::span<const std::span<const SlotState<double>>> states, const ElementContext& ctx,
                             std::span<ElementTangents> out) const {
  for (std::size_t k = 0; k < elements.size(); ++k) elements[k]->tangents(states[k], ctx, out[k]);
}

void Element::output(std::span<const SlotState<double>> state, const ElementContext& ctx, ElementOutput& out) const {
  out.energy = energy(state, ctx);
  out.axial_force = axial_force(state, ctx);
  out.polylines = axis_polylines(state, ctx);
  out.polyline_axial_forces = polyline_axial_forces(state, ctx);
  out.members.clear();
}

}  // namespace latticedyn
