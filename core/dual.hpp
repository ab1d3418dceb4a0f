// Forward-mode automatic differentiation numbers in N variables: Dual (value and gradient) and
// HyperDual (value, gradient and the symmetric Hessian), plain structs with fixed arrays so that
// element energies get their force and stiffness at the cost of straight-line arithmetic.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>

namespace latticedyn {

/// Value and gradient in N variables.
template <int N>
struct Dual {
  double v = 0.0;
  std::array<double, N> g{};

  Dual() = default;
  Dual(double x) : v(x) {}  // NOLINT: constants convert implicitly, as doubles do
  static Dual variable(double x, int i) {
    Dual d(x);
    d.g[i] = 1.0;
    return d;
  }
  double value() const { return v; }

  Dual& operator+=(const Dual& b) {
    v += b.v;
    for (int i = 0; i < N; ++i) g[i] += b.g[i];
    return *this;
  }
  Dual& operator-=(const Dual& b) {
    v -= b.v;
    for (int i = 0; i < N; ++i) g[i] -= b.g[i];
    return *this;
  }
  Dual& operator*=(const Dual& b) {
    for (int i = 0; i < N; ++i) g[i] = g[i] * b.v + v * b.g[i];
    v *= b.v;
    return *this;
  }
  Dual& operator/=(const Dual& b) {
    const double inv = 1.0 / b.v, q = v * inv;
    for (int i = 0; i < N; ++i) g[i] = (g[i] - q * b.g[i]) * inv;
    v = q;
    return *this;
  }
  /// f(this) from f, f' at the value.
  Dual chain(double f, double df) const {
    Dual r(f);
    for (int i = 0; i < N; ++i) r.g[i] = df * g[i];
    return r;
  }
};

/// Value, gradient and Hessian (packed upper triangle, row by row) in N variables.
template <int N>
struct HyperDual {
  static constexpr int kPacked = N * (N + 1) / 2;
  double v = 0.0;
  std::array<double, N> g{};
  std::array<double, kPacked> h{};

  HyperDual() = default;
  HyperDual(double x) : v(x) {}  // NOLINT: constants convert implicitly, as doubles do
  static HyperDual variable(double x, int i) {
    HyperDual d(x);
    d.g[i] = 1.0;
    return d;
  }
  double value() const { return v; }
  /// Hessian entry (i, j), either order.
  double hessian(int i, int j) const { return i <= j ? h[packed(i, j)] : h[packed(j, i)]; }
  static constexpr int packed(int i, int j) { return i * N - i * (i - 1) / 2 + (j - i); }

