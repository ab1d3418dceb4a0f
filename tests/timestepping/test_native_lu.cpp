// PETSc's own LU on constrained Jacobians: the saddle-point ordering factors a full lattice whose
// rigid end sections are frames held by constraints alone (where a band ordering meets a zero
// pivot) to the solution UMFPACK gives, a lattice without constraints in 3 x 3 blocks too, and a
// failed factorisation falls back to UMFPACK. A block matrix numbered along its lattice keeps its
// own order (PETSc's natural-ordering kernels), one numbered at random gets minimum degree.
#include "timestepping/native_lu.hpp"

#include "../assembly/sample_models.hpp"
#include "assembly/lattice_builder.hpp"
#include "assembly/model_builder.hpp"
#include "assembly/system_assembler.hpp"

#include <gtest/gtest.h>

#include <functional>

namespace latticedyn {
namespace {

// Two member-by-member lattice sections with rigid end sections, the first hinged to the ground
// (a revolute joint about y: five multipliers) and the two joined end to end by a fixed
// constraint between their reference frames: frames that only constraints hold, constraints
// between such frames, and a body's worth of multipliers on one frame from several sides.
Model two_section_boom() {
  ModelBuilder b;
  b.set_gravity(Vec3(0, 0, -9.81));
  const TrussSectionSpec spec = testing::rectangular_section();
  const TrussGeometry g = build_truss_geometry(spec);
  FullLatticeOptions o;
  const FullLattice first = add_full_lattice(b, "a", spec, g, o);
  o.position = Vec3(spec.length, 0, 0);
  const FullLattice second = add_full_lattice(b, "b", spec, g, o);
  auto joint = [](const FullLattice& l, const std::string& name) {
    for (const auto& [n, j] : l.joints)
      if (n == name) return j;
    return -1;
  };
  const int hinge = b.add_ground_joint("ground.hinge", Vec3::Zero(), Mat3::Identity());
  b.add_constraint(Constraint{"hinge", ConstraintType::revolute, 1, hinge, joint(first, "1"), -1}, false);
  b.add_constraint(Constraint{"splice", ConstraintType::fixed, 2, joint(first, "2"), joint(second, "1"), -1}, false);
  return b.build();
}

// The generalized-alpha iteration matrix at the initial state (h = 0.01 s, beta = 1/4).
PetscErrorCode iteration_matrix(SystemAssembler& sa, Mat* J, int block_size = 1) {
  Vec U, V;
  PetscFunctionBeginUser;
  PetscCall(sa.create_matrix(J, block_size));
  PetscCall(sa.create_vector(&U));
  PetscCall(sa.create_vector(&V));
  PetscCall(sa.initial_state(U, V));
  const double h = 0.01, beta = 0.25, gamma = 0.5;
  EvaluationSettings how;
  how.constraint_scale = sa.characteristic_mass() / (beta * h * h);
  PetscCall(sa.jacobian(EvaluationPoint{U, V, nullptr, nullptr, 0.0, 0.0}, how, 1.0, gamma / (beta * h),
                        1.0 / (beta * h * h), *J));
  PetscCall(VecDestroy(&U));
  PetscCall(VecDestroy(&V));
  PetscFunctionReturn(0);
}

struct Solve {
  PCFailedReason failure = PC_NOERROR;
  std::vector<double> x;
};

// Solves J x = b (b = 1, 2, 3, ... scaled) with LU by the given package and ordering.
Solve solve(Mat J, const char* package, const char* ordering) {
  Solve out;
  KSP ksp;
  PC pc;
  Vec b, x;
  PetscCallAbort(PETSC_COMM_SELF, KSPCreate(PETSC_COMM_SELF, &ksp));
  PetscCallAbort(PETSC_COMM_SELF, KSPSetOperators(ksp, J, J));
  PetscCallAbort(PETSC_COMM_SELF, KSPSetType(ksp, KSPPREONLY));
  if (std::string_view(package) == MATSOLVERPETSC && std::string_view(ordering) == kSaddlePointOrdering) {
    PetscCallAbort(PETSC_COMM_SELF, use_native_lu(ksp));
    PetscCallAbort(PETSC_COMM_SELF, KSPGetPC(ksp, &pc));
  } else {
    PetscCallAbort(PETSC_COMM_SELF, KSPGetPC(ksp, &pc));
    PetscCallAbort(PETSC_COMM_SELF, PCSetType(pc, PCLU));
    PetscCallAbort(PETSC_COMM_SELF, PCFactorSetMatSolverType(pc, package));
    PetscCallAbort(PETSC_COMM_SELF, PCFactorSetMatOrderingType(pc, ordering));
  }
  PetscCallAbort(PETSC_COMM_SELF, MatCreateVecs(J, &x, &b));
  PetscInt n;
  PetscCallAbort(PETSC_COMM_SELF, VecGetSize(b, &n));
  for (PetscInt i = 0; i < n; ++i) PetscCallAbort(PETSC_COMM_SELF, VecSetValue(b, i, 1.0 + i % 7, INSERT_VALUES));
  PetscCallAbort(PETSC_COMM_SELF, VecAssemblyBegin(b));
  PetscCallAbort(PETSC_COMM_SELF, VecAssemblyEnd(b));
  PetscCallAbort(PETSC_COMM_SELF, KSPSolve(ksp, b, x));
  PetscCallAbort(PETSC_COMM_SELF, PCGetFailedReason(pc, &out.failure));
  if (out.failure == PC_NOERROR) {
    const PetscScalar* a;
    PetscCallAbort(PETSC_COMM_SELF, VecGetArrayRead(x, &a));
    out.x.assign(a, a + n);
    PetscCallAbort(PETSC_COMM_SELF, VecRestoreArrayRead(x, &a));
  }
  VecDestroy(&b);
  VecDestroy(&x);
  KSPDestroy(&ksp);
  return out;
}

// max |a - b| / max |b|
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double largest = 0.0, difference = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    largest = std::max(largest, std::abs(b[i]));
    difference = std::max(difference, std::abs(a[i] - b[i]));
  }
  return difference / largest;
}

