// Truss sections (thesis 3.5.2, Tables D-3 / D-6) and the lattice bodies built from them.
#pragma once

#include "io/reader_context.hpp"

namespace latticedyn {

/// One entry of `truss_sections`.
TrussSectionSpec read_truss_section(const ReaderContext& ctx, const InputNode& n);
/// `type: lattice`: the unreduced model, every member beam elements.
void read_lattice(ReaderContext& ctx, const InputNode& n, const std::string& name);
/// `type: super_truss`: the reduced model, one super truss element on the two end sections.
void read_super_truss(ReaderContext& ctx, const InputNode& n, const std::string& name);

}  // namespace latticedyn
