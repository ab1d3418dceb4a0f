// The minimum-DoF equations (thesis 2.2.2) checked against an independent derivation: each model's
// Lagrangian T - V written out here in its own coordinates (Cardan angles where the library uses
// rotation vectors), Lagrange's equations of the second kind from its exact second derivatives
// (hyper-dual numbers), both integrated by the same Runge-Kutta scheme and compared in space.
// Also: the kinematic maps T_e and T_dot_e q_dot against finite differences, the tree's errors.
#include "assembly/minimum_dof_model.hpp"
#include "core/dual.hpp"
#include "core/rotation.hpp"
#include "io/model_reader.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace latticedyn {
namespace {

// ---------------------------------------------------------------------------------------------
// Models (smooth sine drives, so that a fixed-step Runge-Kutta scheme keeps its order).

const char* kDoublePendulum = R"(
title: double pendulum
gravity: [0, 0, -9.81]
ground: {joints: [{name: pivot, position: [0, 0, 0]}]}
bodies:
  - {name: upper, type: rigid_body, mass: 1.0, centroid: [0.5, 0, 0], inertia: [1.0e-4, 0.0833333333333333, 0.0833333333333333],
     position: [0, 0, 0], joints: [{name: top, position: [0, 0, 0]}, {name: bottom, position: [1, 0, 0]}]}
  - {name: lower, type: rigid_body, mass: 1.0, centroid: [0.5, 0, 0], inertia: [1.0e-4, 0.0833333333333333, 0.0833333333333333],
     position: [1, 0, 0], joints: [{name: top, position: [0, 0, 0]}, {name: tip, position: [1, 0, 0]}]}
constraints:
  - {name: shoulder, type: revolute, axis: y, joints: [ground.pivot, upper.top]}
  - {name: elbow, type: revolute, axis: y, joints: [upper.bottom, lower.top]}
)";

const char* kFoldingBoom = R"(
title: folding boom
gravity: [0, 0, -9.81]
drives:
  slewing: {type: sine, amplitude: 0.6, frequency: 0.1}
  luffing: {type: sine, amplitude: -0.4, frequency: 0.12}
  folding: {type: sine, amplitude: 0.5, frequency: 0.2}
ground: {joints: [{name: base, position: [0, 0, 0]}]}
bodies:
  - {name: column, type: rigid_body, mass: 900, centroid: [0, 0, 1.5], inertia: [700, 700, 60], position: [0, 0, 0],
     joints: [{name: foot, position: [0, 0, 0]}, {name: head, position: [0, 0, 3]}]}
  - {name: main_boom, type: rigid_body, mass: 700, centroid: [2.5, 0, 0], inertia: [15, 1460, 1460], position: [0, 0, 3],
     joints: [{name: heel, position: [0, 0, 0]}, {name: knuckle, position: [5, 0, 0]}]}
  - {name: folding_boom, type: rigid_body, mass: 400, centroid: [2, 0, 0], inertia: [8, 535, 535], position: [5, 0, 3],
     joints: [{name: knuckle, position: [0, 0, 0]}, {name: tip, position: [4, 0, 0]}]}
  - {name: load, type: rigid_body, mass: 300, centroid: [0, 0, -3], inertia: [20, 25, 15], position: [9, 0, 3],
     joints: [{name: hook, position: [0, 0, 0]}, {name: centre, position: [0, 0, -3]}]}
constraints:
  - {name: slewing, type: revolute, axis: z, joints: [ground.base, column.foot], drive: slewing}
  - {name: luffing, type: revolute, axis: y, joints: [column.head, main_boom.heel], drive: luffing}
  - {name: folding, type: revolute, axis: y, joints: [main_boom.knuckle, folding_boom.knuckle], drive: folding}
  - {name: rope, type: spherical, joints: [folding_boom.tip, load.hook]}
)";

Simulation read(const char* yaml) { return read_simulation_from_string(yaml, "test.yaml"); }

// ---------------------------------------------------------------------------------------------
// The independent side: energies of rigid bodies in the test's own kinematics.

