// Super truss element: members by the closed-form co-rotational kernel projected through the node
// Jacobians (member chain rule), the lattice's translational mass as two coupled rigid bodies, the
// rotary inertia of the nodes through the map's rotations.
#include "elements/super_truss.hpp"

#include "elements/strain_rate_damping.hpp"

#include <unsupported/Eigen/KroneckerProduct>

#include <omp.h>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace latticedyn {

namespace {

const TrussSectionSpec& validated(const TrussSectionSpec& spec) {
  spec.validate();
  return spec;
}

SectionForces lane_of(const SectionForcesT<Pack4>& f, int l) {
  return SectionForces{f.N[l], f.Qy[l], f.Qz[l], f.T[l], f.My[l], f.Mz[l]};
}

Row9 contract_row(const Row12& r) {  // the (d, delta_1, delta_2) part of a derivative in the DoFs
  Row9 out;
  out << r.segment<3>(6), r.segment<3>(3), r.segment<3>(9);
  return out;
}

// Node frames' angular-velocity Jacobian of an end-section node.
Mat312 end_rotation_jacobian(int end) {
  Mat312 J = Mat312::Zero();
  J.block<3, 3>(0, end == 1 ? 3 : 9) = Mat3::Identity();
  return J;
}

}  // namespace

/// Scratch of one evaluation: node poses and Jacobians, and the members' node loads.
struct SuperTrussElement::Evaluation {
  std::vector<Vec3> p;
  std::vector<Mat3> R;
  std::vector<Mat312> Jp, Jw;
  std::vector<InternalRotation> rot;
  std::vector<int> internal_of;  // node -> index in rot, or -1
};

/// What the member loop accumulates (one set per chunk of members): the force on each node
/// (inertial axes), the moment on it (node axes), and the members' stiffness projected.
struct SuperTrussElement::MemberLoads {
  std::vector<Vec3> F, M;
  Mat12 K;
  void reset(int nodes) {
    F.assign(nodes, Vec3::Zero());
    M.assign(nodes, Vec3::Zero());
    K.setZero();
  }
};

