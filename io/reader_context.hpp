// State shared while reading a model file: the model under construction and the named things
// (materials, sections, drives, bodies and their joints) that later entries refer to.
#pragma once

#include "assembly/model_builder.hpp"
#include "elements/hydraulic_fluid.hpp"
#include "elements/section.hpp"
#include "elements/truss_section.hpp"
#include "io/input_node.hpp"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace latticedyn {

struct BodyRecord {
  int body = -1;
  std::string type;
  std::map<std::string, int> joints;  ///< joint name within the body -> model joint index
};

class ReaderContext {
 public:
  ModelBuilder builder;
  std::map<std::string, Material> materials;
  std::map<std::string, SectionProperties> sections;
  std::map<std::string, TrussSectionSpec> truss_sections;
  std::map<std::string, int> drives;
  std::map<std::string, BodyRecord> bodies;
  std::map<std::string, int> hydraulic_nodes;  ///< node name -> its pressure's scalar block
  HydraulicFluid fluid;                        ///< of the hydraulic circuit
  /// `truss_bodies`: empty (as given), "lattice" or "super_truss": the type every lattice and
  /// super truss body is built as, so one model file gives the full and the reduced model.
  std::string truss_bodies;

  /// What every body of one truss section shares (elements hold no state): its geometry, the
  /// beam element of each member for a full lattice, its super truss element. Built once per
  /// section (and member type, elements per member): a lattice of 40,960 bays of two sections
  /// generates two geometries, not 40,960.
  struct TrussSectionParts {
    std::shared_ptr<const TrussGeometry> geometry;
    std::map<std::pair<int, int>, std::vector<std::shared_ptr<const Element>>> member_elements;  ///< (member type, per member)
    std::shared_ptr<const Element> super_truss;
  };
  std::map<std::string, TrussSectionParts> truss_parts;

  /// A rope's rest length in motion: its drive key, checked over the run's time span once the
  /// solver settings are read (a rest length through zero stops a run half way).
  struct DrivenRestLength {
    InputNode key;
    int drive = -1;
    double fraction = 1.0;  ///< rest length = fraction * drive value
  };
  std::vector<DrivenRestLength> driven_rest_lengths;

  /// A material given by name (from `materials`) or inline as a map.
  Material material(const InputNode& n) const;
  /// The material of a body (its `material` key) with the body's own `damping`, if given, in
  /// place of the material's.
  Material body_material(const InputNode& body) const;
  /// A section given by name (from `sections`) or inline as a map.
  SectionProperties section(const InputNode& n) const;
  /// "body.joint" -> model joint index.
  int joint(const InputNode& n) const;
  int drive(const InputNode& n) const;
  /// A hydraulic node by name -> its pressure's block.
  int hydraulic_node(const InputNode& n) const;
  /// Orientation from at most one of: rotation (rotation vector, rad), rotation_deg,
  /// axis_angle {axis, angle_deg}, cardan_zyx_deg [x, y, z]; identity if none is given.
  static Mat3 orientation(const InputNode& parent);
  /// A two-ended body's `velocities: [[vx1, vy1, vz1], [vx2, vy2, vz2]]`, zero if not given.
  static std::pair<Vec3, Vec3> end_velocities(const InputNode& body);
  /// Registers a joint of a body under `name` and in the builder as "body.name".
  int add_joint(const InputNode& at, const std::string& body, const std::string& name, Joint joint);
};

Material read_material(const InputNode& n);
/// `damping`: {alpha, beta}, or {ratio, frequency} (one ratio: stiffness-proportional at that
/// frequency in Hz; two ratios at two frequencies: alpha and beta).
RayleighDamping read_damping(const InputNode& n);
SectionProperties read_section(const InputNode& n);

}  // namespace latticedyn