template <class S>
using V3 = Vec3T<S>;
template <class S>
using M3 = Mat3T<S>;

template <class S>
V3<S> vec(double x, double y, double z) {
  return V3<S>(S(x), S(y), S(z));
}

/// T - V of one rigid body: centroid position r and velocity v, angular velocity w (inertial),
/// orientation R, inertia J about the centroid in body axes.
template <class S>
S body_lagrangian(double m, const Vec3& J, const V3<S>& r, const V3<S>& v, const M3<S>& R, const V3<S>& w,
                  const Vec3& g) {
  const V3<S> wb = R.transpose() * w;
  S t = S(0.5 * m) * v.dot(v);
  for (int i = 0; i < 3; ++i) t += S(0.5 * J(i)) * wb(i) * wb(i);
  return t + S(m) * (vec<S>(g(0), g(1), g(2)).dot(r));  // V = -m g . r
}

/// Cardan angles (x, then y, then z about the moving axes) of a spherical joint: the rotation
/// and the angular velocity (in the parent's frame).
template <class S>
void cardan(const S* a, const S* ad, M3<S>& D, V3<S>& w) {
  const M3<S> X = rotation_x(a[0]), Y = rotation_y(a[1]), Z = rotation_z(a[2]);
  D = X * Y * Z;
  w = vec<S>(1, 0, 0) * ad[0] + X * vec<S>(0, 1, 0) * ad[1] + (X * Y) * vec<S>(0, 0, 1) * ad[2];
}

/// A system with n free coordinates and m driven ones, its Lagrangian written as a function of
/// x = [q, q_dot, u, u_dot] and a map to the point whose path is compared.
template <int N>
struct LagrangeModel {
  int n = 0, m = 0;
  std::function<HyperDual<N>(const std::array<HyperDual<N>, N>&)> lagrangian;
  std::function<Vec3(const VecX& q, const VecX& u)> point;
  std::function<void(double t, VecX& u, VecX& ud, VecX& udd)> drives;

  /// q_ddot from Lagrange's equations of the second kind:
  ///   d/dt dL/dq_dot - dL/dq = 0,  M = d2L/dq_dot2.
  VecX accelerations(double t, const VecX& q, const VecX& qd) const {
    VecX u(m), ud(m), udd(m);
    drives(t, u, ud, udd);
    std::array<HyperDual<N>, N> x;
    for (int i = 0; i < n; ++i) {
      x[i] = HyperDual<N>::variable(q(i), i);
      x[n + i] = HyperDual<N>::variable(qd(i), n + i);
    }
    for (int k = 0; k < m; ++k) {
      x[2 * n + k] = HyperDual<N>::variable(u(k), 2 * n + k);
      x[2 * n + m + k] = HyperDual<N>::variable(ud(k), 2 * n + m + k);
    }
    const HyperDual<N> L = lagrangian(x);
    MatX M(n, n);
    VecX rhs(n);
    for (int i = 0; i < n; ++i) {
      const int qdi = n + i;
      for (int j = 0; j < n; ++j) M(i, j) = L.hessian(qdi, n + j);
      double r = L.g[i];
      for (int j = 0; j < n; ++j) r -= L.hessian(qdi, j) * qd(j);
      for (int k = 0; k < m; ++k) r -= L.hessian(qdi, 2 * n + k) * ud(k) + L.hessian(qdi, 2 * n + m + k) * udd(k);
      rhs(i) = r;
    }
    return M.partialPivLu().solve(rhs);
  }
};

/// One classical Runge-Kutta step of q_ddot = f(t, q, q_dot).
void rk4(const std::function<VecX(double, const VecX&, const VecX&)>& f, double t, double h, VecX& q, VecX& v) {
  const VecX a1 = f(t, q, v);
  const VecX q2 = q + 0.5 * h * v, v2 = v + 0.5 * h * a1;
  const VecX a2 = f(t + 0.5 * h, q2, v2);
  const VecX q3 = q + 0.5 * h * v2, v3 = v + 0.5 * h * a2;
  const VecX a3 = f(t + 0.5 * h, q3, v3);
  const VecX q4 = q + h * v3, v4 = v + h * a3;
  const VecX a4 = f(t + h, q4, v4);
  q += h / 6 * (v + 2 * v2 + 2 * v3 + v4);
  v += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
}

