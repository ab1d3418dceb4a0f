// HDF5 layout of a linearised model; matrices transposed into row-major as HDF5 readers expect.
#include "io/linear_model_file.hpp"

#include "io/hdf5_file.hpp"

namespace latticedyn::io {

void write_linear_model(const std::filesystem::path& path, const LinearModel& model) {
  const Hdf5Context ctx{path};
  const Hid file = ctx.own(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create the file");
  const hid_t root = file.get();
  auto matrix = [&](const char* name, const Eigen::MatrixXd& m) {
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = m;
    write_dataset(root, name, {static_cast<hsize_t>(m.rows()), static_cast<hsize_t>(m.cols())}, H5T_IEEE_F64LE,
                  H5T_NATIVE_DOUBLE, rows.data(), ctx);
  };
  matrix("A", model.A);
  matrix("B", model.B);
  matrix("C", model.C);
  matrix("D", model.D);
  write_strings(root, "inputs", model.inputs, ctx);
  write_strings(root, "outputs", model.outputs, ctx);
  write_numeric_attribute(root, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &model.time, ctx);
  write_numeric_attribute(root, "independent", H5T_STD_I32LE, H5T_NATIVE_INT, 1, &model.independent, ctx);
  write_string_attribute(root, "states", "z, z', u, u' (independent coordinates, their rates, the inputs' drive values and rates)", ctx);
}

}  // namespace latticedyn::io
