// Four doubles that act as one scalar: a kernel templated on its scalar type evaluates four
// elements at once with it (each operation a fixed loop of four that the compiler turns into one
// vector instruction), for the many small members of a super truss.
#pragma once

#include "core/rotation.hpp"
#include "core/types.hpp"

#include <Eigen/Core>

#include <cmath>

namespace latticedyn {

struct Pack4 {
  static constexpr int kLanes = 4;
  // GCC's vector extension: +, -, *, / of two of them are one AVX instruction each.
  typedef double Lanes __attribute__((vector_size(32)));
  Lanes x;

  Pack4() = default;
  Pack4(double a) : x{a, a, a, a} {}  // NOLINT: constants convert implicitly, as doubles do
  explicit Pack4(Lanes v) : x(v) {}
  double& operator[](int i) { return reinterpret_cast<double*>(&x)[i]; }
  double operator[](int i) const { return x[i]; }
  /// The largest lane: a branch on scalar_value takes the closed form only if every lane may.
  double value() const {
    double m = x[0];
    for (int i = 1; i < kLanes; ++i) m = x[i] > m ? x[i] : m;
    return m;
  }

  Pack4& operator+=(const Pack4& b) {
    x += b.x;
    return *this;
  }
  Pack4& operator-=(const Pack4& b) {
    x -= b.x;
    return *this;
  }
  Pack4& operator*=(const Pack4& b) {
    x *= b.x;
    return *this;
  }
  Pack4& operator/=(const Pack4& b) {
    x /= b.x;
    return *this;
  }
};

inline Pack4 operator+(const Pack4& a, const Pack4& b) { return Pack4(a.x + b.x); }
inline Pack4 operator-(const Pack4& a, const Pack4& b) { return Pack4(a.x - b.x); }
inline Pack4 operator*(const Pack4& a, const Pack4& b) { return Pack4(a.x * b.x); }
inline Pack4 operator/(const Pack4& a, const Pack4& b) { return Pack4(a.x / b.x); }
inline Pack4 operator+(const Pack4& a, double b) { return Pack4(a.x + b); }
inline Pack4 operator-(const Pack4& a, double b) { return Pack4(a.x - b); }
inline Pack4 operator*(const Pack4& a, double b) { return Pack4(a.x * b); }
inline Pack4 operator/(const Pack4& a, double b) { return Pack4(a.x / b); }
inline Pack4 operator+(double a, const Pack4& b) { return Pack4(a + b.x); }
inline Pack4 operator-(double a, const Pack4& b) { return Pack4(a - b.x); }
inline Pack4 operator*(double a, const Pack4& b) { return Pack4(a * b.x); }
inline Pack4 operator/(double a, const Pack4& b) { return Pack4(a / b.x); }
inline Pack4 operator-(const Pack4& a) { return Pack4(-a.x); }

inline Pack4 sqrt(const Pack4& a) {
  Pack4 out;
  for (int i = 0; i < Pack4::kLanes; ++i) out[i] = std::sqrt(a[i]);
  return out;
}

}  // namespace latticedyn

namespace Eigen {

template <>
struct NumTraits<latticedyn::Pack4> : NumTraits<double> {
  using Real = latticedyn::Pack4;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = double;
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 0, ReadCost = 1, AddCost = 1,
         MulCost = 1 };
};
template <class Op>
struct ScalarBinaryOpTraits<latticedyn::Pack4, double, Op> {
  using ReturnType = latticedyn::Pack4;
};
template <class Op>
struct ScalarBinaryOpTraits<double, latticedyn::Pack4, Op> {
  using ReturnType = latticedyn::Pack4;
};

}  // namespace Eigen

namespace latticedyn {

/// Log map of rotations near the identity (small_rotation_vector): its series on all lanes at once
/// where every lane is small, else lane by lane.
inline Vec3T<Pack4> small_rotation_vector(const Mat3T<Pack4>& R) {
  const Vec3T<Pack4> v = unskew(R);  // sin(theta) n
  const Pack4 s2 = v.squaredNorm();
  if (s2.value() < rotation_detail::kSmallAngleSeriesBelow) return v * rotation_detail::angle_over_sine_series(s2);
  Vec3T<Pack4> out;
  for (int l = 0; l < Pack4::kLanes; ++l) {
    Mat3 Rl;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Rl(i, j) = R(i, j)[l];
    const Vec3 v = small_rotation_vector<double>(Rl);
    for (int i = 0; i < 3; ++i) out(i)[l] = v(i);
  }
  return out;
}

/// c3 of T^-1 (rotation_detail::inverse_coefficient) and dc3/dx: from the series on all lanes at
/// once where every lane is small, else lane by lane.
inline void inverse_coefficient_and_derivative(const Pack4& x, Pack4* c3, Pack4* dc3) {
  if (x.value() < rotation_detail::kSeriesBelow) {
    *c3 = rotation_detail::inverse_coefficient_series(x);
    if (dc3) *dc3 = rotation_detail::inverse_coefficient_derivative_series(x);
    return;
  }
  for (int l = 0; l < Pack4::kLanes; ++l) {
    double c, dc;
    rotation_detail::inverse_coefficient_and_derivative(x[l], &c, &dc);
    (*c3)[l] = c;
    if (dc3) (*dc3)[l] = dc;
  }
}

/// T(phi)^-T m (tangent_inverse_transpose_times) on four lanes.
inline Vec3T<Pack4> tangent_inverse_transpose_times(const Vec3T<Pack4>& phi, const Vec3T<Pack4>& m) {
  Pack4 c3;
  inverse_coefficient_and_derivative(phi.squaredNorm(), &c3, nullptr);
  const Vec3T<Pack4> pm = phi.cross(m);
  return m - pm * Pack4(0.5) + phi.cross(pm) * c3;
}

/// T(phi)^-1 (tangent_operator_inverse) on four lanes.
inline Mat3T<Pack4> tangent_operator_inverse(const Vec3T<Pack4>& phi) {
  Pack4 c3;
  inverse_coefficient_and_derivative(phi.squaredNorm(), &c3, nullptr);
  const Mat3T<Pack4> P = skew(phi);
  return Mat3T<Pack4>::Identity() + P * Pack4(0.5) + (P * P) * c3;
}

/// d(T^-T m)/dphi (tangent_inverse_transpose_derivative) on four lanes.
inline Mat3T<Pack4> tangent_inverse_transpose_derivative(const Vec3T<Pack4>& phi, const Vec3T<Pack4>& m) {
  Pack4 c3, dc3;
  inverse_coefficient_and_derivative(phi.squaredNorm(), &c3, &dc3);
  return tangent_inverse_transpose_derivative<Pack4>(phi, m, c3, dc3);
}

}  // namespace latticedyn

namespace latticedyn {

/// Lane l of a fixed-size matrix of packs, as doubles.
template <class Derived>
Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime> lane(const Eigen::MatrixBase<Derived>& m,
                                                                                     int l) {
  Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime> out;
  for (int j = 0; j < m.cols(); ++j)
    for (int i = 0; i < m.rows(); ++i) out(i, j) = m(i, j)[l];
  return out;
}

/// Sets lane l of a fixed-size matrix of packs from doubles.
template <class Derived, class Other>
void set_lane(Eigen::MatrixBase<Derived>& m, int l, const Eigen::MatrixBase<Other>& v) {
  for (int j = 0; j < m.cols(); ++j)
    for (int i = 0; i < m.rows(); ++i) m(i, j)[l] = v(i, j);
}

}  // namespace latticedyn
