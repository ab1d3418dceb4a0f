// Small models built in code for the assembly tests: every constraint type, loads in both
// frames, a driven joint, strut ties, shared nodes, rotations far from the reference.
#pragma once

#include "assembly/lattice_builder.hpp"
#include "assembly/model_builder.hpp"
#include "core/rotation.hpp"
#include "elements/rope.hpp"
#include "elements/cubic_spline_beam.hpp"
#include "elements/rigid_body.hpp"
#include "elements/strut_tie.hpp"
#include "elements/timoshenko_beam.hpp"

#include <memory>

namespace latticedyn::testing {

inline RigidBodyProperties box_properties(double mass) {
  RigidBodyProperties p;
  p.mass = mass;
  p.centroid = Vec3(0.5, 0.05, -0.02);
  p.inertia_centroid = Vec3(0.2, 0.5, 0.6).asDiagonal();
  return p;
}

struct BodyBlocks {
  int body, t, r;
};

inline BodyBlocks add_rigid_body(ModelBuilder& b, const std::string& name, double mass, const Vec3& pos, const Vec3& phi,
                                 const Vec3& v = Vec3::Zero(), const Vec3& w = Vec3::Zero()) {
  BodyBlocks out;
  out.body = b.add_body(name, "rigid_body");
  out.t = b.add_block(DofBlock::translation(pos, v, name));
  out.r = b.add_block(DofBlock::rotation(rotation_matrix(phi), w, name));
  b.add_element(out.body, std::make_shared<RigidBody>(box_properties(mass)), {{out.t}, {out.r}});
  return out;
}

inline int add_body_joint(ModelBuilder& b, const BodyBlocks& body, const std::string& name, const Vec3& offset,
                          const Mat3& frame = Mat3::Identity()) {
  Joint j;
  j.name = b.peek().bodies[body.body].name + "." + name;
  j.translation_block = body.t;
  j.rotation_block = body.r;
  j.offset = offset;
  j.frame = frame;
  return b.add_joint(body.body, j);
}

struct StrutBlocks {
  int body, t1, t2, j1, j2;
};

inline StrutBlocks add_strut(ModelBuilder& b, const std::string& name, const Vec3& p1, const Vec3& p2, double E = 1e7) {
  StrutBlocks out;
  out.body = b.add_body(name, "strut_tie");
  out.t1 = b.add_block(DofBlock::translation(p1, Vec3::Zero(), name + ".1"));
  out.t2 = b.add_block(DofBlock::translation(p2, Vec3::Zero(), name + ".2"));
  StrutTieProperties p;
  p.material = Material{7800.0, E, 0.3, {}, 0.0};
  p.section = round_tube_section(0.02, 0.0);
  p.rest_length = (p2 - p1).norm();
  p.smoothing = 1e-3;
  b.add_element(out.body, std::make_shared<StrutTie>(p), {{out.t1}, {out.t2}});
  Joint j;
  j.name = name + ".1";
  j.translation_block = out.t1;
  out.j1 = b.add_joint(out.body, j);
  j.name = name + ".2";
  j.translation_block = out.t2;
  out.j2 = b.add_joint(out.body, j);
  return out;
}

/// A flexible chain hung on a joint: a Timoshenko beam welded to it, a cubic spline beam sharing
/// the beam's end node with its frame turned (slot offsets), a rope from there to the ground.
inline void add_flexible_chain(ModelBuilder& b, int attach_joint, int ground_joint) {
  const Material soft{2000.0, 5e6, 0.3, {}, 0.0};
  const SectionProperties tube = round_tube_section(0.03, 0.02);
  const Vec3 p0 = Vec3(1.5, 1.0, 0.2) + Vec3(0.3, 0.1, 0.0), p1 = p0 + Vec3(0.6, 0.2, -0.1), p2 = p1 + Vec3(0.1, 0.5, 0.2);
  const Mat3 R01 = rotation_matrix<double>(Vec3(0.2, -0.3, 0.1)), R12 = rotation_matrix<double>(Vec3(-0.4, 0.2, 0.5));
  const int body = b.add_body("flex", "timoshenko_beam");
  const int t0 = b.add_block(DofBlock::translation(p0, Vec3(0.1, 0, 0), "flex.0"));
  const int r0 = b.add_block(DofBlock::rotation(R01, Vec3(0.2, 0.1, 0), "flex.0"));
  const int t1 = b.add_block(DofBlock::translation(p1, Vec3(0, 0.2, 0), "flex.1"));
  const int r1 = b.add_block(DofBlock::rotation(R01, Vec3(0, -0.1, 0.3), "flex.1"));
  // The beam's frame x runs from p0 to p1 in the slots' frames: offsets from the node blocks.
  const Mat3 beam_frame = rotation_matrix<double>(Vec3::UnitX().cross((p1 - p0).normalized()).normalized() *
                                                  std::acos(Vec3::UnitX().dot((p1 - p0).normalized())));
  const Mat3 off = R01.transpose() * beam_frame;
  b.add_element(body, std::make_shared<TimoshenkoBeam>(BeamProperties{soft, tube, (p1 - p0).norm(), 0.0}),
                {{t0}, {r0, off}, {t1}, {r1, off}});
  // Cubic spline beam from the beam's end node (a node shared at an angle) to a new node.
  const Mat3 spline_frame = rotation_matrix<double>(Vec3::UnitX().cross((p2 - p1).normalized()).normalized() *
                                                    std::acos(Vec3::UnitX().dot((p2 - p1).normalized())));
  const int t2 = b.add_block(DofBlock::translation(p2, Vec3(0, 0, 0.1), "flex.2"));
  const int r2 = b.add_block(DofBlock::rotation(R12, Vec3(0.1, 0, 0), "flex.2"));
  const int s1 = b.add_block(DofBlock::scalar(1.01, 0.02, "flex.s1"));
  const int s2 = b.add_block(DofBlock::scalar(0.99, -0.01, "flex.s2"));
  b.add_element(body, std::make_shared<CubicSplineBeam>(CubicSplineBeamProperties{BeamProperties{soft, tube, (p2 - p1).norm(), 0.0}, 3}),
                {{t1}, {r1, R01.transpose() * spline_frame}, {s1}, {t2}, {r2, R12.transpose() * spline_frame}, {s2}});
  // A rope from the spline's end to the ground joint, slightly stretched.
  RopeProperties rope;
  rope.material = Material{1000.0, 1e6, 0.3, {}, 0.0};
  rope.section = round_tube_section(0.01, 0.0);
  const Vec3 pg = b.peek().blocks[b.peek().joints[ground_joint].translation_block].position0;
  rope.rest_length = 0.98 * (pg - p2).norm();
  const int v2 = b.add_block(DofBlock::vector((pg - p2) / rope.rest_length + Vec3(0.01, 0, 0), Vec3(0, 0.05, 0), "flex.slope2"));
  const int tg = b.add_block(DofBlock::translation(pg, Vec3::Zero(), "flex.g"));
  const int vg = b.add_block(DofBlock::vector((pg - p2) / rope.rest_length, Vec3(0.02, 0, 0), "flex.slopeg"));
  b.add_element(body, std::make_shared<Rope>(rope), {{t2}, {v2}, {tg}, {vg}});
  Joint j0;
  j0.name = "flex.0";
  j0.translation_block = t0;
  j0.rotation_block = r0;
  const int jf = b.add_joint(body, j0);
  Joint jg;
  jg.name = "flex.g";
  jg.translation_block = tg;
  const int jr = b.add_joint(body, jg);
  Constraint weld;
  weld.name = "flex_weld";
  weld.type = ConstraintType::spherical;
  weld.joint1 = attach_joint;
  weld.joint2 = jf;
  b.add_constraint(weld, false);
  Constraint anchor;
  anchor.name = "flex_anchor";
  anchor.type = ConstraintType::spherical;
  anchor.joint1 = ground_joint;
  anchor.joint2 = jr;
  b.add_constraint(anchor, true);
}

/// A force and a moment on `joint` that turn with its frame (LoadFrame::body for both).
inline NodalLoad follower_load(const std::string& name, int joint, const Vec3& force, const Vec3& moment) {
  NodalLoad l;
  l.name = name;
  l.joint = joint;
  l.force = force;
  l.force_frame = LoadFrame::body;
  l.moment = moment;
  l.moment_frame = LoadFrame::body;
  return l;
}

/// A mechanism using everything the assembly supports: four rigid bodies chained by a driven
/// revolute, a spherical, a prismatic and a fixed joint, two strut ties (one attached by
/// multipliers, one by a shared node), loads in the inertial and the body frame, and a flexible
/// chain of a Timoshenko beam, a cubic spline beam and a rope with vector and scalar blocks.
inline Model kitchen_sink_model() {
  ModelBuilder b;
  b.set_gravity(Vec3(0, 0, -9.81));
  const int g0 = b.add_ground_joint("ground.o", Vec3::Zero(), rotation_matrix<double>(Vec3(0.3, 0, 0)));
  const int g1 = b.add_ground_joint("ground.p", Vec3(2.0, 0.5, 0.0), Mat3::Identity());
  const auto A = add_rigid_body(b, "a", 2.0, Vec3::Zero(), Vec3(0.3, 0, 0), Vec3(0.1, 0, 0), Vec3(0.2, -0.1, 0.3));
  const auto B = add_rigid_body(b, "b", 3.0, Vec3(1.0, 0, 0), Vec3(0.1, 0.2, -0.3));
  const auto C = add_rigid_body(b, "c", 1.5, Vec3(1.0, 1.0, 0.0), Vec3(-0.2, 0.1, 0.4));
  const auto D = add_rigid_body(b, "d", 1.0, Vec3(1.5, 1.0, 0.2), Vec3(0.0, 0.0, 0.0));
  const int a0 = add_body_joint(b, A, "0", Vec3::Zero());
  const int a1 = add_body_joint(b, A, "1", Vec3(1.0, 0, 0));
  const int b0 = add_body_joint(b, B, "0", Vec3::Zero(), rotation_matrix<double>(Vec3(0, 0.2, 0)));
  const int b1 = add_body_joint(b, B, "1", Vec3(0, 1.0, 0));
  const int c0 = add_body_joint(b, C, "0", Vec3::Zero());
  const int c1 = add_body_joint(b, C, "1", Vec3(0.5, 0, 0.2));
  const int d0 = add_body_joint(b, D, "0", Vec3::Zero());
  const int d1 = add_body_joint(b, D, "1", Vec3(0.3, 0.1, 0));
  b.add_drive("spin", Drive(Drive::CosineStep{0.0, 1.0, 0.0, 0.5}));

  auto con = [&](const char* name, ConstraintType type, int axis, int j1, int j2, int drive = -1) {
    Constraint c;
    c.name = name;
    c.type = type;
    c.axis = axis;
    c.joint1 = j1;
    c.joint2 = j2;
    c.drive = drive;
    return c;
  };
  b.add_constraint(con("hinge", ConstraintType::revolute, 2, g0, a0, 0), false);
  b.add_constraint(con("ball", ConstraintType::spherical, 0, a1, b0), false);
  b.add_constraint(con("slider", ConstraintType::prismatic, 1, b1, c0), false);
  b.add_constraint(con("weld", ConstraintType::fixed, 0, c1, d0), false);
  const auto S = add_strut(b, "tie", Vec3(2.0, 0.5, 0.0), Vec3(1.8, 1.1, 0.2));
  b.add_constraint(con("tie_ground", ConstraintType::spherical, 0, g1, S.j1), true);  // shared: fixed node
  b.add_constraint(con("tie_d", ConstraintType::spherical, 0, S.j2, d1), false);
  const auto S2 = add_strut(b, "tie2", Vec3(1.8, 1.1, 0.2), Vec3(1.0, 1.0, 0.0));
  b.add_constraint(con("tie2_tie", ConstraintType::spherical, 0, S.j2, S2.j1), true);  // shared free node
  b.add_constraint(con("tie2_c", ConstraintType::spherical, 0, S2.j2, c0), false);

  add_flexible_chain(b, d1, b.add_ground_joint("ground.q", Vec3(2.5, 2.0, -0.5), Mat3::Identity()));

  b.add_load(follower_load("push", d1, Vec3(1.0, -2.0, 0.5), Vec3(0.3, 0.1, -0.2)));
  NodalLoad g;
  g.name = "pull";
  g.joint = a1;
  g.force = Vec3(0.0, 0.0, 5.0);
  g.moment = Vec3(0.5, 0.0, 0.0);
  g.drive = 0;
  b.add_load(g);
  return b.build();
}

/// A 5 m steel lattice section of rectangular cross-section (1.5 x 1.4 m), order 2.
inline TrussSectionSpec rectangular_section() {
  TrussSectionSpec s = rectangular_truss_section(5.0, 2, 0.75, 0.7);
  s.material = Material{7800, 2.06e11, 0.3, {}, 0.0};
  s.main_section = s.cross_section = round_tube_section(0.1, 0.08);
  s.sub_section = round_tube_section(0.05, 0.04);
  return s;
}

/// A lattice section of Timoshenko members clamped at its first end by shared fixed joints, with a
/// follower load at its far end: every unknown a translation or rotation block, no multipliers (the
/// models create_matrix can hold in 3 x 3 blocks).
inline Model clamped_lattice_model() {
  ModelBuilder b;
  b.set_gravity(Vec3(0, 0, -9.81));
  const TrussSectionSpec s = rectangular_section();
  const TrussGeometry g = build_truss_geometry(s);
  FullLatticeOptions o;
  o.rigid_ends = false;
  const FullLattice l = add_full_lattice(b, "lattice", s, g, o);
  int far = -1;
  for (const auto& [name, joint] : l.joints) {
    if (name == "e2n1") far = joint;
    if (name.rfind("e1n", 0) != 0) continue;
    const Joint& j = b.peek().joints[joint];
    const DofBlock& t = b.peek().blocks[j.translation_block];
    const DofBlock& r = b.peek().blocks[j.rotation_block];
    const int ground = b.add_ground_joint("ground." + name, t.position0, r.orientation0 * j.frame);
    b.add_constraint(Constraint{"clamp." + name, ConstraintType::fixed, 0, ground, joint, -1}, true);
  }
  b.add_load(follower_load("follower", far, Vec3(1e4, -2e4, 5e3), Vec3(3e3, 1e3, -2e3)));
  return b.build();
}

}  // namespace latticedyn::testing
