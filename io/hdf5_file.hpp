// Thin RAII layer over the HDF5 C API for the results writer: owned identifiers, errors turned
// into exceptions that carry HDF5's own messages, static datasets and growing time series.
#pragma once

#include <hdf5.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace latticedyn::io {

/// Owns an HDF5 identifier and closes it with the matching H5?close.
class Hid {
 public:
  using Closer = herr_t (*)(hid_t);
  Hid() = default;
  Hid(hid_t id, Closer close) : id_(id), close_(close) {}
  Hid(Hid&& o) noexcept;
  Hid& operator=(Hid&& o) noexcept;
  Hid(const Hid&) = delete;
  Hid& operator=(const Hid&) = delete;
  ~Hid() { reset(); }

  hid_t get() const { return id_; }
  /// Closes the identifier (if any); returns the close call's status.
  herr_t reset();

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

/// Turns off HDF5's automatic printing of error stacks while alive, so that a failure is reported
/// once, in the exception, with the stack's messages (which carry the OS reason, e.g. errno text).
class QuietHdf5Errors {
 public:
  QuietHdf5Errors();
  ~QuietHdf5Errors();
  QuietHdf5Errors(const QuietHdf5Errors&) = delete;
  QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// The outermost and innermost messages on HDF5's default error stack; clears the stack.
std::string hdf5_error_stack();

/// Error context of one file: every failure becomes a std::runtime_error naming the file, the
/// operation and HDF5's reason.
struct Hdf5Context {
  std::filesystem::path file;
  /// Dataset transfer list of every write: H5P_DEFAULT, or an MPI-IO one for a file that several
  /// ranks write together (then every rank makes every call, in the same order).
  hid_t transfer = H5P_DEFAULT;
  /// Whether this process writes the datasets written whole (write_dataset): on a file written
  /// collectively only one rank does, the others take part in the call with nothing selected.
  bool writes_whole = true;

  [[noreturn]] void fail(const std::string& what) const;
  Hid own(hid_t id, Hid::Closer close, const std::string& what) const {
    if (id < 0) fail(what);
    return Hid(id, close);
  }
  void check(herr_t status, const std::string& what) const {
    if (status < 0) fail(what);
  }
};

Hid create_group(hid_t parent, const std::string& name, const Hdf5Context& ctx);
/// An existing group (a results file continued from a checkpoint).
Hid open_group(hid_t parent, const std::string& name, const Hdf5Context& ctx);

/// Scalar variable-length UTF-8 string attribute.
void write_string_attribute(hid_t obj, const char* name, const std::string& value, const Hdf5Context& ctx);
/// Scalar (n == 1) or 1-D numeric attribute stored as `file_type`.
void write_numeric_attribute(hid_t obj, const char* name, hid_t file_type, hid_t mem_type, hsize_t n,
                             const void* data, const Hdf5Context& ctx);

/// Static contiguous dataset; zero-size dimensions are allowed (nothing is written then).
void write_dataset(hid_t parent, const std::string& name, const std::vector<hsize_t>& dims, hid_t file_type,
                   hid_t mem_type, const void* data, const Hdf5Context& ctx);
/// int32 dataset of shape (n) or, with columns > 1, (n / columns, columns).
void write_ints(hid_t parent, const std::string& name, const std::vector<int>& v, const Hdf5Context& ctx,
                hsize_t columns = 1);
/// 1-D dataset of variable-length UTF-8 strings.
void write_strings(hid_t parent, const std::string& name, const std::vector<std::string>& v,
                   const Hdf5Context& ctx);

/// A float64 dataset of shape (T, row...) growing by one entry along its unlimited time axis per
/// step. Chunks hold up to 64 steps but about 1 MiB at most, so a chunk fits HDF5's default
/// per-dataset chunk cache and appending a step never re-reads a chunk from disk.
class Series {
 public:
  /// Every row dimension must be positive (HDF5 rejects zero chunk dimensions). `units` is stored
  /// as the dataset's "units" attribute.
  /// Rows are doubles in memory; `single` stores them as 32-bit floats (drawing coordinates).
  Series(hid_t parent, const std::string& name, std::vector<hsize_t> row, const char* units,
         const Hdf5Context& ctx, bool single = false);
  /// The existing series `name` of an earlier run, cut back to its first `keep` entries, to be
  /// extended from there (a run continued from a checkpoint). Fails if its rows are not `row`
  /// or it holds fewer entries. Cutting back leaves the last kept chunk in HDF5's chunk cache:
  /// flush the file before several ranks write past the cache (MPI-IO), or it would later
  /// overwrite their entries.
  static Series reopen(hid_t parent, const std::string& name, std::vector<hsize_t> row, hsize_t keep,
                       const Hdf5Context& ctx, bool single = false);

  /// This process's part of a row, written from now on: entries [lo, hi) along the row's first
  /// dimension (a row without dimensions: all of it for [0, 1), none for [0, 0)). Several ranks
  /// writing one file collectively each take their part; by default a process writes whole rows.
  void set_part(hsize_t lo, hsize_t hi);
  /// Entries along the row's first dimension (1 for a row without dimensions), and this
  /// process's part of them (set_part).
  hsize_t entries() const { return row_.empty() ? 1 : row_[0]; }
  hsize_t part_begin() const { return part_lo_; }
  hsize_t part_end() const { return part_hi_; }
  /// Doubles of this process's part of a row (what append_row() gives room for).
  int row_size() const { return row_size_; }
  /// Doubles of a whole row, whoever writes them.
  hsize_t whole_row_size() const { return whole_row_size_; }
  /// Bytes of the entries kept in memory until write_pending().
  std::size_t pending_bytes() const { return pending_.size() * sizeof(double); }
  /// Entries kept in memory until write_pending().
  std::size_t pending_rows() const { return pending_rows_; }
  /// Room for `rows` entries kept between writes, allocated once (growing by doubling touches
  /// twice the memory, every new page a fault).
  void reserve_rows(std::size_t rows) { pending_.reserve(rows * static_cast<std::size_t>(row_size_)); }
  /// Space for the next entry (row-major, row_size() doubles, not initialised), kept until
  /// write_pending(): the caller fills it whole before the next call, without a copy in between.
  double* append_row();
  /// Keeps the next entry (row-major `row`) until write_pending().
  void append(const double* row);
  /// Forgets the entries appended after the first `rows` still pending (a step whose filling failed).
  void discard_rows_after(std::size_t rows);
  /// Extends the time axis by the entries appended since the last call and writes them, all in
  /// one HDF5 call (per-call costs, not bytes, dominate the writing of small rows).
  void write_pending(const Hdf5Context& ctx);
  herr_t close() { return ds_.reset(); }

 private:
  Series() = default;
  std::string name_;
  std::vector<hsize_t> row_;
  hsize_t part_lo_ = 0, part_hi_ = 0;  // this process's entries along row_[0] (or 0/1 without dimensions)
  int row_size_ = 0;            // doubles of this process's part of a row
  hsize_t whole_row_size_ = 0;  // doubles of a whole row
  std::size_t pending_rows_ = 0;
  hsize_t written_ = 0;         // entries in the file
  // A vector whose resize leaves new doubles uninitialised: rows are written once, by their filler.
  template <class T>
  struct UninitializedAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
      using other = UninitializedAllocator<U>;
    };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept {
      ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
  };
  std::vector<double, UninitializedAllocator<double>> pending_;  // entries appended since, row after row
  std::vector<float> pending_single_;  // a series stored as float: its pending entries converted to write
  bool single_ = false;                // stored as float: converted here (HDF5's conversion is slower)
  Hid ds_;
};

}  // namespace latticedyn::io