std::function<void(double, VecX&, VecX&, VecX&)> model_drives(const Model& model) {
  return [&model](double t, VecX& u, VecX& ud, VecX& udd) {
    for (std::size_t k = 0; k < model.drives.size(); ++k) {
      const DriveValue d = model.drives[k].evaluate(t);
      u(k) = d.value;
      ud(k) = d.rate;
      udd(k) = d.accel;
    }
  };
}

/// Integrates both formulations from rest in the initial pose and returns the largest distance
/// between the library's joint `joint` and the test's point over [0, t_end].
template <int N>
double largest_path_difference(const Model& model, const LagrangeModel<N>& reference, const std::string& joint,
                               double t_end, double h) {
  const MinimumDofModel library(model);
  EXPECT_EQ(library.num_free(), reference.n);
  const int j = model.find_joint(joint);
  VecX q = VecX::Zero(library.num_free()), v = q;
  VecX p = VecX::Zero(reference.n), w = p;
  double largest = 0.0;
  const auto f_library = [&library](double t, const VecX& a, const VecX& b) { return library.accelerations(t, a, b); };
  const auto f_reference = [&reference](double t, const VecX& a, const VecX& b) { return reference.accelerations(t, a, b); };
  const int steps = static_cast<int>(std::lround(t_end / h));
  for (int s = 1; s <= steps; ++s) {
    const double t = (s - 1) * h;
    rk4(f_library, t, h, q, v);
    rk4(f_reference, t, h, p, w);
    std::vector<BlockState> blocks;
    library.block_states(t + h, q, v, nullptr, blocks);
    Vec3 pos;
    Mat3 rot;
    const Joint& jt = model.joints[j];
    joint_frame(jt, blocks[jt.translation_block], &blocks[jt.rotation_block], pos, rot);
    VecX u(reference.m), ud(reference.m), udd(reference.m);
    reference.drives(t + h, u, ud, udd);
    largest = std::max(largest, (pos - reference.point(p, u)).norm());
  }
  return largest;
}

// ---------------------------------------------------------------------------------------------

TEST(MinimumDofModel, DoublePendulumFollowsItsLagrangeEquations) {
  const Simulation sim = read(kDoublePendulum);
  constexpr int N = 4;
  LagrangeModel<N> ref;
  ref.n = 2;
  ref.m = 0;
  const Vec3 g = sim.model.gravity, J(1.0e-4, 1.0 / 12, 1.0 / 12);
  ref.lagrangian = [g, J](const std::array<HyperDual<N>, N>& x) {
    using S = HyperDual<N>;
    const V3<S> ey = vec<S>(0, 1, 0);
    const M3<S> R1 = rotation_y(x[0]), R2 = R1 * rotation_y(x[1]);
    const V3<S> w1 = ey * x[2], w2 = ey * (x[2] + x[3]);
    const V3<S> c1 = R1 * vec<S>(0.5, 0, 0), elbow = R1 * vec<S>(1, 0, 0), c2rel = R2 * vec<S>(0.5, 0, 0);
    return body_lagrangian<S>(1.0, J, c1, w1.cross(c1), R1, w1, g) +
           body_lagrangian<S>(1.0, J, elbow + c2rel, w1.cross(elbow) + w2.cross(c2rel), R2, w2, g);
  };
  ref.point = [](const VecX& q, const VecX&) {
    return Vec3(rotation_y(q(0)) * Vec3(1, 0, 0) + rotation_y(q(0) + q(1)) * Vec3(1, 0, 0));
  };
  ref.drives = [](double, VecX&, VecX&, VecX&) {};
  // Released from the horizontal: the chaotic motion amplifies round-off only slowly in 2 s.
  EXPECT_LT(largest_path_difference(sim.model, ref, "lower.tip", 2.0, 1e-3), 1e-9);
}