SuperTrussElement::SuperTrussElement(const TrussSectionSpec& spec, const TrussGeometry& g)
    : spec_(validated(spec)), geometry_(g), map_(spec_, g) {
  const int nn = map_.num_nodes();
  lumped_.rotary.assign(nn, Mat3::Zero());
  lumped_.weight.assign(nn, 0.0);
  std::map<std::pair<int, int>, double> pairs;
  for (const TrussMember& tm : g.members) {
    const SectionProperties& section = g.section(spec, tm.kind);
    Member m;
    m.a = tm.a;
    m.b = tm.b;
    m.offset_a = g.member_offset(tm, tm.a);
    m.offset_b = g.member_offset(tm, tm.b);
    m.beam = std::make_shared<TimoshenkoBeam>(BeamProperties{spec.material, section, tm.length, 0.0});
    const double rho = section.effective_density(spec.material);
    const double mass = rho * section.area * tm.length;
    const Vec3 rotary = 0.5 * rho * tm.length * Vec3(section.Iy + section.Iz, section.Iy, section.Iz);
    pairs[{m.a, m.a}] += mass / 3;
    pairs[{m.b, m.b}] += mass / 3;
    pairs[{m.a, m.b}] += mass / 6;
    pairs[{m.b, m.a}] += mass / 6;
    lumped_.rotary[m.a] += m.offset_a * rotary.asDiagonal() * m.offset_a.transpose();
    lumped_.rotary[m.b] += m.offset_b * rotary.asDiagonal() * m.offset_b.transpose();
    lumped_.weight[m.a] += 0.5 * mass;
    lumped_.weight[m.b] += 0.5 * mass;
    members_.push_back(m);
  }
  for (std::size_t first = 0; first < members_.size(); first += Pack4::kLanes) {
    MemberBatch batch;
    batch.count = static_cast<int>(std::min<std::size_t>(Pack4::kLanes, members_.size() - first));
    for (int l = 0; l < Pack4::kLanes; ++l) {
      const bool real = l < batch.count;
      const Member& m = members_[first + (real ? l : 0)];
      batch.a[l] = m.a;
      batch.b[l] = m.b;
      const CorotationalStiffness& k = m.beam->stiffness();
      if (real) {
        set_lane(batch.stiffness, l, k);
      } else {
        batch.stiffness.length[l] = k.length;  // a copy without stiffness: no force
      }
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) batch.offset_a(i, j)[l] = m.offset_a(i, j), batch.offset_b(i, j)[l] = m.offset_b(i, j);
    }
    batches_.push_back(batch);
  }
  for (const auto& [ab, mass] : pairs) lumped_.pairs.push_back({ab.first, ab.second, mass});
  // The translational kinetic energy (1/2) sum m_ab pd_a . pd_b is bilinear in the points'
  // coefficients z: the moment matrix Z = sum m_ab z_a z_b^T carries all of it, as the pairs
  // (e_k, row k of Z).
  Eigen::Matrix<double, 8, 8> Z = Eigen::Matrix<double, 8, 8>::Zero();
  for (const LumpedMass::Pair& pr : lumped_.pairs)
    Z += pr.m * map_.node(pr.a).point.coefficients() * map_.node(pr.b).point.coefficients().transpose();
  for (int k = 0; k < 8; ++k) {
    if (Z.row(k).isZero(0.0)) continue;
    mass_points_.emplace_back(AffinePoint::from_coefficients(Eigen::Matrix<double, 8, 1>::Unit(k)),
                              AffinePoint::from_coefficients(Z.row(k).transpose()));
  }
  for (int n = 0; n < nn; ++n) {
    weight_point_ += map_.node(n).point * lumped_.weight[n];
    if (map_.node(n).end != 0) end_rotary_[map_.node(n).end - 1] += lumped_.rotary[n];
  }
  // The kinetic energy as quadratic forms of point and frame-column rates, for mass-proportional
  // damping: (1/2) e_dot^T (Z (x) I3) e_dot over the 8 basis points e = (r1, r2, R1 e_j, R2 e_j),
  // plus each rotary inertia J as (1/2) tr(R_dot E R_dot^T) with E = tr(J)/2 I - J over its frame's
  // columns (omega^T J omega = tr(S E S^T) for S = skew(omega)).
  auto second_moment = [](const Mat3& J) -> Mat3 { return 0.5 * J.trace() * Mat3::Identity() - J; };
  const Eigen::Matrix<double, 8, 8> Zs = 0.5 * (Z + Z.transpose());
  kinetic_form_ = Eigen::kroneckerProduct(Zs, Mat3::Identity());
  for (int i = 0; i < 2; ++i)
    kinetic_form_.block<9, 9>(6 + 9 * i, 6 + 9 * i) += Eigen::kroneckerProduct(second_moment(end_rotary_[i]), Mat3::Identity());
  for (int n : map_.internal_nodes())
    internal_kinetic_form_.push_back(Eigen::kroneckerProduct(second_moment(lumped_.rotary[n]), Mat3::Identity()));
}

void SuperTrussElement::gather(const std::vector<Vec3>& p, const std::vector<Mat3>& R, const MemberBatch& bt,
                               Vec3T<Pack4>& r1, Vec3T<Pack4>& d, Mat3T<Pack4>& R1, Mat3T<Pack4>& R2) {
  Mat3T<Pack4> Ra, Rb;
  for (int l = 0; l < Pack4::kLanes; ++l) {
    const Vec3 &pa = p[bt.a[l]], &pb = p[bt.b[l]];
    const Mat3 &Ral = R[bt.a[l]], &Rbl = R[bt.b[l]];
    for (int i = 0; i < 3; ++i) {
      r1(i)[l] = pa(i);
      d(i)[l] = pb(i) - pa(i);
      for (int j = 0; j < 3; ++j) Ra(i, j)[l] = Ral(i, j), Rb(i, j)[l] = Rbl(i, j);
    }
  }
  R1 = Ra * bt.offset_a;
  R2 = Rb * bt.offset_b;
}

