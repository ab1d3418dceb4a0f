// Tangents by forward automatic differentiation: an element writes its residual once, templated
// on the scalar, and AutoDiffElement derives K, C and M from it exactly (no finite differences).
#pragma once

#include "core/rotation.hpp"
#include "elements/element.hpp"

#include <unsupported/Eigen/AutoDiff>

#include <array>

namespace latticedyn {

/// CRTP base. Derived provides
///   static constexpr std::array<SlotKind, K> kSlots;
///   template <class S> void compute_residual(std::span<const SlotState<S>>, const ElementContext&,
///                                            Eigen::Matrix<S, N, 1>& r) const;
/// where N is the number of DoFs. One AD pass with 3N derivative directions [dq; d(dq); d(dq_dot)]
/// gives the residual and all three tangents.
template <class Derived, int N>
class AutoDiffElement : public Element {
 public:
  static constexpr int kDofs = N;
  using AD = Eigen::AutoDiffScalar<Eigen::Matrix<double, 3 * N, 1>>;

  std::span<const SlotKind> slots() const override { return Derived::kSlots; }

  void residual(std::span<const SlotState<double>> state, const ElementContext& ctx,
                Eigen::Ref<VecX> r) const override {
    Eigen::Matrix<double, N, 1> rr;
    derived().template compute_residual<double>(state, ctx, rr);
    r = rr;
  }

  void tangents(std::span<const SlotState<double>> state, const ElementContext& ctx,
                ElementTangents& out) const override {
    constexpr auto& kinds = Derived::kSlots;
    std::array<SlotState<AD>, kinds.size()> s;
    int o = 0;
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      seed(kinds[k], state[k], o, s[k]);
      o += slot_size(kinds[k]);
    }
    Eigen::Matrix<AD, N, 1> r;
    derived().template compute_residual<AD>(std::span<const SlotState<AD>>(s), ctx, r);
    out.resize(N);
    for (int i = 0; i < N; ++i) {
      out.residual(i) = r(i).value();
      const auto& d = r(i).derivatives();
      // An output with no dependence on any input keeps an empty derivative vector.
      if (d.size() == 0) {
        out.K.row(i).setZero();
        out.C.row(i).setZero();
        out.M.row(i).setZero();
        continue;
      }
      out.K.row(i) = d.template segment<N>(0).transpose();
      out.C.row(i) = d.template segment<N>(N).transpose();
      out.M.row(i) = d.template segment<N>(2 * N).transpose();
    }
  }

 private:
  const Derived& derived() const { return static_cast<const Derived&>(*this); }

  static AD variable(double value, int index) { return AD(value, 3 * N, index); }
  static AD constant(double value) { return AD(value, Eigen::Matrix<double, 3 * N, 1>::Zero()); }

  // Seeds one slot: its position-level perturbation at index o, velocity at N + o, acceleration
  // at 2N + o. Rotations are perturbed as R (I + skew(dtheta)), exact to first order at 0.
  static void seed(SlotKind kind, const SlotState<double>& in, int o, SlotState<AD>& s) {
    for (int i = 0; i < 3; ++i) {
      s.pos(i) = constant(in.pos(i));
      s.vel(i) = constant(in.vel(i));
      s.acc(i) = constant(in.acc(i));
      for (int j = 0; j < 3; ++j) s.rot(i, j) = constant(in.rot(i, j));
    }
    switch (kind) {
      case SlotKind::translation:
      case SlotKind::vector:
        for (int i = 0; i < 3; ++i) {
          s.pos(i) = variable(in.pos(i), o + i);
          s.vel(i) = variable(in.vel(i), N + o + i);
          s.acc(i) = variable(in.acc(i), 2 * N + o + i);
        }
        break;
      case SlotKind::rotation: {
        Vec3T<AD> dtheta;
        for (int i = 0; i < 3; ++i) {
          dtheta(i) = variable(0.0, o + i);
          s.vel(i) = variable(in.vel(i), N + o + i);
          s.acc(i) = variable(in.acc(i), 2 * N + o + i);
        }
        s.rot = s.rot * (Mat3T<AD>::Identity() + skew(dtheta));
        break;
      }
      case SlotKind::scalar:
        s.pos(0) = variable(in.pos(0), o);
        s.vel(0) = variable(in.vel(0), N + o);
        s.acc(0) = variable(in.acc(0), 2 * N + o);
        break;
    }
  }
};

}  // namespace latticedyn
