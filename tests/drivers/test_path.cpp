// The arc-length path of the two-bar (von Mises) truss against its closed form, P(w) = 2 E A
// (1 - l / L0) (h - w) / l (Crisfield, Non-linear Finite Element Analysis of Solids and Structures,
// vol. 1, 1991, 1.2; scripts/reference/two_bar_truss.py): every point of the path on the curve,
// through the limit load (2960.52 N), the snap-through to the inverted truss and up again.
#include "io/model_reader.hpp"
#include "timestepping/arc_length.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace latticedyn {
namespace {

constexpr double kA = 1.0, kH = 0.2, kEA = 1.0e6, kP = 1000.0;

double closed_form_load(double w) {
  const double L0 = std::hypot(kA, kH), l = std::hypot(kA, kH - w);
  return 2 * kEA * (1 - l / L0) * (kH - w) / l;
}

struct Point {
  double lambda, w;
};

std::vector<Point> trace(double arc, double max_arc_factor, PathReport* report) {
  Simulation sim = read_simulation(TWO_BAR_TRUSS);
  sim.path.arc_length = arc;
  sim.path.max_arc_factor = max_arc_factor;
  SystemAssembler sa(sim.model, PETSC_COMM_SELF);
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  ModelState state(sim.model, sa.dofs());
  const int apex = sim.model.find_joint("apex.pin");
  std::vector<Point> points;
  ArcLengthSolver solver(sa, sim.path);
  const auto on_point = [&](const PathPoint& p) {
    PetscFunctionBeginUser;
    PetscCall(sa.gather(0.0, p.U, V, nullptr, Parametrization::rotation_vector_rates, &state));
    points.push_back(Point{p.load_factor, kH - state.joint_position(apex).z()});
    PetscFunctionReturn(0);
  };
  EXPECT_EQ(solver.trace(U, 0.0, on_point, report), 0);
  VecDestroy(&U);
  VecDestroy(&V);
  return points;
}

TEST(ArcLength, TwoBarTrussFollowsItsClosedFormThroughSnapThrough) {
  PathReport report;
  const std::vector<Point> path = trace(0.005, 1.0, &report);
  ASSERT_TRUE(report.completed) << report.message;
  ASSERT_GT(path.size(), 50u);
  const double pmax = 2960.5176007631;  // the limit load, closed form
  double top = -1e30, bottom = 1e30;
  for (const Point& p : path) {
    // On the curve: the residual tolerance (1e-8 of the reference load) and nothing else.
    EXPECT_NEAR(p.lambda * kP, closed_form_load(p.w), 1e-6 * pmax) << "w = " << p.w;
    if (p.w < kH) top = std::max(top, p.lambda);  // the limit load before the truss turns flat
    if (p.w > kH && p.w < 2 * kH) bottom = std::min(bottom, p.lambda);
  }
  // Through both limit points (sampled every 5 mm of the apex's travel: within 0.2 % of them).
  EXPECT_NEAR(top, pmax / kP, 2e-3 * pmax / kP);
  EXPECT_NEAR(bottom, -pmax / kP, 2e-3 * pmax / kP);
  // Monotone in w: the apex never goes back up, however the load turns.
  for (std::size_t k = 1; k < path.size(); ++k) EXPECT_GT(path[k].w, path[k - 1].w);
  // Past the inverted, unstressed state (w = 2 h) and up to the requested factor.
  EXPECT_GT(path.back().w, 2 * kH);
  EXPECT_GE(path.back().lambda, 4.0);
}

TEST(ArcLength, AdaptedArcsStayOnThePath) {
  PathReport report;
  const std::vector<Point> path = trace(0.01, 10.0, &report);
  ASSERT_TRUE(report.completed) << report.message;
  for (const Point& p : path) EXPECT_NEAR(p.lambda * kP, closed_form_load(p.w), 1e-6 * 2960.5);
  EXPECT_LT(path.size(), 30u);  // arcs grew where the truss needs one iteration
}

}  // namespace
}  // namespace latticedyn