TEST(NativeLU, SaddlePointOrderingFactorsRigidEndSectionsAsUmfpackDoes) {
  const Model model = two_section_boom();
  SystemAssembler sa(model, PETSC_COMM_SELF);
  ASSERT_GT(sa.dofs().num_multipliers(), 50);
  Mat J;
  ASSERT_EQ(iteration_matrix(sa, &J), 0);
  const Solve reference = solve(J, MATSOLVERUMFPACK, MATORDERINGEXTERNAL);
  ASSERT_EQ(reference.failure, PC_NOERROR);
  // Why the ordering exists: the band ordering alone reaches a multiplier before its unknowns.
  EXPECT_NE(solve(J, MATSOLVERPETSC, MATORDERINGRCM).failure, PC_NOERROR);
  const Solve native = solve(J, MATSOLVERPETSC, kSaddlePointOrdering);
  ASSERT_EQ(native.failure, PC_NOERROR);
  EXPECT_LT(relative_difference(native.x, reference.x), 1e-9);
  MatDestroy(&J);
}

TEST(NativeLU, FactorsTheBlockMatrixOfALatticeAsUmfpackDoes) {
  const Model model = testing::clamped_lattice_model();
  SystemAssembler sa(model, PETSC_COMM_SELF);
  Mat rows, blocks;
  ASSERT_EQ(iteration_matrix(sa, &rows), 0);
  SystemAssembler sa_blocks(model, PETSC_COMM_SELF);
  ASSERT_EQ(iteration_matrix(sa_blocks, &blocks, 3), 0);
  const Solve reference = solve(rows, MATSOLVERUMFPACK, MATORDERINGEXTERNAL);
  const Solve native = solve(blocks, MATSOLVERPETSC, kSaddlePointOrdering);  // block AMD
  ASSERT_EQ(reference.failure, PC_NOERROR);
  ASSERT_EQ(native.failure, PC_NOERROR);
  EXPECT_LT(relative_difference(native.x, reference.x), 1e-9);
  MatDestroy(&rows);
  MatDestroy(&blocks);
}