void SuperTrussElement::add_members(const Evaluation& ev, int first, int last, MemberLoads& out, bool tangent) const {
  constexpr int kL = Pack4::kLanes;
  Vec3T<Pack4> r1, d;
  Mat3T<Pack4> R1, R2;
  CorotationalForce<Pack4> force;
  Eigen::Matrix<Pack4, 9, 9> K9;
  Eigen::Matrix<Pack4, 9, 12> P;
  Eigen::Matrix<Pack4, 3, 12> Jwa, Jwb;
  Eigen::Matrix<Pack4, 12, 12> K = Eigen::Matrix<Pack4, 12, 12>::Zero();  // the lanes summed at the end
  for (int k = first; k < last; ++k) {
    const MemberBatch& bt = batches_[k];
    gather(ev.p, ev.R, bt, r1, d, R1, R2);
    corotational_internal_force(bt.stiffness, d, R1, R2, force);
    const Vec3T<Pack4> Ma = bt.offset_a * force.f.segment<3>(3), Mb = bt.offset_b * force.f.segment<3>(6);
    for (int l = 0; l < bt.count; ++l) {
      const Vec3 F = lane(force.f.segment<3>(0), l);
      out.F[bt.a[l]] -= F;
      out.F[bt.b[l]] += F;
      out.M[bt.a[l]] += lane(Ma, l);
      out.M[bt.b[l]] += lane(Mb, l);
    }
    if (!tangent) continue;
    corotational_tangent(bt.stiffness, R1, R2, force, K9);
    // The members' variables (d, delta_a, delta_b) in the element's: rows of P.
    for (int l = 0; l < kL; ++l) {
      const Mat312 Jd = ev.Jp[bt.b[l]] - ev.Jp[bt.a[l]];
      const Mat312 &Ja = ev.Jw[bt.a[l]], &Jb = ev.Jw[bt.b[l]];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 12; ++j) P(i, j)[l] = Jd(i, j), Jwa(i, j)[l] = Ja(i, j), Jwb(i, j)[l] = Jb(i, j);
    }
    P.middleRows<3>(3) = bt.offset_a.transpose() * Jwa;
    P.bottomRows<3>() = bt.offset_b.transpose() * Jwb;
    const Eigen::Matrix<Pack4, 9, 12> KP = K9.lazyProduct(P);
    K.noalias() += P.transpose().lazyProduct(KP);
  }
  if (!tangent) return;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      double sum = 0.0;
      for (int l = 0; l < kL; ++l) sum += K(i, j)[l];
      out.K(i, j) += sum;
    }
}

void SuperTrussElement::add_translational_inertia(std::span<const SlotState<double>> s, const ElementContext& ctx,
                                                  Vec12& r, LocalTangents* t) const {
  const EndFrames f{s.data()};
  for (const auto& [a, b] : mass_points_) {
    const Vec3 acc = acceleration(b, f);
    add_point_force(a, f, acc, r);
    if (!t || ctx.at_rest) continue;  // at rest the accelerations and their tangents vanish
    const Mat123 JaT = jacobian(a, f).transpose();
    // Coefficient-wise products (lazyProduct): at 12 x 3 x 12 Eigen's blocked GEMM costs more.
    t->M.noalias() += JaT.lazyProduct(jacobian(b, f));
    t->C.noalias() += JaT.lazyProduct(acceleration_velocity_derivative(b, f));
    t->K.noalias() += JaT.lazyProduct(acceleration_position_derivative(b, f));
    add_point_force_geometric(a, f, acc, t->K);
  }
  add_point_force(weight_point_, f, Vec3(-ctx.gravity), r);
  if (t) add_point_force_geometric(weight_point_, f, Vec3(-ctx.gravity), t->K);
}

