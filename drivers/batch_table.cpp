// Writing the batch table.
#include "drivers/batch_table.hpp"

#include "io/hdf5_file.hpp"

#include <cstdio>
#include <fstream>
#include <limits>

namespace latticedyn {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

void write_batch_table(const BatchSpec& spec, const std::vector<std::string>& results,
                       const std::map<int, CaseRecord>& records, const std::filesystem::path& csv,
                       const std::filesystem::path& h5) {
  std::vector<std::string> numeric = spec.columns;
  numeric.insert(numeric.end(), results.begin(), results.end());
  const std::size_t n = spec.cases.size();
  std::vector<std::vector<double>> cols(numeric.size() + 3, std::vector<double>(n, kNaN));
  std::vector<std::string> status(n, "not run"), label(n), error(n);
  std::vector<int> index(n);
  for (std::size_t c = 0; c < n; ++c) {
    const BatchCase& bc = spec.cases[c];
    index[c] = bc.index;
    label[c] = bc.label;
    for (std::size_t k = 0; k < bc.values.size(); ++k) cols[k][c] = bc.values[k];
    const auto it = records.find(bc.index);
    if (it == records.end()) continue;
    const CaseRecord& r = it->second;
    status[c] = r.ok ? "ok" : "failed";
    error[c] = r.error;
    for (std::size_t k = 0; k < results.size() && k < r.values.size(); ++k) cols[spec.columns.size() + k][c] = r.values[k];
    cols[numeric.size()][c] = r.evaluations;
    cols[numeric.size() + 1][c] = r.newton_iterations;
    cols[numeric.size() + 2][c] = r.wall_seconds;
  }
  std::vector<std::string> all = numeric;
  all.insert(all.end(), {"evaluations", "newton_iterations", "wall_seconds"});

  const std::filesystem::path tmp = csv.string() + ".part";
  {
    std::ofstream f(tmp);
    f << "case,label,status";
    for (const auto& c : all) f << "," << csv_text(c);
    f << ",error\n";
    char buf[40];
    for (std::size_t c = 0; c < n; ++c) {
      f << index[c] << "," << csv_text(label[c]) << "," << status[c];
      for (const auto& col : cols) {
        std::snprintf(buf, sizeof buf, ",%.17g", col[c]);
        f << buf;
      }
      f << "," << csv_text(error[c]) << "\n";
    }
    if (!f) throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, csv);  // a reader never sees half a table

  const io::Hdf5Context ctx{h5};
  const io::QuietHdf5Errors quiet;
  const std::filesystem::path h5tmp = h5.string() + ".part";
  {
    io::Hid file = ctx.own(H5Fcreate(h5tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create the file");
    io::write_string_attribute(file.get(), "batch", spec.source, ctx);
    io::write_string_attribute(file.get(), "model", spec.model_path, ctx);
    io::Hid table = io::create_group(file.get(), "table", ctx);
    io::write_ints(table.get(), "case", index, ctx);
    io::write_strings(table.get(), "label", label, ctx);
    io::write_strings(table.get(), "status", status, ctx);
    io::write_strings(table.get(), "error", error, ctx);
    io::write_strings(table.get(), "columns", all, ctx);
    for (std::size_t k = 0; k < all.size(); ++k)
      io::write_dataset(table.get(), all[k], {n}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, cols[k].data(), ctx);
  }
  std::filesystem::rename(h5tmp, h5);
}

}  // namespace latticedyn