// A block matrix (3 x 3 blocks) shaped like a lattice along its length: block k couples to the
// blocks two places either side of it along the chain; `place` numbers the chain's blocks.
Mat chain_of_blocks(PetscInt blocks, const std::function<PetscInt(PetscInt)>& place) {
  Mat A;
  PetscCallAbort(PETSC_COMM_SELF, MatCreateSeqBAIJ(PETSC_COMM_SELF, 3, 3 * blocks, 3 * blocks, 5, nullptr, &A));
  for (PetscInt k = 0; k < blocks; ++k)
    for (PetscInt d = -2; d <= 2; ++d) {
      if (k + d < 0 || k + d >= blocks) continue;
      PetscScalar v[9];
      for (int e = 0; e < 9; ++e) v[e] = d == 0 ? (e % 4 == 0 ? 20.0 + k % 5 : 0.3) : -1.0 / (1 + std::abs(d)) + 0.01 * e;
      const PetscInt r = place(k), c = place(k + d);
      PetscCallAbort(PETSC_COMM_SELF, MatSetValuesBlocked(A, 1, &r, 1, &c, v, INSERT_VALUES));
    }
  PetscCallAbort(PETSC_COMM_SELF, MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCallAbort(PETSC_COMM_SELF, MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  return A;
}

TEST(NativeLU, ABlockMatrixKeepsItsOwnOrderWhereItFactorsAsCheaply) {
  ASSERT_EQ(register_saddle_point_ordering(), 0);
  const PetscInt blocks = 60;
  const std::function<PetscInt(PetscInt)> along = [](PetscInt k) { return k; };
  const std::function<PetscInt(PetscInt)> scattered = [&](PetscInt k) { return (7 * k) % blocks; };
  for (const auto* place : {&along, &scattered}) {
    Mat A = chain_of_blocks(blocks, *place);
    IS row, col;
    ASSERT_EQ(MatGetOrdering(A, kSaddlePointOrdering, &row, &col), 0);
    PetscBool own;
    ISIdentity(row, &own);
    // Along the chain its own order has no fill beyond the band; scattered, it fills nearly all.
    EXPECT_EQ(own, place == &along ? PETSC_TRUE : PETSC_FALSE);
    ISDestroy(&row);
    ISDestroy(&col);
    Mat rows;
    ASSERT_EQ(MatConvert(A, MATSEQAIJ, MAT_INITIAL_MATRIX, &rows), 0);
    const Solve reference = solve(rows, MATSOLVERUMFPACK, MATORDERINGEXTERNAL);
    const Solve native = solve(A, MATSOLVERPETSC, kSaddlePointOrdering);
    ASSERT_EQ(reference.failure, PC_NOERROR);
    ASSERT_EQ(native.failure, PC_NOERROR);
    EXPECT_LT(relative_difference(native.x, reference.x), 1e-12);
    MatDestroy(&rows);
    MatDestroy(&A);
  }
}

TEST(NativeLU, FailedFactorisationFallsBackToUmfpack) {
  // [0 1; 1 0]: both rows lack a pivot and nothing gives them one, so PETSc's LU must fail; the
  // fallback's UMFPACK pivots and solves it.
  Mat A;
  ASSERT_EQ(MatCreateSeqAIJ(PETSC_COMM_SELF, 2, 2, 2, nullptr, &A), 0);
  for (PetscInt i = 0; i < 2; ++i) {
    MatSetValue(A, i, i, 0.0, INSERT_VALUES);
    MatSetValue(A, i, 1 - i, 1.0, INSERT_VALUES);
  }
  MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY);
  KSP ksp;
  Vec b, x;
  KSPCreate(PETSC_COMM_SELF, &ksp);
  KSPSetOperators(ksp, A, A);
  KSPSetType(ksp, KSPPREONLY);
  ASSERT_EQ(use_native_lu(ksp), 0);
  MatCreateVecs(A, &x, &b);
  VecSetValue(b, 0, 2.0, INSERT_VALUES);
  VecSetValue(b, 1, 3.0, INSERT_VALUES);
  VecAssemblyBegin(b);
  VecAssemblyEnd(b);
  KSPSolve(ksp, b, x);
  PC pc;
  PCFailedReason reason;
  KSPGetPC(ksp, &pc);
  PCGetFailedReason(pc, &reason);
  EXPECT_NE(reason, PC_NOERROR);
  PetscBool switched;
  ASSERT_EQ(recover_from_failed_factorisation(ksp, &switched), 0);
  EXPECT_TRUE(switched);
  KSPSolve(ksp, b, x);
  PCGetFailedReason(pc, &reason);
  EXPECT_EQ(reason, PC_NOERROR);
  const PetscScalar* a;
  VecGetArrayRead(x, &a);
  EXPECT_NEAR(a[0], 3.0, 1e-14);
  EXPECT_NEAR(a[1], 2.0, 1e-14);
  VecRestoreArrayRead(x, &a);
  // A second call finds nothing to do.
  ASSERT_EQ(recover_from_failed_factorisation(ksp, &switched), 0);
  EXPECT_FALSE(switched);
  VecDestroy(&b);
  VecDestroy(&x);
  KSPDestroy(&ksp);
  MatDestroy(&A);
}

}  // namespace
}  // namespace latticedyn