void SuperTrussElement::evaluate(std::span<const SlotState<double>> s, const ElementContext& ctx, Vec12& r,
                                 ElementTangents* t) const {
  const EndFrames f{s.data()};
  const int nn = map_.num_nodes();
  thread_local Evaluation ev;
  ev.p.resize(nn);
  ev.R.resize(nn);
  ev.Jp.resize(nn);
  ev.Jw.resize(nn);
  ev.internal_of.assign(nn, -1);
  internal_rotations(map_, s, ev.rot, t ? RotationDetail::jacobians : RotationDetail::gradients);
  const std::vector<int>& internal = map_.internal_nodes();
  for (std::size_t k = 0; k < internal.size(); ++k) ev.internal_of[internal[k]] = static_cast<int>(k);
  for (int n = 0; n < nn; ++n) {
    const SuperTrussMap::Node& nd = map_.node(n);
    ev.p[n] = position(nd.point, f);
    if (t) ev.Jp[n] = jacobian(nd.point, f);  // the residual projects node forces without it
    if (nd.end != 0) {
      ev.R[n] = s[nd.end == 1 ? 1 : 3].rot;
      if (t) ev.Jw[n] = end_rotation_jacobian(nd.end);
    } else {
      const InternalRotation& o = ev.rot[ev.internal_of[n]];
      ev.R[n] = o.A * o.C;
      if (t) ev.Jw[n] = o.Jw;
    }
  }

  // Members: independent of each other (thesis Figure 3-2), so chunks of them run as parallel
  // tasks on the threads OpenMP gives a region here (one when the assembler already evaluates
  // several elements in parallel), each into its own node loads and stiffness.
  const bool tangent = t != nullptr;
  const int threads = omp_in_parallel() ? 1 : omp_get_max_threads();
  thread_local MemberLoads loads;
  loads.reset(nn);
  const int nb = static_cast<int>(batches_.size());
  const Evaluation& kin = ev;  // the calling thread's scratch (a thread_local), shared with the tasks
  auto add = [&](int c, int chunks, MemberLoads& out) {
    add_members(kin, c * nb / chunks, (c + 1) * nb / chunks, out, tangent);
  };
  if (threads <= 1) {
    add(0, 1, loads);
  } else {
    const int chunks = 2 * threads;
    std::vector<MemberLoads> part(chunks);
#pragma omp parallel for num_threads(threads) schedule(static, 1)
    for (int c = 0; c < chunks; ++c) {
      part[c].reset(nn);
      add(c, chunks, part[c]);
    }
    for (const MemberLoads& l : part) {
      for (int n = 0; n < nn; ++n) loads.F[n] += l.F[n], loads.M[n] += l.M[n];
      loads.K += l.K;
    }
  }

  r.setZero();
  // Tangents accumulate in fixed-size matrices, copied to t at the end.
  LocalTangents local;
  LocalTangents* lt = t ? &local : nullptr;
  if (t) {
    local.K = loads.K;
    local.C.setZero();
    local.M.setZero();
  }
  add_translational_inertia(s, ctx, r, lt);
  // Node forces through the positions' Jacobians, with the map's second derivatives.
  Mat12 Kg = Mat12::Zero();
  for (int n = 0; n < nn; ++n) {
    add_point_force(map_.node(n).point, f, loads.F[n], r);
    if (t) add_point_force_geometric(map_.node(n).point, f, loads.F[n], Kg);
  }
  // Rotary inertia of the end sections' nodes: rigid bodies.
  for (int i = 0; i < 2; ++i) {
    const Mat3& J = end_rotary_[i];
    const Vec3 &w = s[2 * i + 1].vel, &dw = s[2 * i + 1].acc;
    r.segment<3>(6 * i + 3) += J * dw + w.cross(J * w);
    if (t) {
      local.M.block<3, 3>(6 * i + 3, 6 * i + 3) += J;
      local.C.block<3, 3>(6 * i + 3, 6 * i + 3) += skew<double>(w) * J - skew<double>(Vec3(J * w));
    }
  }
  for (int n = 0; n < nn; ++n)
    if (map_.node(n).end != 0) r.segment<3>(map_.node(n).end == 1 ? 3 : 9) += loads.M[n];

  // Internal nodes: R_n = A C(y), omega_n = C^T wA + T y', wA = F^T w1, so
  // omega_n' = C^T wA' + (C^T wA) x (T y') + T' y' + T y''; their moments M_n + tau_n act through
  // Jw = C^T E1 + T Y.
  std::vector<InternalRotationTangent> tan;
  std::vector<Vec3> angle_weights;  // T^T Mt per internal node: what the angles' Hessians are weighed with
  if (t) {
    if (!ctx.at_rest) internal_rotation_tangents(map_, s, tan);
    angle_weights.resize(internal.size());
  }
  for (std::size_t k = 0; k < internal.size(); ++k) {
    const int n = internal[k];
    const InternalRotation& o = ev.rot[k];
    const Mat3& F = map_.main_beams()[map_.node(n).main_beam].frame;
    const Mat3& J = lumped_.rotary[n];
    const Vec3 wA = F.transpose() * s[1].vel, dwA = F.transpose() * s[1].acc;
    const Vec3 u = o.C.transpose() * wA, Omega = o.T * o.ydot;
    const Vec3 w = u + Omega;
    const Mat3& Tdot = o.Tdot;
    const Vec3 dw = o.C.transpose() * dwA + u.cross(Omega) + Tdot * o.ydot + o.T * o.yddot;
    const Vec3 Mt = loads.M[n] + J * dw + w.cross(J * w);
    if (!t) {
      r += internal_node_moment(o, F, Mt);
      continue;
    }
    r += o.Jw.transpose() * Mt;
    Mat3 dT[2], ddT[3];
    cardan_zyx_tangent_derivatives(o.sphi, o.cphi, o.spsi, o.cpsi, dT, ddT);
    const Mat312 TY = o.T * o.Y;
    if (!ctx.at_rest) {  // the rotary inertia's tangents; at rest they vanish
      const InternalRotationTangent& ot = tan[k];
      auto Dk = [&](const Vec3& v) {  // [dT/dphi v, dT/dpsi v, 0]
        Mat3 D = Mat3::Zero();
        D.col(0) = dT[0] * v;
        D.col(1) = dT[1] * v;
        return D;
      };
      const Mat3 Dyd = Dk(o.ydot), Dydd = Dk(o.yddot);
      Mat3 E = Mat3::Zero();  // d(T' y')/dy at fixed y'
      E.col(0) = (o.ydot(0) * ddT[0] + o.ydot(1) * ddT[1]) * o.ydot;
      E.col(1) = (o.ydot(0) * ddT[1] + o.ydot(1) * ddT[2]) * o.ydot;
      Mat312 CE1 = Mat312::Zero();  // d(C^T wA)/d(dq)
      CE1.block<3, 3>(0, 3) = o.C.transpose() * F.transpose();
      // Derivatives of omega_n and omega_n' at fixed rates (K) and in the rates (C).
      const Mat312 du = skew<double>(u) * TY;
      const Mat312 dOmega = Dyd * o.Y + o.T * ot.dydot;
      const Mat312 w_q = du + dOmega;
      const Mat312 dw_q = skew<double>(Vec3(o.C.transpose() * dwA)) * TY - skew<double>(Omega) * du +
                          skew<double>(u) * dOmega + E * o.Y + (Tdot + Dyd) * ot.dydot + Dydd * o.Y + o.T * ot.dyddot;
      // d(y'')/d(dq) = 2 H dq, H the angles' symmetric Hessian in (d, delta_1, delta_2): from
      // d(y')/d eps = dq^T H + (1/2) (w_i x Y_i) on the rotation blocks.
      Mat312 Hdq2;
      for (int i = 0; i < 3; ++i) {
        Row9 a = contract_row(ot.dydot.row(i));
        const Row9 y9 = contract_row(o.Y.row(i));
        for (int e = 0; e < 2; ++e) {
          const Vec3 we = s[1 + 2 * e].vel;
          a.segment<3>(3 + 3 * e) -= 0.5 * we.cross(Vec3(y9.segment<3>(3 + 3 * e).transpose())).transpose();
        }
        Hdq2.row(i) = expand_row(2.0 * a);
      }
      const Mat312 dw_v = -skew<double>(Omega) * CE1 + skew<double>(u) * TY + (Tdot + Dyd) * o.Y + o.T * Hdq2;
      const Mat3 G = skew<double>(w) * J - skew<double>(Vec3(J * w));
      const Mat123 JwT = o.Jw.transpose();
      local.K.noalias() += JwT.lazyProduct(Mat312(J * dw_q + G * w_q));
      local.C.noalias() += JwT.lazyProduct(Mat312(J * dw_v + G * o.Jw));
      local.M.noalias() += JwT.lazyProduct(Mat312(J * o.Jw));
    }
    // The map's second derivatives against Mt: through C, through T and through the angles.
    Kg.middleRows<3>(3) -= (F * o.C * skew<double>(Mt)) * TY;
    Mat3 Q = Mat3::Zero();
    Q.col(0) = dT[0].transpose() * Mt;
    Q.col(1) = dT[1].transpose() * Mt;
    Kg.noalias() += o.Y.transpose().lazyProduct(Mat312(Q * o.Y));
    angle_weights[k] = o.T.transpose() * Mt;
  }
  if (t) {
    add_expanded(contracted_angle_hessian(map_, s, ev.rot, angle_weights), Kg);
    t->K = local.K + Kg;
    t->C = local.C;
    t->M = local.M;
  }
}