// A slewing jib with a chain of rigid links hanging from its tip on spherical joints (the double
// and triple jib pendulums of thesis Fig. 5-2c, d), each link's top joint at its origin.
struct HangingLink {
  double mass, centroid, length;  // centroid and next joint below the top joint, m
  Vec3 inertia;
};

std::string jib_chain_yaml(const std::vector<HangingLink>& links) {
  std::string y = R"(
title: jib chain
gravity: [0, 0, -9.81]
drives:
  slewing: {type: sine, amplitude: 0.8, frequency: 0.15}
ground: {joints: [{name: column_top, position: [0, 0, 10]}]}
bodies:
  - {name: jib, type: rigid_body, mass: 600, centroid: [3, 0, 0], inertia: [10, 1800, 1800], position: [0, 0, 10],
     joints: [{name: root, position: [0, 0, 0]}, {name: tip, position: [6, 0, 0]}]}
)";
  double z = 10;
  auto num = [](double v) { return std::to_string(v); };
  for (std::size_t i = 0; i < links.size(); ++i) {
    const HangingLink& l = links[i];
    y += "  - {name: l" + std::to_string(i) + ", type: rigid_body, mass: " + num(l.mass) + ", centroid: [0, 0, " +
         num(-l.centroid) + "], inertia: [" + num(l.inertia(0)) + ", " + num(l.inertia(1)) + ", " + num(l.inertia(2)) +
         "], position: [6, 0, " + num(z) + "], joints: [{name: top, position: [0, 0, 0]}, {name: bottom, position: [0, 0, " +
         num(-l.length) + "]}]}\n";
    z -= l.length;
  }
  y += "constraints:\n  - {name: slewing, type: revolute, axis: z, joints: [ground.column_top, jib.root], drive: slewing}\n";
  for (std::size_t i = 0; i < links.size(); ++i)
    y += "  - {name: s" + std::to_string(i) + ", type: spherical, joints: [" +
         (i == 0 ? std::string("jib.tip") : "l" + std::to_string(i - 1) + ".bottom") + ", l" + std::to_string(i) + ".top]}\n";
  return y;
}

// The chain's Lagrangian in Cardan angles (three per link, relative to the link above) and the
// bottom of the last link.
template <int N>
LagrangeModel<N> jib_chain_lagrange(const std::vector<HangingLink>& links, const Model& model) {
  const int k = static_cast<int>(links.size());
  LagrangeModel<N> ref;
  ref.n = 3 * k;
  ref.m = 1;
  const Vec3 g = model.gravity;
  ref.lagrangian = [g, links, k](const std::array<HyperDual<N>, N>& x) {
    using S = HyperDual<N>;
    const S &u = x[6 * k], &ud = x[6 * k + 1];
    const V3<S> top = vec<S>(0, 0, 10);
    const M3<S> Rj = rotation_z(u);
    const V3<S> wj = vec<S>(0, 0, 1) * ud;
    const V3<S> cj = Rj * vec<S>(3, 0, 0);
    S L = body_lagrangian<S>(600, Vec3(10, 1800, 1800), top + cj, wj.cross(cj), Rj, wj, g);
    M3<S> R = Rj;
    V3<S> w = wj, p = top + Rj * vec<S>(6, 0, 0), vp = wj.cross(Rj * vec<S>(6, 0, 0));
    for (int i = 0; i < k; ++i) {
      M3<S> D;
      V3<S> wrel;
      cardan<S>(&x[3 * i], &x[3 * k + 3 * i], D, wrel);
      w = w + R * wrel;
      R = R * D;
      const V3<S> c = R * vec<S>(0, 0, -links[i].centroid), down = R * vec<S>(0, 0, -links[i].length);
      L += body_lagrangian<S>(links[i].mass, links[i].inertia, p + c, vp + w.cross(c), R, w, g);
      vp = vp + w.cross(down);
      p = p + down;
    }
    return L;
  };
  ref.point = [links, k](const VecX& q, const VecX& u) {
    Mat3 R = rotation_z(u(0));
    Vec3 p = Vec3(0, 0, 10) + R * Vec3(6, 0, 0);
    for (int i = 0; i < k; ++i) {
      R = R * rotation_x(q(3 * i)) * rotation_y(q(3 * i + 1)) * rotation_z(q(3 * i + 2));
      p += R * Vec3(0, 0, -links[i].length);
    }
    return p;
  };
  ref.drives = model_drives(model);
  return ref;
}

