// Readers of the body types of the model format (thesis Table 5-1): each creates the body's DoF
// blocks, element and joints in the model under construction.
#pragma once

#include "io/reader_context.hpp"

namespace latticedyn {

/// Reads one entry of `bodies` (its `type` selects the reader).
void read_body(ReaderContext& ctx, const InputNode& n);
/// The ground's fixed joints (thesis's frame, body 0).
void read_ground(ReaderContext& ctx, const InputNode& n);

}  // namespace latticedyn
