// Co-rotational Timoshenko beam: the internal force and its consistent tangent in closed form,
// linearised by hand in 9 directions at once (each varied quantity a 3 x 9 or 1 x 9 matrix).
#include "elements/corotational_beam_kernel.hpp"

namespace latticedyn {

void corotational_force(const CorotationalStiffness& k, const Vec3& d, const Mat3& R1, const Mat3& R2, Vec9& f,
                        Mat9* K) {
  CorotationalForce<double> o;
  corotational_internal_force(k, d, R1, R2, o);
  f = o.f;
  if (!K) return;
  corotational_tangent(k, R1, R2, o, *K);
}

}  // namespace latticedyn
