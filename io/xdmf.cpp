// XDMF text for the results writer. Grids are spelled out in full rather than through XPath
// references, which XDMF readers support unevenly; the extents they declare grow with every step.
#include "io/xdmf.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string_view>
#include <system_error>

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

void XdmfDocument::add_step(double time) {
  std::string& x = grids_;
  const std::string h5 = xml_escape(layout_.h5_name), step = std::to_string(steps_);
  const std::string lines = std::to_string(layout_.lines), points = std::to_string(layout_.points);

  // A DataItem selecting this step's entry of a (T, n) or (T, n, 3) dataset as a (1, n[, 3]) array.
  auto slab = [&](const char* dataset, const std::string& n, bool vector, const std::string& at) {
    x += "          <DataItem ItemType=\"HyperSlab\" Type=\"HyperSlab\" Dimensions=\"1 " + n +
         (vector ? " 3" : "") + "\">\n";
    if (vector)
      x += "            <DataItem Dimensions=\"3 3\" NumberType=\"Int\" Format=\"XML\">" + at + " 0 0 1 1 1 1 " +
           n + " 3</DataItem>\n";
    else
      x += "            <DataItem Dimensions=\"3 2\" NumberType=\"Int\" Format=\"XML\">" + at + " 0 1 1 1 " + n +
           "</DataItem>\n";
    x += "            <DataItem Dimensions=\"";
    gaps_.push_back(x.size());
    // /viz/points is stored in single precision, everything else in double.
    const char* precision = std::string_view(dataset) == "points" ? "4" : "8";
    x += " " + n + (vector ? " 3" : "") + "\" NumberType=\"Float\" Precision=\"" + precision + "\" Format=\"HDF\">" + h5 +
         ":/viz/" + dataset + "</DataItem>\n";
    x += "          </DataItem>\n";
  };
  auto static_cell_ints = [&](const char* name) {
    x += std::string("        <Attribute Name=\"") + name + "\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
    x += "          <DataItem Dimensions=\"" + lines + "\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" + h5 +
         ":/viz/" + name + "</DataItem>\n";
    x += "        </Attribute>\n";
  };

  x += "      <Grid Name=\"step " + step + "\" GridType=\"Uniform\">\n";
  x += "        <Time Value=\"" + format_double(time) + "\"/>\n";
  x += "        <Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" NumberOfElements=\"" + lines + "\">\n";
  x += "          <DataItem Dimensions=\"" + lines + " 2\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" + h5 +
       ":/viz/lines</DataItem>\n";
  x += "        </Topology>\n        <Geometry GeometryType=\"XYZ\">\n";
  slab("points", points, true, step);
  x += "        </Geometry>\n";
  // The displacement since the first output, computed by the reader from the points (the .h5
  // does not repeat them).
  x += "        <Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\">\n";
  x += "          <DataItem ItemType=\"Function\" Function=\"$0 - $1\" Dimensions=\"1 " + points + " 3\">\n";
  slab("points", points, true, step);
  slab("points", points, true, "0");
  x += "          </DataItem>\n";
  x += "        </Attribute>\n";
  x += "        <Attribute Name=\"axial_force\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
  slab("axial_force", lines, false, step);
  x += "        </Attribute>\n";
  static_cell_ints("body");
  static_cell_ints("element");
  x += "      </Grid>\n";
  ++steps_;
}

std::string XdmfDocument::text() const {
  const std::string steps = std::to_string(steps_);
  std::string x;
  x.reserve(grids_.size() + steps.size() * gaps_.size() + 512);
  x += "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n  <Domain>\n";
  x += "    <Grid Name=\"" + xml_escape(layout_.title) + "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  std::size_t from = 0;
  for (std::size_t gap : gaps_) {
    x.append(grids_, from, gap - from);
    x += steps;
    from = gap;
  }
  x.append(grids_, from, std::string::npos);
  x += "    </Grid>\n  </Domain>\n</Xdmf>\n";
  return x;
}

void replace_file(const std::filesystem::path& path, const std::string& text) {
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
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  const int write_errno = errno;
  if (std::fclose(f) != 0) fail("write", tmp, errno);
  if (!written) fail("write", tmp, write_errno);
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
