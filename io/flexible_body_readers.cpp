// Beams and ropes from YAML: the member's nodes (translation, section rotation, stretch or axis
// slope blocks), its n elements, and the joints at its ends and at named nodes.
#include "io/flexible_body_readers.hpp"

#include "assembly/member_builder.hpp"
#include "elements/rope.hpp"
#include "io/rope_shape.hpp"

#include <cmath>
#include <stdexcept>

namespace latticedyn {

namespace {

struct MemberGeometry {
  Vec3 start, end;
  int elements = 1;
  double length() const { return (end - start).norm(); }
  Vec3 node(int k) const { return member_point(start, end, k, elements); }
};

MemberGeometry read_geometry(const InputNode& n) {
  MemberGeometry g;
  const InputNode ends = n["ends"];
  const auto e = ends.items();
  if (e.size() != 2) ends.fail("expected the two end positions [[x1, y1, z1], [x2, y2, z2]]");
  g.start = e[0].as_vec3();
  g.end = e[1].as_vec3();
  if (g.length() == 0.0) ends.fail("the two ends coincide: a member needs a non-zero length axis");
  g.elements = n.get_int("elements", 1);
  if (g.elements < 1 || g.elements > 100000) n["elements"].fail("expected a number of elements from 1 to 100000");
  return g;
}

// Section frame: x along the axis, z the part of `up` across it (default global z, or global y
// for a member along z), y = z x x.
Mat3 section_frame(const InputNode& n, const MemberGeometry& g) {
  const Vec3 x = (g.end - g.start).normalized();
  Vec3 up = std::abs(x.z()) < 0.999 ? Vec3::UnitZ() : Vec3::UnitY();
  if (auto u = n.get("up")) {
    up = u->as_vec3();
    if (up.cross(x).norm() < 1e-6 * up.norm()) u->fail("'up' must not be parallel to the member's axis");
  }
  const Vec3 z = (up - up.dot(x) * x).normalized();
  Mat3 R;
  R << x, z.cross(x), z;
  return R;
}

// The joints "1" and "2" at the ends and the ones listed under `joints` at interior nodes;
// a rotation block of -1 makes translation-only joints (ropes).
void add_member_joints(ReaderContext& ctx, const InputNode& n, const std::string& name, const MemberGeometry& g,
                       const std::vector<int>& translation, const std::vector<int>& rotation,
                       const Mat3& section_frame_inverse) {
  auto joint_at = [&](int k, const Mat3& frame) {
    Joint j;
    j.translation_block = translation[k];
    j.rotation_block = rotation.empty() ? -1 : rotation[k];
    j.frame = rotation.empty() ? frame : Mat3(section_frame_inverse * frame);
    return j;
  };
  ctx.add_joint(n["ends"], name, "1", joint_at(0, Mat3::Identity()));
  ctx.add_joint(n["ends"], name, "2", joint_at(g.elements, Mat3::Identity()));
  if (auto joints = n.get("joints")) {
    for (const InputNode& j : joints->items()) {
      j.allow_only({"name", "node", "rotation", "rotation_deg", "axis_angle", "cardan_zyx_deg"});
      const int k = j["node"].as_int();
      if (k < 0 || k > g.elements)
        j["node"].fail("expected a node index from 0 to " + std::to_string(g.elements) + " (the member has " +
                       std::to_string(g.elements) + " elements)");
      ctx.add_joint(j, name, j["name"].as_string(), joint_at(k, ReaderContext::orientation(j)));
    }
  }
}

// Rigid initial velocity of the member: v(r) = velocity + omega x (r - start); the sections turn
// with omega (given in the inertial frame; the rotation blocks take it in body axes).
struct InitialRates {
  Vec3 velocity = Vec3::Zero(), omega = Vec3::Zero();
};

InitialRates read_rates(const InputNode& n) {
  return InitialRates{n.get_vec3("velocity", Vec3::Zero()), n.get_vec3("angular_velocity", Vec3::Zero())};
}

}  // namespace

void read_beam(ReaderContext& ctx, const InputNode& n, const std::string& name, const std::string& type) {
  const bool spline = type == "cubic_spline_beam";
  if (spline)
    n.allow_only({"name", "type", "material", "section", "ends", "elements", "up", "gauss_points", "velocity",
                  "angular_velocity", "joints", "damping"});
  else
    n.allow_only({"name", "type", "material", "section", "ends", "elements", "up", "shear_coefficient", "velocity",
                  "angular_velocity", "joints", "damping"});
  const MemberGeometry g = read_geometry(n);
  BeamProperties beam;
  beam.material = ctx.body_material(n);
  beam.section = ctx.section(n["section"]);
  beam.length = g.length() / g.elements;
  beam.shear_coefficient = n.get_positive("shear_coefficient", 0.0);
  const MemberElement kind = spline ? MemberElement::cubic_spline_beam : MemberElement::timoshenko_beam;
  int gauss_points = 5;
  if (auto k = n.get("gauss_points")) {
    gauss_points = k->as_int();
    if (gauss_points < 1 || gauss_points > 64) k->fail("expected 1 to 64 Gauss points");
  }
  std::shared_ptr<const Element> element;
  try {
    element = make_beam_element(kind, beam, gauss_points);
  } catch (const std::invalid_argument& e) {
    n.fail(e.what());
  }
  const Mat3 R0 = section_frame(n, g);
  const InitialRates rates = read_rates(n);
  const int body = ctx.builder.add_body(name, type);
  ctx.bodies[name] = BodyRecord{body, type, {}};
  std::vector<MemberNode> nodes;
  std::vector<int> t, r;
  for (int k = 0; k <= g.elements; ++k) {
    const std::string label = name + ".node" + std::to_string(k);
    const Vec3 v = rates.velocity + rates.omega.cross(g.node(k) - g.start);
    MemberNode& node = nodes.emplace_back();
    node.translation = ctx.builder.add_block(DofBlock::translation(g.node(k), v, label));
    node.orientation = ctx.builder.add_block(DofBlock::rotation(R0, R0.transpose() * rates.omega, label));
    if (spline) node.stretch = ctx.builder.add_block(DofBlock::scalar(1.0, 0.0, label));
    t.push_back(node.translation);
    r.push_back(node.orientation);
  }
  add_member_elements(ctx.builder, body, kind, element, nodes);
  add_member_joints(ctx, n, name, g, t, r, R0.transpose());
}

void read_rope(ReaderContext& ctx, const InputNode& n, const std::string& name) {
  n.allow_only({"name", "type", "material", "section", "ends", "elements", "rest_length", "rest_length_drive",
                "initial_sag", "gauss_points", "velocities", "joints", "damping"});
  const MemberGeometry g = read_geometry(n);
  RopeProperties p;
  p.material = ctx.body_material(n);
  if (p.material.damping.alpha != 0)
    (n.has("damping") ? n["damping"] : n["material"])
        .fail("a rope takes stiffness-proportional damping only (beta, or a ratio at one frequency), not alpha: alpha "
              "would drag the load's swing through the rope's mass");
  p.section = ctx.section(n["section"]);
  double L0 = g.length();
  if (n.has("rest_length") && n.has("rest_length_drive"))
    n["rest_length_drive"].fail("give either rest_length or rest_length_drive, not both");
  if (auto d = n.get("rest_length_drive")) {
    const int drive_index = ctx.drive(*d);
    const Drive& drive = ctx.builder.peek().drives[drive_index];
    ctx.driven_rest_lengths.push_back({*d, drive_index, 1.0});
    p.drive = drive;
    p.fraction = 1.0 / g.elements;
    L0 = drive.evaluate(0.0).value;
    if (!(L0 > 0)) d->fail("the drive gives a rest length of " + std::to_string(L0) + " m at t = 0; expected > 0");
  } else {
    L0 = n.get_positive("rest_length", L0);
    p.rest_length = L0 / g.elements;
  }
  if (auto k = n.get("gauss_points")) {
    p.gauss_points = k->as_int();
    if (p.gauss_points < 1 || p.gauss_points > 64) k->fail("expected 1 to 64 Gauss points");
  }
  std::shared_ptr<const Element> element;
  try {
    element = std::make_shared<Rope>(p);
  } catch (const std::invalid_argument& e) {
    n.fail(e.what());
  }
  // Initial shape: straight, or a parabola sagging across the chord towards gravity in tension.
  const double D = g.length();
  const Vec3 chord = (g.end - g.start) / D;
  const Vec3 gravity = ctx.builder.peek().gravity;
  Vec3 across = gravity - gravity.dot(chord) * chord;
  if (across.norm() < 1e-9 * std::max(1.0, gravity.norm())) across = chord.unitOrthogonal();
  across.normalize();
  std::optional<double> sag;
  if (n.has("initial_sag")) sag = n["initial_sag"].as_non_negative();
  const double weight = p.section.effective_density(p.material) * p.section.area * gravity.norm();
  const RopeShape shape = rope_initial_shape(g.start, g.end, L0, g.elements, across, weight,
                                             p.material.youngs_modulus * p.section.area, sag);
  // End velocities, interpolated linearly along the rope (the slopes change at (v2 - v1) / L0).
  const auto [v1, v2] = ReaderContext::end_velocities(n);
  const int body = ctx.builder.add_body(name, "rope");
  ctx.bodies[name] = BodyRecord{body, "rope", {}};
  std::vector<MemberNode> nodes;
  std::vector<int> t;
  for (int k = 0; k <= g.elements; ++k) {
    const std::string label = name + ".node" + std::to_string(k);
    MemberNode& node = nodes.emplace_back();
    node.translation = ctx.builder.add_block(
        DofBlock::translation(shape.positions[k], member_point(v1, v2, k, g.elements), label));
    node.orientation = ctx.builder.add_block(DofBlock::vector(shape.slopes[k], (v2 - v1) / L0, label + ".slope"));
    t.push_back(node.translation);
  }
  add_member_elements(ctx.builder, body, MemberElement::rope, element, nodes);
  add_member_joints(ctx, n, name, g, t, {}, Mat3::Identity());
}

}  // namespace latticedyn
