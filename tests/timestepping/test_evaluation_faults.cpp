// Failed evaluations inside the solvers' PETSc callbacks (issue 13): an exception thrown while an
// element is evaluated never unwinds through PETSc; it becomes a domain error, so the step (or the
// load step) is cut, and a run that cutting cannot save ends with a message that names it.
#include "timestepping/generalized_alpha.hpp"
#include "timestepping/static_solver.hpp"

#include "../assembly/sample_models.hpp"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <memory>
#include <new>
#include <stdexcept>

namespace latticedyn {
namespace {

// Adds nothing to the mechanics (zero residual and tangents on one translation slot) but, once
// armed (after the assembler's set-up), throws while its slot's z lies below `below`: as long as
// `budget` allows (then it is harmless again), a std::runtime_error, or std::bad_alloc.
class FaultyElement final : public Element {
 public:
  FaultyElement(double below, int budget, bool bad_alloc) : below_(below), budget_(budget), bad_alloc_(bad_alloc) {}
  std::string_view type_name() const override { return "faulty"; }
  std::span<const SlotKind> slots() const override { return kSlots; }
  void residual(std::span<const SlotState<double>> state, const ElementContext&, Eigen::Ref<VecX> r) const override {
    check(state);
    r.setZero();
  }
  void tangents(std::span<const SlotState<double>> state, const ElementContext&, ElementTangents& out) const override {
    check(state);
    out.resize(3);
    out.residual.setZero();
    for (auto* m : {&out.K, &out.C, &out.M}) m->setZero();
  }
  ElementEnergy energy(std::span<const SlotState<double>>, const ElementContext&) const override { return {}; }
  int thrown() const { return thrown_; }
  void arm() { armed_ = true; }

 private:
  void check(std::span<const SlotState<double>> state) const {
    if (!armed_ || state[0].pos.z() >= below_ || thrown_ >= budget_) return;
    ++thrown_;
    if (bad_alloc_) throw std::bad_alloc();
    throw std::runtime_error("the faulty element's test fault");
  }
  static constexpr std::array<SlotKind, 1> kSlots{SlotKind::translation};
  double below_;
  int budget_;
  bool bad_alloc_;
  mutable std::atomic<int> thrown_{0};
  bool armed_ = false;
};

// A box falling from rest under gravity, the faulty element on its translation.
Model falling_box(const std::shared_ptr<FaultyElement>& faulty) {
  ModelBuilder b;
  b.set_gravity(Vec3(0, 0, -9.81));
  const testing::BodyBlocks box = testing::add_rigid_body(b, "box", 1.0, Vec3::Zero(), Vec3::Zero());
  b.add_element(box.body, faulty, {{box.t}});
  testing::add_body_joint(b, box, "o", Vec3::Zero());
  return b.build();
}

DynamicReport fall(const Model& model, FaultyElement& faulty, double t_end) {
  SystemAssembler sa(model, PETSC_COMM_WORLD);
  faulty.arm();
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  DynamicSettings s;
  s.t_end = t_end;
  s.time_step = 0.01;
  GeneralizedAlphaIntegrator integrator(sa, s);
  DynamicReport report;
  EXPECT_EQ(integrator.run(U, V, nullptr, &report), 0);  // no PETSc error, no exception
  VecDestroy(&U);
  VecDestroy(&V);
  return report;
}

// The box passes z = -0.1 m at t = 0.143 s. Two faults there: the step is cut, retried, and the
// run completes.
TEST(EvaluationFaults, AnExceptionInAnElementCutsTheStep) {
  auto faulty = std::make_shared<FaultyElement>(-0.1, 2, false);
  const DynamicReport r = fall(falling_box(faulty), *faulty, 0.3);
  EXPECT_TRUE(r.completed) << r.message;
  EXPECT_EQ(faulty->thrown(), 2);
  EXPECT_GE(r.rejected_steps, 1) << r.message;
}

// A fault that every retry meets: the run stops after its step cuts, at the place, with the
// element's type and the exception's message (also for std::bad_alloc).
TEST(EvaluationFaults, AFaultThatCuttingCannotAvoidEndsTheRunWithItsMessage) {
  for (const bool bad_alloc : {false, true}) {
    auto faulty = std::make_shared<FaultyElement>(-0.1, 1000000, bad_alloc);
    const DynamicReport r = fall(falling_box(faulty), *faulty, 0.3);
    EXPECT_FALSE(r.completed);
    EXPECT_NEAR(r.time_reached, 0.14, 0.011) << r.message;
    EXPECT_NE(r.message.find(bad_alloc ? "evaluating a faulty element ran out of memory"
                                       : "evaluating a faulty element failed: the faulty element's test fault"),
              std::string::npos)
        << r.message;
  }
}

// Statics: a fault at the start state fails the solve with the message; it cannot go unnoticed.
TEST(EvaluationFaults, StaticSolveNamesTheFault) {
  auto faulty = std::make_shared<FaultyElement>(1.0, 1000000, false);  // z = 0 < 1: always
  const Model model = falling_box(faulty);
  SystemAssembler sa(model, PETSC_COMM_WORLD);
  faulty->arm();
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  StaticSolver solver(sa, StaticSettings{});
  StaticReport report;
  EXPECT_EQ(solver.solve(U, &report), 0);
  EXPECT_FALSE(report.converged);
  EXPECT_NE(report.message.find("the faulty element's test fault"), std::string::npos) << report.message;
  VecDestroy(&U);
  VecDestroy(&V);
}

}  // namespace
}  // namespace latticedyn
