// The system's characteristic scales (mass, stiffness, load, length) on several ranks: each rank
// sums a share of the elements, and the shares must add up to what one rank computes over all.
// Run under mpiexec with 3 ranks (ctest label mpi); on one rank it compares a rank with itself.
#include "assembly/system_assembler.hpp"

#include "sample_models.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace latticedyn {
namespace {

void expect_same_scales(const Model& model) {
  SystemAssembler all(model, PETSC_COMM_WORLD);
  SystemAssembler one(model, PETSC_COMM_SELF);
  // Sums in another order: equal to round-off.
  const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-13 * std::abs(b); };
  EXPECT_PRED2(near, all.characteristic_mass(), one.characteristic_mass());
  EXPECT_PRED2(near, all.characteristic_stiffness(), one.characteristic_stiffness());
  EXPECT_PRED2(near, all.characteristic_load(), one.characteristic_load());
  EXPECT_PRED2(near, all.characteristic_length(), one.characteristic_length());
}

TEST(SystemAssemblerOnRanks, ScalesOfTheKitchenSinkModelAsOnOneRank) {
  int ranks = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &ranks);
  const Model model = testing::kitchen_sink_model();
  // More ranks than elements would leave a rank without a share: the test needs every rank to sum.
  ASSERT_GE(static_cast<int>(model.elements.size()), ranks);
  expect_same_scales(model);
}

TEST(SystemAssemblerOnRanks, ScalesOfTheClampedLatticeAsOnOneRank) {
  expect_same_scales(testing::clamped_lattice_model());
}

}  // namespace
}  // namespace latticedyn
