// Rigid bodies (3.1, Tables D-2, D-5, D-12) and strut ties (3.2, Table D-8) from YAML.
#include "io/body_readers.hpp"

#include "io/flexible_body_readers.hpp"
#include "io/lattice_readers.hpp"

#include "elements/rigid_body.hpp"
#include "elements/strut_tie.hpp"
#include "io/hydraulic_readers.hpp"

#include <stdexcept>

namespace latticedyn {

namespace {

// Custom mass properties, or a homogeneous cylinder along x from a round-tube section, length
// and material (Table D-12's load).
RigidBodyProperties read_mass_properties(const ReaderContext& ctx, const InputNode& n) {
  RigidBodyProperties p;
  if (n.has("section") || n.has("length")) {
    for (const char* k : {"mass", "inertia", "centroid"})
      if (n.has(k)) n[k].fail("give either mass/inertia/centroid or section/material/length, not both");
    const SectionProperties s = ctx.section(n["section"]);
    if (s.shape != SectionProperties::Shape::round_tube)
      n["section"].fail("a rigid body built from a section needs a round_tube section (a cylinder along x)");
    const Material m = ctx.material(n["material"]);
    p = cylinder_body(m.density, n["length"].as_positive(), s.outer_radius, s.inner_radius);
    p.damping_alpha = m.damping.alpha;  // a rigid body has no stiffness for the material's beta
    return p;
  }
  if (n.has("material")) n["material"].fail("a material applies to a rigid body built from section and length, not to one with mass and inertia");
  p.mass = n["mass"].as_positive();
  p.centroid = n.get_vec3("centroid", Vec3::Zero());
  const InputNode in = n["inertia"];
  if (in.is_sequence() && in.items().size() == 3 && in.items()[0].is_scalar())
    p.inertia_centroid = in.as_vec3().asDiagonal();
  else
    p.inertia_centroid = in.as_mat3();
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    in.fail(e.what());
  }
  return p;
}

void read_rigid_body(ReaderContext& ctx, const InputNode& n, const std::string& name) {
  n.allow_only({"name", "type", "mass", "inertia", "centroid", "section", "material", "length", "position", "rotation",
                "rotation_deg", "axis_angle", "cardan_zyx_deg", "velocity", "angular_velocity", "joints", "draw",
                "damping"});
  RigidBodyProperties props = read_mass_properties(ctx, n);
  if (auto d = n.get("damping")) {
    const RayleighDamping damping = read_damping(*d);
    if (damping.beta > 0) d->fail("a rigid body has no stiffness to damp: give alpha (1/s), the mass-proportional part");
    props.damping_alpha = damping.alpha;
  }
  const int body = ctx.builder.add_body(name, "rigid_body");
  ctx.bodies[name] = BodyRecord{body, "rigid_body", {}};
  const int t = ctx.builder.add_block(DofBlock::translation(n.get_vec3("position", Vec3::Zero()), n.get_vec3("velocity", Vec3::Zero()), name));
  const int r = ctx.builder.add_block(
      DofBlock::rotation(ReaderContext::orientation(n), n.get_vec3("angular_velocity", Vec3::Zero()), name));
  ctx.builder.add_element(body, std::make_shared<RigidBody>(props), {{t}, {r}});

  std::vector<int> order;
  if (auto joints = n.get("joints")) {
    int index = 1;
    for (const InputNode& j : joints->items()) {
      j.allow_only({"name", "position", "rotation", "rotation_deg", "axis_angle", "cardan_zyx_deg"});
      Joint joint;
      joint.translation_block = t;
      joint.rotation_block = r;
      joint.offset = j.get_vec3("position", Vec3::Zero());
      joint.frame = ReaderContext::orientation(j);
      const std::string jname = j.get_string("name", std::to_string(index));
      ctx.add_joint(j, name, jname, joint);
      order.push_back(static_cast<int>(order.size()));
      ++index;
    }
  }
  if (auto draw = n.get("draw")) {
    std::vector<int> seq;
    const BodyRecord& rec = ctx.bodies.at(name);
    const auto& body_joints = ctx.builder.peek().bodies[body].joints;
    for (const InputNode& d : draw->items()) {
      const std::string jn = d.as_string();
      const auto it = rec.joints.find(jn);
      if (it == rec.joints.end()) d.fail("body '" + name + "' has no joint '" + jn + "' to draw");
      for (std::size_t k = 0; k < body_joints.size(); ++k)
        if (body_joints[k] == it->second) seq.push_back(static_cast<int>(k));
    }
    ctx.builder.set_draw_sequence(body, seq);
  }
}

void read_strut_tie(ReaderContext& ctx, const InputNode& n, const std::string& name) {
  n.allow_only({"name", "type", "material", "section", "ends", "rest_length", "smoothing", "velocities", "damping"});
  StrutTieProperties p;
  p.material = ctx.body_material(n);
  p.section = ctx.section(n["section"]);
  const InputNode ends = n["ends"];
  const auto e = ends.items();
  if (e.size() != 2) ends.fail("expected the two end positions [[x1, y1, z1], [x2, y2, z2]]");
  const Vec3 r1 = e[0].as_vec3(), r2 = e[1].as_vec3();
  if ((r2 - r1).norm() == 0.0) ends.fail("the two ends coincide: a strut tie needs a non-zero length axis");
  p.rest_length = n.get_positive("rest_length", (r2 - r1).norm());
  p.smoothing = n.get_non_negative("smoothing", 0.0);
  const auto [v1, v2] = ReaderContext::end_velocities(n);
  const int body = ctx.builder.add_body(name, "strut_tie");
  ctx.bodies[name] = BodyRecord{body, "strut_tie", {}};
  const int t1 = ctx.builder.add_block(DofBlock::translation(r1, v1, name + ".1"));
  const int t2 = ctx.builder.add_block(DofBlock::translation(r2, v2, name + ".2"));
  ctx.builder.add_element(body, std::make_shared<StrutTie>(p), {{t1}, {t2}});
  // The thesis puts a joint at each end of a flexible element: "name.1" and "name.2".
  Joint j;
  j.translation_block = t1;
  ctx.add_joint(ends, name, "1", j);
  j.translation_block = t2;
  ctx.add_joint(ends, name, "2", j);
}

}  // namespace

