// HDF5 helpers of the results writer. Every call's failure is turned into an exception at once,
// while HDF5's error stack still describes it.
#include "io/hdf5_file.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace latticedyn::io {

namespace {
constexpr hsize_t kMaxChunkSteps = 64;
// A flush writes every chunk the steps since the last one touched whole: chunks of about 4 kB keep
// that near the size of those steps (chunks of 1 MiB, flushed after every step, wrote a viz
// dataset's whole chunk, 23 steps of it, at every step: 2 GB for a 60 s crane run).
constexpr hsize_t kChunkBytes = hsize_t{1} << 12;

Hid string_type(const Hdf5Context& ctx) {
  Hid t = ctx.own(H5Tcopy(H5T_C_S1), H5Tclose, "create a string type");
  ctx.check(H5Tset_size(t.get(), H5T_VARIABLE), "create a string type");
  ctx.check(H5Tset_cset(t.get(), H5T_CSET_UTF8), "create a string type");
  return t;
}
}  // namespace

Hid::Hid(Hid&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}

Hid& Hid::operator=(Hid&& o) noexcept {
  if (this != &o) {
    reset();
    id_ = std::exchange(o.id_, H5I_INVALID_HID);
    close_ = o.close_;
  }
  return *this;
}

herr_t Hid::reset() {
  herr_t status = 0;
  if (id_ >= 0 && close_) status = close_(id_);
  id_ = H5I_INVALID_HID;
  return status;
}

QuietHdf5Errors::QuietHdf5Errors() {
  H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

QuietHdf5Errors::~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }

std::string hdf5_error_stack() {
  // The outermost message says what failed, the innermost why (for files: errno and its text);
  // the frames between repeat them.
  std::vector<std::string> messages;
  auto collect = [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
    if (e->desc && *e->desc) static_cast<std::vector<std::string>*>(data)->emplace_back(e->desc);
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collect, &messages);
  H5Eclear2(H5E_DEFAULT);
  if (messages.empty()) return "unknown HDF5 error";
  std::string text = messages.front();
  if (messages.size() > 1) text += "; " + messages.back();
  std::replace(text.begin(), text.end(), '\n', ' ');  // HDF5 embeds ctime() output
  return text;
}

void Hdf5Context::fail(const std::string& what) const {
  throw std::runtime_error("ResultWriter: '" + file.string() + "': cannot " + what + ": " + hdf5_error_stack());
}

Hid create_group(hid_t parent, const std::string& name, const Hdf5Context& ctx) {
  return ctx.own(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                 "create group '" + name + "'");
}

Hid open_group(hid_t parent, const std::string& name, const Hdf5Context& ctx) {
  return ctx.own(H5Gopen2(parent, name.c_str(), H5P_DEFAULT), H5Gclose, "open group '" + name + "'");
}