void SuperTrussElement::residual(std::span<const SlotState<double>> s, const ElementContext& ctx,
                                 Eigen::Ref<VecX> r) const {
  Vec12 rr;
  evaluate(s, ctx, rr, nullptr);
  add_damping(s, ctx, rr, nullptr);
  r = rr;
}

void SuperTrussElement::tangents(std::span<const SlotState<double>> s, const ElementContext& ctx,
                                 ElementTangents& out) const {
  out.resize(12);
  Vec12 rr;
  evaluate(s, ctx, rr, &out);
  add_damping(s, ctx, rr, &out);
  out.residual = rr;
}

template <class Seeds, class Add>
void SuperTrussElement::damping_measures(std::span<const SlotState<double>> s, Seeds& ad, Add&& add) const {
  using S = typename Seeds::S;
  const RayleighDamping& d = spec_.material.damping;
  // Each rotation seeded once: EnergyAD adds its right-perturbation term once per seed.
  const Vec3T<S> r1 = ad.vec(s[0].pos, 0), r2 = ad.vec(s[2].pos, 6);
  const Mat3T<S> R1 = ad.rot(s[1].rot, 3), R2 = ad.rot(s[3].rot, 9);
  if (d.alpha > 0) {
    std::array<S, 24> e;
    const Vec3T<S>* basis[8] = {&r1, &r2, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
    for (int k = 0; k < 8; ++k) {
      const Vec3T<S> x = k < 2 ? *basis[k] : Vec3T<S>(k < 5 ? R1.col(k - 2) : R2.col(k - 5));
      for (int i = 0; i < 3; ++i) e[static_cast<std::size_t>(3 * k + i)] = x(i);
    }
    add(std::span<const S>(e), MatX(d.alpha * kinetic_form_));
  }
  const bool internal_rotary = d.alpha > 0 && !internal_kinetic_form_.empty();
  if (!(d.beta > 0) && !internal_rotary) return;
  thread_local std::vector<Vec3T<S>> p;
  thread_local std::vector<Mat3T<S>> R;
  map_.node_poses<S>(r1, R1, r2, R2, p, R);
  if (internal_rotary) {
    const std::vector<int>& internal = map_.internal_nodes();
    for (std::size_t k = 0; k < internal.size(); ++k) {
      const Mat3T<S>& Rn = R[static_cast<std::size_t>(internal[k])];
      std::array<S, 9> e;
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) e[static_cast<std::size_t>(3 * j + i)] = Rn(i, j);
      add(std::span<const S>(e), MatX(d.alpha * internal_kinetic_form_[k]));
    }
  }
  if (!(d.beta > 0)) return;
  for (const Member& m : members_) {
    const CorotationalStiffness& k = m.beam->stiffness();
    const auto def = corotational_deformation<S>(k, Vec3T<S>(p[m.b] - p[m.a]), Mat3T<S>(R[m.a] * m.offset_a),
                                                 Mat3T<S>(R[m.b] * m.offset_b));
    const auto e = corotational_deformation_measures(def);
    add(std::span<const S>(e), MatX(d.beta * corotational_local_stiffness(k)));
  }
}