// Thesis Fig. 5-2b: a 500 kg load on a 4 m rope (its inertia not axisymmetric, so the rope's
// spin matters too).
const std::vector<HangingLink> kSingleJib{{500, 4, 4, Vec3(40, 30, 20)}};

TEST(MinimumDofModel, SingleJibPendulumFollowsItsLagrangeEquations) {
  const Simulation sim = read(jib_chain_yaml(kSingleJib).c_str());
  const auto ref = jib_chain_lagrange<8>(kSingleJib, sim.model);
  // Rotation vector against Cardan angles, virtual power of the element residuals against the
  // energy: the same path to the integrators' (fourth-order) error.
  EXPECT_LT(largest_path_difference(sim.model, ref, "l0.bottom", 4.0, 2e-3), 1e-9);
}

TEST(MinimumDofModel, DoubleJibPendulumFollowsItsLagrangeEquations) {
  // examples/minimum_dof/double_jib_pendulum.yaml's hook block and load, slewed by a sine.
  const std::vector<HangingLink> links{{50, 4, 4, Vec3(2, 2, 1)}, {500, 1.5, 1.5, Vec3(40, 40, 40)}};
  const Simulation sim = read(jib_chain_yaml(links).c_str());
  const auto ref = jib_chain_lagrange<14>(links, sim.model);
  EXPECT_LT(largest_path_difference(sim.model, ref, "l1.bottom", 3.0, 2e-3), 1e-9);
}

TEST(MinimumDofModel, TripleJibPendulumFollowsItsLagrangeEquations) {
  // examples/minimum_dof/triple_jib_pendulum.yaml's hook block, spreader bar and load.
  const std::vector<HangingLink> links{
      {50, 3, 3, Vec3(2, 2, 1)}, {120, 1, 2, Vec3(15, 15, 5)}, {500, 1, 1, Vec3(40, 40, 40)}};
  const Simulation sim = read(jib_chain_yaml(links).c_str());
  const auto ref = jib_chain_lagrange<20>(links, sim.model);
  EXPECT_LT(largest_path_difference(sim.model, ref, "l2.bottom", 3.0, 2e-3), 1e-9);
}

