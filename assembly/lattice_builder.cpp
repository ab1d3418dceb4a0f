// Member-by-member lattice: node blocks, beam elements bound to them with the constant frame
// offsets of rigid connections, reference nodes with fixed constraints for rigid end sections.
#include "assembly/lattice_builder.hpp"

#include <stdexcept>

namespace latticedyn {

std::vector<std::shared_ptr<const Element>> lattice_member_elements(const TrussSectionSpec& spec,
                                                                    const TrussGeometry& g,
                                                                    const FullLatticeOptions& opt) {
  if (opt.elements_per_member < 1) throw std::invalid_argument("elements per member must be at least 1");
  std::vector<std::shared_ptr<const Element>> out;
  out.reserve(g.members.size());
  for (const TrussMember& m : g.members) {
    const BeamProperties beam{spec.material, g.section(spec, m.kind), m.length / opt.elements_per_member, 0.0};
    out.push_back(make_beam_element(opt.member, beam));
  }
  return out;
}

FullLattice add_full_lattice(ModelBuilder& builder, const std::string& name, const TrussSectionSpec& spec,
                             const TrussGeometry& g, const FullLatticeOptions& opt,
                             const std::vector<std::shared_ptr<const Element>>* member_elements) {
  if (opt.elements_per_member < 1) throw std::invalid_argument("elements per member must be at least 1");
  std::vector<std::shared_ptr<const Element>> made;
  if (!member_elements) {
    made = lattice_member_elements(spec, g, opt);
    member_elements = &made;
  }
  FullLattice out;
  out.body = builder.add_body(name, "lattice");
  const Mat3& Q = opt.orientation;
  auto place = [&](const Vec3& local) { return Vec3(opt.position + Q * local); };

  // One translation and one rotation block per lattice node; its frame: the end section's for
  // end nodes, the main beam's for internal nodes.
  std::vector<int> t(g.nodes.size()), r(g.nodes.size());
  for (std::size_t n = 0; n < g.nodes.size(); ++n) {
    const std::string label = name + ".node" + std::to_string(n + 1);
    t[n] = builder.add_block(DofBlock::translation(place(g.nodes[n].position), Vec3::Zero(), label));
    r[n] = builder.add_block(DofBlock::rotation(Q * g.nodes[n].frame, Vec3::Zero(), label));
  }
  out.nodes = static_cast<int>(g.nodes.size());

  // Members: n elements each, in the member's frame; rigid connection = constant offset from the
  // node's frame to the member's.
  for (const TrussMember& m : g.members) {
    const int ne = opt.elements_per_member;
    const std::shared_ptr<const Element>& element = member_elements->at(static_cast<std::size_t>(out.members));
    const Mat3 member_frame = Q * m.frame0;
    const Vec3 a = place(g.nodes[m.a].position), b = place(g.nodes[m.b].position);
    // The member's own nodes: its two lattice nodes (frame offsets: the rigid connection) and
    // ne - 1 between them.
    std::vector<MemberNode> nodes{{t[m.a], r[m.a], g.member_offset(m, m.a)}};
    for (int k = 1; k < ne; ++k) {
      const std::string label = name + ".member" + std::to_string(out.members + 1) + "." + std::to_string(k);
      nodes.push_back({builder.add_block(DofBlock::translation(member_point(a, b, k, ne), Vec3::Zero(), label)),
                       builder.add_block(DofBlock::rotation(member_frame, Vec3::Zero(), label))});
    }
    nodes.push_back({t[m.b], r[m.b], g.member_offset(m, m.b)});
    // Cubic spline members carry the axis stretch at each of their own nodes.
    if (opt.member == MemberElement::cubic_spline_beam)
      for (MemberNode& n : nodes) n.stretch = builder.add_block(DofBlock::scalar(1.0, 0.0, name + ".stretch"));
    out.elements += add_member_elements(builder, out.body, opt.member, element, nodes);
    ++out.members;
  }

  // Joints at the end-section nodes, in the end section's frame.
  const int n1 = static_cast<int>(spec.end1.size());
  for (std::size_t n = 0; n < g.nodes.size(); ++n) {
    if (g.nodes[n].kind == TrussNode::Kind::internal) continue;
    Joint j;
    j.translation_block = t[n];
    j.rotation_block = r[n];
    const bool first = g.nodes[n].kind == TrussNode::Kind::end1;
    const int k = first ? static_cast<int>(n) + 1 : static_cast<int>(n) - n1 + 1;
    const std::string jname = std::string(first ? "e1n" : "e2n") + std::to_string(k);
    j.name = name + "." + jname;
    out.joints.emplace_back(jname, builder.add_joint(out.body, j));
  }
  if (!opt.rigid_ends) return out;

  // Rigid end sections: a reference node on the axis per end, each end node fixed to it.
  for (int end = 1; end <= 2; ++end) {
    const Vec3 local_ref(end == 1 ? 0.0 : spec.length, 0.0, 0.0);
    const std::string label = name + ".end" + std::to_string(end);
    const int rt = builder.add_block(DofBlock::translation(place(local_ref), Vec3::Zero(), label));
    const int rr = builder.add_block(DofBlock::rotation(Q, Vec3::Zero(), label));
    Joint ref;
    ref.name = name + "." + std::to_string(end);
    ref.translation_block = rt;
    ref.rotation_block = rr;
    out.joints.emplace_back(std::to_string(end), builder.add_joint(out.body, ref));
    for (std::size_t n = 0; n < g.nodes.size(); ++n) {
      const bool on_this_end = (end == 1 && g.nodes[n].kind == TrussNode::Kind::end1) ||
                               (end == 2 && g.nodes[n].kind == TrussNode::Kind::end2);
      if (!on_this_end) continue;
      Joint arm;
      arm.name = name + ".end" + std::to_string(end) + "_arm" + std::to_string(n + 1);
      arm.translation_block = rt;
      arm.rotation_block = rr;
      arm.offset = g.nodes[n].position - local_ref;
      const int ja = builder.add_joint(out.body, arm);
      Joint node;
      node.name = name + ".end" + std::to_string(end) + "_node" + std::to_string(n + 1);
      node.translation_block = t[n];
      node.rotation_block = r[n];
      const int jn = builder.add_joint(out.body, node);
      Constraint c;
      c.name = name + ".rigid_end" + std::to_string(end) + "_" + std::to_string(n + 1);
      c.type = ConstraintType::fixed;
      c.joint1 = ja;
      c.joint2 = jn;
      builder.add_constraint(c, false);
    }
  }
  return out;
}

}  // namespace latticedyn