void SuperTrussElement::add_damping(std::span<const SlotState<double>> s, const ElementContext& ctx, Vec12& r,
                                    ElementTangents* t) const {
  const RayleighDamping& d = spec_.material.damping;
  if (!d.active() || ctx.at_rest) return;
  Vec12 v;
  v << s[0].vel, s[1].vel, s[2].vel, s[3].vel;
  Vec12 f = Vec12::Zero();
  if (!t) {
    EnergyAD<12>::FirstOrder ad;
    damping_measures(s, ad, [&](std::span<const Dual<12>> e, const MatX& Cd) {
      add_strain_rate_damping_force<12>(e, Cd, v, f);
    });
    r += f;
    return;
  }
  EnergyAD<12>::SecondOrder ad;
  Mat12 K = Mat12::Zero(), C = Mat12::Zero();
  damping_measures(s, ad, [&](std::span<const HyperDual<12>> e, const MatX& Cd) {
    add_strain_rate_damping<12>(e, ad, Cd, v, f, K, C);
  });
  r += f;
  t->K += K;
  t->C += C;
}

ElementEnergy SuperTrussElement::energy(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  ElementOutput out;
  output(s, ctx, out);
  return out.energy;
}

void SuperTrussElement::output(std::span<const SlotState<double>> s, const ElementContext& ctx, ElementOutput& out) const {
  const EndFrames f{s.data()};
  Vec12 dq;
  dq << s[0].vel, s[1].vel, s[2].vel, s[3].vel;
  ElementEnergy& e = out.energy;
  e = ElementEnergy{};
  for (const auto& [a, b] : mass_points_) e.kinetic += 0.5 * (jacobian(a, f) * dq).dot(jacobian(b, f) * dq);
  for (int i = 0; i < 2; ++i) e.kinetic += 0.5 * s[2 * i + 1].vel.dot(end_rotary_[i] * s[2 * i + 1].vel);
  e.gravity_potential = -ctx.gravity.dot(position(weight_point_, f));
  // Node poses once, then every member's co-rotational frame once: strain energy, axial force and
  // drawn axis from it.
  thread_local std::vector<InternalRotation> rot;
  internal_rotations(map_, s, rot, RotationDetail::frames);
  const int nn = map_.num_nodes();
  thread_local std::vector<Vec3> p;
  thread_local std::vector<Mat3> R;
  p.resize(nn);
  R.resize(nn);
  for (int n = 0; n < nn; ++n) {
    const SuperTrussMap::Node& nd = map_.node(n);
    p[n] = position(nd.point, f);
    if (nd.end != 0) R[n] = s[nd.end == 1 ? 1 : 3].rot;
  }
  const std::vector<int>& internal = map_.internal_nodes();
  for (std::size_t k = 0; k < internal.size(); ++k) {
    const InternalRotation& o = rot[k];
    R[internal[k]] = o.A * o.C;
    const Mat3& F = map_.main_beams()[map_.node(internal[k]).main_beam].frame;
    const Vec3 w = o.C.transpose() * (F.transpose() * s[1].vel) + o.T * o.ydot;  // = Jw dq
    e.kinetic += 0.5 * w.dot(lumped_.rotary[internal[k]] * w);
  }
  // The members four at a time (TimoshenkoBeam::deformed_state on Pack4).
  const int nm = num_members();
  constexpr int kPoints = TimoshenkoBeam::kAxisPoints;
  out.axial_force.reset();
  out.polylines.resize(nm);
  out.polyline_axial_forces.resize(nm);
  out.members.resize(nm);
  Vec3T<Pack4> r1, d;
  Mat3T<Pack4> R1, R2;
  for (std::size_t k = 0; k < batches_.size(); ++k) {
    const MemberBatch& bt = batches_[k];
    gather(p, R, bt, r1, d, R1, R2);
    const CorotationalDeformation<Pack4> def = corotational_deformation<Pack4>(bt.stiffness, d, R1, R2);
    const Pack4 strain = corotational_strain_energy<Pack4>(bt.stiffness, def), axial = def.u * bt.stiffness.ea;
    // The members' section forces recovered from the node poses (thesis 3.5: the super truss's
    // coordinates carry every member's deformation).
    const std::array<SectionForcesT<Pack4>, 2> ends = corotational_section_forces<Pack4>(bt.stiffness, def);
    Vec3T<Pack4> axis[kPoints];
    for (int i = 0; i < kPoints; ++i) axis[i] = corotational_axis_point(def, r1, d, i / (kPoints - 1.0));
    for (int l = 0; l < bt.count; ++l) {
      const std::size_t m = k * Pack4::kLanes + static_cast<std::size_t>(l);
      e.strain += strain[l];
      out.polyline_axial_forces[m] = axial[l];
      const BeamProperties& beam = members_[m].beam->properties();
      out.members[m] = member_stress(beam.section, beam.material, lane_of(ends[0], l), lane_of(ends[1], l));
      out.polylines[m].resize(kPoints);
      for (int i = 0; i < kPoints; ++i) out.polylines[m][i] = lane(axis[i], l);
    }
  }
}

