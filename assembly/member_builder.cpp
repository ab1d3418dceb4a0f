// Members as elements between consecutive nodes: each element type's slot order.
#include "assembly/member_builder.hpp"

#include "elements/cubic_spline_beam.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace latticedyn {

Vec3 member_point(const Vec3& a, const Vec3& b, int k, int n) { return a + (b - a) * (double(k) / n); }

std::shared_ptr<const Element> make_beam_element(MemberElement kind, const BeamProperties& beam, int gauss_points) {
  switch (kind) {
    case MemberElement::timoshenko_beam: return std::make_shared<TimoshenkoBeam>(beam);
    case MemberElement::cubic_spline_beam: return std::make_shared<CubicSplineBeam>(CubicSplineBeamProperties{beam, gauss_points});
    case MemberElement::rope: break;
  }
  throw std::invalid_argument("make_beam_element: a rope is not a beam");
}

int add_member_elements(ModelBuilder& builder, int body, MemberElement kind, const std::shared_ptr<const Element>& element,
                        std::span<const MemberNode> nodes) {
  if (nodes.size() < 2) throw std::invalid_argument("a member needs at least two nodes");
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const MemberNode& n = nodes[k];
    if (n.translation < 0 || n.orientation < 0 || (kind == MemberElement::cubic_spline_beam && n.stretch < 0))
      throw std::invalid_argument("member node " + std::to_string(k) + " lacks a block its element needs");
  }
  // The element's own slot list must be the one bound here: a mismatch would bind blocks to the
  // wrong slots silently.
  const SlotKind orientation = kind == MemberElement::rope ? SlotKind::vector : SlotKind::rotation;
  std::vector<SlotKind> node{SlotKind::translation, orientation};
  if (kind == MemberElement::cubic_spline_beam) node.push_back(SlotKind::scalar);
  std::vector<SlotKind> expected = node;
  expected.insert(expected.end(), node.begin(), node.end());
  const auto actual = element->slots();
  if (!std::equal(expected.begin(), expected.end(), actual.begin(), actual.end()))
    throw std::invalid_argument("a member element of type " + std::string(element->type_name()) +
                                " does not take the slots of its member kind");
  auto node_slots = [kind](const MemberNode& n) {
    std::vector<SlotBinding> s{{n.translation, Mat3::Identity()}, {n.orientation, n.offset}};
    if (kind == MemberElement::cubic_spline_beam) s.push_back({n.stretch, Mat3::Identity()});
    return s;
  };
  for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
    std::vector<SlotBinding> slots = node_slots(nodes[k]);
    const std::vector<SlotBinding> second = node_slots(nodes[k + 1]);
    slots.insert(slots.end(), second.begin(), second.end());
    builder.add_element(body, element, std::move(slots));
  }
  return static_cast<int>(nodes.size()) - 1;
}

}  // namespace latticedyn
