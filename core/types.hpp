// Small fixed-size Eigen types shared by every layer, templated on the scalar so that the same
// kernels run on double and on Eigen::AutoDiffScalar (automatic differentiation of tangents).
#pragma once

#include <Eigen/Dense>

#include <type_traits>

namespace latticedyn {

template <class S>
using Vec3T = Eigen::Matrix<S, 3, 1>;
template <class S>
using Mat3T = Eigen::Matrix<S, 3, 3>;

using Vec3 = Vec3T<double>;
using Mat3 = Mat3T<double>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;
using Row9 = Eigen::Matrix<double, 1, 9>;
using Vec12 = Eigen::Matrix<double, 12, 1>;
using Row12 = Eigen::Matrix<double, 1, 12>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat312 = Eigen::Matrix<double, 3, 12>;  ///< a 3-vector's derivative in the 12 DoFs of two frames
using Mat123 = Eigen::Matrix<double, 12, 3>;  ///< its transpose
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

/// The plain double value of a scalar that may be an (optionally nested) AutoDiffScalar.
/// Kernels use it to choose between a closed form and its series near a removable singularity.
template <class S>
double scalar_value(const S& s) {
  if constexpr (std::is_arithmetic_v<S>) {
    return static_cast<double>(s);
  } else {
    return scalar_value(s.value());
  }
}

/// Cast a double vector or matrix to scalar type S (constant: no derivative part).
template <class S, class Derived>
auto cast_to(const Eigen::MatrixBase<Derived>& m) {
  return m.template cast<S>().eval();
}

}  // namespace latticedyn
