// Round trip of the results writer: states of small models written, the .h5 read back with the
// HDF5 C API, the XDMF checked against it, the CSV parsed; readability mid-run and error paths.
#include "io/recorded_state.hpp"
#include "io/result_writer.hpp"
#include "io/viz_geometry.hpp"
#include "io/xdmf.hpp"

#include "assembly/system_assembler.hpp"
#include "core/rotation.hpp"
#include "elements/super_truss.hpp"
#include "io/model_reader.hpp"
#include "tests/assembly/sample_models.hpp"
#include "tests/io/recording.hpp"

#include <gtest/gtest.h>

#include <hdf5.h>
#include <petscvec.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <regex>
#include <sstream>

namespace latticedyn {
namespace {

namespace fs = std::filesystem;
using testing::Recording;

// ---- scratch folder and model states ----------------------------------------------------------

/// A fresh folder per test (ctest may run tests in parallel), removed afterwards.
struct ScratchDir {
  fs::path path;
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path = fs::temp_directory_path() /
           ("latticedyn_io_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// ---- reading HDF5 back --------------------------------------------------------------------------

struct H5File {
  hid_t id;
  explicit H5File(const fs::path& p) : id(H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)) {}
  ~H5File() {
    if (id >= 0) H5Fclose(id);
  }
};

bool exists(hid_t file, const std::string& path) {
  std::size_t pos = 0;
  while ((pos = path.find('/', pos + 1)) != std::string::npos)
    if (H5Lexists(file, path.substr(0, pos).c_str(), H5P_DEFAULT) <= 0) return false;
  return H5Lexists(file, path.c_str(), H5P_DEFAULT) > 0;
}

template <class T>
struct Data {
  std::vector<hsize_t> dims;
  std::vector<T> v;
  /// Row-major element at a multi-index.
  T at(std::initializer_list<hsize_t> idx) const {
    hsize_t off = 0, d = 0;
    for (hsize_t i : idx) off = off * dims[d++] + i;
    return v.at(off);
  }
};

std::vector<hsize_t> shape(hid_t ds) {
  const hid_t space = H5Dget_space(ds);
  std::vector<hsize_t> dims(H5Sget_simple_extent_ndims(space));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  H5Sclose(space);
  return dims;
}

template <class T>
Data<T> read(hid_t file, const std::string& path) {
  const hid_t ds = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (ds < 0) throw std::runtime_error("no dataset " + path);
  Data<T> d{shape(ds), {}};
  hsize_t n = 1;
  for (hsize_t x : d.dims) n *= x;
  d.v.resize(n);
  const hid_t mem = std::is_same_v<T, double> ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT;
  if (n > 0) {
    EXPECT_GE(H5Dread(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.v.data()), 0) << path;
  }
  H5Dclose(ds);
  return d;
}

hid_t vlen_string_type() {
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  return t;
}

std::vector<std::string> read_strings(hid_t file, const std::string& path) {
  const hid_t ds = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (ds < 0) throw std::runtime_error("no dataset " + path);
  const auto dims = shape(ds);
  std::vector<char*> raw(dims.at(0));
  const hid_t t = vlen_string_type();
  if (!raw.empty()) {
    EXPECT_GE(H5Dread(ds, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()), 0);
  }
  std::vector<std::string> out;
  for (char* s : raw) {
    out.emplace_back(s);
    H5free_memory(s);
  }
  H5Tclose(t);
  H5Dclose(ds);
  return out;
}

std::string string_attribute(hid_t file, const char* name) {
  const hid_t a = H5Aopen_by_name(file, "/", name, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) throw std::runtime_error(std::string("no attribute ") + name);
  const hid_t t = vlen_string_type();
  char* s = nullptr;
  H5Aread(a, t, &s);
  std::string out = s ? s : "";
  H5free_memory(s);
  H5Tclose(t);
  H5Aclose(a);
  return out;
}

int int_attribute(hid_t file, const char* name) {
  const hid_t a = H5Aopen_by_name(file, "/", name, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) throw std::runtime_error(std::string("no attribute ") + name);
  int v = -1;
  H5Aread(a, H5T_NATIVE_INT, &v);
  H5Aclose(a);
  return v;
}

// ---- XDMF and CSV ------------------------------------------------------------------------------

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// Well-formedness for the subset of XML the writer produces: every element closed, properly
/// nested, one root.
void expect_well_formed(const std::string& xml) {
  std::vector<std::string> open;
  int roots = 0;
  for (std::size_t i = xml.find('<'); i != std::string::npos; i = xml.find('<', i + 1)) {
    const std::size_t end = xml.find('>', i);
    ASSERT_NE(end, std::string::npos);
    const std::string tag = xml.substr(i + 1, end - i - 1);
    if (tag[0] == '?' || tag[0] == '!') continue;
    if (tag[0] == '/') {
      ASSERT_FALSE(open.empty()) << tag;
      EXPECT_EQ(open.back(), tag.substr(1));
      open.pop_back();
      continue;
    }
    const std::string name = tag.substr(0, tag.find_first_of(" />"));
    if (open.empty()) ++roots;
    if (tag.back() != '/') open.push_back(name);
  }
  EXPECT_TRUE(open.empty());
  EXPECT_EQ(roots, 1);
}

/// The attribute names of the first grid of an XDMF block, in order.
std::vector<std::string> attribute_names(const std::string& block_text) {
  std::vector<std::string> names;
  const std::string first = block_text.substr(0, block_text.find("</Grid>"));
  const std::regex attribute("<Attribute Name=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(first.begin(), first.end(), attribute); it != std::sregex_iterator(); ++it)
    names.push_back((*it)[1]);
  return names;
}

/// Checks the XDMF's structure and that each of its HDF references names an existing dataset of
/// the declared dimensions in `h5`, by a file name relative to the XDMF: a spatial collection of
/// the temporal collections "members", then "joints" and, for a model with constraints, a spatial
/// collection "constraints" of one temporal collection per constraint named after it
/// (`constraints`: their names), each with one grid per time and the attributes ParaView shows,
/// units in their names. With `bodies` (their names), "members" is a spatial collection of one
/// temporal collection per body, named after it.
void expect_xdmf_matches(const fs::path& xdmf, hid_t h5, const std::vector<double>& times, bool joints = true,
                         const std::vector<std::string>& constraints = {}, const std::vector<std::string>& bodies = {}) {
  const std::string text = slurp(xdmf);
  expect_well_formed(text);
  EXPECT_NE(text.find("CollectionType=\"Spatial\""), std::string::npos);
  EXPECT_EQ(text.find("<Grid Name=\"constraints\" GridType=\"Collection\" CollectionType=\"Spatial\">") !=
                std::string::npos,
            !constraints.empty());
  EXPECT_EQ(text.find("<Grid Name=\"members\" GridType=\"Collection\" CollectionType=\"Spatial\">") !=
                std::string::npos,
            !bodies.empty());

  std::vector<std::string> expected_blocks = bodies;
  if (bodies.empty()) expected_blocks.emplace_back("members");
  const std::size_t member_blocks = expected_blocks.size();
  if (joints) expected_blocks.emplace_back("joints");
  expected_blocks.insert(expected_blocks.end(), constraints.begin(), constraints.end());
  const std::regex temporal("<Grid Name=\"([^\"]+)\" GridType=\"Collection\" CollectionType=\"Temporal\">");
  std::vector<std::string> blocks;
  std::vector<std::size_t> starts;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), temporal); it != std::sregex_iterator(); ++it) {
    blocks.push_back((*it)[1]);
    starts.push_back(static_cast<std::size_t>(it->position()));
  }
  ASSERT_EQ(blocks, expected_blocks);
  starts.push_back(text.size());
  const std::vector<std::string> reactions{"reaction_force [N]", "reaction_moment [N m]", "constraint"};
  const std::map<std::string, std::vector<std::string>> attributes{
      {"members",
       {"displacement [m]", "axial_force [N]", "utilization", "von_mises [Pa]", "bending_moment [N m]",
        "shear_force [N]", "torque [N m]", "section_forces [N, N m]", "body", "element"}},
      {"joints", {"velocity [m/s]", "axis_x", "axis_y", "axis_z", "body"}}};
  // HDF references per grid: cells, points, displacement (points now and at step 0), axial
  // force, the five member stress arrays, the section forces, body, element; joints: vertices,
  // positions, then one
  // per attribute; a constraint: its position, force and moment (its vertex and index are inline
  // numbers).
  const std::map<std::string, int> references_per_grid{{"members", 13}, {"joints", 7}};
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const std::string block = text.substr(starts[b], starts[b + 1] - starts[b]);
    SCOPED_TRACE(blocks[b]);
    const bool constraint = b >= member_blocks + (joints ? 1u : 0u);
    const std::string kind = b < member_blocks ? "members" : blocks[b];
    const std::regex uniform("<Grid Name=\"" + blocks[b] + " ([0-9]+)\" GridType=\"Uniform\">");
    long k = 0;
    for (auto it = std::sregex_iterator(block.begin(), block.end(), uniform); it != std::sregex_iterator(); ++it, ++k)
      EXPECT_EQ(std::stol((*it)[1]), k);
    EXPECT_EQ(k, static_cast<long>(times.size()));
    const std::regex time("<Time Value=\"([^\"]+)\"/>");
    std::size_t t = 0;
    for (auto it = std::sregex_iterator(block.begin(), block.end(), time); it != std::sregex_iterator(); ++it, ++t) {
      ASSERT_LT(t, times.size());
      EXPECT_EQ(std::stod((*it)[1]), times[t]);
    }
    EXPECT_EQ(t, times.size());
    EXPECT_EQ(attribute_names(block), constraint ? reactions : attributes.at(kind));
    if (constraint) {  // its own row of the constraint series
      EXPECT_NE(block.find(">0 " + std::to_string(b - member_blocks - (joints ? 1 : 0)) + " 0 1 1 1 1 1 3<"),
                std::string::npos);
    }

