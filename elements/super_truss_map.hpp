// The kinematic map of the super truss (thesis 3.5.1): lattice node poses as functions of the two
// end sections' frames, written once (templated) and evaluated in double, through time jets and
// with automatic differentiation of the internal nodes' three Cardan angles.
#pragma once

#include "core/dual.hpp"
#include "core/jet.hpp"
#include "core/rotation.hpp"
#include "elements/affine_point.hpp"
#include "elements/corotational_beam_kernel.hpp"
#include "elements/truss_section.hpp"

#include <vector>

namespace latticedyn {

/// Assumptions of 3.5.1:
/// - end-section nodes ride rigidly on their end frame: p = r_i + R_i s (3-87);
/// - each main beam is a cubic Hermite curve between its end nodes with end tangents L_m R_i a_m
///   (a_m its undeformed direction, no axial strain, rigid connection to the end sections, 3-90);
///   its internal nodes sit at equal parameter steps xi, oriented by relative Cardan angles from
///   the main beam's frame at end 1, A = R_1 F: R_n = A Rz(theta) Ry(psi) Rx(phi), theta and psi
///   the direction of the curve's tangent in A, phi = xi phi_12 the interpolated twist (3.4, 3-92).
/// Every node position is therefore affine in the end frames (AffinePoint); the internal nodes'
/// rotations depend on the end frames through the relative pose (R_1^T (r_2 - r_1), R_1^T R_2) only.
class SuperTrussMap {
 public:
  struct MainBeam {
    int start = -1, end = -1;  ///< end-section nodes
    Mat3 frame;                ///< F: the main beam's frame in the truss frame
    std::vector<int> internal;
  };
  struct Node {
    int end = 0;          ///< 1 or 2 for end-section nodes, 0 for internal nodes
    int main_beam = -1;   ///< internal nodes
    double xi = 0.0;      ///< internal nodes: parameter along the main beam
    AffinePoint point;    ///< the position
    // Internal nodes: the curve's tangent dr/dxi = g2 (r2 - r1) + R1 t1 + R2 t2.
    double g2 = 0.0;
    Vec3 t1 = Vec3::Zero(), t2 = Vec3::Zero();
  };

  /// R_1^T (r_2 - r_1) and R_1^T R_2.
  template <class T>
  struct RelativePose {
    Vec3T<T> d;
    Mat3T<T> Q;
  };

  SuperTrussMap(const TrussSectionSpec& spec, const TrussGeometry& g);

  int num_nodes() const { return static_cast<int>(nodes_.size()); }
  const Node& node(int n) const { return nodes_[n]; }
  const std::vector<MainBeam>& main_beams() const { return main_beams_; }
  /// Internal nodes in the order of main_beams() and their internal lists.
  const std::vector<int>& internal_nodes() const { return internal_; }

  template <class T>
  static RelativePose<T> relative_pose(const Vec3T<T>& d, const Mat3T<T>& R1, const Mat3T<T>& R2) {
    return {R1.transpose() * d, R1.transpose() * R2};
  }
  /// phi_12 of a main beam: the twist angle of C_12 = F^T Q F about x.
  template <class T>
  static T twist(const MainBeam& mb, const Mat3T<T>& Q) {
    using std::atan2;
    const Vec3T<T> qf1 = Q * mb.frame.col(1), qf2 = Q * mb.frame.col(2);
    const Vec3 f2 = mb.frame.col(2);
    return atan2(f2.dot(qf1), f2.dot(qf2));
  }
  /// (phi, psi, theta) of an internal node: m = F^T (g2 d + t1 + Q t2) is the tangent in A.
  template <class T>
  Vec3T<T> cardan_angles(const Node& nd, const RelativePose<T>& rel, const T& phi12) const {
    using std::atan2;
    using std::sqrt;
    const Mat3& F = main_beams_[nd.main_beam].frame;
    const Vec3T<T> w = rel.d * nd.g2 + rel.Q * nd.t2;
    const Vec3T<T> m = F.transpose() * Vec3T<T>(w + nd.t1);
    const T psi = atan2(-m(2), sqrt(m(0) * m(0) + m(1) * m(1)));
    const T theta = atan2(m(1), m(0));
    return Vec3T<T>(phi12 * nd.xi, psi, theta);
  }
  /// Cardan angles of every internal node (in the order of internal_nodes()).
  template <class T>
  void all_cardan_angles(const Vec3T<T>& d, const Mat3T<T>& R1, const Mat3T<T>& R2, std::vector<Vec3T<T>>& y) const {
    const RelativePose<T> rel = relative_pose<T>(d, R1, R2);
    y.resize(internal_.size());
    std::size_t k = 0;
    for (const MainBeam& mb : main_beams_) {
      const T phi12 = twist<T>(mb, rel.Q);
      for (int n : mb.internal) y[k++] = cardan_angles<T>(nodes_[n], rel, phi12);
    }
  }

