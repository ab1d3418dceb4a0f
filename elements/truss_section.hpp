// A lattice truss section (thesis 3.5.2, Tables D-3 and D-6) and the one place where its
// geometry is generated: nodes, faces and members, used by the full member-by-member model and
// by the super truss element alike.
#pragma once

#include "core/types.hpp"
#include "elements/section.hpp"

#include <array>
#include <string>
#include <vector>

namespace latticedyn {

/// How the sub-beams (diagonals) run in a face between two main beams (the thesis's "SB
/// connection form"; its figures are missing, see docs/lattice.md for the pattern chosen).
/// In every face the stations k = 0..order along both main beams are joined by a zig-zag:
/// (m, k) - (n, k + 1) for k + phase even, (n, k) - (m, k + 1) for k + phase odd.
enum class ConnectionForm {
  type1,          ///< phase 0 in every face
  tp_type1,       ///< "triangular prism": phase 0 in quadrilateral faces, phase 1 in faces whose
                  ///< main beams meet at end 1 (no diagonal from the apex)
  tp_anti_type1,  ///< the reverse taper: as tp_type1 with the roles of end 1 and end 2 swapped
};

ConnectionForm connection_form_from_string(const std::string& name);  ///< throws invalid_argument
const char* to_string(ConnectionForm f);

/// The parameters of a truss section. Local frame: x along the truss from end section 1
/// (x = 0) to end section 2 (x = length); node coordinates are (y, z) in the end sections.
struct TrussSectionSpec {
  double length = 0.0;
  int order = 1;                             ///< bays along the main beams
  std::vector<std::array<double, 2>> end1;   ///< (y, z) of the nodes of end section 1
  std::vector<std::array<double, 2>> end2;   ///< (y, z) of the nodes of end section 2
  std::vector<std::array<int, 2>> main_beams;  ///< (node of end 1, node of end 2), 0-based, in cyclic order
  std::vector<std::array<int, 2>> cross_beams1;  ///< pairs of end-1 nodes
  std::vector<std::array<int, 2>> cross_beams2;  ///< pairs of end-2 nodes
  ConnectionForm form = ConnectionForm::type1;
  Material material;
  SectionProperties main_section, cross_section, sub_section;
  /// Throws std::invalid_argument naming the offending entry.
  void validate() const;
};

enum class TrussMemberKind { main, cross, sub };
const char* to_string(TrussMemberKind k);

/// A node of the lattice in the truss's local frame.
struct TrussNode {
  enum class Kind { end1, end2, internal };
  Kind kind = Kind::internal;
  Vec3 position = Vec3::Zero();
  Mat3 frame = Mat3::Identity();  ///< end nodes: the identity (the end section); internal: the main beam's frame
  int main_beam = -1;             ///< internal nodes: the main beam they lie on
  int station = -1;               ///< internal nodes: 1..order-1 along that main beam
};

/// A member between two nodes; frame0: x from node a to node b, z the face normal (main and
/// sub-beams) or the truss axis (cross-section beams).
struct TrussMember {
  TrussMemberKind kind = TrussMemberKind::main;
  int a = -1, b = -1;
  Mat3 frame0 = Mat3::Identity();
  double length = 0.0;
  int face = -1;  ///< sub-beams: their face; main-beam segments: their main beam
};

/// A face (sub-beam plane) between two consecutive main beams.
struct TrussFace {
  int main_beam_m = -1, main_beam_n = -1;
  Vec3 normal = Vec3::Zero();  ///< outward (away from the truss axis)
  bool apex_at_end1 = false, apex_at_end2 = false;  ///< the two main beams share that end node
};

/// The generated lattice: nodes (end-1 nodes first, then end-2 nodes, then internal nodes main
/// beam by main beam), faces and members (main-beam segments, cross-section beams, sub-beams).
struct TrussGeometry {
  std::vector<TrussNode> nodes;
  std::vector<TrussFace> faces;
  std::vector<TrussMember> members;
  /// The node at station k (0..order) of main beam m (stations 0 and order are its end nodes).
  std::vector<std::vector<int>> main_beam_stations;
  int count(TrussMemberKind k) const;
  const SectionProperties& section(const TrussSectionSpec& spec, TrussMemberKind k) const;
  /// The rigid connection of member `m` at its end node `node` (m.a or m.b): the constant rotation
  /// from that node's frame to the member's, the same in the full lattice and the super truss.
  Mat3 member_offset(const TrussMember& m, int node) const { return nodes[node].frame.transpose() * m.frame0; }
};

/// Generates the lattice of `spec` (validated first).
TrussGeometry build_truss_geometry(const TrussSectionSpec& spec);

/// The layout of a box lattice (the booms of thesis Table D-3): four main beams along the edges of
/// a prism, the end-1 nodes at (y, z) = (+-half_width, +-half_height) in cyclic order, the end-2
/// nodes the same unless given, cross beams around both ends. Material and sections are left to
/// the caller.
TrussSectionSpec rectangular_truss_section(double length, int order, double half_width, double half_height);

/// Closed forms of the equivalent beam (for checks): axial stiffness E * sum of the main beams'
/// areas (for main beams parallel to the axis) and the bending stiffnesses about y and z from
/// the parallel-axis sums E * sum A_i z_i^2 and E * sum A_i y_i^2 of the main chords about the
/// section's centroid (the chords' own I neglected); the mass per length of all members.
struct EquivalentBeam {
  double EA = 0.0, EIy = 0.0, EIz = 0.0, mass_per_length = 0.0;
};
EquivalentBeam equivalent_beam(const TrussSectionSpec& spec, const TrussGeometry& g);

}  // namespace latticedyn