    const std::regex item("<DataItem Dimensions=\"([0-9 ]+)\"([^>]*)Format=\"HDF\">([^<:]+):([^<]+)</DataItem>");
    int references = 0;
    for (auto it = std::sregex_iterator(block.begin(), block.end(), item); it != std::sregex_iterator(); ++it) {
      ++references;
      const std::string attrs = (*it)[2], file = (*it)[3], path = (*it)[4];
      EXPECT_EQ(file, xdmf.stem().string() + ".h5");
      ASSERT_TRUE(exists(h5, path)) << path;
      const hid_t ds = H5Dopen2(h5, path.c_str(), H5P_DEFAULT);
      std::vector<hsize_t> declared;
      std::istringstream dims((*it)[1]);
      for (hsize_t d; dims >> d;) declared.push_back(d);
      EXPECT_EQ(shape(ds), declared) << path;
      const hid_t type = H5Dget_type(ds);
      if (H5Tget_class(type) == H5T_FLOAT) {  // the declared precision is the dataset's
        EXPECT_NE(attrs.find("Precision=\"" + std::to_string(H5Tget_size(type)) + "\""), std::string::npos) << path;
      }
      H5Tclose(type);
      H5Dclose(ds);
    }
    EXPECT_EQ(references, (constraint ? 3 : references_per_grid.at(kind)) * static_cast<int>(times.size()));
  }
  const std::regex function("<DataItem ItemType=\"Function\" Function=\"\\$0 - \\$1\" Dimensions=\"1 [0-9]+ 3\">");
  EXPECT_EQ(std::distance(std::sregex_iterator(text.begin(), text.end(), function), std::sregex_iterator()),
            static_cast<long>(times.size() * member_blocks));
}

/// The model's constraint names, in order.
std::vector<std::string> constraint_names(const Model& model) {
  std::vector<std::string> names;
  for (const Constraint& c : model.constraints) names.push_back(c.name);
  return names;
}

std::vector<std::vector<std::string>> read_csv(const fs::path& p) {
  std::ifstream f(p);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(f, line);) {
    rows.emplace_back();
    std::istringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) rows.back().push_back(cell);
  }
  return rows;
}

// ---- tests ----------------------------------------------------------------------------------------

