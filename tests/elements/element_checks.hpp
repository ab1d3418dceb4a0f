// Checks every element must pass: tangents against central finite differences at arbitrary
// (large-rotation) states, and the power identity d/dt(T + V + U) = dq . r of a conservative element.
#pragma once

#include "core/rotation.hpp"
#include "elements/element.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace latticedyn::testing {

/// A random state: positions of order `scale`, rotations up to pi, rates of order 1.
inline std::vector<SlotState<double>> random_state(const Element& e, std::mt19937& rng, double scale = 1.0) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto v3 = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  std::vector<SlotState<double>> s(e.slots().size());
  for (std::size_t k = 0; k < s.size(); ++k) {
    s[k].pos = scale * v3();
    s[k].rot = rotation_matrix<double>(3.0 * v3() / std::sqrt(3.0));
    s[k].vel = v3();
    s[k].acc = v3();
  }
  return s;
}

/// Perturbs coordinate i of slot k at derivative level `level` (0: q, 1: dq, 2: dq_dot) by h.
inline void perturb(SlotKind kind, SlotState<double>& s, int level, int i, double h) {
  if (level == 1) {
    s.vel(i) += h;
  } else if (level == 2) {
    s.acc(i) += h;
  } else if (kind == SlotKind::rotation) {
    s.rot = s.rot * rotation_matrix<double>(h * Vec3::Unit(i));
  } else {
    s.pos(i) += h;
  }
}

/// Max |AD - FD| relative to max |tangent| for K, C and M; central differences with step 1e-5
/// (relative to the coordinate's size), allowing for their round-off 1e-14 max|r| / h.
inline void expect_tangents_match_finite_differences(const Element& e, const std::vector<SlotState<double>>& state,
                                                     const ElementContext& ctx, double rel_tol = 1e-6) {
  ElementTangents t;
  e.tangents(state, ctx, t);
  const int n = e.num_dofs();
  VecX r0(n);
  e.residual(state, ctx, r0);
  EXPECT_LT((t.residual - r0).cwiseAbs().maxCoeff(), 1e-12 * (1 + r0.cwiseAbs().maxCoeff()))
      << "AD residual differs from the double residual";
  const MatX* ad[3] = {&t.K, &t.C, &t.M};
  const char* names[3] = {"K = dr/dq", "C = dr/d(dq)", "M = dr/d(dq_dot)"};
  const auto kinds = e.slots();
  for (int level = 0; level < 3; ++level) {
    MatX fd(n, n);
    int col = 0;
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      for (int i = 0; i < slot_size(kinds[k]); ++i, ++col) {
        const double ref = level == 0 && kinds[k] != SlotKind::rotation ? std::max(1.0, state[k].pos.norm()) : 1.0;
        const double h = 1e-5 * ref;
        auto sp = state, sm = state;
        perturb(kinds[k], sp[k], level, i, h);
        perturb(kinds[k], sm[k], level, i, -h);
        VecX rp(n), rm(n);
        e.residual(sp, ctx, rp);
        e.residual(sm, ctx, rm);
        fd.col(col) = (rp - rm) / (2 * h);
      }
    }
    const double noise = 1e-14 * r0.cwiseAbs().maxCoeff() / 1e-5;
    const double scale = std::max(ad[level]->cwiseAbs().maxCoeff(), 1e-12);
    const double err = std::max(0.0, (*ad[level] - fd).cwiseAbs().maxCoeff() - noise) / scale;
    EXPECT_LT(err, rel_tol) << e.type_name() << " " << names[level] << "\nAD:\n" << *ad[level] << "\nFD:\n" << fd;
  }
}

/// Advances a state along its own rates by t (second order): rotations R exp(omega t + ...).
inline std::vector<SlotState<double>> advance(const Element& e, std::vector<SlotState<double>> s, double t) {
  const auto kinds = e.slots();
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (kinds[k] == SlotKind::rotation)
      s[k].rot = s[k].rot * rotation_matrix<double>(s[k].vel * t + 0.5 * s[k].acc * t * t);
    else
      s[k].pos += s[k].vel * t + 0.5 * s[k].acc * t * t;
    s[k].vel += s[k].acc * t;
  }
  return s;
}

/// For a conservative element the residual is Lagrange's: the power dq . r equals the rate of
/// kinetic + gravity + strain energy along any motion.
inline void expect_power_identity(const Element& e, const std::vector<SlotState<double>>& s, const ElementContext& ctx,
                                  double rel_tol = 1e-6) {
  auto total = [&](double t) {
    const ElementEnergy en = e.energy(advance(e, s, t), ctx);
    return en.kinetic + en.gravity_potential + en.strain;
  };
  const double h = 1e-5;
  const double rate_fd = (total(h) - total(-h)) / (2 * h);
  VecX r(e.num_dofs());
  e.residual(s, ctx, r);
  double power = 0.0;
  int o = 0;
  const auto kinds = e.slots();
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    const int n = slot_size(kinds[k]);
    power += s[k].vel.head(n).dot(r.segment(o, n));
    o += n;
  }
  EXPECT_NEAR(power, rate_fd, rel_tol * (1 + std::abs(power))) << e.type_name();
}

}  // namespace latticedyn::testing
