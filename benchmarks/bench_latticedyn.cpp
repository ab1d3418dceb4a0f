// Google Benchmark timings: element evaluation (residual, and residual with all tangents by AD)
// for every element type, constraint evaluation at first and second order, one implicit step of
// a 10-segment cantilever per beam type, and on a ~1000-bar space truss the global residual, the
// global Jacobian and one implicit generalized-alpha step per direct solver.
// Results and the command are recorded in docs/performance.md; tests never assert times.
#include "assembly/constraint_evaluator.hpp"
#include "assembly/system_assembler.hpp"
#include "elements/rope.hpp"
#include "elements/cubic_spline_beam.hpp"
#include "elements/rigid_body.hpp"
#include "elements/strut_tie.hpp"
#include "elements/super_truss.hpp"
#include "elements/timoshenko_beam.hpp"
#include "io/model_reader.hpp"
#include "space_truss_model.hpp"
#include "timestepping/generalized_alpha.hpp"

#include <benchmark/benchmark.h>
#include <slepcsys.h>

#include <fstream>
#include <random>
#include <sstream>

namespace latticedyn {
namespace {

enum ElementKind { kRigidBody, kStrutTie, kTimoshenkoBeam, kCubicSplineBeam, kRope, kSuperTruss, kElementKinds };

// The type 2 section of thesis Table D-3: 15 m, order 6, 56 members.
TrussSectionSpec type2_section() {
  TrussSectionSpec s = rectangular_truss_section(15.0, 6, 1.5, 1.4);
  s.material = Material{7800, 2.06e11, 0.25, {}, 0.0};
  s.main_section = s.cross_section = round_tube_section(0.1, 0.08);
  s.sub_section = round_tube_section(0.05, 0.04);
  return s;
}

std::unique_ptr<Element> make(int kind) {
  const Material steel{7800, 2.06e11, 0.3, {}, 0.0};
  if (kind == kRigidBody) {
    RigidBodyProperties p;
    p.mass = 10;
    p.centroid = Vec3(0.5, 0.1, 0);
    p.inertia_centroid = Vec3(1, 2, 2.5).asDiagonal();
    return std::make_unique<RigidBody>(p);
  }
  if (kind == kStrutTie) {
    StrutTieProperties p;
    p.material = steel;
    p.section = round_tube_section(0.05, 0.04);
    p.rest_length = 1.5;
    p.smoothing = 1e-3;
    return std::make_unique<StrutTie>(p);
  }
  if (kind == kSuperTruss) {
    const TrussSectionSpec spec = type2_section();
    return std::make_unique<SuperTrussElement>(spec, build_truss_geometry(spec));
  }
  BeamProperties beam{steel, round_tube_section(0.05, 0.04), 1.5, 0.0};
  if (kind == kTimoshenkoBeam) return std::make_unique<TimoshenkoBeam>(beam);
  if (kind == kCubicSplineBeam) return std::make_unique<CubicSplineBeam>(CubicSplineBeamProperties{beam, 5});
  RopeProperties rope;
  rope.material = steel;
  rope.section = round_tube_section(0.01, 0.0);
  rope.drive = Drive::Sine{2.0, 0.1, 0.0, 10.0};  // a rest length in motion: all inertia terms on
  rope.fraction = 0.1;
  return std::make_unique<Rope>(rope);
}

// A deformed state near the element's reference (axis along x, length 1.5 m), moving.
std::vector<SlotState<double>> deformed_slots(const Element& e, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  auto v3 = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  const auto kinds = e.slots();
  std::vector<SlotState<double>> s(kinds.size());
  int translation = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    s[k].vel = v3();
    s[k].acc = v3();
    s[k].rot = rotation_matrix<double>(0.1 * v3());
    const double length = e.type_name() == "super_truss" ? 15.0 : 1.5;
    if (kinds[k] == SlotKind::translation) s[k].pos = Vec3(length * translation++, 0, 0) + 0.01 * v3();
    if (kinds[k] == SlotKind::vector) s[k].pos = Vec3(1.001, 0, 0) + 0.01 * v3();
    if (kinds[k] == SlotKind::scalar) s[k].pos = Vec3(1.0 + 0.001 * u(rng), 0, 0);
  }
  return s;
}

void BM_ElementResidual(benchmark::State& st) {
  const auto e = make(static_cast<int>(st.range(0)));
  const auto s = deformed_slots(*e, 1);
  VecX r(e->num_dofs());
  const ElementContext ctx{Vec3(0, 0, -9.81), 0};
  for (auto _ : st) {
    e->residual(s, ctx, r);
    benchmark::DoNotOptimize(r.data());
  }
  st.SetLabel(std::string(e->type_name()));
}
BENCHMARK(BM_ElementResidual)->DenseRange(0, kElementKinds - 1);

void BM_ElementTangents(benchmark::State& st) {
  const auto e = make(static_cast<int>(st.range(0)));
  const auto s = deformed_slots(*e, 2);
  ElementTangents t;
  const ElementContext ctx{Vec3(0, 0, -9.81), 0};
  for (auto _ : st) {
    e->tangents(s, ctx, t);
    benchmark::DoNotOptimize(t.K.data());
  }
  st.SetLabel(std::string(e->type_name()) + " residual + K, C, M");
}
BENCHMARK(BM_ElementTangents)->DenseRange(0, kElementKinds - 1);

// Four elements of one kind through the batched interface (Element::tangents_batch: the Timoshenko
// beam's kernel on the lanes of Pack4, others one by one); the time is per element.
void BM_ElementTangentsBatch(benchmark::State& st) {
  std::vector<std::unique_ptr<Element>> owned;
  std::vector<std::vector<SlotState<double>>> states;
  std::vector<const Element*> elements;
  std::vector<std::span<const SlotState<double>>> spans;
  for (int k = 0; k < kMaxElementBatch; ++k) {
    owned.push_back(make(static_cast<int>(st.range(0))));
    states.push_back(deformed_slots(*owned.back(), 2 + k));
  }
  for (int k = 0; k < kMaxElementBatch; ++k) {
    elements.push_back(owned[k].get());
    spans.emplace_back(states[k]);
  }
  std::vector<ElementTangents> t(kMaxElementBatch);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0};
  for (auto _ : st) {
    owned[0]->tangents_batch(elements, spans, ctx, t);
    benchmark::DoNotOptimize(t[0].K.data());
  }
  st.SetItemsProcessed(st.iterations() * kMaxElementBatch);
  st.SetLabel(std::string(owned[0]->type_name()) + " residual + K, C, M, batch of 4");
}
BENCHMARK(BM_ElementTangentsBatch)->Arg(kTimoshenkoBeam);

