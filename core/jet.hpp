// Second-order Taylor jets in time: a quantity with its first and second time derivatives,
// propagated through arithmetic and elementary functions. Kinematic maps written once then give
// velocities and accelerations (the super truss's internal nodes) on any scalar type S.
#pragma once

#include "core/fast_atan2.hpp"
#include "core/types.hpp"

#include <cmath>

namespace latticedyn {

/// x(t) to second order: value x, rate dx = x', acceleration ddx = x''.
template <class S>
struct Jet {
  S x{}, dx{}, ddx{};

  Jet() = default;
  Jet(double c) : x(c), dx(0.0), ddx(0.0) {}  // NOLINT: constants convert implicitly
  Jet(const S& value, const S& rate, const S& accel) : x(value), dx(rate), ddx(accel) {}
  static Jet constant(const S& c) { return Jet(c, S(0.0), S(0.0)); }

  Jet& operator+=(const Jet& b) {
    x += b.x;
    dx += b.dx;
    ddx += b.ddx;
    return *this;
  }
  Jet& operator-=(const Jet& b) {
    x -= b.x;
    dx -= b.dx;
    ddx -= b.ddx;
    return *this;
  }
  Jet& operator*=(const Jet& b) {
    const S nx = x * b.x, ndx = dx * b.x + x * b.dx, nddx = ddx * b.x + S(2.0) * (dx * b.dx) + x * b.ddx;
    x = nx;
    dx = ndx;
    ddx = nddx;
    return *this;
  }
  Jet& operator/=(const Jet& b) { return *this *= b.reciprocal(); }
  Jet reciprocal() const {
    const S inv = S(1.0) / x;
    return chain(inv, -inv * inv, S(2.0) * inv * inv * inv);
  }
  /// f(x(t)) from f, f', f'' at x.
  Jet chain(const S& f, const S& df, const S& ddf) const { return Jet(f, df * dx, ddf * dx * dx + df * ddx); }
};

template <class S>
Jet<S> operator+(Jet<S> a, const Jet<S>& b) { return a += b; }
template <class S>
Jet<S> operator-(Jet<S> a, const Jet<S>& b) { return a -= b; }
template <class S>
Jet<S> operator*(Jet<S> a, const Jet<S>& b) { return a *= b; }
template <class S>
Jet<S> operator/(Jet<S> a, const Jet<S>& b) { return a /= b; }
template <class S>
Jet<S> operator-(const Jet<S>& a) { return Jet<S>(-a.x, -a.dx, -a.ddx); }
template <class S>
Jet<S> operator*(const Jet<S>& a, double c) { return Jet<S>(a.x * c, a.dx * c, a.ddx * c); }
template <class S>
Jet<S> operator*(double c, const Jet<S>& a) { return a * c; }
template <class S>
Jet<S> operator/(const Jet<S>& a, double c) { return a * (1.0 / c); }
template <class S>
Jet<S> operator+(const Jet<S>& a, double c) { return Jet<S>(a.x + c, a.dx, a.ddx); }
template <class S>
Jet<S> operator-(const Jet<S>& a, double c) { return Jet<S>(a.x - c, a.dx, a.ddx); }
template <class S>
Jet<S> operator-(double c, const Jet<S>& a) { return Jet<S>(c - a.x, -a.dx, -a.ddx); }
template <class S>
bool operator<(const Jet<S>& a, const Jet<S>& b) { return scalar_value(a.x) < scalar_value(b.x); }
template <class S>
bool operator>(const Jet<S>& a, const Jet<S>& b) { return scalar_value(a.x) > scalar_value(b.x); }

template <class S>
Jet<S> sqrt(const Jet<S>& a) {
  using std::sqrt;
  const S s = sqrt(a.x);
  return a.chain(s, S(0.5) / s, S(-0.25) / (s * a.x));
}
template <class S>
Jet<S> sin(const Jet<S>& a) {
  using std::cos;
  using std::sin;
  const S s = sin(a.x), c = cos(a.x);
  return a.chain(s, c, -s);
}
template <class S>
Jet<S> cos(const Jet<S>& a) {
  using std::cos;
  using std::sin;
  const S s = sin(a.x), c = cos(a.x);
  return a.chain(c, -s, -c);
}
/// atan2(y, x): with D = x^2 + y^2 and N = x y' - y x', the rate is N / D and the acceleration
/// (x y'' - y x'') / D - N D' / D^2.
template <class S>
Jet<S> atan2(const Jet<S>& y, const Jet<S>& x) {
  using std::atan2;
  const S D = x.x * x.x + y.x * y.x;
  const S N = x.x * y.dx - y.x * x.dx;
  const S dD = S(2.0) * (x.x * x.dx + y.x * y.dx);
  S value;
  if constexpr (std::is_same_v<S, double>)
    value = fast_atan2(y.x, x.x);
  else
    value = atan2(y.x, x.x);
  return Jet<S>(value, N / D, (x.x * y.ddx - y.x * x.ddx) / D - N * dD / (D * D));
}

/// The value of a jet's scalar (for branches on removable singularities).
template <class S>
double scalar_value(const Jet<S>& j) {
  return scalar_value(j.x);
}

/// A rotation matrix jet from R, its body angular velocity w and acceleration dw:
/// R' = R skew(w), R'' = R (skew(dw) + skew(w)^2).
template <class S>
Mat3T<Jet<S>> rotation_jet(const Mat3T<S>& R, const Vec3T<S>& w, const Vec3T<S>& dw) {
  Mat3T<S> W;
  W << S(0.0), -w(2), w(1), w(2), S(0.0), -w(0), -w(1), w(0), S(0.0);
  Mat3T<S> dW;
  dW << S(0.0), -dw(2), dw(1), dw(2), S(0.0), -dw(0), -dw(1), dw(0), S(0.0);
  const Mat3T<S> dR = R * W, ddR = R * (dW + W * W);
  Mat3T<Jet<S>> out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = Jet<S>(R(i, j), dR(i, j), ddR(i, j));
  return out;
}

/// Body angular velocity and acceleration of a rotation matrix jet: w = unskew(R^T R'),
/// dw = unskew(R^T R'') (R'^T R' is symmetric and drops out of the skew part).
template <class S>
void body_rates(const Mat3T<Jet<S>>& R, Vec3T<S>& w, Vec3T<S>& dw) {
  Mat3T<S> R0, R1, R2;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      R0(i, j) = R(i, j).x;
      R1(i, j) = R(i, j).dx;
      R2(i, j) = R(i, j).ddx;
    }
  const Mat3T<S> A = R0.transpose() * R1, B = R0.transpose() * R2;
  w = Vec3T<S>(S(0.5) * (A(2, 1) - A(1, 2)), S(0.5) * (A(0, 2) - A(2, 0)), S(0.5) * (A(1, 0) - A(0, 1)));
  dw = Vec3T<S>(S(0.5) * (B(2, 1) - B(1, 2)), S(0.5) * (B(0, 2) - B(2, 0)), S(0.5) * (B(1, 0) - B(0, 1)));
}

}  // namespace latticedyn

namespace Eigen {
template <class S>
struct NumTraits<latticedyn::Jet<S>> : NumTraits<double> {
  using Real = latticedyn::Jet<S>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = double;
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 1, ReadCost = 3, AddCost = 3, MulCost = 9 };
};
template <class S, class Op>
struct ScalarBinaryOpTraits<latticedyn::Jet<S>, double, Op> {
  using ReturnType = latticedyn::Jet<S>;
};
template <class S, class Op>
struct ScalarBinaryOpTraits<double, latticedyn::Jet<S>, Op> {
  using ReturnType = latticedyn::Jet<S>;
};
}  // namespace Eigen
