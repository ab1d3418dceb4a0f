// atan2 for the small angles kinematics mostly sees: an odd series where it is exact to round-off,
// the library function elsewhere.
#pragma once

#include <cmath>

namespace latticedyn {

/// atan2(y, x) in double, from the odd series of atan(y/x) where x > 0 and |y| < x/20 (the first
/// omitted term, t^13/13, is below 2e-17 of the result there), else std::atan2: the small angles
/// of a lattice's twist are the common case, and std::atan2 costs several times more.
inline double fast_atan2(double y, double x) {
  if (x > 0.0 && std::abs(y) < 0.05 * x) {
    const double t = y / x, t2 = t * t;
    return t * (1.0 - t2 * (1.0 / 3 - t2 * (1.0 / 5 - t2 * (1.0 / 7 - t2 * (1.0 / 9 - t2 * (1.0 / 11))))));
  }
  return std::atan2(y, x);
}

}  // namespace latticedyn
