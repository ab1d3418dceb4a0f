// Lattice generation: end-section nodes, main beams divided into `order` bays, one face per
// pair of consecutive main beams with a zig-zag of sub-beams, cross-section beams at the ends.
#include "elements/truss_section.hpp"

#include <cmath>
#include <stdexcept>

namespace latticedyn {

namespace {

std::string pair_text(const std::array<int, 2>& p) {
  return "(" + std::to_string(p[0] + 1) + ", " + std::to_string(p[1] + 1) + ")";
}

// Frame with x along `x` and z the part of `z_hint` across it.
Mat3 frame_from(const Vec3& x_dir, const Vec3& z_hint) {
  const Vec3 x = x_dir.normalized();
  const Vec3 z = (z_hint - z_hint.dot(x) * x).normalized();
  Mat3 R;
  R << x, z.cross(x), z;
  return R;
}

}  // namespace

ConnectionForm connection_form_from_string(const std::string& name) {
  if (name == "type1") return ConnectionForm::type1;
  if (name == "tp_type1") return ConnectionForm::tp_type1;
  if (name == "tp_anti_type1") return ConnectionForm::tp_anti_type1;
  throw std::invalid_argument("unknown connection form '" + name + "' (expected type1, tp_type1 or tp_anti_type1)");
}

const char* to_string(ConnectionForm f) {
  switch (f) {
    case ConnectionForm::type1: return "type1";
    case ConnectionForm::tp_type1: return "tp_type1";
    case ConnectionForm::tp_anti_type1: return "tp_anti_type1";
  }
  return "?";
}

const char* to_string(TrussMemberKind k) {
  switch (k) {
    case TrussMemberKind::main: return "main";
    case TrussMemberKind::cross: return "cross";
    case TrussMemberKind::sub: return "sub";
  }
  return "?";
}

void TrussSectionSpec::validate() const {
  if (!(std::isfinite(length) && length > 0)) throw std::invalid_argument("truss length must be positive");
  if (order < 1 || order > 1000) throw std::invalid_argument("truss order must be 1..1000");
  if (end1.size() < 2 || end2.size() < 2)
    throw std::invalid_argument("each end section needs at least 2 nodes");
  if (main_beams.size() < 3) throw std::invalid_argument("a truss needs at least 3 main beams");
  auto check_pairs = [](const std::vector<std::array<int, 2>>& pairs, std::size_t n1, std::size_t n2, const char* what) {
    for (const auto& p : pairs) {
      if (p[0] < 0 || p[1] < 0 || p[0] >= static_cast<int>(n1) || p[1] >= static_cast<int>(n2))
        throw std::invalid_argument(std::string(what) + " " + pair_text(p) + " refers to a node that does not exist");
    }
  };
  check_pairs(main_beams, end1.size(), end2.size(), "main beam");
  check_pairs(cross_beams1, end1.size(), end1.size(), "cross-section beam of end 1");
  check_pairs(cross_beams2, end2.size(), end2.size(), "cross-section beam of end 2");
  for (const auto* cb : {&cross_beams1, &cross_beams2})
    for (const auto& p : *cb)
      if (p[0] == p[1]) throw std::invalid_argument("cross-section beam " + pair_text(p) + " joins a node to itself");
  material.validate();
  main_section.validate();
  cross_section.validate();
  sub_section.validate();
}

int TrussGeometry::count(TrussMemberKind k) const {
  int n = 0;
  for (const auto& m : members) n += m.kind == k ? 1 : 0;
  return n;
}

const SectionProperties& TrussGeometry::section(const TrussSectionSpec& spec, TrussMemberKind k) const {
  return k == TrussMemberKind::main ? spec.main_section : k == TrussMemberKind::cross ? spec.cross_section : spec.sub_section;
}

TrussGeometry build_truss_geometry(const TrussSectionSpec& spec) {
  spec.validate();
  TrussGeometry g;
  const int n1 = static_cast<int>(spec.end1.size());
  for (const auto& yz : spec.end1) g.nodes.push_back({TrussNode::Kind::end1, Vec3(0, yz[0], yz[1])});
  for (const auto& yz : spec.end2) g.nodes.push_back({TrussNode::Kind::end2, Vec3(spec.length, yz[0], yz[1])});
  const int nm = static_cast<int>(spec.main_beams.size());
  auto start = [&](int m) { return spec.main_beams[m][0]; };
  auto end = [&](int m) { return n1 + spec.main_beams[m][1]; };

  // Faces between consecutive main beams; outward normal, planarity checked.
  Vec3 centroid = Vec3::Zero();
  for (const auto& n : g.nodes) centroid += n.position;
  centroid /= static_cast<double>(g.nodes.size());
  for (int m = 0; m < nm; ++m) {
    const int n = (m + 1) % nm;
    TrussFace f;
    f.main_beam_m = m;
    f.main_beam_n = n;
    const Vec3 A = g.nodes[start(m)].position, B = g.nodes[end(m)].position;
    const Vec3 C = g.nodes[end(n)].position, D = g.nodes[start(n)].position;
    f.apex_at_end1 = start(m) == start(n);
    f.apex_at_end2 = end(m) == end(n);
    if (f.apex_at_end1 && f.apex_at_end2)
      throw std::invalid_argument("main beams " + std::to_string(m + 1) + " and " + std::to_string(n + 1) + " coincide");
    Vec3 normal = (C - A).cross(D - B);
    if (normal.norm() < 1e-9 * spec.length * spec.length)
      throw std::invalid_argument("main beams " + std::to_string(m + 1) + " and " + std::to_string(n + 1) +
                                  " do not span a face (collinear)");
    normal.normalize();
    for (const Vec3& P : {B, C, D})
      if (std::abs(normal.dot(P - A)) > 1e-6 * spec.length)
        throw std::invalid_argument("main beams " + std::to_string(m + 1) + " and " + std::to_string(n + 1) +
                                    " do not lie in one plane: sub-beams need a planar face");
    if (normal.dot(0.25 * (A + B + C + D) - centroid) < 0) normal = -normal;
    f.normal = normal;
    g.faces.push_back(f);
  }

  // Internal nodes, station by station along each main beam, in the main beam's frame.
  g.main_beam_stations.resize(nm);
  for (int m = 0; m < nm; ++m) {
    const Vec3 a = g.nodes[start(m)].position, b = g.nodes[end(m)].position;
    if ((b - a).norm() < 1e-9 * spec.length) throw std::invalid_argument("main beam " + std::to_string(m + 1) + " has zero length");
    const Mat3 frame = frame_from(b - a, g.faces[m].normal);
    g.main_beam_stations[m].push_back(start(m));
    for (int k = 1; k < spec.order; ++k) {
      TrussNode node{TrussNode::Kind::internal, a + (b - a) * (double(k) / spec.order), frame, m, k};
      g.main_beam_stations[m].push_back(static_cast<int>(g.nodes.size()));
      g.nodes.push_back(node);
    }
    g.main_beam_stations[m].push_back(end(m));
  }

  auto add_member = [&](TrussMemberKind kind, int a, int b, const Vec3& z_hint, int face) {
    const Vec3 d = g.nodes[b].position - g.nodes[a].position;
    if (d.norm() < 1e-9 * spec.length) throw std::invalid_argument(std::string("a ") + to_string(kind) + " member has zero length");
    g.members.push_back({kind, a, b, frame_from(d, z_hint), d.norm(), face});
  };
  for (int m = 0; m < nm; ++m)
    for (int k = 0; k < spec.order; ++k)
      add_member(TrussMemberKind::main, g.main_beam_stations[m][k], g.main_beam_stations[m][k + 1], g.faces[m].normal, m);
  for (const auto& p : spec.cross_beams1) add_member(TrussMemberKind::cross, p[0], p[1], Vec3::UnitX(), -1);
  for (const auto& p : spec.cross_beams2) add_member(TrussMemberKind::cross, n1 + p[0], n1 + p[1], Vec3::UnitX(), -1);
  for (int f = 0; f < nm; ++f) {
    const TrussFace& face = g.faces[f];
    const auto& sm = g.main_beam_stations[face.main_beam_m];
    const auto& sn = g.main_beam_stations[face.main_beam_n];
    const bool anti = spec.form == ConnectionForm::tp_anti_type1;
    int phase = 0;
    if (spec.form == ConnectionForm::tp_type1 && face.apex_at_end1) phase = 1;
    if (anti && face.apex_at_end2) phase = 1;
    for (int j = 0; j < spec.order; ++j) {
      // Station pair (k, k + 1), counted from end 1, or from end 2 for the anti form.
      const int k = anti ? spec.order - 1 - j : j;
      const bool from_m = (j + phase) % 2 == 0;
      const int lo = anti ? k + 1 : k, hi = anti ? k : k + 1;
      int a = from_m ? sm[lo] : sn[lo], b = from_m ? sn[hi] : sm[hi];
      // At an apex (two main beams sharing an end node) a diagonal would repeat a main-beam
      // segment: that bay gets the transverse member between its other two stations instead.
      const bool at_apex1 = face.apex_at_end1 && k == 0, at_apex2 = face.apex_at_end2 && k == spec.order - 1;
      if (at_apex1 || at_apex2) {
        const int station = at_apex1 ? k + 1 : k;
        a = sm[station];
        b = sn[station];
        if (a == b) continue;
      }
      add_member(TrussMemberKind::sub, a, b, face.normal, f);
    }
  }
  return g;
}

EquivalentBeam equivalent_beam(const TrussSectionSpec& spec, const TrussGeometry& g) {
  EquivalentBeam e;
  const double E = spec.material.youngs_modulus, A = spec.main_section.area;
  double y0 = 0, z0 = 0;
  for (const auto& mb : spec.main_beams) {
    y0 += spec.end1[mb[0]][0];
    z0 += spec.end1[mb[0]][1];
  }
  const double n = static_cast<double>(spec.main_beams.size());
  y0 /= n;
  z0 /= n;
  for (const auto& mb : spec.main_beams) {
    const double y = spec.end1[mb[0]][0] - y0, z = spec.end1[mb[0]][1] - z0;
    e.EA += E * A;
    e.EIy += E * A * z * z;
    e.EIz += E * A * y * y;
  }
  for (const auto& m : g.members)
    e.mass_per_length += spec.material.density * g.section(spec, m.kind).area * m.length;
  e.mass_per_length /= spec.length;
  return e;
}

TrussSectionSpec rectangular_truss_section(double length, int order, double half_width, double half_height) {
  TrussSectionSpec s;
  s.length = length;
  s.order = order;
  s.end1 = {{half_width, half_height}, {-half_width, half_height}, {-half_width, -half_height}, {half_width, -half_height}};
  s.end2 = s.end1;
  s.main_beams = {{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  s.cross_beams1 = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  s.cross_beams2 = s.cross_beams1;
  return s;
}

}  // namespace latticedyn
