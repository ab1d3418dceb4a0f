// Polyline-cell geometry of the model for the XDMF output; the point list is fixed at the first
// output because XDMF shares one topology (/viz/cells) between all time steps.
#include "io/viz_geometry.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace latticedyn::io {

void VizGeometry::check_draw_sequences(const Model& model) {
  for (const Body& body : model.bodies)
    for (int i : body.draw_sequence)
      if (i < 0 || i >= static_cast<int>(body.joints.size()))
        throw std::invalid_argument("ResultWriter: body '" + body.name + "' draws joint " + std::to_string(i) +
                                    " but has " + std::to_string(body.joints.size()) + " joints");
}

void VizGeometry::add_cell(const std::vector<int>& points, int body, int element, int polyline) {
  const int cell = num_cells();
  cells_.push_back(kPolylineCode);
  cells_.push_back(static_cast<int>(points.size()));
  cells_.insert(cells_.end(), points.begin(), points.end());
  cell_offsets_.push_back(static_cast<int>(cells_.size()));
  cell_body_.push_back(body);
  cell_element_.push_back(element);
  cell_polyline_.push_back(polyline);
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    lines_.push_back(points[i]);
    lines_.push_back(points[i + 1]);
    line_cell_.push_back(cell);
  }
}

void VizGeometry::add_rigid_body(const Model& model, int b) {
  const Body& body = model.bodies[b];
  std::vector<int> point_of(body.joints.size(), -1);  // per body joint: one point however often drawn
  auto joint_point = [&](int k) {
    if (point_of[k] < 0) {
      point_of[k] = num_points();
      frame_points_.push_back({true, body.joints[k]});
    }
    return point_of[k];
  };
  const auto& seq = body.draw_sequence;
  if (!seq.empty()) {
    for (std::size_t i = 0; i + 1 < seq.size(); ++i) {
      if (seq[i] == seq[i + 1]) continue;
      const int from = joint_point(seq[i]);  // numbered in drawing order, not argument order
      add_cell({from, joint_point(seq[i + 1])}, b, -1);
    }
  } else if (body.joints.size() >= 2) {
    const int hub = joint_point(0);
    for (std::size_t k = 1; k < body.joints.size(); ++k) add_cell({hub, joint_point(static_cast<int>(k))}, b, -1);
  } else if (body.joints.size() == 1) {
    // Origin and joint coincide at all times exactly when the constant body-frame offset is zero.
    const Joint& j = model.joints[body.joints[0]];
    if (j.rotation_block >= 0 && j.offset.norm() > 0) {
      const int origin = num_points();
      frame_points_.push_back({false, j.translation_block});
      add_cell({origin, joint_point(0)}, b, -1);
    }
  }
}

VizGeometry VizGeometry::plan(const ModelState& state) {
  const Model& model = state.model();
  VizGeometry g;
  int next = 0;
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    const auto polylines =
        model.elements[e].element->axis_polylines(state.element_slots(static_cast<int>(e)), state.context());
    std::vector<int> counts, points;
    g.element_first_.push_back(next);
    for (const auto& line : polylines) {
      const int n = line.size() >= 2 ? static_cast<int>(line.size()) : 0;  // a single point draws no line
      counts.push_back(n);
      if (n > 0) {
        points.resize(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) points[static_cast<std::size_t>(i)] = next + i;
        g.add_cell(points, model.elements[e].body, static_cast<int>(e), static_cast<int>(counts.size()) - 1);
      }
      next += n;
    }
    g.axis_count_.push_back(std::move(counts));
  }
  g.first_frame_point_ = next;
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    if (model.bodies[b].type == "rigid_body") g.add_rigid_body(model, static_cast<int>(b));
  return g;
}

std::vector<VizGeometry::BodyRange> VizGeometry::body_ranges() const {
  std::vector<BodyRange> ranges;
  std::vector<char> seen;
  for (int c = 0; c < num_cells(); ++c) {
    const int b = cell_body_[c];
    const int* p = cells_.data() + cell_offsets_[c] + 2;
    const int n = cells_[static_cast<std::size_t>(cell_offsets_[c]) + 1];
    const auto [lo, hi] = std::minmax_element(p, p + n);
    if (ranges.empty() || ranges.back().body != b) {
      if (b < 0) return {};
      if (static_cast<int>(seen.size()) <= b) seen.resize(b + 1, 0);
      if (seen[b]) return {};  // the body's cells come in two runs
      seen[b] = 1;
      ranges.push_back(BodyRange{b, c, 0, *lo, 0, cell_offsets_[c], 0});
    }
    BodyRange& r = ranges.back();
    ++r.cells;
    r.entries = cell_offsets_[c + 1] - r.first_entry;
    const int last = std::max(r.first_point + r.points - 1, *hi);
    r.first_point = std::min(r.first_point, *lo);
    r.points = last - r.first_point + 1;
  }
  return ranges;
}

int VizGeometry::first_cell_of(int element) const {
  // Element cells first (cell_element_ non-decreasing over them), then rigid-body cells (-1).
  const auto element_cells = std::find(cell_element_.begin(), cell_element_.end(), -1);
  return static_cast<int>(std::lower_bound(cell_element_.begin(), element_cells, element) - cell_element_.begin());
}

void VizGeometry::points(const ModelState& state, const std::vector<ElementOutput>& elements, int first_element,
                         int end_element, bool frames, std::vector<double>& xyz) const {
  const Model& model = state.model();
  xyz.resize(3 * static_cast<std::size_t>(num_points()));  // every point of the range is written below
  for (auto e = static_cast<std::size_t>(first_element); e < static_cast<std::size_t>(end_element); ++e) {
    const Element& element = *model.elements[e].element;
    const auto& polylines = elements.at(e).polylines;
    bool same = polylines.size() == axis_count_[e].size();
    for (std::size_t k = 0; same && k < polylines.size(); ++k)
      same = (polylines[k].size() >= 2 ? static_cast<int>(polylines[k].size()) : 0) == axis_count_[e][k];
    if (!same)
      throw std::runtime_error("ResultWriter: element " + std::to_string(e) + " (" + std::string(element.type_name()) +
                               ") changed the number of its drawn axis points since the first output; the drawn "
                               "geometry must keep its size");
    int at = element_first_[e];
    for (std::size_t k = 0; k < polylines.size(); ++k) {
      for (int i = 0; i < axis_count_[e][k]; ++i)
        Eigen::Map<Vec3>(xyz.data() + 3 * (at + i)) = polylines[k][i];
      at += axis_count_[e][k];
    }
  }
  for (std::size_t k = 0; frames && k < frame_points_.size(); ++k) {
    const FramePoint& p = frame_points_[k];
    Eigen::Map<Vec3>(xyz.data() + 3 * (first_frame_point_ + k)) =
        p.joint ? state.joint_position(p.index) : state.block(p.index).pos;
  }
}

}  // namespace latticedyn::io
