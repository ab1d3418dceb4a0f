// The growing time series of the results file: rows filled in place, kept until written, stored as
// float64 or float32, and a step whose filling failed forgotten; read back with the HDF5 C API.
#include "io/hdf5_file.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <vector>

namespace latticedyn::io {
namespace {

namespace fs = std::filesystem;

struct ScratchFile {
  fs::path path = fs::temp_directory_path() / ("latticedyn_series_" + std::to_string(::getpid()) + "_" +
                                               ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".h5");
  ~ScratchFile() {
    std::error_code ec;
    fs::remove(path, ec);
  }
};

// The dataset `name` of `file` as doubles, with its dimensions.
std::vector<double> read_all(const fs::path& file, const char* name, std::vector<hsize_t>& dims, hid_t* type_class = nullptr) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  dims.assign(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  if (!v.empty()) H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  if (type_class) {
    const hid_t t = H5Dget_type(ds);
    *type_class = static_cast<hid_t>(H5Tget_size(t));
    H5Tclose(t);
  }
  H5Sclose(space);
  H5Dclose(ds);
  H5Fclose(f);
  return v;
}

TEST(Hdf5Series, RowsFilledInPlaceAreWrittenInOrderInBothPrecisions) {
  ScratchFile scratch;
  const Hdf5Context ctx{scratch.path};
  {
    const Hid file = ctx.own(H5Fcreate(scratch.path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create");
    Series wide(file.get(), "wide", {2, 3}, "m", ctx);
    Series narrow(file.get(), "narrow", {4}, "m", ctx, true);
    wide.reserve_rows(2);  // fewer than will be kept: the rows grow past it
    for (int step = 0; step < 5; ++step) {
      double* w = wide.append_row();
      for (int i = 0; i < 6; ++i) w[i] = 10.0 * step + i + 0.125;
      const double n[4] = {step + 1.0 / 3.0, -1.0 * step, 1e-3 * step, 7.0};
      narrow.append(n);
      EXPECT_EQ(wide.pending_rows(), static_cast<std::size_t>(step % 3 + 1));
      if (step == 2) {  // a write in the middle, as the writer does when rows pile up
        wide.write_pending(ctx);
        narrow.write_pending(ctx);
        EXPECT_EQ(wide.pending_rows(), 0u);
        EXPECT_EQ(wide.pending_bytes(), 0u);
      }
    }
    wide.write_pending(ctx);
    narrow.write_pending(ctx);
  }
  std::vector<hsize_t> dims;
  hid_t size = 0;
  const std::vector<double> w = read_all(scratch.path, "wide", dims, &size);
  ASSERT_EQ(dims, (std::vector<hsize_t>{5, 2, 3}));
  EXPECT_EQ(size, 8);
  for (int step = 0; step < 5; ++step)
    for (int i = 0; i < 6; ++i) EXPECT_EQ(w[static_cast<std::size_t>(6 * step + i)], 10.0 * step + i + 0.125);
  const std::vector<double> n = read_all(scratch.path, "narrow", dims, &size);
  ASSERT_EQ(dims, (std::vector<hsize_t>{5, 4}));
  EXPECT_EQ(size, 4);  // stored as float32: the values rounded to float
  for (int step = 0; step < 5; ++step) {
    EXPECT_EQ(n[static_cast<std::size_t>(4 * step)], static_cast<double>(static_cast<float>(step + 1.0 / 3.0)));
    EXPECT_EQ(n[static_cast<std::size_t>(4 * step + 2)], static_cast<double>(static_cast<float>(1e-3 * step)));
    EXPECT_EQ(n[static_cast<std::size_t>(4 * step + 3)], 7.0);
  }
}

TEST(Hdf5Series, AStepWhoseFillingFailedIsNotWritten) {
  ScratchFile scratch;
  const Hdf5Context ctx{scratch.path};
  {
    const Hid file = ctx.own(H5Fcreate(scratch.path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create");
    Series s(file.get(), "s", {3}, "1", ctx);
    for (int step = 0; step < 2; ++step) {
      double* r = s.append_row();
      for (int i = 0; i < 3; ++i) r[i] = step + 0.5 * i;
    }
    double* half = s.append_row();  // the third step's filler fails after one entry
    half[0] = -99.0;
    s.discard_rows_after(2);
    EXPECT_EQ(s.pending_rows(), 2u);
    s.write_pending(ctx);
  }
  std::vector<hsize_t> dims;
  const std::vector<double> v = read_all(scratch.path, "s", dims);
  ASSERT_EQ(dims, (std::vector<hsize_t>{2, 3}));
  EXPECT_EQ(v, (std::vector<double>{0.0, 0.5, 1.0, 1.0, 1.5, 2.0}));
}

}  // namespace
}  // namespace latticedyn::io