void write_string_attribute(hid_t obj, const char* name, const std::string& value, const Hdf5Context& ctx) {
  const std::string what = std::string("write attribute '") + name + "'";
  const Hid type = string_type(ctx);
  const Hid space = ctx.own(H5Screate(H5S_SCALAR), H5Sclose, what);
  const Hid attr =
      ctx.own(H5Acreate2(obj, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose, what);
  const char* c = value.c_str();
  ctx.check(H5Awrite(attr.get(), type.get(), &c), what);
}

void write_numeric_attribute(hid_t obj, const char* name, hid_t file_type, hid_t mem_type, hsize_t n,
                             const void* data, const Hdf5Context& ctx) {
  const std::string what = std::string("write attribute '") + name + "'";
  const Hid space =
      ctx.own(n == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr), H5Sclose, what);
  const Hid attr = ctx.own(H5Acreate2(obj, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose, what);
  ctx.check(H5Awrite(attr.get(), mem_type, data), what);
}

void write_dataset(hid_t parent, const std::string& name, const std::vector<hsize_t>& dims, hid_t file_type,
                   hid_t mem_type, const void* data, const Hdf5Context& ctx) {
  const std::string what = "write dataset '" + name + "'";
  const Hid space =
      ctx.own(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose, what);
  const Hid ds = ctx.own(
      H5Dcreate2(parent, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
      what);
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;
  if (total == 0) return;
  if (ctx.writes_whole) {
    ctx.check(H5Dwrite(ds.get(), mem_type, H5S_ALL, H5S_ALL, ctx.transfer, data), what);
  } else {  // another rank writes the whole dataset: this one takes part with nothing selected
    ctx.check(H5Sselect_none(space.get()), what);
    ctx.check(H5Dwrite(ds.get(), mem_type, space.get(), space.get(), ctx.transfer, data), what);
  }
}

void write_ints(hid_t parent, const std::string& name, const std::vector<int>& v, const Hdf5Context& ctx,
                hsize_t columns) {
  std::vector<hsize_t> dims{v.size() / columns};
  if (columns > 1) dims.push_back(columns);
  write_dataset(parent, name, dims, H5T_STD_I32LE, H5T_NATIVE_INT, v.data(), ctx);
}

void write_strings(hid_t parent, const std::string& name, const std::vector<std::string>& v,
                   const Hdf5Context& ctx) {
  std::vector<const char*> c;
  for (const auto& s : v) c.push_back(s.c_str());
  const Hid type = string_type(ctx);
  write_dataset(parent, name, {v.size()}, type.get(), type.get(), c.data(), ctx);
}

Series::Series(hid_t parent, const std::string& name, std::vector<hsize_t> row, const char* units,
               const Hdf5Context& ctx, bool single)
    : name_(name), row_(std::move(row)), single_(single) {
  const std::string what = "create dataset '" + name + "'";
  hsize_t size = 1;
  for (hsize_t d : row_) size *= d;
  set_part(0, row_.empty() ? 1 : row_[0]);
  std::vector<hsize_t> dims{0}, max_dims{H5S_UNLIMITED};
  std::vector<hsize_t> chunk{std::clamp<hsize_t>(kChunkBytes / (sizeof(double) * size), 1, kMaxChunkSteps)};
  for (hsize_t d : row_) {
    dims.push_back(d);
    max_dims.push_back(d);
    chunk.push_back(d);
  }
  const int rank = static_cast<int>(dims.size());
  const Hid space = ctx.own(H5Screate_simple(rank, dims.data(), max_dims.data()), H5Sclose, what);
  const Hid dcpl = ctx.own(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, what);
  ctx.check(H5Pset_chunk(dcpl.get(), rank, chunk.data()), what);
  // Every entry is written before it is read: no fill values (HDF5 would zero each new chunk).
  ctx.check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), what);
  // A series whose chunk is one row is only ever written in whole chunks: without a chunk cache
  // HDF5 writes them straight to the file instead of copying each through the cache first.
  const Hid dapl = ctx.own(H5Pcreate(H5P_DATASET_ACCESS), H5Pclose, what);
  if (chunk[0] == 1) ctx.check(H5Pset_chunk_cache(dapl.get(), 0, 0, H5D_CHUNK_CACHE_W0_DEFAULT), what);
  ds_ = ctx.own(
      H5Dcreate2(parent, name.c_str(), single ? H5T_IEEE_F32LE : H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, dcpl.get(),
                 dapl.get()),
      H5Dclose, what);
  write_string_attribute(ds_.get(), "units", units, ctx);
}

