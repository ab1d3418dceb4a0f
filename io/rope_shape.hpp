// Initial shape of a rope longer than its span: a parabola sagging towards gravity with its nodes
// at equal arc length, so that statics starts from a rope in uniform tension, not a slack one.
#pragma once

#include "core/types.hpp"

#include <optional>
#include <vector>

namespace latticedyn {

struct RopeShape {
  std::vector<Vec3> positions;  ///< nodes 0..n
  std::vector<Vec3> slopes;     ///< dr/dS at the nodes (S: unstretched arc length)
};

/// Nodes of a rope of unstretched length L0 between `start` and `end` in n elements. A rope at
/// most as long as its span is straight and uniformly stretched. A longer one hangs as a parabola
/// in the plane of the chord and `across` (a unit vector normal to the chord, towards gravity)
/// whose arc length is L0 (1 + strain): the strain of its horizontal pull w D^2 / (8 f EA)
/// (parabolic cable theory, Irvine, Cable Structures, 1981, 2.3), so every element starts in
/// tension. `sag` overrides the sag f (the strain then follows from the arc length).
RopeShape rope_initial_shape(const Vec3& start, const Vec3& end, double L0, int n, const Vec3& across,
                             double weight_per_length, double axial_stiffness, std::optional<double> sag);

}  // namespace latticedyn
