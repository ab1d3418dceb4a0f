// Super truss element: precomputed lattice data, the elastic part by HyperDual<12> through the
// kinematic map and the members' energies, the inertial part through AutoDiffElement.
#include "elements/super_truss.hpp"

#include "elements/energy_ad.hpp"

#include <omp.h>

#include <map>
#include <stdexcept>

namespace latticedyn {

namespace {
using TrussAD = EnergyAD<12>;  // r1 (0..2), rotation 1 (3..5), r2 (6..8), rotation 2 (9..11): the DoF order
}

SuperTrussElement::SuperTrussElement(const TrussSectionSpec& spec, const TrussGeometry& g) : spec_(spec), geometry_(g) {
  spec_.validate();
  const int n1 = static_cast<int>(spec.end1.size());
  const Vec3 end2_origin(spec.length, 0, 0);
  for (const TrussNode& n : g.nodes) {
    NodeData d;
    if (n.kind == TrussNode::Kind::end1) d.end = 1, d.offset = n.position;
    if (n.kind == TrussNode::Kind::end2) d.end = 2, d.offset = n.position - end2_origin;
    if (n.kind == TrussNode::Kind::internal) d.main_beam = n.main_beam, d.xi = double(n.station) / spec.order;
    nodes_.push_back(d);
    node_frames_.push_back(n.frame);
  }
  for (std::size_t m = 0; m < spec.main_beams.size(); ++m) {
    MainBeamData mb;
    mb.start = spec.main_beams[m][0];
    mb.end = n1 + spec.main_beams[m][1];
    const Vec3 d = g.nodes[mb.end].position - g.nodes[mb.start].position;
    mb.direction = d.normalized();
    mb.length = d.norm();
    for (const TrussMember& member : g.members)
      if (member.kind == TrussMemberKind::main && member.face == static_cast<int>(m)) mb.frame = member.frame0;
    for (std::size_t n = 0; n < g.nodes.size(); ++n)
      if (g.nodes[n].kind == TrussNode::Kind::internal && g.nodes[n].main_beam == static_cast<int>(m))
        mb.internal.push_back(static_cast<int>(n));
    main_beams_.push_back(mb);
  }
  node_rotary_.assign(nodes_.size(), Mat3::Zero());
  node_weight_.assign(nodes_.size(), 0.0);
  std::map<std::pair<int, int>, double> pairs;
  for (const TrussMember& tm : g.members) {
    const SectionProperties& section = g.section(spec, tm.kind);
    MemberData m;
    m.a = tm.a;
    m.b = tm.b;
    m.offset_a = g.nodes[tm.a].frame.transpose() * tm.frame0;
    m.offset_b = g.nodes[tm.b].frame.transpose() * tm.frame0;
    m.beam = std::make_shared<TimoshenkoBeam>(BeamProperties{spec.material, section, tm.length, 0.0});
    const double rho = section.effective_density(spec.material);
    m.mass = rho * section.area * tm.length;
    m.rotary = 0.5 * rho * tm.length * Vec3(section.Iy + section.Iz, section.Iy, section.Iz);
    pairs[{m.a, m.a}] += m.mass / 3;
    pairs[{m.b, m.b}] += m.mass / 3;
    pairs[{m.a, m.b}] += m.mass / 6;
    pairs[{m.b, m.a}] += m.mass / 6;
    node_rotary_[m.a] += m.offset_a * m.rotary.asDiagonal() * m.offset_a.transpose();
    node_rotary_[m.b] += m.offset_b * m.rotary.asDiagonal() * m.offset_b.transpose();
    node_weight_[m.a] += 0.5 * m.mass;
    node_weight_[m.b] += 0.5 * m.mass;
    members_.push_back(m);
  }
  for (const auto& [ab, mass] : pairs) mass_pairs_.push_back({ab.first, ab.second, mass});
}

void SuperTrussElement::residual(std::span<const SlotState<double>> s, const ElementContext& ctx,
                                 Eigen::Ref<VecX> r) const {
  AutoDiffElement::residual(s, ctx, r);
  // The elastic force by virtual power, member by member: each member's gradient in its own
  // variables (d = p_b - p_a and right rotations of its end frames, 9 directions of AD) projected
  // with the closed-form node Jacobians, r += (Jp_b - Jp_a)^T f_d + Jw_a^T O_a m_a + Jw_b^T O_b m_b.
  // Seeding the 12 end-section coordinates through the whole map instead costs 3 to 4 times more
  // (docs/performance.md); the tangent keeps that route (it needs the map's second derivatives).
  std::vector<Vec3> p;
  std::vector<Mat3> R;
  node_map<double>(s[0].pos, s[1].rot, s[2].pos, s[3].rot, p, R);
  std::vector<Eigen::Matrix<double, 3, 12>> Jp, Jw;
  node_jacobians<double>(s, Jp, Jw);
  using MemberAD = EnergyAD<9>;
  for (const MemberData& m : members_) {
    MemberAD::FirstOrder ad;
    const auto U = m.beam->strain_energy(ad.vec(Vec3(p[m.b] - p[m.a]), 0), ad.rot(Mat3(R[m.a] * m.offset_a), 3),
                                         ad.rot(Mat3(R[m.b] * m.offset_b), 6));
    MemberAD::Gradient g;
    MemberAD::extract(U, nullptr, &g);
    const Vec3 f_d = g.segment<3>(0), m_a = m.offset_a * g.segment<3>(3), m_b = m.offset_b * g.segment<3>(6);
    r += (Jp[m.b] - Jp[m.a]).transpose() * f_d + Jw[m.a].transpose() * m_a + Jw[m.b].transpose() * m_b;
  }
}

void SuperTrussElement::tangents(std::span<const SlotState<double>> s, const ElementContext& ctx,
                                 ElementTangents& out) const {
  TrussAD::SecondOrder ad;
  using S = decltype(ad)::S;
  std::vector<Vec3T<S>> p;
  std::vector<Mat3T<S>> R;
  node_map<S>(ad.vec(s[0].pos, 0), ad.rot(s[1].rot, 3), ad.vec(s[2].pos, 6), ad.rot(s[3].rot, 9), p, R);
  // The inertial part and chunks of the member loop are independent (members do not affect each
  // other, Figure 3-2): tasks on the threads OpenMP gives a region here, which is one when the
  // assembler already evaluates several elements in parallel.
  const int threads = omp_in_parallel() ? 1 : omp_get_max_threads();
  const int chunks = threads > 1 ? 2 * threads : 1;
  const int nm = static_cast<int>(members_.size());
  std::vector<S> partial(chunks, S(0.0));
#pragma omp parallel num_threads(threads) if (threads > 1)
#pragma omp single
  {
#pragma omp task
    AutoDiffElement::tangents(s, ctx, out);
    for (int c = 0; c < chunks; ++c) {
#pragma omp task firstprivate(c)
      partial[c] = member_energy<S>(p, R, c * nm / chunks, (c + 1) * nm / chunks);
    }
  }
  S U = partial[0];
  for (int c = 1; c < chunks; ++c) U += partial[c];
  TrussAD::Gradient g;
  TrussAD::Stiffness K;
  TrussAD::extract(U, ad, nullptr, &g, &K);
  out.residual += g;
  out.K += K;
}

ElementEnergy SuperTrussElement::energy(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  std::vector<Vec3> p, pd, w;
  node_kinematics<double>(s, s[0].vel, s[1].vel, s[2].vel, s[3].vel, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(),
                          Vec3::Zero(), &p, pd, nullptr, w, nullptr);
  ElementEnergy e;
  for (const MassPair& mp : mass_pairs_) e.kinetic += 0.5 * mp.m * pd[mp.a].dot(pd[mp.b]);
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    e.kinetic += 0.5 * w[n].dot(node_rotary_[n] * w[n]);
    e.gravity_potential -= node_weight_[n] * ctx.gravity.dot(p[n]);
  }
  e.strain = strain_energy<double>(s[0].pos, s[1].rot, s[2].pos, s[3].rot);
  return e;
}