void read_ground(ReaderContext& ctx, const InputNode& n) {
  n.allow_only({"joints"});
  if (auto joints = n.get("joints")) {
    int index = 1;
    for (const InputNode& j : joints->items()) {
      j.allow_only({"name", "position", "rotation", "rotation_deg", "axis_angle", "cardan_zyx_deg"});
      const std::string jname = j.get_string("name", std::to_string(index++));
      if (jname.empty() || jname.find('.') != std::string::npos) j.fail("joint names must be non-empty and contain no '.'");
      BodyRecord& ground = ctx.bodies.at("ground");
      if (ground.joints.count(jname)) j.fail("the ground has two joints named '" + jname + "'");
      ground.joints[jname] = ctx.builder.add_ground_joint("ground." + jname, j.get_vec3("position", Vec3::Zero()),
                                                          ReaderContext::orientation(j));
    }
  }
}

void read_body(ReaderContext& ctx, const InputNode& n) {
  const InputNode name_node = n["name"];
  const std::string name = name_node.as_string();
  if (name.empty() || name.find('.') != std::string::npos) name_node.fail("body names must be non-empty and contain no '.'");
  if (ctx.bodies.count(name)) name_node.fail("a body named '" + name + "' exists already");
  std::string type =
      n["type"].as_choice({"rigid_body", "strut_tie", "timoshenko_beam", "cubic_spline_beam", "rope", "lattice", "super_truss",
                           "hydraulic_cylinder"});
  if ((type == "lattice" || type == "super_truss") && !ctx.truss_bodies.empty()) type = ctx.truss_bodies;
  try {
    if (type == "rigid_body") read_rigid_body(ctx, n, name);
    if (type == "strut_tie") read_strut_tie(ctx, n, name);
    if (type == "timoshenko_beam" || type == "cubic_spline_beam") read_beam(ctx, n, name, type);
    if (type == "rope") read_rope(ctx, n, name);
    if (type == "lattice") read_lattice(ctx, n, name);
    if (type == "super_truss") read_super_truss(ctx, n, name);
    if (type == "hydraulic_cylinder") read_hydraulic_cylinder(ctx, n, name);
  } catch (const std::invalid_argument& e) {
    n.fail(e.what());
  }
}

}  // namespace latticedyn
