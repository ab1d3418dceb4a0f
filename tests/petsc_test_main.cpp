// GoogleTest main for tests that use PETSc or MPI: initialises PETSc around the test run, and
// lets only rank 0 print so that MPI runs stay readable.
#include <gtest/gtest.h>
#include <slepcsys.h>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (SlepcInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  PetscMPIInt rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int result = RUN_ALL_TESTS();
  // Every rank must agree on the outcome, or ctest would only see rank 0's.
  int all = 0;
  MPI_Allreduce(&result, &all, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  SlepcFinalize();
  return all;
}
