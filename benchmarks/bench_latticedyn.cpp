// Google Benchmark timings: element evaluation (residual, and residual with all tangents by AD),
// constraint evaluation at first and second order, and on a ~1000-bar space truss the global
// residual, the global Jacobian and one implicit generalized-alpha step per direct solver.
// Results and the command are recorded in docs/performance.md; tests never assert times.
#include "assembly/constraint_evaluator.hpp"
#include "assembly/system_assembler.hpp"
#include "elements/rigid_body.hpp"
#include "elements/strut_tie.hpp"
#include "space_truss_model.hpp"
#include "timestepping/generalized_alpha.hpp"

#include <benchmark/benchmark.h>
#include <petscsys.h>

#include <random>

namespace latticedyn {
namespace {

std::vector<SlotState<double>> random_slots(const Element& e, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<SlotState<double>> s(e.slots().size());
  for (auto& x : s) {
    x.pos = Vec3(u(rng), u(rng), u(rng));
    x.rot = rotation_matrix<double>(Vec3(u(rng), u(rng), u(rng)));
    x.vel = Vec3(u(rng), u(rng), u(rng));
    x.acc = Vec3(u(rng), u(rng), u(rng));
  }
  return s;
}

std::unique_ptr<Element> make(int kind) {
  if (kind == 0) {
    RigidBodyProperties p;
    p.mass = 10;
    p.centroid = Vec3(0.5, 0.1, 0);
    p.inertia_centroid = Vec3(1, 2, 2.5).asDiagonal();
    return std::make_unique<RigidBody>(p);
  }
  StrutTieProperties p;
  p.material = Material{7800, 2.06e11, 0.3};
  p.section = round_tube_section(0.05, 0.04);
  p.rest_length = 1.5;
  p.smoothing = 1e-3;
  return std::make_unique<StrutTie>(p);
}

void BM_ElementResidual(benchmark::State& st) {
  const auto e = make(static_cast<int>(st.range(0)));
  const auto s = random_slots(*e, 1);
  VecX r(e->num_dofs());
  const ElementContext ctx{Vec3(0, 0, -9.81), 0};
  for (auto _ : st) {
    e->residual(s, ctx, r);
    benchmark::DoNotOptimize(r.data());
  }
  st.SetLabel(std::string(e->type_name()));
}
BENCHMARK(BM_ElementResidual)->Arg(0)->Arg(1);

void BM_ElementTangents(benchmark::State& st) {
  const auto e = make(static_cast<int>(st.range(0)));
  const auto s = random_slots(*e, 2);
  ElementTangents t;
  const ElementContext ctx{Vec3(0, 0, -9.81), 0};
  for (auto _ : st) {
    e->tangents(s, ctx, t);
    benchmark::DoNotOptimize(t.K.data());
  }
  st.SetLabel(std::string(e->type_name()) + " residual + K, C, M");
}
BENCHMARK(BM_ElementTangents)->Arg(0)->Arg(1);

// A revolute joint between two free rigid bodies: G alone (residuals) and with dG/dq (Jacobians).
void BM_ConstraintRevolute(benchmark::State& st) {
  ModelBuilder b;
  std::vector<int> joints;
  for (int k = 0; k < 2; ++k) {
    const std::string name = k == 0 ? "b0" : "b1";
    const int body = b.add_body(name, "rigid_body");
    const int t = b.add_block(DofBlock::translation(Vec3(k, 0, 0), Vec3::Zero(), "t"));
    const int r = b.add_block(DofBlock::rotation(rotation_matrix<double>(Vec3(0.1 * k, 0.2, 0.3)), Vec3::Zero(), "r"));
    b.add_element(body, make(0), {{t}, {r}});
    Joint j;
    j.name = name + ".j";
    j.translation_block = t;
    j.rotation_block = r;
    j.offset = Vec3(0.5 - k, 0, 0);
    joints.push_back(b.add_joint(body, j));
  }
  Constraint c;
  c.name = "hinge";
  c.type = ConstraintType::revolute;
  c.joint1 = joints[0];
  c.joint2 = joints[1];
  b.add_constraint(c, false);
  const Model m = b.build();
  std::vector<BlockState> states(m.blocks.size());
  for (std::size_t i = 0; i < m.blocks.size(); ++i) {
    states[i].pos = m.blocks[i].position0;
    states[i].rot = m.blocks[i].orientation0;
    states[i].vel = Vec3(0.1, 0.2, 0.3);
  }
  const double lambda[5] = {1, 2, 3, 4, 5};
  ConstraintInputs in;
  in.model = &m;
  in.constraint = &m.constraints[0];
  in.block_state = [&](int i) -> const BlockState& { return states[i]; };
  if (st.range(0) == 1) in.lambda = lambda;
  for (auto _ : st) benchmark::DoNotOptimize(evaluate_constraint(in).g(0));
  st.SetLabel(st.range(0) == 1 ? "g, G and d(G^T lambda)/dq (nested AD)" : "g and G (first-order AD)");
}
BENCHMARK(BM_ConstraintRevolute)->Arg(0)->Arg(1);

// The space truss, assembled once per benchmark.
struct Truss {
  Model model = bench::space_truss();
  SystemAssembler sa{model, PETSC_COMM_WORLD};
  Vec U = nullptr, V = nullptr, F = nullptr;
  Mat J = nullptr;
  Truss() {
    sa.create_vector(&U);
    sa.create_vector(&V);
    sa.create_vector(&F);
    sa.create_matrix(&J);
    sa.initial_state(U, V);
  }
  ~Truss() {
    VecDestroy(&U);
    VecDestroy(&V);
    VecDestroy(&F);
    MatDestroy(&J);
  }
  std::string label() const {
    return std::to_string(model.elements.size()) + " bars, " + std::to_string(sa.dofs().global_size()) + " unknowns";
  }
};

void BM_TrussResidual(benchmark::State& st) {
  Truss t;
  EvaluationSettings how;
  PetscBool finite;
  for (auto _ : st) t.sa.residual(EvaluationPoint{t.U, t.V, nullptr, nullptr, 0, 0}, how, t.F, &finite);
  st.SetLabel(t.label());
}
BENCHMARK(BM_TrussResidual)->Unit(benchmark::kMicrosecond);

void BM_TrussJacobian(benchmark::State& st) {
  Truss t;
  EvaluationSettings how;
  for (auto _ : st) t.sa.jacobian(EvaluationPoint{t.U, t.V, nullptr, nullptr, 0, 0}, how, 1, 100, 1e4, t.J);
  st.SetLabel(t.label());
}
BENCHMARK(BM_TrussJacobian)->Unit(benchmark::kMicrosecond);

// One generalized-alpha step (Newton iterations with assembly and a sparse LU each) with the
// direct solver given by the argument.
void BM_TrussImplicitStep(benchmark::State& st) {
  static const char* solvers[] = {"umfpack", "klu", "mumps", "superlu"};
  const char* solver = solvers[st.range(0)];
  PetscOptionsSetValue(nullptr, "-pc_factor_mat_solver_type", solver);
  Truss t;
  DynamicSettings s;
  s.t_end = 1e6;
  s.time_step = 1e-3;
  s.rho_infinity = 0.8;
  GeneralizedAlphaIntegrator integrator(t.sa, s);
  TS ts = integrator.ts();
  TS2SetSolution(ts, t.U, t.V);
  TSSetUp(ts);
  TSRestartStep(ts);
  TSStep(ts);  // the start-up step is not timed
  PetscInt its0;
  TSGetSNESIterations(ts, &its0);
  long steps = 0;
  for (auto _ : st) {
    TSStep(ts);
    ++steps;
  }
  PetscInt its;
  TSGetSNESIterations(ts, &its);
  st.counters["newton_per_step"] = static_cast<double>(its - its0) / static_cast<double>(std::max(1L, steps));
  st.SetLabel(t.label() + ", " + solver);
  PetscOptionsClearValue(nullptr, "-pc_factor_mat_solver_type");
}
BENCHMARK(BM_TrussImplicitStep)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace latticedyn

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  PetscFinalize();
  return 0;
}