TEST(ResultWriter, RoundTripOfThreeSteps) {
  ScratchDir dir;
  Recording run(testing::kitchen_sink_model(), 3);
  const Model& model = run.model;
  const int probe_d = model.find_joint("d.1"), probe_a = model.find_joint("a.0");
  ResultWriter writer(model, {dir.path.string(), "results", {probe_d, probe_a}, {}});
  EXPECT_EQ(writer.h5_path(), dir.path / "results.h5");
  for (const auto& s : run.states) writer.append(s);
  EXPECT_EQ(writer.steps_written(), 3);
  writer.close();
  writer.close();  // idempotent
  EXPECT_THROW(writer.append(run.states[0]), std::logic_error);

  H5File f(writer.h5_path());
  ASSERT_GE(f.id, 0);
  EXPECT_EQ(string_attribute(f.id, "generator"), "latticedyn");
  EXPECT_EQ(string_attribute(f.id, "title"), model.title);
  EXPECT_EQ(int_attribute(f.id, "format_version"), 4);

  const std::vector<double> times{0.0, 0.1, 0.2};
  EXPECT_EQ(read<double>(f.id, "/time").v, times);

  // Static description.
  std::vector<int> trans, rot, scal, vect;
  for (int b = 0; b < static_cast<int>(model.blocks.size()); ++b) {
    switch (model.blocks[b].kind) {
      case SlotKind::translation: trans.push_back(b); break;
      case SlotKind::rotation: rot.push_back(b); break;
      case SlotKind::scalar: scal.push_back(b); break;
      case SlotKind::vector: vect.push_back(b); break;
    }
  }
  ASSERT_FALSE(scal.empty());  // the kitchen sink's cubic spline beam
  ASSERT_FALSE(vect.empty());  // and rope
  EXPECT_EQ(read<int>(f.id, "/model/translation_blocks").v, trans);
  EXPECT_EQ(read<int>(f.id, "/model/rotation_blocks").v, rot);
  const auto joint_names = read_strings(f.id, "/model/joint_names");
  ASSERT_EQ(joint_names.size(), model.joints.size());
  for (std::size_t j = 0; j < model.joints.size(); ++j) EXPECT_EQ(joint_names[j], model.joints[j].name);
  const auto types = read_strings(f.id, "/model/constraint_types");
  const auto rows = read<int>(f.id, "/model/constraint_rows").v;
  ASSERT_EQ(types.size(), model.constraints.size());
  for (std::size_t c = 0; c < model.constraints.size(); ++c) {
    EXPECT_EQ(types[c], to_string(model.constraints[c].type));
    EXPECT_EQ(rows[c], model.constraints[c].rows());
  }
  EXPECT_EQ(read_strings(f.id, "/model/element_types").at(0), "rigid_body");
  EXPECT_EQ(read_strings(f.id, "/model/body_names").at(0), "ground");

  const auto pos = read<double>(f.id, "/blocks/position");
  const auto vel = read<double>(f.id, "/blocks/velocity");
  const auto phi = read<double>(f.id, "/blocks/rotation_vector");
  const auto R = read<double>(f.id, "/blocks/rotation_matrix");
  const auto omega = read<double>(f.id, "/blocks/angular_velocity");
  EXPECT_EQ(pos.dims, (std::vector<hsize_t>{3, trans.size(), 3}));
  EXPECT_EQ(R.dims, (std::vector<hsize_t>{3, rot.size(), 3, 3}));
  EXPECT_EQ(read<int>(f.id, "/model/scalar_blocks").v, scal);
  EXPECT_EQ(read<int>(f.id, "/model/vector_blocks").v, vect);
  const auto scalar = read<double>(f.id, "/blocks/scalar_position");
  const auto vector = read<double>(f.id, "/blocks/vector");
  EXPECT_EQ(scalar.dims, (std::vector<hsize_t>{3, scal.size()}));
  EXPECT_EQ(vector.dims, (std::vector<hsize_t>{3, vect.size(), 3}));
  const auto jpos = read<double>(f.id, "/joints/position");
  const auto jvel = read<double>(f.id, "/joints/velocity");
  EXPECT_EQ(jpos.dims, (std::vector<hsize_t>{3, model.joints.size(), 3}));
  const auto lambda = read<double>(f.id, "/constraints/multipliers");
  const auto violation = read<double>(f.id, "/constraints/violation");
  EXPECT_EQ(lambda.dims, (std::vector<hsize_t>{3, static_cast<hsize_t>(model.num_multipliers())}));
  const auto axial = read<double>(f.id, "/elements/axial_force");
  const auto energy = read<double>(f.id, "/energy");
  const auto energy_total = read<double>(f.id, "/energy_total");
  const auto drive_value = read<double>(f.id, "/drives/value");
  EXPECT_EQ(read_strings(f.id, "/model/drive_names"), model.drive_names);
  ASSERT_EQ(drive_value.dims, (std::vector<hsize_t>{3, model.drives.size()}));
  for (hsize_t k = 0; k < 3; ++k)
    for (hsize_t d = 0; d < model.drives.size(); ++d)
      EXPECT_EQ(drive_value.at({k, d}), model.drives[d].evaluate(run.states[k].time()).value);

  for (hsize_t k = 0; k < 3; ++k) {
    const ModelState& s = run.states[k];
    for (hsize_t i = 0; i < trans.size(); ++i)
      for (hsize_t c = 0; c < 3; ++c) {
        EXPECT_EQ(pos.at({k, i, c}), s.block(trans[i]).pos(c));
        EXPECT_EQ(vel.at({k, i, c}), s.block(trans[i]).vel(c));
      }
    for (hsize_t i = 0; i < rot.size(); ++i) {
      const Vec3 p = rotation_vector(s.block(rot[i]).rot);
      EXPECT_LE(p.norm(), std::numbers::pi + 1e-12);
      for (hsize_t c = 0; c < 3; ++c) {
        EXPECT_EQ(phi.at({k, i, c}), p(c));
        EXPECT_EQ(omega.at({k, i, c}), s.block(rot[i]).vel(c));
        for (hsize_t d = 0; d < 3; ++d) EXPECT_EQ(R.at({k, i, c, d}), s.block(rot[i]).rot(c, d));  // row-major
      }
    }
    for (hsize_t i = 0; i < scal.size(); ++i) EXPECT_EQ(scalar.at({k, i}), s.block(scal[i]).pos(0));
    for (hsize_t i = 0; i < vect.size(); ++i)
      for (hsize_t c = 0; c < 3; ++c) EXPECT_EQ(vector.at({k, i, c}), s.block(vect[i]).pos(c));
    for (hsize_t j = 0; j < model.joints.size(); ++j)
      for (hsize_t c = 0; c < 3; ++c) {
        EXPECT_EQ(jpos.at({k, j, c}), s.joint_position(static_cast<int>(j))(c));
        EXPECT_EQ(jvel.at({k, j, c}), s.joint_velocity(static_cast<int>(j))(c));
      }
    hsize_t row = 0;
    for (std::size_t c = 0; c < model.constraints.size(); ++c) {
      const Eigen::VectorXd l = s.multipliers(static_cast<int>(c));
      for (int i = 0; i < l.size(); ++i) EXPECT_EQ(lambda.at({k, row++}), l(i));
      EXPECT_EQ(violation.at({k, c}), s.constraint_values(static_cast<int>(c)).cwiseAbs().maxCoeff());
    }
    if (k == 2) {
      EXPECT_NE(lambda.at({k, 0}), 0.0);  // the multipliers did move
    }
    for (hsize_t e = 0; e < model.elements.size(); ++e) {
      const auto N = s.axial_force(static_cast<int>(e));
      if (N) {
        EXPECT_EQ(axial.at({k, e}), *N);
      } else {
        EXPECT_TRUE(std::isnan(axial.at({k, e})));
      }
    }
    const ElementEnergy E = s.energy();
    EXPECT_EQ(energy.at({k, 0}), E.kinetic);
    EXPECT_EQ(energy.at({k, 1}), E.gravity_potential);
    EXPECT_EQ(energy.at({k, 2}), E.strain);
    EXPECT_DOUBLE_EQ(energy_total.v[k], E.kinetic + E.gravity_potential + E.strain);
  }

  // Drawing: 2 strut ties (2 axis points, a cell of 1 line each), 4 rigid bodies with 2 joints (a
  // star of one 2-point cell each), 3 beam and rope elements (5 axis points, a polyline cell of 4
  // lines each); rigid body elements have no axis points. A cell carries its values once.
  const auto points = read<double>(f.id, "/viz/points");
  EXPECT_FALSE(exists(f.id, "/viz/displacement")) << "the XDMF computes the displacement from the points";
  const auto cells = read<int>(f.id, "/viz/cells");
  const auto offsets = read<int>(f.id, "/viz/cell_offsets");
  const auto lines = read<int>(f.id, "/viz/lines");
  const auto line_cell = read<int>(f.id, "/viz/line_cell");
  const auto body = read<int>(f.id, "/viz/body");
  const auto element = read<int>(f.id, "/viz/element");
  const auto viz_axial = read<double>(f.id, "/viz/axial_force");
  const hsize_t np = 2 * 2 + 4 * 2 + 3 * 5, nc = 2 + 4 + 3, nl = 2 + 4 + 3 * 4;
  EXPECT_EQ(points.dims, (std::vector<hsize_t>{3, np, 3}));
  EXPECT_EQ(cells.dims, (std::vector<hsize_t>{(2 + 4) * (2 + 2) + 3 * (2 + 5)}));
  EXPECT_EQ(offsets.dims, (std::vector<hsize_t>{nc + 1}));
  EXPECT_EQ(lines.dims, (std::vector<hsize_t>{nl, 2}));
  EXPECT_EQ(line_cell.dims, (std::vector<hsize_t>{nl}));
  EXPECT_EQ(body.dims, (std::vector<hsize_t>{nc}));
  EXPECT_EQ(element.dims, (std::vector<hsize_t>{nc}));
  EXPECT_EQ(viz_axial.dims, (std::vector<hsize_t>{3, nc}));
  // Every cell a polyline (XDMF's mixed topology: code 2, point count, points) whose segments are
  // its lines, in order.
  ASSERT_EQ(offsets.v.front(), 0);
  ASSERT_EQ(offsets.v.back(), static_cast<int>(cells.v.size()));
  std::size_t line = 0;
  for (hsize_t c = 0; c < nc; ++c) {
    const int at = offsets.v[c], n = cells.v[static_cast<std::size_t>(at) + 1];
    EXPECT_EQ(cells.v[static_cast<std::size_t>(at)], 2);
    ASSERT_EQ(offsets.v[c + 1] - at, n + 2);
    for (int i = 0; i + 1 < n; ++i, ++line) {
      ASSERT_LT(line, nl);
      EXPECT_EQ(line_cell.v[line], static_cast<int>(c));
      EXPECT_EQ(lines.v[2 * line], cells.v[static_cast<std::size_t>(at + 2 + i)]);
      EXPECT_EQ(lines.v[2 * line + 1], cells.v[static_cast<std::size_t>(at + 3 + i)]);
    }
  }
  EXPECT_EQ(line, nl);
  for (hsize_t k = 0; k < 3; ++k) {
    const ModelState& s = run.states[k];
    auto point = [&](int p) {
      return Vec3(points.at({k, hsize_t(p), 0}), points.at({k, hsize_t(p), 1}), points.at({k, hsize_t(p), 2}));
    };
    for (hsize_t c = 0; c < nc; ++c) {
      const int e = element.v[c], n = cells.v[static_cast<std::size_t>(offsets.v[c]) + 1];
      std::vector<Vec3> expected;
      if (e >= 0) {
        expected = model.elements[e].element->axis_points(s.element_slots(e), s.context());
        EXPECT_EQ(body.v[c], model.elements[e].body);
        EXPECT_EQ(viz_axial.at({k, c}), *s.axial_force(e));
      } else {
        const Body& bd = model.bodies[body.v[c]];
        EXPECT_EQ(bd.type, "rigid_body");
        expected = {s.joint_position(bd.joints[0]), s.joint_position(bd.joints[1])};
        EXPECT_EQ(viz_axial.at({k, c}), 0.0);
      }
      ASSERT_EQ(n, static_cast<int>(expected.size()));
      for (int i = 0; i < n; ++i) {
        const int p = cells.v[static_cast<std::size_t>(offsets.v[c] + 2 + i)];
        ASSERT_TRUE(p >= 0 && p < static_cast<int>(np));
        // Drawing coordinates are stored in single precision.
        EXPECT_LT((point(p) - expected[static_cast<std::size_t>(i)]).norm(),
                  1e-6 * (1 + expected[static_cast<std::size_t>(i)].norm()));
      }
    }
  }

  expect_xdmf_matches(writer.xdmf_path(), f.id, times, true, constraint_names(model));

  const auto csv = read_csv(writer.csv_path());
  ASSERT_EQ(csv.size(), 4u);
  for (const auto& row : csv) EXPECT_EQ(row.size(), 13u);
  EXPECT_EQ(csv[0][0], "time [s]");
  EXPECT_EQ(csv[0][1], "d.1.x [m]");
  EXPECT_EQ(csv[0][12], "a.0.vz [m/s]");
  for (int k = 0; k < 3; ++k) {
    const ModelState& s = run.states[k];
    EXPECT_EQ(std::stod(csv[k + 1][0]), times[k]);
    EXPECT_EQ(std::stod(csv[k + 1][2]), s.joint_position(probe_d).y());  // the shortest round-trip text reads back exactly
    EXPECT_EQ(std::stod(csv[k + 1][12]), s.joint_velocity(probe_a).z());
  }
}

