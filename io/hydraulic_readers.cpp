// Hydraulic circuit readers: nodes, valves, pumps and cylinders into the model under construction.
#include "io/hydraulic_readers.hpp"

#include "elements/hydraulic_cylinder.hpp"
#include "elements/hydraulic_node_elements.hpp"
#include "elements/hydraulic_orifice.hpp"

#include <stdexcept>

namespace latticedyn {

namespace {

int add_hydraulic_body(ReaderContext& ctx, const InputNode& name_node, const std::string& type) {
  const std::string name = name_node.as_string();
  if (name.empty() || name.find('.') != std::string::npos) name_node.fail("names must be non-empty and contain no '.'");
  if (ctx.bodies.count(name)) name_node.fail("a body named '" + name + "' exists already");
  const int body = ctx.builder.add_body(name, type);
  ctx.bodies[name] = BodyRecord{body, type, {}};
  return body;
}

std::optional<Drive> drive_of(ReaderContext& ctx, const InputNode& n, const char* key) {
  if (auto d = n.get(key)) return ctx.builder.peek().drives[ctx.drive(*d)];
  return std::nullopt;
}

HydraulicOrificeProperties orifice_properties(const ReaderContext& ctx, const InputNode& n) {
  HydraulicOrificeProperties p;
  p.area = n["area"].as_positive();
  p.discharge_coefficient = n.get_positive("discharge_coefficient", p.discharge_coefficient);
  p.transition_pressure = n.get_positive("transition_pressure", p.transition_pressure);
  p.fluid = ctx.fluid;
  return p;
}

}  // namespace

void read_hydraulic_nodes(ReaderContext& ctx, const InputNode& h) {
  h.allow_only({"fluid", "nodes", "elements"});
  if (auto f = h.get("fluid")) {
    f->allow_only({"bulk_modulus", "density"});
    ctx.fluid.bulk_modulus = f->get_positive("bulk_modulus", ctx.fluid.bulk_modulus);
    ctx.fluid.density = f->get_positive("density", ctx.fluid.density);
  }
  const InputNode nodes = h["nodes"];
  for (const InputNode& n : nodes.items()) {
    n.allow_only({"name", "pressure", "volume", "fixed"});
    const InputNode name_node = n["name"];
    const std::string name = name_node.as_string();
    if (name.empty() || name.find('.') != std::string::npos) name_node.fail("names must be non-empty and contain no '.'");
    if (ctx.hydraulic_nodes.count(name)) name_node.fail("a hydraulic node named '" + name + "' exists already");
    const bool fixed = n.get_bool("fixed", false);
    const double pressure = n.get_double("pressure", 0.0);
    DofBlock node = DofBlock::scalar(pressure, 0.0, std::string(kHydraulicNodeLabel) + name, fixed);
    node.first_order = true;
    const int block = ctx.builder.add_block(node);
    ctx.hydraulic_nodes[name] = block;
    if (fixed) {
      if (n.has("volume")) n["volume"].fail("a fixed node (a tank or a pressure supply) holds its pressure: no volume");
      continue;
    }
    // Every free node's row is a pressure build-up equation: it needs the oil volume it holds.
    const InputNode volume = n["volume"];
    const int body = add_hydraulic_body(ctx, name_node, "hydraulic_node");
    try {
      ctx.builder.add_element(body, std::make_shared<HydraulicVolume>(volume.as_positive(), ctx.fluid), {{block}});
    } catch (const std::invalid_argument& e) {
      volume.fail(e.what());
    }
  }
}

void read_hydraulic_elements(ReaderContext& ctx, const InputNode& h) {
  const auto elements = h.get("elements");
  if (!elements) return;
  for (const InputNode& n : elements->items()) {
    const std::string type = n["type"].as_choice({"orifice", "relief_valve", "directional_valve", "pump"});
    try {
      if (type == "pump") {
        n.allow_only({"name", "type", "node", "flow", "drive"});
        const int node = ctx.hydraulic_node(n["node"]);
        const int body = add_hydraulic_body(ctx, n["name"], "hydraulic_pump");
        ctx.builder.add_element(body, std::make_shared<HydraulicPump>(n["flow"].as_double(), drive_of(ctx, n, "drive")),
                                {{node}});
      } else if (type == "orifice" || type == "relief_valve") {
        n.allow_only({"name", "type", "from", "to", "area", "discharge_coefficient", "transition_pressure", "drive",
                      "cracking_pressure", "full_open_pressure"});
        HydraulicOrificeProperties p = orifice_properties(ctx, n);
        if (type == "relief_valve") {
          p.opening = OrificeOpening::relief;
          p.cracking_pressure = n["cracking_pressure"].as_non_negative();
          const InputNode full = n["full_open_pressure"];
          p.full_open_pressure = full.as_positive();
          if (!(p.full_open_pressure > p.cracking_pressure)) full.fail("must be above cracking_pressure");
        } else if (auto d = n.get("drive")) {
          p.opening = OrificeOpening::drive;
          p.drive = ctx.builder.peek().drives[ctx.drive(*d)];
        }
        const int from = ctx.hydraulic_node(n["from"]), to = ctx.hydraulic_node(n["to"]);
        const int body = add_hydraulic_body(ctx, n["name"], type == "orifice" ? "hydraulic_orifice" : "relief_valve");
        ctx.builder.add_element(body, std::make_shared<HydraulicOrifice>(p), {{from}, {to}});
      } else {  // a 4/3 reversing valve: four orifices opened by the spool position u in [-1, 1]
        n.allow_only({"name", "type", "ports", "area", "discharge_coefficient", "transition_pressure", "spool"});
        const InputNode ports = n["ports"];
        ports.allow_only({"P", "T", "A", "B"});
        const int P = ctx.hydraulic_node(ports["P"]), T = ctx.hydraulic_node(ports["T"]);
        const int A = ctx.hydraulic_node(ports["A"]), B = ctx.hydraulic_node(ports["B"]);
        HydraulicOrificeProperties p = orifice_properties(ctx, n);
        p.drive = ctx.builder.peek().drives[ctx.drive(n["spool"])];
        const int body = add_hydraulic_body(ctx, n["name"], "directional_valve");
        // u > 0: P -> A and B -> T; u < 0: P -> B and A -> T.
        auto path = [&](OrificeOpening opening, const char* name, int from, int to) {
          p.opening = opening;
          p.flow_name = name;
          ctx.builder.add_element(body, std::make_shared<HydraulicOrifice>(p), {{from}, {to}});
        };
        path(OrificeOpening::spool_positive, "Q_PA", P, A);
        path(OrificeOpening::spool_positive, "Q_BT", B, T);
        path(OrificeOpening::spool_negative, "Q_PB", P, B);
        path(OrificeOpening::spool_negative, "Q_AT", A, T);
      }
    } catch (const std::invalid_argument& e) {
      n.fail(e.what());
    }
  }
}

void read_hydraulic_cylinder(ReaderContext& ctx, const InputNode& n, const std::string& name) {
  n.allow_only({"name", "type", "ends", "velocities", "ports", "piston_diameter", "rod_diameter", "stroke",
                "retracted_length", "dead_volumes", "viscous_friction", "coulomb_friction", "friction_velocity",
                "leakage", "mass", "end_stop_stiffness", "end_stop_damping"});
  HydraulicCylinderProperties p;
  p.piston_diameter = n["piston_diameter"].as_positive();
  p.rod_diameter = n["rod_diameter"].as_positive();
  p.stroke = n["stroke"].as_positive();
  p.retracted_length = n["retracted_length"].as_positive();
  const InputNode dead = n["dead_volumes"];
  const auto dv = dead.items();
  if (dv.size() != 2) dead.fail("expected the oil volumes [piston chamber at zero stroke, rod chamber at full stroke], m^3");
  p.dead_volume_piston = dv[0].as_positive();
  p.dead_volume_rod = dv[1].as_positive();
  p.viscous_friction = n.get_non_negative("viscous_friction", 0.0);
  p.coulomb_friction = n.get_non_negative("coulomb_friction", 0.0);
  p.friction_velocity = n.get_positive("friction_velocity", p.friction_velocity);
  p.leakage = n.get_non_negative("leakage", 0.0);
  p.mass = n.get_non_negative("mass", 0.0);
  p.end_stop_stiffness = n.get_positive("end_stop_stiffness", 0.0);
  p.end_stop_damping = n.get_non_negative("end_stop_damping", 0.0);
  p.fluid = ctx.fluid;
  const InputNode ends = n["ends"];
  const auto e = ends.items();
  if (e.size() != 2) ends.fail("expected the cap end and the rod end [[x1, y1, z1], [x2, y2, z2]]");
  const Vec3 r1 = e[0].as_vec3(), r2 = e[1].as_vec3();
  const double s0 = (r2 - r1).norm() - p.retracted_length;
  if (s0 < 0 || s0 > p.stroke)
    ends.fail("the ends are " + std::to_string((r2 - r1).norm()) + " m apart: the stroke " + std::to_string(s0) +
              " m is outside [0, stroke] for retracted_length " + std::to_string(p.retracted_length) + " m");
  const auto [v1, v2] = ReaderContext::end_velocities(n);
  const InputNode ports = n["ports"];
  const auto pv = ports.items();
  if (pv.size() != 2) ports.fail("expected the hydraulic nodes of [piston chamber, rod chamber]");
  const int n1 = ctx.hydraulic_node(pv[0]), n2 = ctx.hydraulic_node(pv[1]);
  if (n1 == n2) ports.fail("the two chambers need two different nodes");
  const auto element = std::make_shared<HydraulicCylinder>(p);  // validates
  const int body = ctx.builder.add_body(name, "hydraulic_cylinder");
  ctx.bodies[name] = BodyRecord{body, "hydraulic_cylinder", {}};
  const int t1 = ctx.builder.add_block(DofBlock::translation(r1, v1, name + ".1"));
  const int t2 = ctx.builder.add_block(DofBlock::translation(r2, v2, name + ".2"));
  ctx.builder.add_element(body, element, {{t1}, {t2}, {n1}, {n2}});
  Joint j;
  j.translation_block = t1;
  ctx.add_joint(ends, name, "1", j);
  j.translation_block = t2;
  ctx.add_joint(ends, name, "2", j);
}

}  // namespace latticedyn
