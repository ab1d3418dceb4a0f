// Truss section definitions and full lattice bodies from YAML; node numbers are 1-based as in
// the thesis's tables.
#include "io/lattice_readers.hpp"

#include "assembly/lattice_builder.hpp"
#include "elements/super_truss.hpp"

#include <stdexcept>

namespace latticedyn {

namespace {

std::vector<std::array<double, 2>> read_section_nodes(const InputNode& n) {
  std::vector<std::array<double, 2>> out;
  for (const InputNode& p : n.items()) {
    const std::vector<double> yz = p.as_doubles();
    if (yz.size() != 2) p.fail("expected a node as [y, z] in the end section's plane");
    out.push_back({yz[0], yz[1]});
  }
  if (out.size() < 2) n.fail("an end section needs at least 2 nodes");
  return out;
}

std::vector<std::array<int, 2>> read_pairs(const InputNode& n, std::size_t count1, std::size_t count2, const char* what) {
  std::vector<std::array<int, 2>> out;
  for (const InputNode& p : n.items()) {
    const auto items = p.items();
    if (items.size() != 2) p.fail(std::string("expected a pair of node numbers [a, b] for a ") + what);
    const int a = items[0].as_int(), b = items[1].as_int();
    if (a < 1 || a > static_cast<int>(count1)) items[0].fail("no node " + std::to_string(a) + " (1.." + std::to_string(count1) + ")");
    if (b < 1 || b > static_cast<int>(count2)) items[1].fail("no node " + std::to_string(b) + " (1.." + std::to_string(count2) + ")");
    out.push_back({a - 1, b - 1});
  }
  return out;
}

}  // namespace

TrussSectionSpec read_truss_section(const ReaderContext& ctx, const InputNode& n) {
  n.allow_only({"length", "order", "end1", "end2", "main_beams", "cross_beams1", "cross_beams2", "connection",
                "material", "main_section", "cross_section", "sub_section"});
  TrussSectionSpec s;
  s.length = n["length"].as_positive();
  s.order = n["order"].as_int();
  if (s.order < 1 || s.order > 1000) n["order"].fail("expected a truss order from 1 to 1000");
  s.end1 = read_section_nodes(n["end1"]);
  s.end2 = n.has("end2") ? read_section_nodes(n["end2"]) : s.end1;
  s.main_beams = read_pairs(n["main_beams"], s.end1.size(), s.end2.size(), "main beam (end-1 node, end-2 node)");
  if (s.main_beams.size() < 3) n["main_beams"].fail("a truss needs at least 3 main beams");
  if (auto c = n.get("cross_beams1")) s.cross_beams1 = read_pairs(*c, s.end1.size(), s.end1.size(), "cross-section beam");
  if (auto c = n.get("cross_beams2")) s.cross_beams2 = read_pairs(*c, s.end2.size(), s.end2.size(), "cross-section beam");
  if (auto c = n.get("connection")) s.form = connection_form_from_string(c->as_choice({"type1", "tp_type1", "tp_anti_type1"}));
  s.material = ctx.material(n["material"]);
  s.main_section = ctx.section(n["main_section"]);
  s.cross_section = n.has("cross_section") ? ctx.section(n["cross_section"]) : s.main_section;
  s.sub_section = ctx.section(n["sub_section"]);
  try {
    build_truss_geometry(s);  // planarity and the rest, reported at the section's place
  } catch (const std::invalid_argument& e) {
    n.fail(e.what());
  }
  return s;
}

namespace {

const TrussSectionSpec& truss_section_of(const ReaderContext& ctx, const InputNode& n) {
  const InputNode sn = n["section"];
  const auto it = ctx.truss_sections.find(sn.as_string());
  if (it == ctx.truss_sections.end()) sn.fail("no truss section named '" + sn.as_string() + "' (define it under 'truss_sections')");
  return it->second;
}

// The parts every body of the section names shares, its geometry generated on first use.
ReaderContext::TrussSectionParts& truss_parts_of(ReaderContext& ctx, const InputNode& n, const TrussSectionSpec& spec) {
  ReaderContext::TrussSectionParts& parts = ctx.truss_parts[n["section"].as_string()];
  if (!parts.geometry) parts.geometry = std::make_shared<const TrussGeometry>(build_truss_geometry(spec));
  return parts;
}

}  // namespace

void read_super_truss(ReaderContext& ctx, const InputNode& n, const std::string& name) {
  // A lattice body that `truss_bodies` switched to a super truss keeps its full-model keys,
  // which are then ignored; written on a super truss body they are errors.
  if (n["type"].as_string() == "lattice")
    n.allow_only({"name", "type", "section", "position", "rotation", "rotation_deg", "axis_angle", "cardan_zyx_deg",
                  "member_type", "elements_per_member", "rigid_ends"});
  else
    n.allow_only({"name", "type", "section", "position", "rotation", "rotation_deg", "axis_angle", "cardan_zyx_deg"});
  const TrussSectionSpec& spec = truss_section_of(ctx, n);
  ReaderContext::TrussSectionParts& parts = truss_parts_of(ctx, n, spec);
  if (!parts.super_truss) parts.super_truss = std::make_shared<SuperTrussElement>(spec, *parts.geometry);
  const Vec3 position = n.get_vec3("position", Vec3::Zero());
  const Mat3 Q = ReaderContext::orientation(n);
  const int body = ctx.builder.add_body(name, "super_truss");
  ctx.bodies[name] = BodyRecord{body, "super_truss", {}};
  const Vec3 origin2 = position + Q * Vec3(spec.length, 0, 0);
  const int t1 = ctx.builder.add_block(DofBlock::translation(position, Vec3::Zero(), name + ".1"));
  const int r1 = ctx.builder.add_block(DofBlock::rotation(Q, Vec3::Zero(), name + ".1"));
  const int t2 = ctx.builder.add_block(DofBlock::translation(origin2, Vec3::Zero(), name + ".2"));
  const int r2 = ctx.builder.add_block(DofBlock::rotation(Q, Vec3::Zero(), name + ".2"));
  ctx.builder.add_element(body, parts.super_truss, {{t1}, {r1}, {t2}, {r2}});
  // Joints: the end sections' reference points, and every end-section node on its rigid section.
  auto joint = [&](int t, int r, const Vec3& offset) {
    Joint j;
    j.translation_block = t;
    j.rotation_block = r;
    j.offset = offset;
    return j;
  };
  ctx.add_joint(n, name, "1", joint(t1, r1, Vec3::Zero()));
  ctx.add_joint(n, name, "2", joint(t2, r2, Vec3::Zero()));
  for (std::size_t k = 0; k < spec.end1.size(); ++k)
    ctx.add_joint(n, name, "e1n" + std::to_string(k + 1), joint(t1, r1, Vec3(0, spec.end1[k][0], spec.end1[k][1])));
  for (std::size_t k = 0; k < spec.end2.size(); ++k)
    ctx.add_joint(n, name, "e2n" + std::to_string(k + 1), joint(t2, r2, Vec3(0, spec.end2[k][0], spec.end2[k][1])));
}

void read_lattice(ReaderContext& ctx, const InputNode& n, const std::string& name) {
  n.allow_only({"name", "type", "section", "position", "rotation", "rotation_deg", "axis_angle", "cardan_zyx_deg",
                "member_type", "elements_per_member", "rigid_ends"});
  const TrussSectionSpec& spec = truss_section_of(ctx, n);
  FullLatticeOptions opt;
  opt.position = n.get_vec3("position", Vec3::Zero());
  opt.orientation = ReaderContext::orientation(n);
  if (auto m = n.get("member_type"))
    opt.member = m->as_choice({"timoshenko_beam", "cubic_spline_beam"}) == "timoshenko_beam" ? MemberElement::timoshenko_beam
                                                                                             : MemberElement::cubic_spline_beam;
  opt.elements_per_member = n.get_int("elements_per_member", 1);
  if (opt.elements_per_member < 1 || opt.elements_per_member > 100) n["elements_per_member"].fail("expected 1 to 100");
  opt.rigid_ends = n.get_bool("rigid_ends", true);
  ReaderContext::TrussSectionParts& parts = truss_parts_of(ctx, n, spec);
  auto& elements = parts.member_elements[{static_cast<int>(opt.member), opt.elements_per_member}];
  if (elements.empty()) elements = lattice_member_elements(spec, *parts.geometry, opt);
  const FullLattice lattice = add_full_lattice(ctx.builder, name, spec, *parts.geometry, opt, &elements);
  BodyRecord rec{lattice.body, "lattice", {}};
  for (const auto& [jname, index] : lattice.joints) rec.joints[jname] = index;
  ctx.bodies[name] = rec;
}

}  // namespace latticedyn