// A revolute joint between two free rigid bodies: G alone (residuals) and with dG/dq (Jacobians).
void BM_ConstraintRevolute(benchmark::State& st) {
  ModelBuilder b;
  std::vector<int> joints;
  for (int k = 0; k < 2; ++k) {
    const std::string name = k == 0 ? "b0" : "b1";
    const int body = b.add_body(name, "rigid_body");
    const int t = b.add_block(DofBlock::translation(Vec3(k, 0, 0), Vec3::Zero(), "t"));
    const int r = b.add_block(DofBlock::rotation(rotation_matrix<double>(Vec3(0.1 * k, 0.2, 0.3)), Vec3::Zero(), "r"));
    b.add_element(body, make(kRigidBody), {{t}, {r}});
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
  st.SetLabel(st.range(0) == 1 ? "g, G and d(G^T lambda)/dq (closed form)" : "g and G (closed form)");
}
BENCHMARK(BM_ConstraintRevolute)->Arg(0)->Arg(1);

// Times generalized-alpha steps of size h from the state U, V (the start-up step is not timed);
// counts Newton iterations per step.
void time_steps(benchmark::State& st, SystemAssembler& sa, Vec U, Vec V, double h, double rho_infinity) {
  DynamicSettings s;
  s.t_end = 1e6;
  s.time_step = h;
  s.rho_infinity = rho_infinity;
  GeneralizedAlphaIntegrator integrator(sa, s);
  TS ts = integrator.ts();
  TS2SetSolution(ts, U, V);
  TSSetUp(ts);
  TSRestartStep(ts);
  TSStep(ts);
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
}

// One generalized-alpha step of the beam of thesis Table 8-1 (L = 15 m, solid r = 0.15 m) as a
// 10-segment cantilever swinging under its weight (the self-weight study), per beam type.
void BM_CantileverImplicitStep(benchmark::State& st) {
  const std::string type = st.range(0) == 0 ? "cubic_spline_beam" : "timoshenko_beam";
  const Simulation sim = read_simulation_from_string(R"(gravity: [0, 0, -9.81]
materials: {steel: {density: 7800, youngs_modulus: 2.06e11, poisson_ratio: 0.25}}
sections: {solid: {type: round_tube, outer_radius: 0.15}}
ground: {joints: [{name: clamp}]}
bodies:
  - {name: beam, type: )" + type + R"(, material: steel, section: solid, ends: [[0, 0, 0], [15, 0, 0]], elements: 10}
constraints:
  - {name: clamp, type: fixed, joints: [ground.clamp, beam.1]}
)",
                                                     "cantilever.yaml");
  SystemAssembler sa(sim.model, PETSC_COMM_WORLD);
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  time_steps(st, sa, U, V, 4e-3, 1.0);
  st.SetLabel(type + ", 10 segments, " + std::to_string(sa.dofs().global_size()) + " unknowns");
  VecDestroy(&U);
  VecDestroy(&V);
}
BENCHMARK(BM_CantileverImplicitStep)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

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
  time_steps(st, t.sa, t.U, t.V, 1e-3, 0.8);
  st.SetLabel(t.label() + ", " + solver);
  PetscOptionsClearValue(nullptr, "-pc_factor_mat_solver_type");
}
BENCHMARK(BM_TrussImplicitStep)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

