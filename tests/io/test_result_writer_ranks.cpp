// The results written collectively by several ranks (run under mpiexec with 2 and 3 ranks) against
// the same states written by one rank alone: the files must hold the same bytes.
#include "io/checkpoint.hpp"
#include "io/model_reader.hpp"
#include "io/result_writer.hpp"

#include "tests/io/recording.hpp"

#include <gtest/gtest.h>

#include <hdf5.h>
#include <petscvec.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace latticedyn {
namespace {

namespace fs = std::filesystem;

int rank_in_world() {
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  return rank;
}

/// One folder for all ranks (rank 0's process id), removed afterwards.
struct SharedDir {
  fs::path path;
  SharedDir() {
    long pid = ::getpid();
    MPI_Bcast(&pid, 1, MPI_LONG, 0, PETSC_COMM_WORLD);
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path = fs::temp_directory_path() / ("latticedyn_ranks_" + std::string(info->name()) + "_" + std::to_string(pid));
    if (rank_in_world() == 0) fs::remove_all(path);
    MPI_Barrier(PETSC_COMM_WORLD);
  }
  ~SharedDir() {
    MPI_Barrier(PETSC_COMM_WORLD);
    std::error_code ec;
    if (rank_in_world() == 0) fs::remove_all(path, ec);
  }
};

/// The model of `path` (its probes too) and states of it, the same on every rank (each rank
/// numbers the whole model alone).
struct Recorded {
  std::vector<int> probe_joints;
  testing::Recording recording;
  Recorded(const std::string& path, int n) : Recorded(read_simulation(path), n) {}
  Recorded(Simulation sim, int n) : probe_joints(sim.output.probe_joints), recording(std::move(sim.model), n) {}
  const Model& model() const { return recording.model; }
  const std::vector<ModelState>& states() const { return recording.states; }

  ResultWriterOptions options(const fs::path& dir, MPI_Comm comm) const {
    ResultWriterOptions o;
    o.directory = dir.string();
    o.base_name = "crane";
    o.probe_joints = probe_joints;
    o.comm = comm;
    return o;
  }
};

Checkpoint checkpoint_after(const Recorded& r, int outputs) {
  Checkpoint c;
  c.time = r.states()[outputs - 1].time();
  c.resume.step = outputs;
  c.integrator = "generalized_alpha";
  c.coordinates = r.states()[outputs - 1].coordinates_in_model_order();
  c.velocities.assign(c.coordinates.size(), 0.25);
  c.accelerations.assign(c.coordinates.size(), -1.5);
  c.outputs_written = outputs;
  c.last_output = c.time;
  c.next_output = c.time + 0.1;
  return c;
}

// ---- comparing two results files ------------------------------------------------------------

std::vector<std::string> objects(hid_t file) {
  std::vector<std::string> names;
  H5Ovisit(file, H5_INDEX_NAME, H5_ITER_INC,
           [](hid_t, const char* name, const H5O_info_t*, void* out) -> herr_t {
             static_cast<std::vector<std::string>*>(out)->emplace_back(name);
             return 0;
           },
           &names);
  return names;
}

/// A dataset's or attribute's values as text (strings) or raw bytes of its native type.
template <class Get, class Read>
std::string values(hid_t type_in_file, hssize_t n, Get native, Read read) {
  if (H5Tget_class(type_in_file) == H5T_STRING && H5Tis_variable_str(type_in_file) > 0) {
    std::vector<char*> s(static_cast<std::size_t>(n));
    const hid_t mem = H5Tcopy(H5T_C_S1);
    H5Tset_size(mem, H5T_VARIABLE);
    H5Tset_cset(mem, H5Tget_cset(type_in_file));
    read(mem, s.data());
    std::string text;
    for (char* p : s) text += std::string(p ? p : "") + '\n';
    for (char* p : s) H5free_memory(p);
    H5Tclose(mem);
    return text;
  }
  const hid_t mem = native();
  std::string bytes(static_cast<std::size_t>(n) * H5Tget_size(mem), '\0');
  read(mem, bytes.data());
  H5Tclose(mem);
  return bytes;
}

std::string dataset_values(hid_t ds) {
  const hid_t type = H5Dget_type(ds), space = H5Dget_space(ds);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::string out = values(
      type, n, [&] { return H5Tget_native_type(type, H5T_DIR_ASCEND); },
      [&](hid_t mem, void* buf) { H5Dread(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf); });
  H5Sclose(space);
  H5Tclose(type);
  return out;
}

std::string attributes(hid_t obj) {
  std::string out;
  H5O_info_t info;
  H5Oget_info(obj, &info);
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    const hid_t a = H5Aopen_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT);
    char name[256];
    H5Aget_name(a, sizeof name, name);
    const hid_t type = H5Aget_type(a), space = H5Aget_space(a);
    out += std::string(name) + "=" +
           values(
               type, H5Sget_simple_extent_npoints(space), [&] { return H5Tget_native_type(type, H5T_DIR_ASCEND); },
               [&](hid_t mem, void* buf) { H5Aread(a, mem, buf); }) +
           ";";
    H5Sclose(space);
    H5Tclose(type);
    H5Aclose(a);
  }
  return out;
}