TEST(ResultWriter, RecordsTheCoordinatesAStartStateReadsBack) {
  ScratchDir dir;
  Recording run(testing::kitchen_sink_model(), 3);
  ResultWriter writer(run.model, {dir.path.string(), "results", {}, {}});
  for (const auto& s : run.states) writer.append(s);
  writer.close();
  {
    H5File f(writer.h5_path());
    const auto q = read<double>(f.id, "/state/coordinates");
    ASSERT_EQ(q.dims, (std::vector<hsize_t>{3, run.states[0].coordinates().size()}));
  }
  for (long step : {0L, 1L, -1L}) {
    const RecordedState r = read_recorded_state(writer.h5_path(), step);
    const std::size_t k = step < 0 ? 2 : static_cast<std::size_t>(step);
    const auto expected = run.states[k].coordinates_in_model_order();
    EXPECT_EQ(r.coordinates, std::vector<double>(expected.begin(), expected.end())) << step;
    EXPECT_EQ(r.time, run.states[k].time());
    EXPECT_EQ(r.steps, 3);
  }
  auto message = [&](const fs::path& p, long step) {
    try {
      read_recorded_state(p, step);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(writer.h5_path(), 3).find("step 3 is out of range: the file holds 3 steps"), std::string::npos);
  EXPECT_NE(message(writer.h5_path(), -4).find("out of range"), std::string::npos);
  EXPECT_NE(message(dir.path / "none.h5", -1).find("no such file"), std::string::npos);
  std::ofstream(dir.path / "text.h5") << "not hdf5";
  EXPECT_NE(message(dir.path / "text.h5", -1).find("not an HDF5 file"), std::string::npos);
}

TEST(ResultWriter, FilesAreReadableWhileTheWriterIsOpen) {
  ScratchDir dir;
  Recording run(testing::kitchen_sink_model(), 2);
  ResultWriter writer(run.model, {dir.path.string(), "partial", {0}, {}});
  for (const auto& s : run.states) writer.append(s);

  // What a killed process leaves is the file's bytes on disk: read a copy of them.
  const fs::path copy = dir.path / "copy.h5";
  fs::copy_file(writer.h5_path(), copy);
  {
    H5File f(copy);
    ASSERT_GE(f.id, 0);
    EXPECT_EQ(read<double>(f.id, "/time").v, (std::vector<double>{0.0, 0.1}));
    const auto jpos = read<double>(f.id, "/joints/position");
    ASSERT_EQ(jpos.dims.at(0), 2u);
    EXPECT_EQ(jpos.at({1, 3, 2}), run.states[1].joint_position(3).z());
    EXPECT_EQ(read<double>(f.id, "/viz/points").dims.at(0), 2u);
    EXPECT_EQ(read<double>(f.id, "/constraints/multipliers").dims.at(0), 2u);
  }
  {
    H5File f(writer.h5_path());  // the file itself, writer still open
    ASSERT_GE(f.id, 0);
    EXPECT_EQ(read<double>(f.id, "/energy_total").dims.at(0), 2u);
    expect_xdmf_matches(writer.xdmf_path(), f.id, {0.0, 0.1}, true, constraint_names(run.model));
  }
  EXPECT_FALSE(fs::exists(dir.path / "partial.xdmf.tmp"));
  EXPECT_EQ(read_csv(writer.csv_path()).size(), 3u);
  EXPECT_EQ(writer.steps_written(), 2);
}

TEST(ResultWriter, ModelWithoutConstraintsAndDrawSequences) {
  ModelBuilder b;
  b.set_title("two bodies");
  const auto boom = testing::add_rigid_body(b, "boom", 2.0, Vec3::Zero(), Vec3(0.1, 0.2, 0.3));
  for (int i = 0; i < 3; ++i) testing::add_body_joint(b, boom, std::to_string(i), Vec3(i, 0.5 * i * i, 0));
  b.set_draw_sequence(boom.body, {0, 1, 2, 0});  // closed triangle: 3 points, 3 lines
  const auto hook = testing::add_rigid_body(b, "hook", 1.0, Vec3(3, 0, 0), Vec3::Zero());
  testing::add_body_joint(b, hook, "eye", Vec3(0, 0, -1));  // origin to joint: 2 points, 1 line
  Recording run(b.build(), 2);

  ScratchDir dir;
  ResultWriter writer(run.model, {dir.path.string(), "free", {}, {}});
  for (const auto& s : run.states) writer.append(s);
  writer.close();

  H5File f(writer.h5_path());
  ASSERT_GE(f.id, 0);
  EXPECT_EQ(string_attribute(f.id, "title"), "two bodies");
  EXPECT_FALSE(exists(f.id, "/constraints/multipliers"));
  EXPECT_FALSE(exists(f.id, "/constraints/violation"));
  EXPECT_EQ(read<int>(f.id, "/model/constraint_rows").dims, (std::vector<hsize_t>{0}));
  EXPECT_EQ(read_strings(f.id, "/model/constraint_names").size(), 0u);
  EXPECT_EQ(read<int>(f.id, "/model/constraint_joints").dims, (std::vector<hsize_t>{0, 2}));

  const auto points = read<double>(f.id, "/viz/points");
  const auto lines = read<int>(f.id, "/viz/lines");
  EXPECT_EQ(points.dims, (std::vector<hsize_t>{2, 5, 3}));
  EXPECT_EQ(lines.v, (std::vector<int>{0, 1, 1, 2, 2, 0, 3, 4}));
  // A rigid body draws 2-point cells, one per line.
  EXPECT_EQ(read<int>(f.id, "/viz/cells").v, (std::vector<int>{2, 2, 0, 1, 2, 2, 1, 2, 2, 2, 2, 0, 2, 2, 3, 4}));
  EXPECT_EQ(read<int>(f.id, "/viz/body").v, (std::vector<int>{boom.body, boom.body, boom.body, hook.body}));
  const ModelState& s = run.states[1];
  const int eye = run.model.find_joint("hook.eye");
  for (hsize_t c = 0; c < 3; ++c) {
    EXPECT_EQ(points.at({1, 3, c}), static_cast<float>(s.block(run.model.joints[eye].translation_block).pos(c)));
    EXPECT_EQ(points.at({1, 4, c}), static_cast<float>(s.joint_position(eye)(c)));
  }
  // The joints' frames, for glyphs in ParaView: the columns of the joint's rotation.
  const Mat3 frame = s.joint_frame_of(eye).second;
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = read<double>(f.id, std::string("/viz/joint_axis_") + "xyz"[axis]);
    ASSERT_EQ(a.dims, (std::vector<hsize_t>{2, run.model.joints.size(), 3}));
    for (hsize_t c = 0; c < 3; ++c)
      EXPECT_EQ(a.at({1, static_cast<hsize_t>(eye), c}), static_cast<float>(frame(static_cast<int>(c), axis)));
  }
  EXPECT_EQ(read<int>(f.id, "/viz/joint_vertices").v.size(), run.model.joints.size());
  EXPECT_FALSE(exists(f.id, "/viz/constraint_vertices"));
  expect_xdmf_matches(writer.xdmf_path(), f.id, {0.0, 0.1});
  const auto csv = read_csv(writer.csv_path());
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv[0], std::vector<std::string>{"time [s]"});
}