// One generalized-alpha step of a lattice cantilever as the full model (every member a
// Timoshenko beam) and as super truss elements: the type 2 section of Table D-3 (15 m) and the
// whole main boom (types 1, 2, 2, 2, 3, 55 m), the sections taken from examples/main_boom.yaml.
// Arguments: 0/1 type 2 full/reduced, 2/3 main boom full/reduced. Settings of the reduction study
// (verification/studies/lattice_*.yaml): horizontal, clamped at end 1, 1 % of g.
void BM_LatticeImplicitStep(benchmark::State& st) {
  const bool reduced = st.range(0) % 2 == 1, boom = st.range(0) >= 2;
  const std::string type = reduced ? "super_truss" : "lattice";
  std::ifstream in(std::string(LATTICEDYN_SOURCE_DIR) + "/examples/main_boom.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  yaml = yaml.substr(yaml.find("materials:"), yaml.find("ground:") - yaml.find("materials:"));
  yaml += "gravity: [0, 0, -0.0981]\nground: {joints: [{name: root}]}\nbodies:\n";
  if (boom) {
    const char* parts[][2] = {{"foot", "type1"}, {"s1", "type2"}, {"s2", "type2"}, {"s3", "type2"}, {"top", "type3"}};
    const double at[] = {0, 5, 20, 35, 50};
    for (int k = 0; k < 5; ++k)
      yaml += "  - {name: " + std::string(parts[k][0]) + ", type: " + type + ", section: " + parts[k][1] +
              ", position: [" + std::to_string(at[k]) + ", 0, 0]}\n";
    yaml += "constraints:\n  - {name: clamp, type: fixed, joints: [ground.root, foot.1]}\n";
    for (int k = 0; k < 4; ++k)
      yaml += "  - {name: splice" + std::to_string(k) + ", type: fixed, joints: [" + parts[k][0] + ".2, " +
              parts[k + 1][0] + ".1], shared: true}\n";
  } else {
    yaml += "  - {name: boom, type: " + type + ", section: type2}\n";
    yaml += "constraints:\n  - {name: clamp, type: fixed, joints: [ground.root, boom.1]}\n";
  }
  const Simulation sim = read_simulation_from_string(yaml, "lattice_step.yaml");
  SystemAssembler sa(sim.model, PETSC_COMM_WORLD);
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  time_steps(st, sa, U, V, boom ? 0.01 : 0.002, 0.8);
  st.SetLabel(std::string(boom ? "main boom" : "type 2 section") + ", " + type + ", " +
              std::to_string(sa.dofs().global_size()) + " unknowns");
  VecDestroy(&U);
  VecDestroy(&V);
}
BENCHMARK(BM_LatticeImplicitStep)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace latticedyn

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (SlepcInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  SlepcFinalize();
  return 0;
}