Series Series::reopen(hid_t parent, const std::string& name, std::vector<hsize_t> row, hsize_t keep,
                      const Hdf5Context& ctx, bool single) {
  const std::string what = "continue dataset '" + name + "'";
  Series s;
  s.name_ = name;
  s.row_ = std::move(row);
  s.single_ = single;
  s.set_part(0, s.row_.empty() ? 1 : s.row_[0]);
  s.ds_ = ctx.own(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), H5Dclose, what);
  const Hid space = ctx.own(H5Dget_space(s.ds_.get()), H5Sclose, what);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 1)));
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  if (rank != static_cast<int>(s.row_.size()) + 1 || !std::equal(s.row_.begin(), s.row_.end(), dims.begin() + 1))
    throw std::runtime_error("ResultWriter: '" + ctx.file.string() + "': dataset '" + name +
                             "' has rows of another shape: the file was written for another model");
  if (dims[0] < keep)
    throw std::runtime_error("ResultWriter: '" + ctx.file.string() + "': dataset '" + name + "' holds " +
                             std::to_string(dims[0]) + " steps, fewer than the " + std::to_string(keep) +
                             " the checkpoint counts");
  dims[0] = keep;
  ctx.check(H5Dset_extent(s.ds_.get(), dims.data()), what);
  s.written_ = keep;
  return s;
}

void Series::set_part(hsize_t lo, hsize_t hi) {
  const hsize_t n = row_.empty() ? 1 : row_[0];
  if (lo > hi || hi > n)
    throw std::invalid_argument("Series '" + name_ + "': part [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                ") outside its " + std::to_string(n) + " entries");
  hsize_t inner = 1;
  for (std::size_t d = 1; d < row_.size(); ++d) inner *= row_[d];
  part_lo_ = lo;
  part_hi_ = hi;
  row_size_ = static_cast<int>((hi - lo) * inner);
  whole_row_size_ = n * inner;
}

double* Series::append_row() {
  const std::size_t n = pending_.size();
  pending_.resize(n + static_cast<std::size_t>(row_size_));
  ++pending_rows_;
  return pending_.data() + n;
}

void Series::append(const double* row) { std::copy(row, row + row_size_, append_row()); }

void Series::discard_rows_after(std::size_t rows) {
  pending_rows_ = std::min(pending_rows_, rows);
  pending_.resize(pending_rows_ * static_cast<std::size_t>(row_size_));
}

void Series::write_pending(const Hdf5Context& ctx) {
  const auto rows = static_cast<hsize_t>(pending_rows_);
  if (rows == 0) return;
  const std::string what = "write steps " + std::to_string(written_) + ".." + std::to_string(written_ + rows - 1) +
                           " of '" + name_ + "'";
  std::vector<hsize_t> dims{written_ + rows}, start{written_}, count{rows};
  for (std::size_t d = 0; d < row_.size(); ++d) {
    dims.push_back(row_[d]);
    start.push_back(d == 0 ? part_lo_ : 0);
    count.push_back(d == 0 ? part_hi_ - part_lo_ : row_[d]);
  }
  const int rank = static_cast<int>(dims.size());
  ctx.check(H5Dset_extent(ds_.get(), dims.data()), what);
  const Hid file_space = ctx.own(H5Dget_space(ds_.get()), H5Sclose, what);
  const bool none = row_size_ == 0;  // another rank writes this row: take part in the call only
  if (none)
    ctx.check(H5Sselect_none(file_space.get()), what);
  else
    ctx.check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr),
              what);
  const Hid mem_space =
      none ? ctx.own(H5Scopy(file_space.get()), H5Sclose, what)
           : ctx.own(H5Screate_simple(rank, count.data(), nullptr), H5Sclose, what);
  static const double nothing = 0.0;
  if (single_) {
    pending_single_.assign(pending_.begin(), pending_.end());
    ctx.check(H5Dwrite(ds_.get(), H5T_NATIVE_FLOAT, mem_space.get(), file_space.get(), ctx.transfer,
                       none ? static_cast<const void*>(&nothing) : pending_single_.data()),
              what);
  } else {
    ctx.check(H5Dwrite(ds_.get(), H5T_NATIVE_DOUBLE, mem_space.get(), file_space.get(), ctx.transfer,
                       none ? &nothing : pending_.data()),
              what);
  }
  written_ += rows;
  pending_.clear();
  pending_rows_ = 0;
  pending_single_.clear();
}

}  // namespace latticedyn::io
