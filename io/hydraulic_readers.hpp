// Readers of the hydraulic circuit (thesis 5.1.2): the fluid and its nodes (pressures), the valves
// and pumps between them, and the hydraulic cylinder body that joins circuit and mechanism.
#pragma once

#include "io/reader_context.hpp"

#include <string_view>

namespace latticedyn {

/// Label of a hydraulic node's pressure block, "hydraulic node NAME": how the results writer and
/// the verification runner find the pressures.
inline constexpr std::string_view kHydraulicNodeLabel = "hydraulic node ";

/// `hydraulics.fluid` and `hydraulics.nodes`: a scalar pressure block per node (fixed for a tank
/// or pressure supply) with its oil volume. Before the bodies, whose cylinders name the nodes.
void read_hydraulic_nodes(ReaderContext& ctx, const InputNode& hydraulics);
/// `hydraulics.elements`: orifices, relief valves, directional valves and pumps, each a body of
/// its own name.
void read_hydraulic_elements(ReaderContext& ctx, const InputNode& hydraulics);
/// A `bodies` entry of type hydraulic_cylinder: two end nodes (joints name.1, name.2) and its
/// chambers on two hydraulic nodes (`ports`).
void read_hydraulic_cylinder(ReaderContext& ctx, const InputNode& n, const std::string& name);

}  // namespace latticedyn