void SuperTrussElement::node_poses(std::span<const SlotState<double>> s, std::vector<Vec3>& p, std::vector<Mat3>& R) const {
  map_.node_poses<double>(s[0].pos, s[1].rot, s[2].pos, s[3].rot, p, R);
}

std::vector<double> SuperTrussElement::member_axial_forces(std::span<const SlotState<double>> s) const {
  ElementOutput out;
  output(s, ElementContext{}, out);
  return out.polyline_axial_forces;
}

std::vector<Vec3> SuperTrussElement::node_velocities(std::span<const SlotState<double>> s) const {
  const EndFrames f{s.data()};
  Vec12 dq;
  dq << s[0].vel, s[1].vel, s[2].vel, s[3].vel;
  std::vector<Vec3> out;
  for (int n = 0; n < map_.num_nodes(); ++n) out.push_back(jacobian(map_.node(n).point, f) * dq);
  return out;
}

std::vector<Vec3> SuperTrussElement::axis_points(std::span<const SlotState<double>> s, const ElementContext&) const {
  return {s[0].pos, s[2].pos};
}

std::vector<std::vector<Vec3>> SuperTrussElement::axis_polylines(std::span<const SlotState<double>> s,
                                                                 const ElementContext& ctx) const {
  ElementOutput out;
  output(s, ctx, out);
  return out.polylines;
}

}  // namespace latticedyn
