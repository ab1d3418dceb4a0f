// The unreduced lattice model: every member of a truss section becomes beam elements on shared,
// rigidly connected nodes (thesis 3.5.1, assumption 3), placed in space, with optional rigid end
// sections tied to a reference node per end so that it connects where a super truss would.
#pragma once

#include "assembly/member_builder.hpp"
#include "assembly/model_builder.hpp"
#include "elements/truss_section.hpp"

#include <string>
#include <utility>
#include <vector>

namespace latticedyn {

struct FullLatticeOptions {
  MemberElement member = MemberElement::timoshenko_beam;
  int elements_per_member = 1;
  bool rigid_ends = true;  ///< tie each end section's nodes rigidly to a reference node (fixed constraints)
  Vec3 position = Vec3::Zero();     ///< where the truss frame's origin (end section 1, y = z = 0) is
  Mat3 orientation = Mat3::Identity();  ///< the truss frame: x along the truss
};

/// What was created: the body, its joints by name within the body ("1", "2" at the reference
/// points when the ends are rigid; "e1n<k>", "e2n<k>" at the end-section nodes, k from 1).
struct FullLattice {
  int body = -1;
  std::vector<std::pair<std::string, int>> joints;
  int nodes = 0, members = 0, elements = 0;
};

/// The beam element of every member of `geometry` for `options`' member type and elements per
/// member, in the order of geometry.members. Elements hold no state, so one set serves a member's
/// elements and every body of the section alike.
std::vector<std::shared_ptr<const Element>> lattice_member_elements(const TrussSectionSpec& spec,
                                                                    const TrussGeometry& geometry,
                                                                    const FullLatticeOptions& options);

/// Adds the body `name` with the members of `geometry` (generated from `spec`) to the builder,
/// their elements from `member_elements` (lattice_member_elements; made here when null).
FullLattice add_full_lattice(ModelBuilder& builder, const std::string& name, const TrussSectionSpec& spec,
                             const TrussGeometry& geometry, const FullLatticeOptions& options,
                             const std::vector<std::shared_ptr<const Element>>* member_elements = nullptr);

}  // namespace latticedyn