  HyperDual& operator+=(const HyperDual& b) {
    v += b.v;
    for (int i = 0; i < N; ++i) g[i] += b.g[i];
    for (int k = 0; k < kPacked; ++k) h[k] += b.h[k];
    return *this;
  }
  HyperDual& operator-=(const HyperDual& b) {
    v -= b.v;
    for (int i = 0; i < N; ++i) g[i] -= b.g[i];
    for (int k = 0; k < kPacked; ++k) h[k] -= b.h[k];
    return *this;
  }
  HyperDual& operator*=(const HyperDual& b) {
    int k = 0;
    for (int i = 0; i < N; ++i)
      for (int j = i; j < N; ++j, ++k) h[k] = h[k] * b.v + v * b.h[k] + g[i] * b.g[j] + b.g[i] * g[j];
    for (int i = 0; i < N; ++i) g[i] = g[i] * b.v + v * b.g[i];
    v *= b.v;
    return *this;
  }
  HyperDual& operator/=(const HyperDual& b) { return *this *= b.reciprocal(); }
  HyperDual reciprocal() const {
    const double inv = 1.0 / v;
    return chain(inv, -inv * inv, 2 * inv * inv * inv);
  }
  /// f(this) from f, f', f'' at the value.
  HyperDual chain(double f, double df, double ddf) const {
    HyperDual r(f);
    for (int i = 0; i < N; ++i) r.g[i] = df * g[i];
    int k = 0;
    for (int i = 0; i < N; ++i)
      for (int j = i; j < N; ++j, ++k) r.h[k] = df * h[k] + ddf * g[i] * g[j];
    return r;
  }
};

// Arithmetic shared by both number types.
template <class T>
concept ForwardNumber = requires(T t) { t.chain(0.0, 0.0); } || requires(T t) { t.chain(0.0, 0.0, 0.0); };

template <ForwardNumber T>
T operator+(T a, const T& b) { return a += b; }
template <ForwardNumber T>
T operator-(T a, const T& b) { return a -= b; }
template <ForwardNumber T>
T operator*(T a, const T& b) { return a *= b; }
template <ForwardNumber T>
T operator/(T a, const T& b) { return a /= b; }
template <ForwardNumber T>
T operator+(T a, double b) { a.v += b; return a; }
template <ForwardNumber T>
T operator+(double b, T a) { a.v += b; return a; }
template <ForwardNumber T>
T operator-(T a, double b) { a.v -= b; return a; }
template <ForwardNumber T>
T operator-(double b, const T& a) { return T(b) -= a; }
template <ForwardNumber T>
T operator*(T a, double b) {
  a.v *= b;
  for (auto& x : a.g) x *= b;
  if constexpr (requires { a.h; })
    for (auto& x : a.h) x *= b;
  return a;
}
template <ForwardNumber T>
T operator*(double b, const T& a) { return a * b; }
template <ForwardNumber T>
T operator/(const T& a, double b) { return a * (1.0 / b); }
template <ForwardNumber T>
T operator/(double b, const T& a) { return T(b) /= a; }
template <ForwardNumber T>
T operator-(const T& a) { return a * -1.0; }
template <ForwardNumber T>
T operator+(const T& a) { return a; }

template <ForwardNumber T>
bool operator<(const T& a, const T& b) { return a.v < b.v; }
template <ForwardNumber T>
bool operator>(const T& a, const T& b) { return a.v > b.v; }
template <ForwardNumber T>
bool operator<=(const T& a, const T& b) { return a.v <= b.v; }
template <ForwardNumber T>
bool operator>=(const T& a, const T& b) { return a.v >= b.v; }
template <ForwardNumber T>
bool operator==(const T& a, const T& b) { return a.v == b.v; }
template <ForwardNumber T>
bool operator!=(const T& a, const T& b) { return a.v != b.v; }

namespace dual_detail {
// f(a) from the value and the first two derivatives of f there.
template <int N>
Dual<N> apply(const Dual<N>& a, double f, double df, double) { return a.chain(f, df); }
template <int N>
HyperDual<N> apply(const HyperDual<N>& a, double f, double df, double ddf) { return a.chain(f, df, ddf); }
}  // namespace dual_detail

template <ForwardNumber T>
T sqrt(const T& a) {
  const double s = std::sqrt(a.v);
  return dual_detail::apply(a, s, 0.5 / s, -0.25 / (s * a.v));
}
template <ForwardNumber T>
T sin(const T& a) {
  const double s = std::sin(a.v), c = std::cos(a.v);
  return dual_detail::apply(a, s, c, -s);
}
template <ForwardNumber T>
T cos(const T& a) {
  const double s = std::sin(a.v), c = std::cos(a.v);
  return dual_detail::apply(a, c, -s, -c);
}
template <ForwardNumber T>
T exp(const T& a) {
  const double e = std::exp(a.v);
  return dual_detail::apply(a, e, e, e);
}
template <ForwardNumber T>
T log(const T& a) {
  return dual_detail::apply(a, std::log(a.v), 1.0 / a.v, -1.0 / (a.v * a.v));
}
template <ForwardNumber T>
T asin(const T& a) {
  const double q = 1.0 / (1.0 - a.v * a.v);
  return dual_detail::apply(a, std::asin(a.v), std::sqrt(q), a.v * q * std::sqrt(q));
}
template <ForwardNumber T>
T acos(const T& a) {
  const double q = 1.0 / (1.0 - a.v * a.v);
  return dual_detail::apply(a, std::acos(a.v), -std::sqrt(q), -a.v * q * std::sqrt(q));
}
template <ForwardNumber T>
T abs(const T& a) { return a.v < 0 ? -a : a; }

/// atan2(y, x) = the angle of (x, y): d = (x dy - y dx) / r^2 and its derivative.
template <int N>
Dual<N> atan2(const Dual<N>& y, const Dual<N>& x) {
  const double r2 = x.v * x.v + y.v * y.v;
  Dual<N> out(std::atan2(y.v, x.v));
  for (int i = 0; i < N; ++i) out.g[i] = (x.v * y.g[i] - y.v * x.g[i]) / r2;
  return out;
}
template <int N>
HyperDual<N> atan2(const HyperDual<N>& y, const HyperDual<N>& x) {
  const double r2 = x.v * x.v + y.v * y.v, r4 = r2 * r2;
  const double fy = x.v / r2, fx = -y.v / r2;
  const double fyy = -2 * x.v * y.v / r4, fxx = 2 * x.v * y.v / r4, fxy = (y.v * y.v - x.v * x.v) / r4;
  HyperDual<N> out(std::atan2(y.v, x.v));
  for (int i = 0; i < N; ++i) out.g[i] = fy * y.g[i] + fx * x.g[i];
  int k = 0;
  for (int i = 0; i < N; ++i)
    for (int j = i; j < N; ++j, ++k)
      out.h[k] = fy * y.h[k] + fx * x.h[k] + fyy * y.g[i] * y.g[j] + fxx * x.g[i] * x.g[j] +
                 fxy * (x.g[i] * y.g[j] + y.g[i] * x.g[j]);
  return out;
}

}  // namespace latticedyn

namespace Eigen {

template <int N>
struct NumTraits<latticedyn::Dual<N>> : NumTraits<double> {
  using Real = latticedyn::Dual<N>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = double;
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 1, ReadCost = N + 1, AddCost = N + 1,
         MulCost = 3 * N + 1 };
};
template <int N>
struct NumTraits<latticedyn::HyperDual<N>> : NumTraits<double> {
  using Real = latticedyn::HyperDual<N>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = double;
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 1, ReadCost = N * N,
         AddCost = N * N, MulCost = 3 * N * N };
};
template <int N, class Op>
struct ScalarBinaryOpTraits<latticedyn::Dual<N>, double, Op> {
  using ReturnType = latticedyn::Dual<N>;
};
template <int N, class Op>
struct ScalarBinaryOpTraits<double, latticedyn::Dual<N>, Op> {
  using ReturnType = latticedyn::Dual<N>;
};
template <int N, class Op>
struct ScalarBinaryOpTraits<latticedyn::HyperDual<N>, double, Op> {
  using ReturnType = latticedyn::HyperDual<N>;
};
template <int N, class Op>
struct ScalarBinaryOpTraits<double, latticedyn::HyperDual<N>, Op> {
  using ReturnType = latticedyn::HyperDual<N>;
};

}  // namespace Eigen