TEST(ResultWriter, SuperTrussIsDrawnMemberByMemberWithItsMemberForces) {
  // A 3-bay triangular section as one super truss; the recorded states stretch and bend it, so
  // members carry different forces, and each drawn member cell must carry its own.
  const char* text = R"(materials:
  steel: {density: 7800, youngs_modulus: 2.06e11, poisson_ratio: 0.25}
sections:
  chord: {type: round_tube, outer_radius: 0.1, inner_radius: 0.08}
  lacing: {type: round_tube, outer_radius: 0.05, inner_radius: 0.04}
truss_sections:
  tri:
    length: 6
    order: 3
    end1: [[1, 0], [-0.5, 0.8], [-0.5, -0.8]]
    main_beams: [[1, 1], [2, 2], [3, 3]]
    cross_beams1: [[1, 2], [2, 3], [3, 1]]
    cross_beams2: [[1, 2], [2, 3], [3, 1]]
    material: steel
    main_section: chord
    sub_section: lacing
bodies:
  - {name: boom, type: super_truss, section: tri}
)";
  Recording run(read_simulation_from_string(text, "tri.yaml").model, 2);
  const Model& model = run.model;
  ASSERT_EQ(model.elements.size(), 1u);
  const auto& truss = dynamic_cast<const SuperTrussElement&>(*model.elements[0].element);
  ScratchDir dir;
  ResultWriter writer(model, {dir.path.string(), "truss", {}, {}});
  for (const auto& s : run.states) writer.append(s);
  writer.close();

  H5File f(writer.h5_path());
  const auto cells = read<int>(f.id, "/viz/cells");
  const auto offsets = read<int>(f.id, "/viz/cell_offsets");
  const auto element = read<int>(f.id, "/viz/element");
  const auto viz_axial = read<double>(f.id, "/viz/axial_force");
  const auto viz_member = read<int>(f.id, "/viz/member");
  const auto section_forces = read<double>(f.id, "/viz/section_forces");
  const auto von_mises = read<double>(f.id, "/viz/von_mises");
  const ModelState& s = run.states[1];
  ElementOutput out;
  truss.output(s.element_slots(0), s.context(), out);
  const auto polylines = truss.axis_polylines(s.element_slots(0), s.context());
  const std::vector<double> forces = truss.member_axial_forces(s.element_slots(0));
  ASSERT_EQ(polylines.size(), forces.size());
  // One cell per member, in member order, through its axis points.
  ASSERT_EQ(element.v.size(), polylines.size());
  ASSERT_EQ(viz_axial.dims, (std::vector<hsize_t>{2, polylines.size()}));
  ASSERT_EQ(section_forces.dims, (std::vector<hsize_t>{2, polylines.size(), 12}));
  double smallest = INFINITY, largest = -INFINITY;
  for (std::size_t m = 0; m < polylines.size(); ++m) {
    EXPECT_EQ(element.v[m], 0);
    EXPECT_EQ(cells.v[static_cast<std::size_t>(offsets.v[m]) + 1], static_cast<int>(polylines[m].size()));
    EXPECT_EQ(viz_axial.at({1, m}), forces[m]) << "member " << m;
    // Each cell carries its own member's recovered resultants and stress.
    EXPECT_EQ(viz_member.v[m], static_cast<int>(m));
    EXPECT_EQ(section_forces.at({1, m, 0}), out.members[m].end[0].N) << "member " << m;
    EXPECT_EQ(section_forces.at({1, m, 10}), out.members[m].end[1].My) << "member " << m;
    EXPECT_EQ(von_mises.at({1, m}), out.members[m].von_mises) << "member " << m;
    smallest = std::min(smallest, forces[m]);
    largest = std::max(largest, forces[m]);
  }
  EXPECT_GT(largest - smallest, 1e3);  // the members really differ, so a mix-up would show
  expect_xdmf_matches(writer.xdmf_path(), f.id, {0.0, 0.1});
}