  /// Positions and orientations of every lattice node (double, jets, AD numbers alike).
  template <class T>
  void node_poses(const Vec3T<T>& r1, const Mat3T<T>& R1, const Vec3T<T>& r2, const Mat3T<T>& R2,
                  std::vector<Vec3T<T>>& p, std::vector<Mat3T<T>>& R) const;

 private:
  std::vector<Node> nodes_;
  std::vector<MainBeam> main_beams_;
  std::vector<int> internal_;
};

/// Rotation data of one internal node at a state, in double: the sines and cosines of its angles
/// phi and psi (T depends on no other), the Cardan matrix C, its tangent T (body rate C^T C' =
/// skew(T y')) and T's rate, the angles' Jacobian Y (y' = Y dq), the node's angular-velocity
/// Jacobian Jw = C^T E1 + T Y (E1 dq = F^T w1), the angle rates y', y'' of the current motion, and
/// A = R1 F (R_n = A C).
struct InternalRotation {
  // Filled whole by internal_rotations: an empty constructor keeps std::vector::resize from zeroing
  // a kilobyte per node each time one thread's scratch moves between elements of different sizes.
  InternalRotation() {}
  double sphi, cphi, spsi, cpsi;
  Vec3 ydot, yddot;
  Mat3 C, T, A;
  Vec3 m;                              ///< the main beam's tangent in A (theta, psi its direction)
  // RotationDetail::gradients and more:
  Mat3 Tdot;
  Eigen::Matrix<double, 3, 9> dm;      ///< dm/d(d, delta_1, delta_2)
  Row9 dphi;                           ///< the twist angle's gradient in (d, delta_1, delta_2)
  Eigen::RowVector3d gpsi, gtheta;     ///< dpsi/dm, dtheta/dm
  // RotationDetail::jacobians:
  Mat312 Y, Jw;
};

/// Jw^T v: a moment v on an internal node's frame as generalized force on the 12 DoFs (virtual
/// power), from the angles' gradients without forming Y and Jw; F is its main beam's frame.
Vec12 internal_node_moment(const InternalRotation& o, const Mat3& F, const Vec3& v);

/// What the tangents of the rotary inertia need beyond InternalRotation: the derivatives of y' and
/// y'' under a right perturbation of the state at fixed rates (d(y', y'')/d eps).
struct InternalRotationTangent {
  InternalRotationTangent() {}  // filled whole: no zeroing on resize
  Mat312 dydot, dyddot;
};

/// How much of InternalRotation an evaluation needs: the frames and angle rates (output: drawing
/// and energies), the angles' gradients as well (the residual projects moments with them), or the
/// Jacobians Y and Jw too (tangents).
enum class RotationDetail { frames, gradients, jacobians };

/// Evaluations of the map's internal rotations at the slots' state, to the detail asked for.
void internal_rotations(const SuperTrussMap& map, std::span<const SlotState<double>> s,
                        std::vector<InternalRotation>& out, RotationDetail detail = RotationDetail::jacobians);
void internal_rotation_tangents(const SuperTrussMap& map, std::span<const SlotState<double>> s,
                                std::vector<InternalRotationTangent>& out);

/// The angles' second derivatives against weights: K = d/d eps [sum_n c_n . y_n'(x (+) eps)] as a
/// matrix over the variables x = (d, delta_1, delta_2) on both sides (rows: the virtual
/// displacement, columns: eps): the symmetric Hessian of sum_n c_n . y_n plus skew(g)/2 on each
/// rotation's diagonal block, g its gradient. In closed form: every angle is a function of the
/// relative pose (R1^T d, Q = R1^T R2), on which the weights act linearly, so their second
/// derivatives reduce to those of v . R1^T d and tr(B^T Q) and the angle functions' own Hessians.
Mat9 contracted_angle_hessian(const SuperTrussMap& map, std::span<const SlotState<double>> s,
                              const std::vector<InternalRotation>& rot, const std::vector<Vec3>& c);

// ---------------------------------------------------------------------------------------------

template <class T>
void SuperTrussMap::node_poses(const Vec3T<T>& r1, const Mat3T<T>& R1, const Vec3T<T>& r2, const Mat3T<T>& R2,
                               std::vector<Vec3T<T>>& p, std::vector<Mat3T<T>>& R) const {
  p.resize(nodes_.size());
  R.resize(nodes_.size());
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    const AffinePoint& a = nodes_[n].point;
    p[n] = r1 * a.alpha[0] + R1 * a.c[0] + r2 * a.alpha[1] + R2 * a.c[1];
    if (nodes_[n].end != 0) R[n] = nodes_[n].end == 1 ? R1 : R2;
  }
  std::vector<Vec3T<T>> y;
  all_cardan_angles<T>(Vec3T<T>(r2 - r1), R1, R2, y);
  for (std::size_t k = 0; k < internal_.size(); ++k) {
    const int n = internal_[k];
    const Mat3& F = main_beams_[nodes_[n].main_beam].frame;
    R[n] = Mat3T<T>(R1 * F) * rotation_z<T>(y[k](2)) * rotation_y<T>(y[k](1)) * rotation_x<T>(y[k](0));
  }
}

}  // namespace latticedyn
