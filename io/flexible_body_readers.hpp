// Readers of the flexible members of the model format: beams (co-rotational Timoshenko or cubic
// spline) and ropes, each a straight member split into n elements that share their nodes.
#pragma once

#include "io/reader_context.hpp"

namespace latticedyn {

/// `type: timoshenko_beam` or `type: cubic_spline_beam` (thesis 3.3, 3.4).
void read_beam(ReaderContext& ctx, const InputNode& n, const std::string& name, const std::string& type);
/// `type: rope` (thesis 7.2).
void read_rope(ReaderContext& ctx, const InputNode& n, const std::string& name);

}  // namespace latticedyn
