// The model drawn as polyline cells for ParaView: element polylines through their axis points and
// rigid bodies through their joints, with a point list whose size is fixed for the whole run.
#pragma once

#include "assembly/model_state.hpp"

#include <vector>

namespace latticedyn::io {

/// Points, cells and lines, in this order: every element contributes its polylines (element
/// order; a polyline of fewer than two points draws nothing), each one cell through consecutive
/// points; every body of type "rigid_body" contributes 2-point cells through its joints (body
/// order): its draw_sequence as a chain, else a star from its first joint, else (one joint) a cell
/// from its translation block's origin to the joint when the joint's offset is non-zero. Points are
/// not shared between elements or bodies. A cell is what carries results (an element polyline is
/// one member: its forces and stresses once, not once per segment); lines are the cells' segments.
class VizGeometry {
 public:
  /// Throws std::invalid_argument for a draw_sequence entry outside its body's joints.
  static void check_draw_sequences(const Model& model);
  /// Fixes the geometry from the first state (elements' axis point counts).
  static VizGeometry plan(const ModelState& state);

  int num_points() const { return first_frame_point_ + static_cast<int>(frame_points_.size()); }
  int num_cells() const { return static_cast<int>(cell_body_.size()); }
  int num_lines() const { return static_cast<int>(line_cell_.size()); }
  /// The cells in XDMF's mixed-topology layout: per cell kPolylineCode, its number of points n, and
  /// its n point indices.
  const std::vector<int>& cells() const { return cells_; }
  /// Where each cell starts in cells(), and cells().size() at the end (num_cells() + 1 entries).
  const std::vector<int>& cell_offsets() const { return cell_offsets_; }
  /// Body index of each cell.
  const std::vector<int>& cell_body() const { return cell_body_; }
  /// Element index of each cell, -1 for rigid-body cells.
  const std::vector<int>& cell_element() const { return cell_element_; }
  /// Index of each cell's polyline within its element's axis_polylines, -1 for rigid-body cells.
  const std::vector<int>& cell_polyline() const { return cell_polyline_; }
  /// Point indices, 2 per line (segment).
  const std::vector<int>& lines() const { return lines_; }
  /// The cell each line is a segment of.
  const std::vector<int>& line_cell() const { return line_cell_; }

  /// XDMF's code of a polyline cell in a mixed topology.
  static constexpr int kPolylineCode = 2;

  /// The cells and points one body draws: cells [first_cell, first_cell + cells), through points
  /// [first_point, first_point + points), their entries of cells() [first_entry, first_entry + entries).
  struct BodyRange {
    int body = -1;
    int first_cell = 0, cells = 0, first_point = 0, points = 0, first_entry = 0, entries = 0;
  };
  /// Per drawn body (body order), its cells and points when every body's cells are consecutive,
  /// as the element and rigid-body order makes them; empty otherwise (then no body can be drawn
  /// as a block of its own without copying its data).
  std::vector<BodyRange> body_ranges() const;
  /// Point positions (3 per point) at `state`, the elements' polylines taken from `elements`
  /// (Element::output at the same state, one per model element). Throws std::runtime_error if an
  /// element's number of axis points differs from the first state's.
  void points(const ModelState& state, const std::vector<ElementOutput>& elements, std::vector<double>& xyz) const {
    points(state, elements, 0, static_cast<int>(axis_count_.size()), true, xyz);
  }
  /// The same for the points of elements [first_element, end_element) only (their outputs alone
  /// are read) and, with `frames`, the rigid bodies' points; the other entries of xyz (sized for
  /// every point) are left as they were.
  void points(const ModelState& state, const std::vector<ElementOutput>& elements, int first_element, int end_element,
              bool frames, std::vector<double>& xyz) const;
  /// The first cell drawn by an element from `element` on, or the first rigid-body cell (num_cells()
  /// without any) when no later element draws one: cells come in element order.
  int first_cell_of(int element) const;
  /// The first point of an element from `element` on (the rigid bodies' first point when none is).
  int first_point_of(int element) const {
    return element < static_cast<int>(element_first_.size()) ? element_first_[element] : first_frame_point_;
  }

 private:
  /// A point at a joint's position or at a block's origin.
  struct FramePoint {
    bool joint = true;
    int index = -1;
  };
  /// A cell through `points` in turn, and its segments as lines.
  void add_cell(const std::vector<int>& points, int body, int element, int polyline = -1);
  void add_rigid_body(const Model& model, int body);

  std::vector<std::vector<int>> axis_count_;  // per element and polyline, from the first state
  std::vector<int> element_first_;  // per element, its first point; -1 if not drawn
  int first_frame_point_ = 0;
  std::vector<FramePoint> frame_points_;
  std::vector<int> cells_, cell_offsets_{0}, cell_body_, cell_element_, cell_polyline_;
  std::vector<int> lines_, line_cell_;
};

}  // namespace latticedyn::io
