// What both constraint evaluators (closed form, and the AD reference) share: the free blocks a
// constraint's joints move with, and a joint's frame from its blocks' state.
#pragma once

#include "assembly/constraint_evaluator.hpp"

namespace latticedyn::constraint_detail {

/// The distinct free blocks of a constraint's joints, in order of appearance (3 columns each),
/// into out.blocks and out.cols; returns their number.
int collect_blocks(const ConstraintInputs& in, ConstraintEval& out);

/// Position and orientation of a joint frame from its translation r and its body's rotation R
/// (none: the joint's frame is fixed in space).
template <class S>
void frame_of(const Joint& j, const Vec3T<S>& r, const Mat3T<S>* R, Vec3T<S>& pos, Mat3T<S>& rot) {
  if (R) {
    pos = r + (*R) * cast_to<S>(j.offset);
    rot = (*R) * cast_to<S>(j.frame);
  } else {
    pos = r;
    rot = cast_to<S>(j.frame);
  }
}

}  // namespace latticedyn::constraint_detail