void SuperTrussElement::node_poses(std::span<const SlotState<double>> s, std::vector<Vec3>& p, std::vector<Mat3>& R) const {
  node_map<double>(s[0].pos, s[1].rot, s[2].pos, s[3].rot, p, R);
}

std::vector<double> SuperTrussElement::member_axial_forces(std::span<const SlotState<double>> s) const {
  std::vector<Vec3> p;
  std::vector<Mat3> R;
  node_poses(s, p, R);
  std::vector<double> out;
  for (const MemberData& m : members_) {
    const BeamProperties& b = m.beam->properties();
    out.push_back(b.material.youngs_modulus * b.section.area * ((p[m.b] - p[m.a]).norm() - b.length) / b.length);
  }
  return out;
}

std::vector<Vec3> SuperTrussElement::node_velocities(std::span<const SlotState<double>> s) const {
  std::vector<Eigen::Matrix<double, 3, 12>> Jp, Jw;
  node_jacobians<double>(s, Jp, Jw);
  Eigen::Matrix<double, 12, 1> dq;
  dq << s[0].vel, s[1].vel, s[2].vel, s[3].vel;
  std::vector<Vec3> out;
  for (const auto& J : Jp) out.push_back(J * dq);
  return out;
}

std::vector<Vec3> SuperTrussElement::axis_points(std::span<const SlotState<double>> s, const ElementContext&) const {
  return {s[0].pos, s[2].pos};
}

std::vector<std::vector<Vec3>> SuperTrussElement::axis_polylines(std::span<const SlotState<double>> s,
                                                                 const ElementContext& ctx) const {
  std::vector<Vec3> p;
  std::vector<Mat3> R;
  node_poses(s, p, R);
  std::vector<std::vector<Vec3>> out;
  std::vector<SlotState<double>> ends(4);
  for (const MemberData& m : members_) {
    ends[0].pos = p[m.a];
    ends[1].rot = R[m.a] * m.offset_a;
    ends[2].pos = p[m.b];
    ends[3].rot = R[m.b] * m.offset_b;
    out.push_back(m.beam->axis_points(ends, ctx));
  }
  return out;
}

}  // namespace latticedyn
