// Writing and reading /checkpoints/<step> groups: scalars as attributes, vectors as datasets.
#include "io/checkpoint.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace latticedyn {

namespace {

constexpr const char* kGroup = "checkpoints";

std::string group_name(long step) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%010ld", step);  // sorts by step
  return buf;
}

void put(hid_t g, const char* name, double v, const io::Hdf5Context& ctx) {
  io::write_numeric_attribute(g, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &v, ctx);
}
void put(hid_t g, const char* name, long v, const io::Hdf5Context& ctx) {
  io::write_numeric_attribute(g, name, H5T_STD_I64LE, H5T_NATIVE_LONG, 1, &v, ctx);
}
void put_vector(hid_t g, const char* name, const std::vector<double>& v, const io::Hdf5Context& ctx) {
  io::write_dataset(g, name, {v.size()}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), ctx);
}

// Reading: every failure names the file and the item.
struct Reader {
  std::filesystem::path file;
  [[noreturn]] void fail(const std::string& what) const { throw std::runtime_error("'" + file.string() + "': " + what); }
  template <class T>
  T attribute(hid_t g, const char* name, hid_t mem_type) const {
    T v{};
    const hid_t a = H5Aopen(g, name, H5P_DEFAULT);
    if (a < 0) fail(std::string("checkpoint without attribute '") + name + "'");
    const herr_t status = H5Aread(a, mem_type, &v);
    H5Aclose(a);
    if (status < 0) fail(std::string("cannot read attribute '") + name + "'");
    return v;
  }
  std::string text(hid_t g, const char* name) const {
    const hid_t a = H5Aopen(g, name, H5P_DEFAULT);
    if (a < 0) fail(std::string("checkpoint without attribute '") + name + "'");
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    char* s = nullptr;
    const herr_t status = H5Aread(a, type, &s);
    std::string out = status >= 0 && s ? s : "";
    if (s) H5free_memory(s);
    H5Tclose(type);
    H5Aclose(a);
    if (status < 0) fail(std::string("cannot read attribute '") + name + "'");
    return out;
  }
  std::vector<double> vector(hid_t g, const char* name) const {
    const hid_t ds = H5Dopen2(g, name, H5P_DEFAULT);
    if (ds < 0) fail(std::string("checkpoint without dataset '") + name + "'");
    const hid_t space = H5Dget_space(ds);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    std::vector<double> v(static_cast<std::size_t>(std::max<hssize_t>(n, 0)));
    const herr_t status = v.empty() ? 0 : H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Sclose(space);
    H5Dclose(ds);
    if (n < 0 || status < 0) fail(std::string("cannot read dataset '") + name + "'");
    return v;
  }
};

std::vector<std::string> member_names(hid_t group) {
  std::vector<std::string> names;
  H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr,
             [](hid_t, const char* name, const H5L_info_t*, void* out) -> herr_t {
               static_cast<std::vector<std::string>*>(out)->emplace_back(name);
               return 0;
             },
             &names);
  return names;
}

}  // namespace

void write_checkpoint(hid_t file, const Checkpoint& c, const io::Hdf5Context& ctx) {
  const io::Hid root = H5Lexists(file, kGroup, H5P_DEFAULT) > 0 ? io::open_group(file, kGroup, ctx)
                                                               : io::create_group(file, kGroup, ctx);
  const std::string name = group_name(c.resume.step);
  if (H5Lexists(root.get(), name.c_str(), H5P_DEFAULT) > 0)
    ctx.check(H5Ldelete(root.get(), name.c_str(), H5P_DEFAULT), "replace checkpoint " + name);
  const io::Hid g = io::create_group(root.get(), name, ctx);
  const hid_t h = g.get();
  put(h, "time", c.time, ctx);
  put(h, "step", c.resume.step, ctx);
  put(h, "next_time_step", c.resume.next_time_step, ctx);
  io::write_string_attribute(h, "integrator", c.integrator, ctx);
  io::write_string_attribute(h, "velocities", c.velocities_are_rates ? "rotation_vector_rates" : "velocity_variables",
                             ctx);
  put(h, "newton_iterations", c.resume.newton_iterations, ctx);
  put(h, "rejected_steps", c.resume.rejected_steps, ctx);
  put(h, "rotation_rescales", c.resume.rotation_rescales, ctx);
  put(h, "jacobians", c.resume.jacobians, ctx);
  put(h, "max_violation", c.resume.max_violation, ctx);
  put(h, "violation_constraint", static_cast<long>(c.resume.violation_constraint), ctx);
  put(h, "outputs_written", c.outputs_written, ctx);
  put(h, "last_output", c.last_output, ctx);
  put(h, "next_output", c.next_output, ctx);
  put_vector(h, "coordinates", c.coordinates, ctx);
  put_vector(h, "velocities", c.velocities, ctx);
  put_vector(h, "accelerations", c.accelerations, ctx);
}

