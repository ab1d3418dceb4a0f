// The global Jacobian of the assembled system against central finite differences of the global
// residual, through the whole chain: elements, loads, every constraint type, node sharing and the
// rotation-vector parametrisation far from the reference (thesis 4.1-4.4).
#include "assembly/system_assembler.hpp"

#include "sample_models.hpp"

#include <gtest/gtest.h>

#include <ostream>
#include <petscvec.h>

#include <random>
#include <set>

namespace latticedyn {
namespace {

Eigen::VectorXd to_eigen(Vec v) {
  PetscInt n;
  VecGetSize(v, &n);
  const PetscScalar* x;
  VecGetArrayRead(v, &x);
  Eigen::VectorXd out = Eigen::Map<const Eigen::VectorXd>(x, n);
  VecRestoreArrayRead(v, &x);
  return out;
}

void from_eigen(const Eigen::VectorXd& e, Vec v) {
  PetscScalar* x;
  VecGetArray(v, &x);
  for (int i = 0; i < e.size(); ++i) x[i] = e(i);
  VecRestoreArray(v, &x);
}

Eigen::MatrixXd to_dense(Mat J, int n) {
  Eigen::MatrixXd out(n, n);
  std::vector<PetscInt> idx(n);
  for (int i = 0; i < n; ++i) idx[i] = i;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rm(n, n);
  MatGetValues(J, n, idx.data(), n, idx.data(), rm.data());
  out = rm;
  return out;
}

struct Case {
  const char* name;
  Parametrization param;
  ConstraintRows rows;
  bool end_of_step;  // generalized-alpha: constraints and multipliers at Uc = U0 + (U - U0)/af
  double cq, cv, ca;
};
// ctest names the instances by this (stable across builds), not by their bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class AssembledJacobian : public ::testing::TestWithParam<Case> {};

TEST_P(AssembledJacobian, MatchesFiniteDifferencesOfTheResidual) {
  const Case c = GetParam();
  const Model model = testing::kitchen_sink_model();
  SystemAssembler sa(model, PETSC_COMM_SELF);
  const int n = sa.dofs().global_size();
  Vec U, V, A, Uc, F;
  for (Vec* v : {&U, &V, &A, &Uc, &F}) ASSERT_EQ(sa.create_vector(v), 0);
  ASSERT_EQ(sa.initial_state(U, V), 0);

  // Far from the reference: rotation vectors of size ~1.5, arbitrary rates and multipliers.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd u0 = to_eigen(U), v0(n), a0(n);
  for (int i = 0; i < n; ++i) {
    u0(i) += 0.9 * u(rng);
    v0(i) = u(rng);
    a0(i) = u(rng);
  }
  Eigen::VectorXd u_start = u0;
  for (int i = 0; i < n; ++i) u_start(i) -= 0.05 * u(rng);
  const double af = 0.6;

  EvaluationSettings how;
  how.param = c.param;
  how.rows = c.rows;
  how.constraint_scale = 7.0;
  how.uc_per_u = c.end_of_step ? 1.0 / af : 1.0;
  how.baumgarte_alpha = 3.0;
  how.baumgarte_beta = 0.8;

  auto residual = [&](const Eigen::VectorXd& uu, const Eigen::VectorXd& vv, const Eigen::VectorXd& aa) {
    from_eigen(uu, U);
    from_eigen(vv, V);
    from_eigen(aa, A);
    EvaluationPoint at{U, V, A, nullptr, 0.3, 0.4};
    if (c.end_of_step) {
      from_eigen(u_start + (uu - u_start) / af, Uc);
      at.Uc = Uc;
    }
    PetscBool finite;
    EXPECT_EQ(sa.residual(at, how, F, &finite), 0);
    EXPECT_TRUE(finite);
    return to_eigen(F);
  };

  Mat J;
  ASSERT_EQ(sa.create_matrix(&J), 0);
  // A first Jacobian elsewhere fixes the pattern and plans the direct writes into the value
  // arrays; the one checked is the second, written that way.
  residual(u0 + Eigen::VectorXd::Constant(n, 0.01), v0, a0);
  EvaluationPoint at{U, V, A, c.end_of_step ? Uc : nullptr, 0.3, 0.4};
  ASSERT_EQ(sa.jacobian(at, how, 2.0 * c.cq + 1.0, 0.5 * c.cv, 3.0 * c.ca, J), 0);
  residual(u0, v0, a0);  // loads U, V, A, Uc
  ASSERT_EQ(sa.jacobian(at, how, c.cq, c.cv, c.ca, J), 0);
  const Eigen::MatrixXd Jad = to_dense(J, n);

  // Multiplier columns enter the Jacobian with weight 1 whatever cq is (they carry G^T in the
  // saddle-point matrix of the Baumgarte route too).
  std::vector<bool> is_multiplier(n, false);
  for (std::size_t k = 0; k < model.constraints.size(); ++k)
    for (int i = 0; i < model.constraints[k].rows(); ++i) is_multiplier[sa.dofs().multiplier_dof(static_cast<int>(k)) + i] = true;

  Eigen::MatrixXd Jfd = Eigen::MatrixXd::Zero(n, n);
  const double h = 1e-6;
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd e = Eigen::VectorXd::Unit(n, j) * h;
    const double wq = is_multiplier[j] ? 1.0 : c.cq;
    if (wq != 0) Jfd.col(j) += wq * (residual(u0 + e, v0, a0) - residual(u0 - e, v0, a0)) / (2 * h);
    if (c.cv != 0) Jfd.col(j) += c.cv * (residual(u0, v0 + e, a0) - residual(u0, v0 - e, a0)) / (2 * h);
    if (c.ca != 0) Jfd.col(j) += c.ca * (residual(u0, v0, a0 + e) - residual(u0, v0, a0 - e)) / (2 * h);
  }
  const double scale = Jad.cwiseAbs().maxCoeff();
  const Eigen::MatrixXd diff = (Jad - Jfd).cwiseAbs();
  Eigen::Index r, col;
  const double worst = diff.maxCoeff(&r, &col);
  EXPECT_LT(worst, 2e-6 * scale) << c.name << ": worst entry (" << r << ", " << col << "): AD " << Jad(r, col)
                                 << " FD " << Jfd(r, col) << " (max |J| " << scale << ")";
  MatDestroy(&J);
  for (Vec* v : {&U, &V, &A, &Uc, &F}) VecDestroy(v);
}

INSTANTIATE_TEST_SUITE_P(
    Modes, AssembledJacobian,
    ::testing::Values(Case{"statics", Parametrization::rotation_vector_rates, ConstraintRows::position, false, 1, 0, 0},
                      Case{"generalized_alpha", Parametrization::rotation_vector_rates, ConstraintRows::position, true, 1,
                           35.0, 900.0},
                      Case{"velocity_variables", Parametrization::velocity_variables, ConstraintRows::position, false, 1,
                           20.0, 300.0},
                      Case{"saddle_point", Parametrization::velocity_variables, ConstraintRows::acceleration, false, 0, 0,
                           1}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

// The same Jacobian in 3 x 3 blocks and in each node's 6 x 6 block (BAIJ) as in compressed rows
// (AIJ): written through MatSetValues the first time and straight into the block value arrays
// after, with a follower load whose stiffness always goes through MatSetValues.
class BlockMatrix : public ::testing::TestWithParam<int> {};

TEST_P(BlockMatrix, HoldsTheSameJacobian) {
  const int block_size = GetParam();
  const Model model = testing::clamped_lattice_model();
  SystemAssembler sa(model, PETSC_COMM_SELF);
  ASSERT_TRUE(sa.uniform_blocks(3));
  ASSERT_TRUE(sa.uniform_blocks(6)) << "each node's translation and rotation side by side";
  EXPECT_FALSE(sa.uniform_blocks(4)) << "blocks of three do not fill groups of four";
  EXPECT_FALSE(SystemAssembler(testing::kitchen_sink_model(), PETSC_COMM_SELF).uniform_blocks(3));
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  PetscInt n;
  VecGetSize(U, &n);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-0.05, 0.05);
  for (PetscInt i = 0; i < n; ++i) {  // off the reference: rotations, stretches, rates
    VecSetValue(U, i, d(rng), ADD_VALUES);
    VecSetValue(V, i, 20 * d(rng), ADD_VALUES);
  }
  VecAssemblyBegin(U);
  VecAssemblyEnd(U);
  VecAssemblyBegin(V);
  VecAssemblyEnd(V);
  // An assembler plans its direct writes for one matrix: one for each.
  SystemAssembler sa_blocks(model, PETSC_COMM_SELF);
  Mat rows, blocks;
  ASSERT_EQ(sa.create_matrix(&rows), 0);
  ASSERT_EQ(sa_blocks.create_matrix(&blocks, block_size), 0);
  PetscInt bs;
  MatGetBlockSize(blocks, &bs);
  EXPECT_EQ(bs, block_size);
  MatType type;
  MatGetType(blocks, &type);
  EXPECT_STREQ(type, MATSEQBAIJ);
  EvaluationSettings how;
  const EvaluationPoint at{U, V, nullptr, nullptr, 0.3, 0.4};
  for (int pass = 0; pass < 2; ++pass) {
    const double cq = 1.0 + pass, cv = 35.0, ca = 900.0;
    ASSERT_EQ(sa.jacobian(at, how, cq, cv, ca, rows), 0);
    ASSERT_EQ(sa_blocks.jacobian(at, how, cq, cv, ca, blocks), 0);
    const Eigen::MatrixXd a = to_dense(rows, n), b = to_dense(blocks, n);
    EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-12 * a.cwiseAbs().maxCoeff()) << "pass " << pass;
  }
  MatInfo info;
  MatGetInfo(blocks, MAT_LOCAL, &info);
  EXPECT_EQ(info.nz_unneeded, 0.0) << "preallocated more than used";
  for (Mat* m : {&rows, &blocks}) MatDestroy(m);
  VecDestroy(&U);
  VecDestroy(&V);
}

INSTANTIATE_TEST_SUITE_P(SystemAssembler, BlockMatrix, ::testing::Values(3, 6));

// A node whose rotation is held leaves its translation without a partner: no 6 x 6 blocks then,
// the 3 x 3 ones still.
TEST(SystemAssembler, ANodeWithoutItsRotationKeepsTheMatrixIn3x3Blocks) {
  Model model = testing::clamped_lattice_model();
  int held = -1;
  for (const ElementEntry& e : model.elements)
    for (const SlotBinding& slot : e.slots)
      if (held < 0 && model.blocks[slot.block].kind == SlotKind::rotation && !model.blocks[slot.block].fixed)
        held = slot.block;
  ASSERT_GE(held, 0);
  model.blocks[held].fixed = true;
  const SystemAssembler sa(model, PETSC_COMM_SELF);
  EXPECT_TRUE(sa.uniform_blocks(3));
  EXPECT_FALSE(sa.uniform_blocks(6));
  Mat J;
  ASSERT_EQ(sa.create_matrix(&J, 3), 0);
  MatDestroy(&J);
}

TEST(SystemAssembler, PreallocationIsExactAndPatternFixed) {
  const Model model = testing::kitchen_sink_model();
  SystemAssembler sa(model, PETSC_COMM_SELF);
  Vec U, V;
  Mat J;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  sa.create_matrix(&J);
  EvaluationSettings how;
  // Inserting outside the preallocated pattern is an error (MAT_NEW_NONZERO_ALLOCATION_ERR).
  ASSERT_EQ(sa.jacobian(EvaluationPoint{U, V, nullptr, nullptr, 0, 0}, how, 1, 1, 1, J), 0);
  MatInfo info;
  MatGetInfo(J, MAT_LOCAL, &info);
  EXPECT_EQ(info.nz_unneeded, 0.0) << "preallocated more than used";
  PetscObjectState s1, s2;
  MatGetNonzeroState(J, &s1);
  ASSERT_EQ(sa.jacobian(EvaluationPoint{U, V, nullptr, nullptr, 0.5, 0.5}, how, 1, 2, 3, J), 0);
  MatGetNonzeroState(J, &s2);
  EXPECT_EQ(s1, s2) << "the nonzero pattern changed between evaluations";
  MatDestroy(&J);
  VecDestroy(&U);
  VecDestroy(&V);
}

// The violation reported after every step: the largest |g| over the constraints and the one it
// belongs to, equal to the constraint values evaluated on every block's state (constraint_values);
// the block states left by an evaluation at another point must not leak in (only the constraints'
// blocks are evaluated); nothing for a model without constraints.
TEST(SystemAssembler, MaxConstraintViolationNamesTheWorstConstraint) {
  const Model model = testing::kitchen_sink_model();
  SystemAssembler sa(model, PETSC_COMM_SELF);
  Vec U, V, other, G;
  for (Vec* v : {&U, &V, &other, &G}) ASSERT_EQ(sa.create_vector(v), 0);
  ASSERT_EQ(sa.initial_state(U, V), 0);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const Eigen::VectorXd q0 = to_eigen(U);
  std::vector<int> worst_seen;
  for (int trial = 0; trial < 6; ++trial) {
    Eigen::VectorXd q = q0, p = q0;
    for (int i = 0; i < q.size(); ++i) {
      q(i) += 0.3 * u(rng);
      p(i) += 0.3 * u(rng);
    }
    from_eigen(q, U);
    from_eigen(p, other);
    const double t = 0.15 * trial;  // the driven hinge's angle moves with t
    ASSERT_EQ(sa.constraint_values(other, V, t, false, G), 0);  // every block's state at another point
    double value = -1.0;
    int where = -2;
    ASSERT_EQ(sa.max_constraint_violation(U, t, &value, &where), 0);
    ASSERT_EQ(sa.constraint_values(U, V, t, false, G), 0);
    const Eigen::VectorXd g = to_eigen(G);
    double expected = -1.0;
    int worst = -1;
    for (int c = 0; c < static_cast<int>(model.constraints.size()); ++c)
      for (int j = 0; j < model.constraints[c].rows(); ++j) {
        const double gj = std::abs(g(sa.dofs().multiplier_dof(c) + j));
        if (gj > expected) {
          expected = gj;
          worst = c;
        }
      }
    EXPECT_EQ(where, worst) << "trial " << trial;
    EXPECT_NEAR(value, expected, 1e-14 * expected) << "trial " << trial;
    EXPECT_GT(value, 1e-3);  // violated: the state is off the constraints
    worst_seen.push_back(worst);
  }
  // Different constraints are the worst in different trials: the index is not a constant.
  EXPECT_GT(std::set<int>(worst_seen.begin(), worst_seen.end()).size(), 1u);
  for (Vec* v : {&U, &V, &other, &G}) VecDestroy(v);

  ModelBuilder b;
  testing::add_rigid_body(b, "alone", 2.0, Vec3(0.5, 0, 0), Vec3(0.1, 0.2, 0.3));
  const Model free_body = b.build();
  SystemAssembler sf(free_body, PETSC_COMM_SELF);
  Vec W, Wv;
  ASSERT_EQ(sf.create_vector(&W), 0);
  ASSERT_EQ(sf.create_vector(&Wv), 0);
  ASSERT_EQ(sf.initial_state(W, Wv), 0);
  double value = -1.0;
  int where = 5;
  ASSERT_EQ(sf.max_constraint_violation(W, 0.0, &value, &where), 0);
  EXPECT_EQ(value, 0.0);
  EXPECT_EQ(where, -1);
  VecDestroy(&W);
  VecDestroy(&Wv);
}

TEST(SystemAssembler, SharedNodesCostNoMultipliers) {
  const Model model = testing::kitchen_sink_model();
  // Three shared connections: tie's first node merged with the ground (fixed), tie2's first node
  // with tie's second node, the rope's far end with a ground joint; 7 constraints keep rows.
  int rows = 0;
  for (const auto& c : model.constraints) rows += c.rows();
  EXPECT_EQ(model.constraints.size(), 7u);
  // driven revolute, spherical, prismatic, fixed, 2 spherical, the flexible chain's spherical
  EXPECT_EQ(rows, 6 + 3 + 5 + 6 + 3 + 3 + 3);
  // 4 bodies x 6 + tie's free end 3 + tie2's far end 3 (its near end is shared, the tie's
  // ground end is fixed) + the flexible chain: 3 nodes x 6, 2 stretches, the rope's near slope 3
  // and far slope 3 (its far end is on the ground).
  EXPECT_EQ(model.num_free_dofs(), 4 * 6 + 3 + 3 + 3 * 6 + 2 + 3 + 3);
}

}  // namespace
}  // namespace latticedyn
