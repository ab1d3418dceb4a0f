// A member (beam, rope, lattice member) as elements between consecutive nodes along it: where its
// nodes lie and in which order each element type binds them, in one place for every builder.
#pragma once

#include "assembly/model_builder.hpp"
#include "elements/timoshenko_beam.hpp"

#include <memory>
#include <span>

namespace latticedyn {

enum class MemberElement { timoshenko_beam, cubic_spline_beam, rope };

/// A node of a member as its elements see it: the translation block; the orientation block (the
/// rotation for beams, with the constant offset from the block's frame to the member's, as at a
/// rigid lattice joint; the slope vector r' for ropes); a cubic spline beam's axis stretch.
struct MemberNode {
  int translation = -1;
  int orientation = -1;
  Mat3 offset = Mat3::Identity();
  int stretch = -1;
};

/// The k-th of n + 1 equally spaced points from a (k = 0) to b (k = n): a straight member's nodes.
Vec3 member_point(const Vec3& a, const Vec3& b, int k, int n);

/// The element of a beam member of `kind` (Timoshenko or cubic spline with `gauss_points`).
/// Elements hold no state: one serves every element of a member. Throws std::invalid_argument for
/// invalid properties or a rope.
std::shared_ptr<const Element> make_beam_element(MemberElement kind, const BeamProperties& beam, int gauss_points = 5);

/// Binds `element` between each pair of consecutive `nodes` (nodes.size() - 1 elements) in the slot
/// order of `kind`: Timoshenko (t, R, t', R'), cubic spline (t, R, s, t', R', s'), rope (t, r', t',
/// r''). Returns the number of elements added. Throws std::invalid_argument for fewer than two
/// nodes or a node without a block its kind needs.
int add_member_elements(ModelBuilder& builder, int body, MemberElement kind, const std::shared_ptr<const Element>& element,
                        std::span<const MemberNode> nodes);

}  // namespace latticedyn