// A hydraulic circuit's results: every flow by name (pumps, valves, the four paths of a reversing
// valve, the cylinder's chambers) in the HDF5 file and the probe CSV, the oil's energy, and the
// energy account as handed to the writer.
TEST(ResultWriter, HydraulicFlowsAndTheEnergyAccount) {
  const char* text = R"(title: circuit
gravity: [0, 0, -9.81]
drives:
  spool: {type: constant, value: 0.5}
hydraulics:
  nodes:
    - {name: supply, volume: 1.0e-3, pressure: 1.0e7}
    - {name: a, volume: 1.0e-4, pressure: 2.0e6}
    - {name: b, volume: 1.0e-4, pressure: 1.0e6}
    - {name: tank, pressure: 0, fixed: true}
  elements:
    - {name: pump, type: pump, node: supply, flow: 1.0e-4}
    - {name: relief, type: relief_valve, from: supply, to: tank, area: 1.0e-5, cracking_pressure: 2.0e7, full_open_pressure: 2.2e7}
    - {name: valve, type: directional_valve, ports: {P: supply, T: tank, A: a, B: b}, area: 2.0e-5, spool: spool}
bodies:
  - {name: ram, type: hydraulic_cylinder, ends: [[0, 0, 0], [0, 0, 1.5]], retracted_length: 1.0, stroke: 1.0,
     piston_diameter: 0.1, rod_diameter: 0.05, dead_volumes: [1.0e-4, 1.0e-4], ports: [a, b]}
)";
  Recording run(read_simulation_from_string(text, "circuit.yaml").model, 2);
  const Model& model = run.model;
  ScratchDir dir;
  const int probe = model.find_joint("ram.2");
  ResultWriter writer(model, {dir.path.string(), "circuit", {probe}, {}});
  EnergyAccount account;
  for (std::size_t k = 0; k < run.states.size(); ++k) {
    account.supplied = 100.0 * (k + 1), account.dissipated = 60.0 * (k + 1), account.compression = 3.0 * (k + 1);
    account.mechanical_change = 30.0 * (k + 1), account.fluid_change = 2.5 * (k + 1);
    writer.set_energy_account(account);
    writer.append(run.states[k]);
  }
  writer.close();

  // In element order: the bodies come before the circuit's elements.
  const std::vector<std::string> names = {"ram.Q_piston", "ram.Q_rod", "pump.Q", "relief.Q", "valve.Q_PA", "valve.Q_BT",
                                          "valve.Q_PB", "valve.Q_AT"};
  H5File f(writer.h5_path());
  EXPECT_EQ(read_strings(f.id, "/hydraulics/flow_names"), names);
  const auto flow = read<double>(f.id, "/hydraulics/flow");
  const ModelState& s = run.states[1];
  std::size_t column = 0;
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    const Element& el = *model.elements[e].element;
    std::vector<double> q(el.flow_names().size());
    el.flows(s.element_slots(static_cast<int>(e)), s.context(), q);
    for (double x : q) EXPECT_EQ(flow.at({1, column++}), x) << names[column - 1];
  }
  ASSERT_EQ(column, names.size());
  EXPECT_NE(flow.at({1, 4}), 0.0);  // P->A is half open
  const auto energy = read<double>(f.id, "/hydraulics/energy");
  EXPECT_EQ(energy.at({1, 0}), 200.0);
  EXPECT_EQ(energy.at({1, 5}), 200.0 - 120.0 - 6.0 - 60.0);  // the imbalance
  const ElementEnergy e1 = s.energy();
  EXPECT_GT(e1.fluid, 0.0);
  EXPECT_DOUBLE_EQ(read<double>(f.id, "/energy_fluid").v[1], e1.fluid);
  EXPECT_DOUBLE_EQ(read<double>(f.id, "/energy_total").v[1], e1.kinetic + e1.gravity_potential + e1.strain + e1.fluid);

  const auto csv = read_csv(writer.csv_path());
  ASSERT_EQ(csv.size(), 3u);
  const auto& header = csv[0];
  const auto at = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  };
  EXPECT_DOUBLE_EQ(std::stod(csv[2][at("valve.Q_PA [m^3/s]")]), flow.at({1, 4}));
  int node_a = -1;
  for (int b = 0; b < static_cast<int>(model.blocks.size()); ++b)
    if (model.blocks[b].label == "hydraulic node a") node_a = b;
  ASSERT_GE(node_a, 0);
  EXPECT_DOUBLE_EQ(std::stod(csv[2][at("a.p [Pa]")]), s.block(node_a).pos(0));
  EXPECT_EQ(std::stod(csv[2][at("work supplied [J]")]), 200.0);
  EXPECT_EQ(std::stod(csv[2][at("energy imbalance [J]")]), 14.0);
}

