// Element evaluation on several threads gives the serial residual and Jacobian: a model of super
// truss elements (threaded inside too), beams, a rope and strut ties, assembled with
// -assembly_threads 1 and 2 at a deformed, moving state.
#include "assembly/element_loop.hpp"
#include "assembly/system_assembler.hpp"
#include "io/model_reader.hpp"

#include <gtest/gtest.h>
#include <petscmat.h>

#include <atomic>
#include <cmath>
#include <stdexcept>

namespace latticedyn {
namespace {

const char* kMixed = R"(gravity: [0, 0, -9.81]
materials:
  steel: {density: 7800, youngs_modulus: 2.06e11, poisson_ratio: 0.25}
sections:
  chord: {type: round_tube, outer_radius: 0.1, inner_radius: 0.08}
  lacing: {type: round_tube, outer_radius: 0.05, inner_radius: 0.04}
  wire: {type: round_tube, outer_radius: 0.02}
truss_sections:
  box:
    length: 6
    order: 3
    end1: [[1, 1], [-1, 1], [-1, -1], [1, -1]]
    main_beams: [[1, 1], [2, 2], [3, 3], [4, 4]]
    cross_beams1: [[1, 2], [2, 3], [3, 4], [4, 1]]
    cross_beams2: [[1, 2], [2, 3], [3, 4], [4, 1]]
    material: steel
    main_section: chord
    sub_section: lacing
ground:
  joints: [{name: root}]
bodies:
  - {name: a, type: super_truss, section: box}
  - {name: b, type: super_truss, section: box, position: [6, 0, 0]}
  - {name: c, type: super_truss, section: box, position: [12, 0, 0]}
  - {name: arm, type: timoshenko_beam, material: steel, section: chord, ends: [[18, 0, 0], [24, 0, 0]], elements: 4}
  - {name: spline, type: cubic_spline_beam, material: steel, section: chord, ends: [[24, 0, 0], [24, 0, -5]], elements: 3}
  - {name: rope, type: rope, material: steel, section: wire, ends: [[24, 0, -5], [24, 0, -15]], elements: 4}
  - {name: tie, type: strut_tie, material: steel, section: lacing, ends: [[0, 0, 0], [12, 0, 3]]}
constraints:
  - {name: clamp, type: fixed, joints: [ground.root, a.1]}
  - {name: ab, type: fixed, joints: [a.2, b.1], shared: true}
  - {name: bc, type: fixed, joints: [b.2, c.1]}
  - {name: c_arm, type: fixed, joints: [c.2, arm.1], shared: true}
  - {name: arm_spline, type: spherical, joints: [arm.2, spline.1]}
  - {name: spline_rope, type: spherical, joints: [spline.2, rope.1], shared: true}
  - {name: tie_a, type: spherical, joints: [a.e1n1, tie.1]}
  - {name: tie_c, type: spherical, joints: [c.e1n2, tie.2]}
)";

struct Assembled {
  std::vector<double> residual;
  Mat J = nullptr;
  ~Assembled() { MatDestroy(&J); }
};

// Residual and Jacobian at a state moved away from the initial one, with `threads` threads.
void assemble(const Model& model, int threads, Assembled* out) {
  const std::string t = std::to_string(threads);
  PetscOptionsSetValue(nullptr, "-assembly_threads", t.c_str());
  SystemAssembler sa(model, PETSC_COMM_SELF);
  PetscOptionsClearValue(nullptr, "-assembly_threads");
  Vec U, V, F;
  ASSERT_EQ(sa.create_vector(&U), 0);
  ASSERT_EQ(sa.create_vector(&V), 0);
  ASSERT_EQ(sa.create_vector(&F), 0);
  ASSERT_EQ(sa.create_matrix(&out->J), 0);
  ASSERT_EQ(sa.initial_state(U, V), 0);
  PetscInt n;
  VecGetSize(U, &n);
  PetscScalar *u, *v;
  VecGetArray(U, &u);
  VecGetArray(V, &v);
  for (PetscInt i = 0; i < n; ++i) {
    u[i] += 0.01 * std::sin(1.7 * i + 0.3);
    v[i] += 0.2 * std::cos(0.9 * i);
  }
  VecRestoreArray(U, &u);
  VecRestoreArray(V, &v);
  const EvaluationSettings how;
  PetscBool finite = PETSC_FALSE;
  ASSERT_EQ(sa.residual(EvaluationPoint{U, V, nullptr, nullptr, 0.3, 0.3}, how, F, &finite), 0);
  EXPECT_TRUE(finite);
  ASSERT_EQ(sa.jacobian(EvaluationPoint{U, V, nullptr, nullptr, 0.3, 0.3}, how, 1.0, 50.0, 2500.0, out->J), 0);
  const PetscScalar* f;
  VecGetArrayRead(F, &f);
  out->residual.assign(f, f + n);
  VecRestoreArrayRead(F, &f);
  VecDestroy(&U);
  VecDestroy(&V);
  VecDestroy(&F);
}

// One super truss alone: no elements to share out, so the element runs its own tasks.
std::string single_super_truss() {
  std::string text = kMixed;
  text = text.substr(0, text.find("bodies:"));
  return text + "bodies:\n  - {name: a, type: super_truss, section: box}\nconstraints:\n"
                "  - {name: clamp, type: fixed, joints: [ground.root, a.1]}\n";
}

class ElementThreadsOn : public ::testing::TestWithParam<bool> {};

TEST_P(ElementThreadsOn, TwoThreadsGiveTheSerialResidualAndJacobian) {
  const Model model = GetParam() ? read_simulation_from_string(kMixed, "mixed.yaml").model
                                 : read_simulation_from_string(single_super_truss(), "single.yaml").model;
  Assembled serial, threaded;
  assemble(model, 1, &serial);
  assemble(model, 2, &threaded);
  ASSERT_EQ(serial.residual.size(), threaded.residual.size());
  double scale = 0.0;
  for (double r : serial.residual) scale = std::max(scale, std::abs(r));
  // The super truss sums its members in chunks when threaded: equal up to rounding.
  for (std::size_t i = 0; i < serial.residual.size(); ++i)
    EXPECT_NEAR(threaded.residual[i], serial.residual[i], 1e-12 * scale) << "row " << i;
  Mat D;
  ASSERT_EQ(MatDuplicate(serial.J, MAT_COPY_VALUES, &D), 0);
  ASSERT_EQ(MatAXPY(D, -1.0, threaded.J, SAME_NONZERO_PATTERN), 0);
  PetscReal diff, norm;
  MatNorm(D, NORM_INFINITY, &diff);
  MatNorm(serial.J, NORM_INFINITY, &norm);
  EXPECT_GT(norm, 0.0);
  EXPECT_LE(diff, 1e-12 * norm);
  MatDestroy(&D);
}

INSTANTIATE_TEST_SUITE_P(Models, ElementThreadsOn, ::testing::Values(true, false),
                         [](const auto& info) { return info.param ? "mixed_elements" : "one_super_truss"; });

TEST(ElementThreads, EveryItemRunsOnceAndTheFirstErrorComesBack) {
  std::vector<std::atomic<int>> calls(1000);
  parallel_for_each(1000, 2, [&](int i) { ++calls[i]; });
  for (const auto& c : calls) EXPECT_EQ(c.load(), 1);
  EXPECT_THROW(parallel_for_each(100, 2,
                                 [](int i) {
                                   if (i == 37) throw std::runtime_error("element 37 failed");
                                 }),
               std::runtime_error);
}

}  // namespace
}  // namespace latticedyn
