// The model drawn as 2-node line cells for ParaView: element polylines through their axis points
// and rigid bodies through their joints, with a point list whose size is fixed for the whole run.
#pragma once

#include "assembly/model_state.hpp"

#include <vector>

namespace latticedyn::io {

/// Points and lines, in this order: every element contributes its polylines (element order; a
/// polyline of fewer than two points draws nothing); every body of type "rigid_body" contributes lines
/// through its joints (body order): its draw_sequence as a polyline, else a star from its first
/// joint, else (one joint) a line from its translation block's origin to the joint when the
/// joint's offset is non-zero. Points are not shared between elements or bodies.
class VizGeometry {
 public:
  /// Throws std::invalid_argument for a draw_sequence entry outside its body's joints.
  static void check_draw_sequences(const Model& model);
  /// Fixes the geometry from the first state (elements' axis point counts).
  static VizGeometry plan(const ModelState& state);

  int num_points() const { return first_frame_point_ + static_cast<int>(frame_points_.size()); }
  int num_lines() const { return static_cast<int>(line_body_.size()); }
  /// Point indices, 2 per line.
  const std::vector<int>& lines() const { return lines_; }
  /// Body index of each line.
  const std::vector<int>& line_body() const { return line_body_; }
  /// Element index of each line, -1 for rigid-body lines.
  const std::vector<int>& line_element() const { return line_element_; }
  /// Index of each line's polyline within its element's axis_polylines, -1 for rigid-body lines.
  const std::vector<int>& line_polyline() const { return line_polyline_; }

  /// The lines and points one body draws: lines [first_line, first_line + lines), through points
  /// [first_point, first_point + points).
  struct BodyRange {
    int body = -1;
    int first_line = 0, lines = 0, first_point = 0, points = 0;
  };
  /// Per drawn body (body order), its lines and points when every body's lines are consecutive,
  /// as the element and rigid-body order makes them; empty otherwise (then no body can be drawn
  /// as a block of its own without copying its data).
  std::vector<BodyRange> body_ranges() const;

  /// Point positions (3 per point) at `state`, the elements' polylines taken from `elements`
  /// (Element::output at the same state, one per model element). Throws std::runtime_error if an
  /// element's number of axis points differs from the first state's.
  void points(const ModelState& state, const std::vector<ElementOutput>& elements, std::vector<double>& xyz) const;

 private:
  /// A point at a joint's position or at a block's origin.
  struct FramePoint {
    bool joint = true;
    int index = -1;
  };
  void add_line(int a, int b, int body, int element, int polyline = -1);
  void add_rigid_body(const Model& model, int body);

  std::vector<std::vector<int>> axis_count_;  // per element and polyline, from the first state
  std::vector<int> element_first_;  // per element, its first point; -1 if not drawn
  int first_frame_point_ = 0;
  std::vector<FramePoint> frame_points_;
  std::vector<int> lines_, line_body_, line_element_, line_polyline_;
};

}  // namespace latticedyn::io