// Constraints get a block each, named after them, up to kMaxNamedConstraints; a model with more
// gets one block of all (a grid per constraint and step would swell the file for a list nobody
// browses).
TEST(Xdmf, ConstraintsAreNamedBlocksUpToALimit) {
  for (const int n : {3, io::kMaxNamedConstraints, io::kMaxNamedConstraints + 1}) {
    SCOPED_TRACE(n);
    // 2 cells of 2 points: 8 entries.
    io::XdmfLayout layout{
        .h5_name = "r.h5", .title = "t", .points = 4, .cells = 2, .cell_entries = 8, .joints = 5, .constraints = n};
    for (int c = 0; c < n; ++c) layout.constraint_names.push_back("c<" + std::to_string(c) + ">");
    io::XdmfDocument doc(layout);
    doc.add_step(0.0);
    doc.add_step(0.5);
    const std::string x = doc.text();
    expect_well_formed(x);
    const bool named = n <= io::kMaxNamedConstraints;
    EXPECT_EQ(x.find("<Grid Name=\"constraints\" GridType=\"Collection\" CollectionType=\"Spatial\">") != std::string::npos,
              named);
    EXPECT_EQ(x.find("<Grid Name=\"constraints\" GridType=\"Collection\" CollectionType=\"Temporal\">") != std::string::npos,
              !named);
    // Names are escaped for XML.
    EXPECT_EQ(x.find("<Grid Name=\"c&lt;0&gt;\" GridType=\"Collection\" CollectionType=\"Temporal\">") != std::string::npos,
              named);
  }
}

// The writer streams the document piece by piece (io::XdmfDocument::write): the same bytes as
// text(), for no steps, one and many (the step count every HDF item declares grows with them).
TEST(Xdmf, WriteStreamsTheSameTextAsText) {
  ScratchDir dir;
  fs::create_directories(dir.path);
  io::XdmfLayout layout{.h5_name = "r.h5",
                        .title = "t",
                        .points = 4,
                        .cells = 2,
                        .cell_entries = 8,
                        .joints = 5,
                        .constraints = 3,
                        .constraint_names = {"a", "b", "c"}};
  io::XdmfDocument doc(layout);
  const fs::path path = dir.path / "r.xdmf";
  for (int steps = 0; steps <= 12; steps += 4) {
    while (doc.steps() < steps) doc.add_step(0.25 * doc.steps());
    io::replace_file(path, [&doc](std::FILE* f) { doc.write(f); });
    std::ifstream in(path, std::ios::binary);
    const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(written, doc.text()) << steps << " steps";
    if (steps > 0) {
      EXPECT_NE(written.find("Dimensions=\"" + std::to_string(steps) + " 5 3\""), std::string::npos);
    }
  }
  EXPECT_NE(doc.text().find("<Time Value=\"2.75\"/>"), std::string::npos);  // step 11's time
}