std::vector<double> doubles(const std::string& bytes) {
  std::vector<double> v(bytes.size() / sizeof(double));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(double));
  return v;
}

/// Every object, attribute and value of `a` equals `b`'s; the energies (sums over elements, in
/// another order on several ranks) to 1e-14 of their size.
void expect_same_results(const fs::path& a, const fs::path& b) {
  const hid_t fa = H5Fopen(a.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), fb = H5Fopen(b.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(fa, 0);
  ASSERT_GE(fb, 0);
  const std::vector<std::string> names = objects(fa);
  EXPECT_EQ(names, objects(fb));
  int datasets = 0;
  for (const std::string& name : names) {
    const hid_t oa = H5Oopen(fa, name.c_str(), H5P_DEFAULT), ob = H5Oopen(fb, name.c_str(), H5P_DEFAULT);
    if (ob < 0) {
      H5Oclose(oa);
      continue;
    }
    EXPECT_EQ(attributes(oa), attributes(ob)) << name;
    if (H5Iget_type(oa) == H5I_DATASET) {
      ++datasets;
      const hid_t sa = H5Dget_space(oa), sb = H5Dget_space(ob);
      std::vector<hsize_t> da(8), db(8);
      const int ra = H5Sget_simple_extent_dims(sa, da.data(), nullptr), rb = H5Sget_simple_extent_dims(sb, db.data(), nullptr);
      EXPECT_EQ(ra, rb) << name;
      EXPECT_EQ(da, db) << name;
      H5Sclose(sa);
      H5Sclose(sb);
      const std::string va = dataset_values(oa), vb = dataset_values(ob);
      if (name == "energy" || name == "energy_total") {
        // Round-off of sums of many terms: relative to the largest energy (the total may cancel).
        const std::vector<double> x = doubles(va), y = doubles(vb);
        double scale = 0.0;
        const hid_t energy = H5Dopen2(fb, "energy", H5P_DEFAULT);
        for (double v : doubles(dataset_values(energy))) scale = std::max(scale, std::abs(v));
        H5Dclose(energy);
        ASSERT_EQ(x.size(), y.size()) << name;
        for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(x[i], y[i], 1e-13 * scale) << name << " " << i;
      } else {
        std::size_t first = 0;
        while (first < std::min(va.size(), vb.size()) && va[first] == vb[first]) ++first;
        EXPECT_TRUE(va == vb) << name << " differs from byte " << first << " of " << va.size() << ": "
                              << (va.size() % 8 == 0 ? doubles(va)[first / 8] : 0) << " against "
                              << (vb.size() % 8 == 0 ? doubles(vb)[first / 8] : 0);
      }
    }
    H5Oclose(oa);
    H5Oclose(ob);
  }
  EXPECT_GT(datasets, 40);
  H5Fclose(fa);
  H5Fclose(fb);
}

std::string text_of(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// ---- the tests ---------------------------------------------------------------------------------

TEST(CollectiveResults, TheSameFilesAsOneRankWrites) {
  // The reduced crane: super trusses (many drawn cells per element), ropes, rigid bodies (drawn
  // by the last rank), constraints, drives and probes.
  const Recorded run(CRANE_MODEL, 5);
  const SharedDir dir;
  ResultWriter collective(run.model(), run.options(dir.path / "together", PETSC_COMM_WORLD));
  EXPECT_EQ(collective.collective(), [] {
    int n = 1;
    MPI_Comm_size(PETSC_COMM_WORLD, &n);
    return n > 1;
  }());
  for (int k = 0; k < 5; ++k) {
    collective.append(run.states()[k]);
    if (k == 2) collective.write_checkpoint(checkpoint_after(run, 3));
  }
  collective.close();
  const std::optional<MemberPeak> peak = collective.member_peak();

  if (rank_in_world() == 0) {
    ResultWriter alone(run.model(), run.options(dir.path / "alone", PETSC_COMM_SELF));
    for (int k = 0; k < 5; ++k) {
      alone.append(run.states()[k]);
      if (k == 2) alone.write_checkpoint(checkpoint_after(run, 3));
    }
    alone.close();
    expect_same_results(collective.h5_path(), alone.h5_path());
    EXPECT_EQ(text_of(collective.xdmf_path()), text_of(alone.xdmf_path()));
    EXPECT_EQ(text_of(collective.csv_path()), text_of(alone.csv_path()));
    ASSERT_TRUE(peak && alone.member_peak());
    EXPECT_EQ(peak->element, alone.member_peak()->element);
    EXPECT_EQ(peak->member, alone.member_peak()->member);
    EXPECT_EQ(peak->time, alone.member_peak()->time);
    EXPECT_EQ(peak->von_mises, alone.member_peak()->von_mises);
  }
  // Every rank knows the peak (for the run's summary) alike.
  int element = peak ? peak->element : -1, lowest = 0;
  MPI_Allreduce(&element, &lowest, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD);
  EXPECT_EQ(lowest, element);
}

TEST(CollectiveResults, ContinuedFromACheckpointLikeOneRank) {
  // Five steps with a checkpoint after the third, then continued from it with two other states:
  // the file cut back and extended by several ranks as by one.
  const Recorded run(CRANE_MODEL, 7);
  const SharedDir dir;
  auto write = [&](const fs::path& folder, MPI_Comm comm) {
    {
      ResultWriter w(run.model(), run.options(folder, comm));
      for (int k = 0; k < 5; ++k) {
        w.append(run.states()[k]);
        if (k == 2) w.write_checkpoint(checkpoint_after(run, 3));
      }
    }
    ResultWriterOptions o = run.options(folder, comm);
    o.continuation = ResultContinuation{3, run.states()[2].time()};
    ResultWriter w(run.model(), o);
    for (int k = 5; k < 7; ++k) w.append(run.states()[k]);
    w.close();
    return w.h5_path();
  };
  const fs::path together = write(dir.path / "together", PETSC_COMM_WORLD);
  if (rank_in_world() == 0) {
    const fs::path alone = write(dir.path / "alone", PETSC_COMM_SELF);
    expect_same_results(together, alone);
    EXPECT_EQ(text_of(together.parent_path() / "crane.xdmf"), text_of(alone.parent_path() / "crane.xdmf"));
    EXPECT_EQ(text_of(together.parent_path() / "crane_probes.csv"), text_of(alone.parent_path() / "crane_probes.csv"));
  }
}

TEST(CollectiveResults, AFailureOnRankZeroStopsEveryRank) {
  // The folder cannot be made (a file stands in the way): every rank throws rank 0's reason
  // instead of waiting for it in a collective call.
  const Recorded run(CRANE_MODEL, 1);
  const SharedDir dir;
  if (rank_in_world() == 0) {
    fs::create_directories(dir.path);
    std::ofstream(dir.path / "file") << "x";
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  try {
    ResultWriter w(run.model(), run.options(dir.path / "file" / "results", PETSC_COMM_WORLD));
    ADD_FAILURE() << "expected the writer to fail";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create directory"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace latticedyn