TEST(MinimumDofModel, FoldingBoomFollowsItsLagrangeEquations) {
  const Simulation sim = read(kFoldingBoom);
  constexpr int N = 12;  // q: the rope's three Cardan angles; u: slewing, luffing, folding
  LagrangeModel<N> ref;
  ref.n = 3;
  ref.m = 3;
  const Vec3 g = sim.model.gravity;
  ref.lagrangian = [g](const std::array<HyperDual<N>, N>& x) {
    using S = HyperDual<N>;
    const S *u = &x[6], *ud = &x[9];
    const V3<S> ey = vec<S>(0, 1, 0);
    const M3<S> Rc = rotation_z(u[0]);
    const V3<S> wc = vec<S>(0, 0, 1) * ud[0];
    const V3<S> head = vec<S>(0, 0, 3);
    const M3<S> Rm = Rc * rotation_y(u[1]);
    const V3<S> wm = wc + Rc * ey * ud[1];
    const V3<S> cm = Rm * vec<S>(2.5, 0, 0), knuckle = Rm * vec<S>(5, 0, 0);
    const M3<S> Rf = Rm * rotation_y(u[2]);
    const V3<S> wf = wm + Rm * ey * ud[2];
    const V3<S> cf = Rf * vec<S>(2, 0, 0), tip = Rf * vec<S>(4, 0, 0);
    const V3<S> v_knuckle = wm.cross(knuckle), v_tip = v_knuckle + wf.cross(tip);
    M3<S> D;
    V3<S> wrel;
    cardan<S>(&x[0], &x[3], D, wrel);
    const M3<S> Rl = Rf * D;
    const V3<S> wl = wf + Rf * wrel, cl = Rl * vec<S>(0, 0, -3);
    return body_lagrangian<S>(900, Vec3(700, 700, 60), vec<S>(0, 0, 1.5), vec<S>(0, 0, 0), Rc, wc, g) +
           body_lagrangian<S>(700, Vec3(15, 1460, 1460), head + cm, wm.cross(cm), Rm, wm, g) +
           body_lagrangian<S>(400, Vec3(8, 535, 535), head + knuckle + cf, v_knuckle + wf.cross(cf), Rf, wf, g) +
           body_lagrangian<S>(300, Vec3(20, 25, 15), head + knuckle + tip + cl, v_tip + wl.cross(cl), Rl, wl, g);
  };
  ref.point = [](const VecX& q, const VecX& u) {
    const Mat3 Rm = rotation_z(u(0)) * rotation_y(u(1)), Rf = Rm * rotation_y(u(2));
    const Mat3 Rl = Rf * rotation_x(q(0)) * rotation_y(q(1)) * rotation_z(q(2));
    return Vec3(Vec3(0, 0, 3) + Rm * Vec3(5, 0, 0) + Rf * Vec3(4, 0, 0) + Rl * Vec3(0, 0, -3));
  };
  ref.drives = model_drives(sim.model);
  EXPECT_LT(largest_path_difference(sim.model, ref, "load.centre", 4.0, 2e-3), 1e-9);
}

// The kinematic maps of (2-14): block velocities T q_dot and accelerations T q_ddot + T_dot q_dot
// (drives included) against central differences of the poses along a path q(t).
TEST(MinimumDofModel, KinematicMapsMatchFiniteDifferences) {
  for (const std::string& yaml : {jib_chain_yaml(kSingleJib), std::string(kFoldingBoom)}) {
    const Simulation sim = read(yaml.c_str());
    const Model& model = sim.model;
    const MinimumDofModel tree(model);
    const int n = tree.num_free();
    const VecX q = VecX::LinSpaced(n, 0.3, -0.4), qd = VecX::LinSpaced(n, -0.7, 0.5), qdd = VecX::LinSpaced(n, 0.9, -1.1);
    const double t0 = 1.3, d = 1e-4;
    auto at = [&](double t, std::vector<BlockState>& s, const VecX* acc) {
      const double dt = t - t0;
      const VecX qt = q + qd * dt + 0.5 * qdd * dt * dt, qdt = qd + qdd * dt;
      tree.block_states(t, qt, qdt, acc, s);
    };
    std::vector<BlockState> s0, sp, sm;
    at(t0, s0, &qdd);
    at(t0 + d, sp, nullptr);
    at(t0 - d, sm, nullptr);
    for (std::size_t b = 0; b < model.blocks.size(); ++b) {
      if (model.blocks[b].fixed) continue;
      const BlockState &c = s0[b], &p = sp[b], &m = sm[b];
      if (model.blocks[b].kind == SlotKind::translation) {
        const Vec3 v_fd = (p.pos - m.pos) / (2 * d), a_fd = (p.pos - 2 * c.pos + m.pos) / (d * d);
        EXPECT_LT((c.vel - v_fd).norm(), 1e-6 * (1 + c.vel.norm())) << model.blocks[b].label;
        EXPECT_LT((c.acc - a_fd).norm(), 1e-4 * (1 + c.acc.norm())) << model.blocks[b].label;
      } else {
        const Vec3 w_fd = unskew(Mat3(c.rot.transpose() * (p.rot - m.rot) / (2 * d)));
        const Vec3 wd_fd = (p.vel - m.vel) / (2 * d);
        EXPECT_LT((c.vel - w_fd).norm(), 1e-6 * (1 + c.vel.norm())) << model.blocks[b].label;
        EXPECT_LT((c.acc - wd_fd).norm(), 1e-6 * (1 + c.acc.norm())) << model.blocks[b].label;
      }
    }
  }
}

