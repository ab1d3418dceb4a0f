// Reads a drive function (thesis Appendix E, (8-3)) from its YAML map.
#pragma once

#include "core/drive.hpp"
#include "io/input_node.hpp"

namespace latticedyn {

/// {type: constant | trapezoidal | cosine_step | quintic_step | cosine_full | tanh | sine | table | sum | external,
/// ...}; an external drive (set by a program through the API, held at `initial` otherwise) is
/// not a term of a sum.
Drive read_drive(const InputNode& n);

}  // namespace latticedyn
