// The reference evaluation of the constraints by nested forward AD over the constraint kernels,
// the tests' oracle for the closed form: the inner level differentiates g with respect to right
// perturbations delta of the free blocks (giving G), the outer level differentiates those with
// respect to a second perturbation eps applied before delta (giving dG/dq and Gamma).
#include "assembly/constraint_blocks.hpp"
#include "assembly/constraint_kernels.hpp"
#include "core/rotation.hpp"

#include <unsupported/Eigen/AutoDiff>

namespace latticedyn {

namespace {

/// AD types for NV variables: 3 per free block, then the drive value u (index NV - 1).
template <int NV>
struct Ad {
  static constexpr int kU = NV - 1;
  using Inner = Eigen::AutoDiffScalar<Eigen::Matrix<double, NV, 1>>;
  using Outer = Eigen::AutoDiffScalar<Eigen::Matrix<Inner, NV, 1>>;
  static Inner inner_var(double v, int i) { return Inner(v, NV, i); }
  static Outer outer_const(const Inner& v) { return Outer(v); }
  // A variable of both levels: value v, d/d(delta_i) = 1 and d/d(eps_i) = 1, mixed derivative 0.
  static Outer both_var(double v, int i) {
    Outer x(inner_var(v, i));
    x.derivatives()(i) = Inner(1.0);
    return x;
  }
};

}  // namespace

namespace {

// The two AD levels: first order (G, g_u) for residuals, second order (also dG/dq, Gamma) for
// Jacobians and the acceleration-level rows. A rotation is perturbed on the right; to second order
// only the mixed eps-delta term matters: R (I + skew(eps)) (I + skew(delta)).
template <int NV>
struct FirstOrder {
  using A = Ad<NV>;
  using S = typename A::Inner;
  static S var(double v, int i) { return A::inner_var(v, i); }
  static S constant(double v) { return S(v); }
  static Mat3T<S> perturbed(const Mat3& R, int c) {
    Vec3T<S> delta;
    for (int i = 0; i < 3; ++i) delta(i) = A::inner_var(0.0, c + i);
    return R.cast<S>() * (Mat3T<S>::Identity() + skew(delta));
  }
  static Mat3T<S> fixed(const Mat3& R) { return R.cast<S>(); }
};

template <int NV>
struct SecondOrder {
  using A = Ad<NV>;
  using Inner = typename A::Inner;
  using S = typename A::Outer;
  static S var(double v, int i) { return A::both_var(v, i); }
  static S constant(double v) { return A::outer_const(Inner(v)); }
  static Mat3T<S> perturbed(const Mat3& R, int c) {
    Vec3T<S> eps, delta;
    for (int i = 0; i < 3; ++i) {
      eps(i) = S(Inner(0.0));
      eps(i).derivatives()(c + i) = Inner(1.0);
      delta(i) = A::outer_const(A::inner_var(0.0, c + i));
    }
    return fixed(R) * (Mat3T<S>::Identity() + skew(eps)) * (Mat3T<S>::Identity() + skew(delta));
  }
  static Mat3T<S> fixed(const Mat3& R) { return R.cast<Inner>().template cast<S>(); }
};

// Joint frames with seeds on the free blocks collected in `out`.
template <class Level>
JointPairFrames<typename Level::S> seeded_frames(const ConstraintInputs& in, const ConstraintEval& out) {
  using S = typename Level::S;
  const Model& model = *in.model;
  const Constraint& c = *in.constraint;
  auto column_of = [&](int block) -> int {
    for (int k = 0; k < 4; ++k)
      if (block >= 0 && out.blocks[k] == block) return 3 * k;
    return -1;
  };
  JointPairFrames<S> f;
  for (int side = 0; side < 2; ++side) {
    const Joint& j = model.joints[side == 0 ? c.joint1 : c.joint2];
    const BlockState& ts = in.block_state(j.translation_block);
    Vec3T<S> r;
    const int ct = column_of(j.translation_block);
    for (int i = 0; i < 3; ++i) r(i) = ct >= 0 ? Level::var(ts.pos(i), ct + i) : Level::constant(ts.pos(i));
    Mat3T<S> R;
    const Mat3T<S>* Rp = nullptr;
    if (j.rotation_block >= 0) {
      const BlockState& rs = in.block_state(j.rotation_block);
      const int cr = column_of(j.rotation_block);
      R = cr >= 0 ? Level::perturbed(rs.rot, cr) : Level::fixed(rs.rot);
      Rp = &R;
    }
    constraint_detail::frame_of<S>(j, r, Rp, side == 0 ? f.r1 : f.r2, side == 0 ? f.R1 : f.R2);
  }
  return f;
}

template <int NV>
void first_order(const ConstraintInputs& in, ConstraintEval& out) {
  using A = Ad<NV>;
  using Inner = typename A::Inner;
  const JointPairFrames<Inner> f = seeded_frames<FirstOrder<NV>>(in, out);
  Inner g[ConstraintEval::kMaxRows];
  constraint_values<Inner>(*in.constraint, f, A::inner_var(in.drive.value, A::kU), g);
  for (int r = 0; r < out.rows; ++r) {
    out.g(r) = g[r].value();
    for (int k = 0; k < out.cols; ++k) out.G(r, k) = g[r].derivatives()(k);
    out.g_u(r) = g[r].derivatives()(A::kU);
  }
}

template <int NV>
void second_order(const ConstraintInputs& in, ConstraintEval& out) {
  using A = Ad<NV>;
  using Outer = typename A::Outer;
  const JointPairFrames<Outer> f = seeded_frames<SecondOrder<NV>>(in, out);
  Outer g[ConstraintEval::kMaxRows];
  constraint_values<Outer>(*in.constraint, f, A::both_var(in.drive.value, A::kU), g);

  const int m = out.rows, n = out.cols;
  Eigen::Matrix<double, ConstraintEval::kMaxCols, 1> v = Eigen::Matrix<double, ConstraintEval::kMaxCols, 1>::Zero();
  for (int k = 0; k < n / 3; ++k) v.segment<3>(3 * k) = in.block_state(out.blocks[k]).vel;

  for (int r = 0; r < m; ++r) {
    const auto& val = g[r].value();
    out.g(r) = val.value();
    for (int k = 0; k < n; ++k) out.G(r, k) = val.derivatives()(k);
    out.g_u(r) = val.derivatives()(A::kU);
    // dG(r, k)/d(eps_l) is the delta_k-derivative of the eps_l-derivative.
    if (in.lambda)
      for (int l = 0; l < n; ++l)
        for (int k = 0; k < n; ++k) out.H(k, l) += in.lambda[r] * g[r].derivatives()(l).derivatives()(k);
    if (in.with_velocity_terms) {
      const double ud = in.drive.rate, udd = in.drive.accel;
      double gamma = 0.0, dGdu_v = 0.0;
      for (int l = 0; l < n; ++l) {
        const auto& dl = g[r].derivatives()(l).derivatives();
        for (int k = 0; k < n; ++k) gamma += dl(k) * v(k) * v(l);
      }
      const auto& du = g[r].derivatives()(A::kU).derivatives();
      for (int k = 0; k < n; ++k) dGdu_v += du(k) * v(k);
      gamma += 2.0 * dGdu_v * ud + du(A::kU) * ud * ud + out.g_u(r) * udd;
      out.gamma(r) = gamma;
      out.g_dot(r) = out.G.row(r).head(n).dot(v.head(n)) + out.g_u(r) * ud;
    }
  }
}

template <int NV>
void evaluate(const ConstraintInputs& in, ConstraintEval& out) {
  if (!in.lambda && !in.with_velocity_terms)
    first_order<NV>(in, out);
  else
    second_order<NV>(in, out);
}

}  // namespace

ConstraintEval evaluate_constraint_ad(const ConstraintInputs& in) {
  ConstraintEval out;
  out.rows = in.constraint->rows();
  switch (constraint_detail::collect_blocks(in, out)) {
    case 1: evaluate<4>(in, out); break;
    case 2: evaluate<7>(in, out); break;
    case 3: evaluate<10>(in, out); break;
    default: evaluate<13>(in, out); break;
  }
  return out;
}

}  // namespace latticedyn