// The mass matrix of the joint coordinates is the kinetic energy's Hessian: symmetric, positive
// definite, and M q_dot . q_dot / 2 is the kinetic energy the elements report (driven rates at rest).
TEST(MinimumDofModel, MassMatrixIsTheKineticEnergysHessian) {
  const Simulation sim = read(kFoldingBoom);
  const Model& model = sim.model;
  const MinimumDofModel tree(model);
  const VecX q(Vec3(0.2, -0.3, 0.4)), qd(Vec3(0.5, 0.7, -0.6));
  const double t = 0.0;  // sine drives: value 0; their rates are not zero, so take them out below
  MatX M;
  VecX f;
  tree.equations(t, q, qd, M, f);
  EXPECT_LT((M - M.transpose()).norm(), 1e-12 * M.norm());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatX>(M).eigenvalues().minCoeff(), 0.0);
  // Kinetic energy of the free coordinates' motion alone: rates of the joint coordinates minus the
  // drives' contribution (the blocks' velocities are linear in all rates).
  std::vector<BlockState> with, without;
  tree.block_states(t, q, qd, nullptr, with);
  tree.block_states(t, q, VecX::Zero(3), nullptr, without);
  double kinetic = 0.0;
  for (std::size_t b = 0; b < model.blocks.size(); ++b) with[b].vel -= without[b].vel;
  for (const ElementEntry& e : model.elements) {
    std::vector<SlotState<double>> slots;
    gather_slots(e, with, slots);
    kinetic += e.element->energy(slots, ElementContext{model.gravity, t}).kinetic;
  }
  EXPECT_NEAR(0.5 * qd.dot(M * qd), kinetic, 1e-10 * kinetic);
}

TEST(MinimumDofModel, RefusesWhatIsNotATreeOfRigidBodies) {
  // A closed loop: a third link back to the ground.
  std::string loop = kDoublePendulum;
  loop += "  - {name: back, type: spherical, joints: [lower.tip, ground.pivot]}\n";
  try {
    const Simulation sim = read(loop.c_str());
    MinimumDofModel tree(sim.model);
    FAIL() << "a closed loop was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'back'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("loop"), std::string::npos) << e.what();
  }
  // A body with no joint to the ground.
  std::string loose = kDoublePendulum;
  loose.replace(loose.find("  - {name: elbow"), std::string::npos, "");
  try {
    const Simulation sim = read(loose.c_str());
    MinimumDofModel tree(sim.model);
    FAIL() << "a free-floating body was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'lower'"), std::string::npos) << e.what();
  }
  // The starting pose must satisfy the joints.
  const Simulation sim = read(kDoublePendulum);
  const MinimumDofModel tree(sim.model);
  std::vector<BlockState> blocks;
  tree.block_states(0.0, VecX::Zero(2), VecX::Zero(2), nullptr, blocks);
  const int lower = sim.model.joints[sim.model.find_joint("lower.top")].translation_block;
  blocks[lower].pos += Vec3(0, 0, 0.01);
  VecX q, qd;
  try {
    tree.coordinates_from_blocks(0.0, blocks, q, qd);
    FAIL() << "an open joint was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'elbow'"), std::string::npos) << e.what();
  }
}

// Poses and velocities back to coordinates: the inverse of block_states.
TEST(MinimumDofModel, CoordinatesFromBlocksInvertTheKinematics) {
  const Simulation sim = read(kFoldingBoom);
  const MinimumDofModel tree(sim.model);
  const VecX q(Vec3(0.2, -0.3, 0.4)), qd(Vec3(0.5, 0.7, -0.6));
  std::vector<BlockState> blocks;
  tree.block_states(2.5, q, qd, nullptr, blocks);
  VecX q2, qd2;
  tree.coordinates_from_blocks(2.5, blocks, q2, qd2);
  EXPECT_LT((q2 - q).norm(), 1e-13);
  EXPECT_LT((qd2 - qd).norm(), 1e-12);
}

}  // namespace
}  // namespace latticedyn
