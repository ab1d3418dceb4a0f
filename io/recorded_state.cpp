// Reads one row of /state/coordinates and the matching /time entry from a results file.
#include "io/recorded_state.hpp"

#include "io/hdf5_file.hpp"

#include <array>
#include <stdexcept>

namespace latticedyn {

namespace {

// Failures name the file and what was expected of it; HDF5's own reason follows where it has one.
struct Reading {
  std::filesystem::path file;
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("'" + file.string() + "': " + what);
  }
  io::Hid own(hid_t id, io::Hid::Closer close, const std::string& what) const {
    if (id < 0) fail("cannot " + what + ": " + io::hdf5_error_stack());
    return io::Hid(id, close);
  }
  void check(herr_t status, const std::string& what) const {
    if (status < 0) fail("cannot " + what + ": " + io::hdf5_error_stack());
  }
};

// Shape of a time series' dataspace, (T, n) or (T), as {T, n}.
std::array<hsize_t, 2> series_shape(hid_t space, const Reading& ctx) {
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 1 || rank > 2) ctx.fail("expected a time series of rows");
  std::array<hsize_t, 2> dims = {0, 1};
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  return dims;
}

hsize_t steps_of(hid_t ds, const Reading& ctx) {
  const io::Hid space = ctx.own(H5Dget_space(ds), H5Sclose, "read a dataspace");
  return series_shape(space.get(), ctx)[0];
}

// Row `row` (< T) of a float64 time series.
std::vector<double> read_row(hid_t ds, hsize_t row, const Reading& ctx) {
  const io::Hid space = ctx.own(H5Dget_space(ds), H5Sclose, "read a dataspace");
  const auto dims = series_shape(space.get(), ctx);
  const hsize_t start[2] = {row, 0}, count[2] = {1, dims[1]};
  ctx.check(H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr), "select a step");
  const io::Hid mem = ctx.own(H5Screate_simple(H5Sget_simple_extent_ndims(space.get()), count, nullptr), H5Sclose,
                              "create a memory space");
  std::vector<double> out(static_cast<std::size_t>(dims[1]));
  ctx.check(H5Dread(ds, H5T_NATIVE_DOUBLE, mem.get(), space.get(), H5P_DEFAULT, out.data()), "read a step");
  return out;
}

}  // namespace

RecordedState read_recorded_state(const std::filesystem::path& file, long step) {
  const Reading ctx{file};
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) ctx.fail("no such file");
  const io::QuietHdf5Errors quiet;
  if (H5Fis_hdf5(file.c_str()) <= 0) ctx.fail("not an HDF5 file");
  const io::Hid f = ctx.own(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open the file");
  if (H5Lexists(f.get(), "state", H5P_DEFAULT) <= 0 || H5Lexists(f.get(), "state/coordinates", H5P_DEFAULT) <= 0)
    ctx.fail("no /state/coordinates: not a latticedyn results file, or one written before states were recorded");
  const io::Hid coords = ctx.own(H5Dopen2(f.get(), "state/coordinates", H5P_DEFAULT), H5Dclose, "open /state/coordinates");
  const io::Hid times = ctx.own(H5Dopen2(f.get(), "time", H5P_DEFAULT), H5Dclose, "open /time");
  const long n = static_cast<long>(steps_of(coords.get(), ctx));
  if (n == 0) ctx.fail("the file holds no step");
  if (static_cast<long>(steps_of(times.get(), ctx)) != n) ctx.fail("/time does not match /state/coordinates");
  const long k = step < 0 ? n + step : step;
  if (k < 0 || k >= n)
    throw RecordedStepOutOfRange("'" + file.string() + "': step " + std::to_string(step) +
                                 " is out of range: the file holds " + std::to_string(n) + " steps (0.." +
                                 std::to_string(n - 1) + ", or -1 for the last)");
  RecordedState s;
  s.coordinates = read_row(coords.get(), static_cast<hsize_t>(k), ctx);
  s.time = read_row(times.get(), static_cast<hsize_t>(k), ctx).at(0);
  s.step = k;
  s.steps = n;
  return s;
}

}  // namespace latticedyn