void remove_checkpoints_after(hid_t file, double t, const io::Hdf5Context& ctx) {
  if (H5Lexists(file, kGroup, H5P_DEFAULT) <= 0) return;
  const io::Hid root = io::open_group(file, kGroup, ctx);
  const Reader r{ctx.file};
  for (const std::string& name : member_names(root.get())) {
    const io::Hid g = io::open_group(root.get(), name, ctx);
    if (r.attribute<double>(g.get(), "time", H5T_NATIVE_DOUBLE) > t)
      ctx.check(H5Ldelete(root.get(), name.c_str(), H5P_DEFAULT), "remove checkpoint " + name);
  }
}

Checkpoint read_checkpoint(const std::filesystem::path& file, long step) {
  const Reader r{file};
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) r.fail("no such file");
  const io::QuietHdf5Errors quiet;
  if (H5Fis_hdf5(file.c_str()) <= 0) r.fail("not an HDF5 file");
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) r.fail("cannot open the file: " + io::hdf5_error_stack());
  const io::Hid owned(f, H5Fclose);
  if (H5Lexists(f, kGroup, H5P_DEFAULT) <= 0)
    r.fail("no checkpoint: the run that wrote it did not end, was not interrupted and had no checkpoint_interval");
  const hid_t root = H5Gopen2(f, kGroup, H5P_DEFAULT);
  if (root < 0) r.fail("cannot open /checkpoints");
  const io::Hid owned_root(root, H5Gclose);
  std::vector<std::string> names = member_names(root);
  if (names.empty()) r.fail("no checkpoint in /checkpoints");
  std::string name = names.back();
  if (step >= 0) {
    name = group_name(step);
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      std::string have;
      for (const std::string& n : names) {
        const std::size_t digits = std::min(n.find_first_not_of('0'), n.size() - 1);  // "0000000012" -> "12"
        have += (have.empty() ? "" : ", ") + n.substr(digits);
      }
      r.fail("no checkpoint at step " + std::to_string(step) + " (checkpoints at steps " + have + ")");
    }
  }
  const hid_t g = H5Gopen2(root, name.c_str(), H5P_DEFAULT);
  if (g < 0) r.fail("cannot open checkpoint " + name);
  const io::Hid owned_g(g, H5Gclose);
  Checkpoint c;
  c.time = r.attribute<double>(g, "time", H5T_NATIVE_DOUBLE);
  c.resume.step = r.attribute<long>(g, "step", H5T_NATIVE_LONG);
  c.resume.next_time_step = r.attribute<double>(g, "next_time_step", H5T_NATIVE_DOUBLE);
  c.integrator = r.text(g, "integrator");
  const std::string velocities = r.text(g, "velocities");
  if (velocities != "rotation_vector_rates" && velocities != "velocity_variables")
    r.fail("checkpoint " + name + ": unknown velocities '" + velocities + "'");
  c.velocities_are_rates = velocities == "rotation_vector_rates";
  c.resume.newton_iterations = r.attribute<long>(g, "newton_iterations", H5T_NATIVE_LONG);
  c.resume.rejected_steps = r.attribute<long>(g, "rejected_steps", H5T_NATIVE_LONG);
  c.resume.rotation_rescales = r.attribute<long>(g, "rotation_rescales", H5T_NATIVE_LONG);
  c.resume.jacobians = r.attribute<long>(g, "jacobians", H5T_NATIVE_LONG);
  c.resume.max_violation = r.attribute<double>(g, "max_violation", H5T_NATIVE_DOUBLE);
  c.resume.violation_constraint = static_cast<int>(r.attribute<long>(g, "violation_constraint", H5T_NATIVE_LONG));
  c.outputs_written = r.attribute<long>(g, "outputs_written", H5T_NATIVE_LONG);
  c.last_output = r.attribute<double>(g, "last_output", H5T_NATIVE_DOUBLE);
  c.next_output = r.attribute<double>(g, "next_output", H5T_NATIVE_DOUBLE);
  c.coordinates = r.vector(g, "coordinates");
  c.velocities = r.vector(g, "velocities");
  c.accelerations = r.vector(g, "accelerations");
  if (c.velocities.size() != c.coordinates.size() || c.accelerations.size() != c.coordinates.size())
    r.fail("checkpoint " + name + ": vectors of different lengths");
  if (!(c.resume.next_time_step > 0.0) || c.resume.step < 0 || c.outputs_written < 0)
    r.fail("checkpoint " + name + ": a step size, step or output count out of range");
  return c;
}

}  // namespace latticedyn
