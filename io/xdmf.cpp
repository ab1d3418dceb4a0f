// XDMF text for the results writer. Grids are spelled out in full rather than through XPath
// references, which XDMF readers support unevenly; the extents they declare grow with every step.
#include "io/xdmf.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace latticedyn::io {

namespace {

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

namespace {
constexpr char kStepMark = '\x01', kTimeMark = '\x02';  // never in XML text we write
}  // namespace

bool XdmfLayout::names_bodies() const {
  return !bodies.empty() && static_cast<int>(bodies.size()) <= kMaxNamedBodies;
}

XdmfDocument::XdmfDocument(XdmfLayout layout) : layout_(std::move(layout)) {
  if (layout_.names_bodies())
    for (const XdmfBody& body : layout_.bodies) named_bodies_.push_back(Block{xml_escape(body.name), {}, {}, {}, false});
  const auto& names = layout_.constraint_names;
  if (!names.empty() && static_cast<int>(names.size()) <= kMaxNamedConstraints)
    for (const std::string& name : names) named_constraints_.push_back(Block{xml_escape(name), {}, {}, {}, false});
  // Every step's grids are the same text but for the step's number, its time and the number of
  // steps: formatted once with marks there and cut into pieces, which add_step joins.
  format_step(std::string(1, kStepMark), std::string(1, kTimeMark));
  for (Block* b : blocks()) {
    // Where the pieces end, in order: a gap at offset p comes before a mark at p.
    std::vector<std::pair<std::size_t, Piece::Then>> cuts;
    for (std::size_t g : b->gaps) cuts.emplace_back(g, Piece::gap);
    for (std::size_t i = 0; i < b->grids.size(); ++i)
      if (b->grids[i] == kStepMark || b->grids[i] == kTimeMark)
        cuts.emplace_back(i, b->grids[i] == kStepMark ? Piece::step : Piece::time);
    std::stable_sort(cuts.begin(), cuts.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    std::size_t from = 0;
    for (const auto& [at, then] : cuts) {
      b->step_pieces.push_back(Piece{b->grids.substr(from, at - from), then});
      from = then == Piece::gap ? at : at + 1;  // a mark is replaced, a gap only filled
    }
    b->step_pieces.push_back(Piece{b->grids.substr(from), Piece::end});
    b->drawn = !b->grids.empty();
    b->grids.clear();
    b->gaps.clear();
  }
}

std::vector<XdmfDocument::Block*> XdmfDocument::blocks() {
  std::vector<Block*> all{&members_, &joints_, &constraints_};
  for (Block& b : named_constraints_) all.push_back(&b);
  for (Block& b : named_bodies_) all.push_back(&b);
  return all;
}

void XdmfDocument::add_step(double time) {
  time_texts_.push_back(format_double(time));
  ++steps_;
}

void XdmfDocument::format_step(const std::string& step, const std::string& time_text) {
  const std::string h5 = xml_escape(layout_.h5_name);
  Block* block = nullptr;  // everything below appends to this block's grids

  auto put = [&](const std::string& s) { block->grids += s; };
  // A DataItem selecting this step's entry `at` of a (T, n) or (T, n, c) dataset as a (1, n[, c])
  // array (columns c = 0 for the first); `precision` is 4 for the drawing data stored in single
  // precision, else 8. `first`: the first of the n rows selected (a single constraint's row) of the
  // dataset's `rows` (n when empty), which the HDF item declares.
  auto slab_columns = [&](const char* dataset, const std::string& n, int columns, const std::string& at,
                          const char* precision = "8", const std::string& first = "0", const std::string& rows = "") {
    // Appended, not " " + to_string(...): GCC 12 misreads that insert at the front as an
    // overlapping memcpy (-Wrestrict).
    std::string c;
    if (columns > 0) c.append(" ").append(std::to_string(columns));
    put("            <DataItem ItemType=\"HyperSlab\" Type=\"HyperSlab\" Dimensions=\"1 " + n + c + "\">\n");
    if (columns > 0)
      put("              <DataItem Dimensions=\"3 3\" NumberType=\"Int\" Format=\"XML\">" + at + " " + first +
          " 0 1 1 1 1 " + n + c + "</DataItem>\n");
    else
      put("              <DataItem Dimensions=\"3 2\" NumberType=\"Int\" Format=\"XML\">" + at + " " + first +
          " 1 1 1 " + n + "</DataItem>\n");
    put("              <DataItem Dimensions=\"");
    block->gaps.push_back(block->grids.size());
    put(" " + (rows.empty() ? n : rows) + c + "\" NumberType=\"Float\" Precision=\"" + precision +
        "\" Format=\"HDF\">" + h5 + ":" + dataset + "</DataItem>\n");
    put("            </DataItem>\n");
  };
  auto slab = [&](const char* dataset, const std::string& n, bool vector, const std::string& at,
                  const char* precision = "8", const std::string& first = "0", const std::string& rows = "") {
    slab_columns(dataset, n, vector ? 3 : 0, at, precision, first, rows);
  };
  auto attribute = [&](const char* name, bool vector, bool cell, const std::function<void()>& data,
                       const char* type = nullptr) {
    put(std::string("          <Attribute Name=\"") + name + "\" AttributeType=\"" +
        (type ? type : vector ? "Vector" : "Scalar") + "\" Center=\"" + (cell ? "Cell" : "Node") + "\">\n");
    data();
    put("          </Attribute>\n");
  };
  auto static_ints = [&](const std::string& n, const char* dataset) {
    put("            <DataItem Dimensions=\"" + n + "\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" + h5 + ":" +
        dataset + "</DataItem>\n");
  };
  // Rows [first, first + n) of a static (rows) or (rows, 2) integer dataset.
  auto static_rows = [&](const char* dataset, int first, int n, int rows, bool pairs) {
    const std::string count = std::to_string(n), pair = pairs ? " 2" : "";
    put("            <DataItem ItemType=\"HyperSlab\" Type=\"HyperSlab\" Dimensions=\"" + count + pair + "\">\n");
    put("              <DataItem Dimensions=\"3" + pair + "\" NumberType=\"Int\" Format=\"XML\">" + std::to_string(first) +
        (pairs ? " 0 1 1 " : " 1 ") + count + pair + "</DataItem>\n");
    put("              <DataItem Dimensions=\"" + std::to_string(rows) + pair +
        "\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" + h5 + ":" + dataset + "</DataItem>\n");
    put("            </DataItem>\n");
  };
  auto begin_grid = [&](Block& b) {
    block = &b;
    put("        <Grid Name=\"" + b.name + " " + step + "\" GridType=\"Uniform\">\n");
    put("          <Time Value=\"" + time_text + "\"/>\n");
  };
  // A grid of one vertex per point of a (T, n, 3) position series.
  auto vertices = [&](Block& b, int count, const char* positions, const char* ids) {
    const std::string n = std::to_string(count);
    begin_grid(b);
    put("          <Topology TopologyType=\"Polyvertex\" NodesPerElement=\"1\" NumberOfElements=\"" + n + "\">\n");
    static_ints(n, ids);
    put("          </Topology>\n          <Geometry GeometryType=\"XYZ\">\n");
    slab(positions, n, true, step);
    put("          </Geometry>\n");
  };

  const std::string points = std::to_string(layout_.points), all_cells = std::to_string(layout_.cells);
  // The members' grid of `part`: the whole model reads the datasets whole; a body's block reads
  // its rows of them, its cells numbered from its first point (/viz/body_cells).
  auto member_grid = [&](Block& b, const XdmfBody& part, bool whole) {
    const std::string n = std::to_string(part.points), cells = std::to_string(part.cells);
    const std::string first_point = std::to_string(part.first_point), first_cell = std::to_string(part.first_cell);
    const std::string point_rows = whole ? "" : points, cell_rows = whole ? "" : all_cells;
    auto rows = [&](const char* dataset) {  // a static integer dataset, per cell
      if (whole)
        static_ints(cells, dataset);
      else
        static_rows(dataset, part.first_cell, part.cells, layout_.cells, false);
    };
    begin_grid(b);
    // Cells of any number of points: XDMF's mixed topology (per cell its type, 2 for a polyline,
    // its point count and its points).
    put("          <Topology TopologyType=\"Mixed\" NumberOfElements=\"" + cells + "\">\n");
    if (whole)
      static_ints(std::to_string(layout_.cell_entries), "/viz/cells");
    else
      static_rows("/viz/body_cells", part.first_entry, part.entries, layout_.cell_entries, false);
    put("          </Topology>\n          <Geometry GeometryType=\"XYZ\">\n");
    slab("/viz/points", n, true, step, "4", first_point, point_rows);
    put("          </Geometry>\n");
    // The displacement since the first output, computed by the reader from the points (the .h5
    // does not repeat them).
    attribute("displacement [m]", true, false, [&] {
      put("            <DataItem ItemType=\"Function\" Function=\"$0 - $1\" Dimensions=\"1 " + n + " 3\">\n");
      slab("/viz/points", n, true, step, "4", first_point, point_rows);
      slab("/viz/points", n, true, "0", "4", first_point, point_rows);
      put("            </DataItem>\n");
    });
    attribute("axial_force [N]", false, true, [&] { slab("/viz/axial_force", cells, false, step, "8", first_cell, cell_rows); });
    // The members' stresses and largest resultants: colour by utilization to see the worst.
    for (const auto& member_array : {std::pair{"utilization", "/viz/utilization"}, std::pair{"von_mises [Pa]", "/viz/von_mises"},
                                     std::pair{"bending_moment [N m]", "/viz/bending_moment"},
                                     std::pair{"shear_force [N]", "/viz/shear_force"}, std::pair{"torque [N m]", "/viz/torque"}}) {
      // Not a structured binding: lambdas may not capture those before Clang 16.
      const char* dataset = member_array.second;
      attribute(member_array.first, false, true, [&] { slab(dataset, cells, false, step, "8", first_cell, cell_rows); });
    }
    // Every resultant of both ends, signed, as one 12-component array (N, Qy, Qz, T, My, Mz at end
    // 1, then end 2): ParaView colours by any component.
    attribute("section_forces [N, N m]", false, true,
              [&] { slab_columns("/viz/section_forces", cells, 12, step, "8", first_cell, cell_rows); }, "Matrix");
    attribute("body", false, true, [&] { rows("/viz/body"); });
    attribute("element", false, true, [&] { rows("/viz/element"); });
    put("        </Grid>\n");
  };
  if (named_bodies_.empty())
    member_grid(members_,
                XdmfBody{.cells = layout_.cells, .points = layout_.points, .entries = layout_.cell_entries},
                true);
  for (std::size_t b = 0; b < named_bodies_.size(); ++b) member_grid(named_bodies_[b], layout_.bodies[b], false);

  if (layout_.joints > 0) {
    const std::string n = std::to_string(layout_.joints);
    vertices(joints_, layout_.joints, "/joints/position", "/viz/joint_vertices");
    attribute("velocity [m/s]", true, false, [&] { slab("/joints/velocity", n, true, step); });
    for (const char* axis : {"axis_x", "axis_y", "axis_z"}) {
      const std::string dataset = std::string("/viz/joint_") + axis;
      attribute(axis, true, false, [&] { slab(dataset.c_str(), n, true, step, "4"); });
    }
    attribute("body", false, false, [&] { static_ints(n, "/model/joint_body"); });
    put("        </Grid>\n");
  }
  // One block per named constraint: a vertex at its second joint, its row of each series.
  const std::string all = std::to_string(layout_.constraints);
  for (std::size_t c = 0; c < named_constraints_.size(); ++c) {
    const std::string row = std::to_string(c);
    begin_grid(named_constraints_[c]);
    put("          <Topology TopologyType=\"Polyvertex\" NodesPerElement=\"1\" NumberOfElements=\"1\">\n");
    put("            <DataItem Dimensions=\"1\" NumberType=\"Int\" Format=\"XML\">0</DataItem>\n");
    put("          </Topology>\n          <Geometry GeometryType=\"XYZ\">\n");
    slab("/constraints/position", "1", true, step, "8", row, all);
    put("          </Geometry>\n");
    attribute("reaction_force [N]", true, false, [&] { slab("/constraints/reaction_force", "1", true, step, "8", row, all); });
    attribute("reaction_moment [N m]", true, false,
              [&] { slab("/constraints/reaction_moment", "1", true, step, "8", row, all); });
    attribute("constraint", false, false, [&] {
      put("            <DataItem Dimensions=\"1\" NumberType=\"Int\" Format=\"XML\">" + row + "</DataItem>\n");
    });
    put("        </Grid>\n");
  }
  if (layout_.constraints > 0 && named_constraints_.empty()) {
    const std::string n = std::to_string(layout_.constraints);
    vertices(constraints_, layout_.constraints, "/constraints/position", "/viz/constraint_vertices");
    attribute("reaction_force [N]", true, false, [&] { slab("/constraints/reaction_force", n, true, step); });
    attribute("reaction_moment [N m]", true, false, [&] { slab("/constraints/reaction_moment", n, true, step); });
    attribute("constraint", false, false, [&] { static_ints(n, "/viz/constraint_vertices"); });
    put("        </Grid>\n");
  }
}

// Every step's grids are joined from the pieces as they are written: the document is never held
// whole, and adding a step stores only its time (a 60 s maneuver's XDMF is 11 MB; kept as text it
// grew by copies into fresh pages, a tenth of the reduced crane's run on a host with costly page
// faults).
template <class Sink>
void XdmfDocument::emit(Sink&& out) const {
  const std::string steps = std::to_string(steps_);
  auto put = [&](const std::string& s) { out(s.data(), s.size()); };
  put("<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n  <Domain>\n");
  put("    <Grid Name=\"" + xml_escape(layout_.title) + "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n");
  auto temporal = [&](const Block& b, const std::string& indent) {
    put(indent + "<Grid Name=\"" + b.name + "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
    char number[16];
    for (int s = 0; s < steps_; ++s) {
      const auto [number_end, ec] = std::to_chars(number, number + sizeof number, s);
      for (const Piece& p : b.step_pieces) {
        put(p.text);
        switch (p.then) {
          case Piece::step: out(number, static_cast<std::size_t>(number_end - number)); break;
          case Piece::time: put(time_texts_[static_cast<std::size_t>(s)]); break;
          case Piece::gap: put(steps); break;
          case Piece::end: break;
        }
      }
    }
    put(indent + "</Grid>\n");
  };
  // A spatial collection named `name` of one temporal collection per named block.
  auto named = [&](const char* name, const std::vector<Block>& named_blocks) {
    if (named_blocks.empty() || steps_ == 0) return;
    put(std::string("      <Grid Name=\"") + name + "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n");
    for (const Block& b : named_blocks) temporal(b, "        ");
    put("      </Grid>\n");
  };
  if (steps_ > 0 && members_.drawn) temporal(members_, "      ");
  named("members", named_bodies_);
  for (const Block* b : {&joints_, &constraints_})
    if (steps_ > 0 && b->drawn) temporal(*b, "      ");
  named("constraints", named_constraints_);
  put("    </Grid>\n  </Domain>\n</Xdmf>\n");
}

std::string XdmfDocument::text() const {
  std::string x;
  emit([&x](const char* data, std::size_t size) { x.append(data, size); });
  return x;
}

void XdmfDocument::write(std::FILE* file) const {
  emit([file](const char* data, std::size_t size) { std::fwrite(data, 1, size, file); });
}

void replace_file(const std::filesystem::path& path, const std::string& text) {
  replace_file(path, [&text](std::FILE* f) { std::fwrite(text.data(), 1, text.size(), f); });
}

void replace_file(const std::filesystem::path& path, const std::function<void(std::FILE*)>& write) {
  auto fail = [](const char* what, const std::filesystem::path& p, int err) {
    throw std::runtime_error(std::string("ResultWriter: cannot ") + what + " '" + p.string() +
                             "': " + std::strerror(err));
  };
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  // A new file of our own: whatever sits at the name (a stale copy, a symbolic link) is removed,
  // not written through.
  if (::unlink(tmp.c_str()) != 0 && errno != ENOENT) fail("remove", tmp, errno);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) fail("create", tmp, errno);
  std::FILE* f = ::fdopen(fd, "wb");
  if (!f) {
    const int err = errno;
    ::close(fd);
    fail("create", tmp, err);
  }
  // Writes of many small pieces: a buffer of 64 KiB makes them few system calls (a larger one
  // costs more in fresh pages than it saves).
  std::vector<char> buffer(std::size_t{64} << 10);
  std::setvbuf(f, buffer.data(), _IOFBF, buffer.size());
  errno = 0;
  try {
    write(f);
  } catch (...) {
    std::fclose(f);
    ::unlink(tmp.c_str());  // no half-written temporary beside the old file, which stays
    throw;
  }
  const bool written = std::ferror(f) == 0;
  const int write_errno = errno != 0 ? errno : EIO;
  const bool closed = std::fclose(f) == 0;
  const int close_errno = errno;
  if (!written || !closed) {
    ::unlink(tmp.c_str());
    fail("write", tmp, written ? close_errno : write_errno);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec)
    throw std::runtime_error("ResultWriter: cannot rename '" + tmp.string() + "' to '" + path.string() +
                             "': " + ec.message());
}

std::string format_double(double x) {
  // The shortest text that reads back as the same double (std::to_chars, about ten times cheaper
  // than printf's %.17g, which also prints digits that carry nothing: 0.1 as 0.10000000000000001).
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, ec == std::errc{} ? end : buf);
}

}  // namespace latticedyn::io
