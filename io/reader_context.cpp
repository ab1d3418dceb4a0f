// Named references, materials, sections and orientations of the model format.
#include "io/reader_context.hpp"

#include "core/rotation.hpp"

#include <numbers>
#include <stdexcept>

namespace latticedyn {

RayleighDamping read_damping(const InputNode& n) {
  n.allow_only({"alpha", "beta", "ratio", "frequency"});
  const bool coefficients = n.has("alpha") || n.has("beta");
  if (coefficients && (n.has("ratio") || n.has("frequency")))
    n.fail("give either alpha and beta, or ratio and frequency, not both");
  if (coefficients) return RayleighDamping{n.get_non_negative("alpha", 0.0), n.get_non_negative("beta", 0.0)};
  const InputNode ratio = n["ratio"], frequency = n["frequency"];
  constexpr double two_pi = 2.0 * std::numbers::pi;
  if (!ratio.is_sequence()) {
    if (frequency.is_sequence()) frequency.fail("expected one frequency in Hz for one damping ratio");
    return rayleigh_from_ratio(ratio.as_non_negative(), two_pi * frequency.as_positive());
  }
  const auto zs = ratio.items(), fs = frequency.items();
  if (zs.size() != 2) ratio.fail("expected one damping ratio, or two [zeta1, zeta2] for two frequencies");
  if (!frequency.is_sequence() || fs.size() != 2) frequency.fail("expected two frequencies [f1, f2] in Hz for two damping ratios");
  try {
    return rayleigh_from_ratios(zs[0].as_non_negative(), two_pi * fs[0].as_positive(), zs[1].as_non_negative(),
                                two_pi * fs[1].as_positive());
  } catch (const std::invalid_argument& e) {
    n.fail(e.what());
  }
}

Material read_material(const InputNode& n) {
  n.allow_only({"density", "youngs_modulus", "poisson_ratio", "damping", "yield_stress"});
  Material m;
  m.density = n["density"].as_positive();
  m.youngs_modulus = n["youngs_modulus"].as_positive();
  const InputNode nu = n["poisson_ratio"];
  m.poisson_ratio = nu.as_double();
  if (!(m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5)) nu.fail("expected a Poisson ratio in (-1, 0.5)");
  if (auto d = n.get("damping")) m.damping = read_damping(*d);
  m.yield_stress = n.get_positive("yield_stress", 0.0);
  return m;
}

SectionProperties read_section(const InputNode& n) {
  const std::string type = n["type"].as_choice({"round_tube", "frame", "custom"});
  if (type == "round_tube") {
    n.allow_only({"type", "outer_radius", "inner_radius"});
    const double ro = n["outer_radius"].as_positive();
    const double ri = n.get_non_negative("inner_radius", 0.0);
    if (ri >= ro) n["inner_radius"].fail("inner radius must be smaller than the outer radius");
    return round_tube_section(ro, ri);
  }
  if (type == "frame") {
    n.allow_only({"type", "height", "width", "thickness"});
    return frame_section(n["height"].as_positive(), n["width"].as_positive(), n["thickness"].as_positive());
  }
  n.allow_only({"type", "area", "Iy", "Iz", "torsion_constant", "shear_coefficient", "mass_per_length", "fibre_y", "fibre_z"});
  SectionProperties s = custom_section(n["area"].as_positive(), n["Iy"].as_positive(), n["Iz"].as_positive(),
                                       n["torsion_constant"].as_positive(), n.get_positive("shear_coefficient", 5.0 / 6.0));
  s.mass_per_length = n.get_positive("mass_per_length", 0.0);
  if (n.has("fibre_y") != n.has("fibre_z")) n.fail("give both fibre_y and fibre_z (the outermost fibres' distances), or neither");
  s.fibre_y = n.get_positive("fibre_y", 0.0);
  s.fibre_z = n.get_positive("fibre_z", 0.0);
  return s;
}

Material ReaderContext::material(const InputNode& n) const {
  if (n.is_map()) return read_material(n);
  const std::string name = n.as_string();
  const auto it = materials.find(name);
  if (it == materials.end()) n.fail("no material named '" + name + "' (define it under 'materials')");
  return it->second;
}

Material ReaderContext::body_material(const InputNode& body) const {
  Material m = material(body["material"]);
  if (auto d = body.get("damping")) m.damping = read_damping(*d);
  return m;
}

SectionProperties ReaderContext::section(const InputNode& n) const {
  if (n.is_map()) return read_section(n);
  const std::string name = n.as_string();
  const auto it = sections.find(name);
  if (it == sections.end()) n.fail("no section named '" + name + "' (define it under 'sections')");
  return it->second;
}

int ReaderContext::joint(const InputNode& n) const {
  const std::string ref = n.as_string();
  const auto dot = ref.find('.');
  if (dot == std::string::npos) n.fail("expected a joint reference 'body.joint', got '" + ref + "'");
  const std::string body = ref.substr(0, dot), joint = ref.substr(dot + 1);
  const auto b = bodies.find(body);
  if (b == bodies.end()) n.fail("no body named '" + body + "'");
  const auto j = b->second.joints.find(joint);
  if (j == b->second.joints.end()) {
    std::string names;
    for (const auto& [k, v] : b->second.joints) names += (names.empty() ? "" : ", ") + k;
    n.fail("body '" + body + "' has no joint '" + joint + "' (its joints: " + (names.empty() ? "none" : names) + ")");
  }
  return j->second;
}

int ReaderContext::drive(const InputNode& n) const {
  const std::string name = n.as_string();
  const auto it = drives.find(name);
  if (it == drives.end()) n.fail("no drive named '" + name + "' (define it under 'drives')");
  return it->second;
}

int ReaderContext::hydraulic_node(const InputNode& n) const {
  const std::string name = n.as_string();
  const auto it = hydraulic_nodes.find(name);
  if (it == hydraulic_nodes.end()) n.fail("no hydraulic node named '" + name + "' (define it under 'hydraulics.nodes')");
  return it->second;
}

std::pair<Vec3, Vec3> ReaderContext::end_velocities(const InputNode& body) {
  std::pair<Vec3, Vec3> v{Vec3::Zero(), Vec3::Zero()};
  if (auto n = body.get("velocities")) {
    const auto vs = n->items();
    if (vs.size() != 2) n->fail("expected the two end velocities [[vx1, vy1, vz1], [vx2, vy2, vz2]]");
    v = {vs[0].as_vec3(), vs[1].as_vec3()};
  }
  return v;
}

Mat3 ReaderContext::orientation(const InputNode& p) {
  int given = 0;
  for (const char* k : {"rotation", "rotation_deg", "axis_angle", "cardan_zyx_deg"}) given += p.has(k) ? 1 : 0;
  if (given > 1) p.fail("give the orientation once: rotation, rotation_deg, axis_angle or cardan_zyx_deg");
  if (auto r = p.get("rotation")) return rotation_matrix(r->as_vec3());
  if (auto r = p.get("rotation_deg")) return rotation_matrix<double>(r->as_vec3() * (std::numbers::pi / 180));
  if (auto r = p.get("cardan_zyx_deg")) return cardan_zyx_matrix<double>(r->as_vec3() * (std::numbers::pi / 180));
  if (auto r = p.get("axis_angle")) {
    r->allow_only({"axis", "angle_deg"});
    const InputNode axis = (*r)["axis"];
    const Vec3 a = axis.as_vec3();
    if (a.norm() == 0.0) axis.fail("the rotation axis has zero length");
    return rotation_matrix<double>(a.normalized() * deg_to_rad((*r)["angle_deg"].as_double()));
  }
  return Mat3::Identity();
}

int ReaderContext::add_joint(const InputNode& at, const std::string& body, const std::string& name, Joint joint) {
  if (name.empty() || name.find('.') != std::string::npos) at.fail("joint names must be non-empty and contain no '.'");
  BodyRecord& rec = bodies.at(body);
  if (rec.joints.count(name)) at.fail("body '" + body + "' has two joints named '" + name + "'");
  joint.name = body + "." + name;
  const int id = builder.add_joint(rec.body, joint);
  rec.joints[name] = id;
  return id;
}

}  // namespace latticedyn