// A writer that fails leaves the file as it was and no temporary beside it.
TEST(Xdmf, ReplaceFileKeepsTheOldFileWhenWritingFails) {
  ScratchDir dir;
  fs::create_directories(dir.path);
  const fs::path path = dir.path / "r.xdmf";
  io::replace_file(path, std::string("old"));
  EXPECT_THROW(io::replace_file(path,
                                [](std::FILE* f) {
                                  std::fputs("half", f);
                                  throw std::runtime_error("interrupted");
                                }),
               std::runtime_error);
  std::ifstream in(path);
  std::string text;
  std::getline(in, text);
  EXPECT_EQ(text, "old");
  EXPECT_FALSE(fs::exists(dir.path / "r.xdmf.tmp"));
  // A stream in error (here: written to after reading was asked for) is a write failure named
  // after the temporary, which is removed.
  try {
    io::replace_file(path, [](std::FILE* f) { std::fgetc(f); });
    FAIL() << "expected a write error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir.path / "r.xdmf.tmp"));
  std::ifstream again(path);
  std::getline(again, text);
  EXPECT_EQ(text, "old");
}

// Bodies get a block each when asked, named after them, up to kMaxNamedBodies; beyond, or
// not asked (no bodies in the layout), one "members" block of all.
TEST(Xdmf, BodiesAreNamedBlocksUpToALimit) {
  for (const int n : {0, 1, io::kMaxNamedBodies, io::kMaxNamedBodies + 1}) {
    SCOPED_TRACE(n);
    // n + 1 cells of 2 points: 4 entries each.
    io::XdmfLayout layout{.h5_name = "r.h5", .title = "t", .points = 2 * n + 2, .cells = n + 1, .cell_entries = 4 * (n + 1)};
    for (int b = 0; b < n; ++b)
      layout.bodies.push_back(io::XdmfBody{.name = "b&" + std::to_string(b),
                                           .first_cell = b,
                                           .cells = 1,
                                           .first_point = 2 * b,
                                           .points = 2,
                                           .first_entry = 4 * b,
                                           .entries = 4});
    io::XdmfDocument doc(layout);
    doc.add_step(0.0);
    doc.add_step(0.5);
    const std::string x = doc.text();
    expect_well_formed(x);
    const bool named = n >= 1 && n <= io::kMaxNamedBodies;
    EXPECT_EQ(layout.names_bodies(), named);
    EXPECT_EQ(x.find("<Grid Name=\"members\" GridType=\"Collection\" CollectionType=\"Spatial\">") != std::string::npos,
              named);
    EXPECT_EQ(x.find("<Grid Name=\"members\" GridType=\"Collection\" CollectionType=\"Temporal\">") != std::string::npos,
              !named);
    EXPECT_EQ(x.find("<Grid Name=\"b&amp;0\" GridType=\"Collection\" CollectionType=\"Temporal\">") != std::string::npos,
              named);
    if (named) {  // the last body: its cell (row n - 1 of n + 1, entries 4 n - 4 to 4 n of the
                  // mixed topology) and its two points from 2 n - 2
      const std::string last = std::to_string(n - 1), point = std::to_string(2 * n - 2);
      EXPECT_NE(x.find(">" + std::to_string(4 * n - 4) + " 1 4</DataItem>"), std::string::npos);
      EXPECT_NE(x.find(">" + last + " 1 1</DataItem>"), std::string::npos);  // its body and element
      EXPECT_NE(x.find(">1 " + point + " 0 1 1 1 1 2 3</DataItem>"), std::string::npos);
      EXPECT_NE(x.find(">1 " + last + " 1 1 1 1</DataItem>"), std::string::npos);  // its axial force at step 1
    }
  }
}

// With output.body_blocks, each drawn body is a block of its own named after it: its rows of the
// /viz datasets, its cells numbered from its first point (/viz/body_cells).
TEST(ResultWriter, BodyBlocksNameEachBodyAndSelectItsRows) {
  ScratchDir dir;
  Recording run(testing::kitchen_sink_model(), 2);
  const Model& model = run.model;
  ResultWriterOptions options{dir.path.string(), "results", {}, {}};
  options.body_blocks = true;
  ResultWriter writer(model, options);
  for (const auto& s : run.states) writer.append(s);
  writer.close();

  H5File f(writer.h5_path());
  const auto cells = read<int>(f.id, "/viz/cells"), local = read<int>(f.id, "/viz/body_cells");
  const auto offsets = read<int>(f.id, "/viz/cell_offsets");
  const auto body = read<int>(f.id, "/viz/body");
  ASSERT_EQ(local.dims, cells.dims);
  // The drawn bodies in cell order, each one run of cells.
  std::vector<std::string> names;
  std::vector<std::size_t> first{0};
  for (std::size_t c = 0; c < body.v.size(); ++c)
    if (c > 0 && body.v[c] != body.v[c - 1]) first.push_back(c);
  first.push_back(body.v.size());
  ASSERT_GE(first.size(), 4u);  // at least three bodies drawn
  const std::string text = slurp(writer.xdmf_path());
  for (std::size_t i = 0; i + 1 < first.size(); ++i) {
    const std::size_t from = first[i], to = first[i + 1];
    names.push_back(model.bodies[body.v[from]].name);
    SCOPED_TRACE(names.back());
    int lo = cells.v[static_cast<std::size_t>(offsets.v[from]) + 2], hi = lo;
    for (std::size_t c = from; c < to; ++c)
      for (int k = offsets.v[c] + 2; k < offsets.v[c + 1]; ++k) {
        lo = std::min(lo, cells.v[static_cast<std::size_t>(k)]);
        hi = std::max(hi, cells.v[static_cast<std::size_t>(k)]);
      }
    // Its cells numbered from its first point; the types and counts as they are.
    for (std::size_t c = from; c < to; ++c) {
      const auto at = static_cast<std::size_t>(offsets.v[c]);
      EXPECT_EQ(local.v[at], cells.v[at]);
      EXPECT_EQ(local.v[at + 1], cells.v[at + 1]);
      for (auto k = at + 2; k < static_cast<std::size_t>(offsets.v[c + 1]); ++k) EXPECT_EQ(local.v[k] + lo, cells.v[k]);
    }
    const std::string entries = std::to_string(offsets.v[to] - offsets.v[from]), points = std::to_string(hi - lo + 1);
    // Its block selects its cells' entries, its rows of the per-cell data and, at every step, its
    // points. The XML item's text is built by appending (">" + std::string trips GCC 12's -Wrestrict).
    auto item = [](const std::string& values) { return std::string(">").append(values).append("</DataItem>"); };
    EXPECT_NE(text.find(item(std::to_string(offsets.v[from]) + " 1 " + entries)), std::string::npos);
    EXPECT_NE(text.find(item(std::to_string(from) + " 1 " + std::to_string(to - from))), std::string::npos);
    for (int step : {0, 1})
      EXPECT_NE(text.find(item(std::to_string(step) + " " + std::to_string(lo) + " 0 1 1 1 1 " + points + " 3")),
                std::string::npos);
  }
  expect_xdmf_matches(writer.xdmf_path(), f.id, {0.0, 0.1}, true, constraint_names(model), names);
}

// A body whose cells come in two runs cannot be a block of its own without copying its data: the
// ranges are then empty (and the XDMF draws one block of all).
TEST(VizGeometry, BodyRangesNeedEachBodysCellsInOneRun) {
  Recording run(testing::kitchen_sink_model(), 1);
  const io::VizGeometry viz = io::VizGeometry::plan(run.states[0]);
  const auto ranges = viz.body_ranges();
  ASSERT_GE(ranges.size(), 2u);
  int cells = 0, entries = 0;
  for (const auto& r : ranges) {
    EXPECT_EQ(r.first_cell, cells);
    EXPECT_EQ(r.first_entry, entries);
    EXPECT_EQ(r.first_entry, viz.cell_offsets()[static_cast<std::size_t>(r.first_cell)]);
    cells += r.cells;
    entries += r.entries;
  }
  EXPECT_EQ(cells, viz.num_cells());
  EXPECT_EQ(entries, static_cast<int>(viz.cells().size()));
  // The first element given to the body of the last one drawn: that body now has two runs.
  std::size_t e = 0;
  while (run.model.elements[e].body != ranges[0].body) ++e;
  run.model.elements[e].body = ranges.back().body;
  EXPECT_TRUE(io::VizGeometry::plan(run.states[0]).body_ranges().empty());
}

TEST(ResultWriter, ANewRunTruncatesTheFilesOfTheLast) {
  ScratchDir dir;
  Recording run(testing::kitchen_sink_model(), 2);
  {
    ResultWriter first(run.model, {dir.path.string(), "results", {}, {}});
    for (const auto& s : run.states) first.append(s);
  }
  ResultWriter second(run.model, {dir.path.string(), "results", {}, {}});
  EXPECT_FALSE(fs::exists(second.xdmf_path()));  // it would describe steps the new .h5 lacks
  H5File f(second.h5_path());
  ASSERT_GE(f.id, 0);
  EXPECT_EQ(read<double>(f.id, "/time").dims, (std::vector<hsize_t>{0}));
  EXPECT_EQ(read_csv(second.csv_path()).size(), 1u);
}

TEST(ResultWriter, UnwritableLocationsNameThePath) {
  ScratchDir dir;
  fs::create_directories(dir.path);
  const Model model = testing::kitchen_sink_model();

  // A regular file where a directory should be (root ignores permission bits, this it cannot).
  std::ofstream(dir.path / "plain_file") << "x";
  const fs::path below_file = dir.path / "plain_file" / "out";
  try {
    ResultWriter w(model, {below_file.string(), "results", {}, {}});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(below_file.string()), std::string::npos) << e.what();
  }

  // The .h5 path taken by a directory: H5Fcreate fails; the message carries HDF5's reason.
  fs::create_directories(dir.path / "taken" / "results.h5");
  try {
    ResultWriter w(model, {(dir.path / "taken").string(), "results", {}, {}});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find((dir.path / "taken" / "results.h5").string()), std::string::npos) << what;
    EXPECT_NE(what.find("Is a directory"), std::string::npos) << what;
  }
}

TEST(ResultWriter, RejectsBadOptions) {
  ScratchDir dir;
  Model model = testing::kitchen_sink_model();
  EXPECT_THROW(ResultWriter(model, {dir.path.string(), "results", {99}, {}}), std::invalid_argument);
  EXPECT_THROW(ResultWriter(model, {dir.path.string(), "a:b", {}, {}}), std::invalid_argument);
  EXPECT_THROW(ResultWriter(model, {dir.path.string(), "", {}, {}}), std::invalid_argument);
  model.bodies[1].draw_sequence = {0, 5};
  EXPECT_THROW(ResultWriter(model, {dir.path.string(), "results", {}, {}}), std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
