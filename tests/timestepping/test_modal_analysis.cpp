// Natural frequencies by SLEPc against Euler-Bernoulli: a steel cantilever (the beam of thesis
// Table 8-1) of 10 co-rotational Timoshenko beams, clamped by a fixed constraint (multipliers),
// has its first three bending frequencies, in both planes, near f_k = (beta_k L)^2 / (2 pi)
// sqrt(EI / (rho A L^4)) with beta_k L = 1.87510, 4.69409, 7.85476 (e.g. Meirovitch,
// Fundamentals of Vibrations, 7.8).
#include "timestepping/modal_analysis.hpp"

#include "assembly/model_builder.hpp"
#include "elements/timoshenko_beam.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace latticedyn {
namespace {

Model cantilever(int n, bool clamped, RayleighDamping damping = {}) {
  ModelBuilder b;
  const int body = b.add_body("beam", "timoshenko_beam");
  const double L = 15.0;
  BeamProperties p{Material{7800, 2.06e11, 0.25, damping, 0.0}, round_tube_section(0.15, 0.0), L / n, 0.0};
  auto beam = std::make_shared<TimoshenkoBeam>(p);
  std::vector<int> t, r;
  for (int k = 0; k <= n; ++k) {
    t.push_back(b.add_block(DofBlock::translation(Vec3(L * k / n, 0, 0), Vec3::Zero(), "n")));
    r.push_back(b.add_block(DofBlock::rotation(Mat3::Identity(), Vec3::Zero(), "n")));
  }
  for (int k = 0; k < n; ++k) b.add_element(body, beam, {{t[k]}, {r[k]}, {t[k + 1]}, {r[k + 1]}});
  if (clamped) {
    Joint j;
    j.name = "beam.1";
    j.translation_block = t[0];
    j.rotation_block = r[0];
    const int jb = b.add_joint(body, j);
    Constraint c;
    c.name = "clamp";
    c.type = ConstraintType::fixed;
    c.joint1 = b.add_ground_joint("ground.o", Vec3::Zero(), Mat3::Identity());
    c.joint2 = jb;
    b.add_constraint(c, false);
  }
  return b.build();
}

// The lowest `count` modes about the model's initial state (the caller destroys them).
std::vector<Mode> lowest_modes(const Model& model, int count) {
  SystemAssembler sa(model, PETSC_COMM_SELF);
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  ModalAnalysis modal(sa, ModalSettings{count, 1e-10});
  std::vector<Mode> modes;
  std::string message;
  EXPECT_EQ(modal.solve(U, 0.0, &modes, &message), 0);
  EXPECT_EQ(static_cast<int>(modes.size()), count) << message;
  VecDestroy(&U);
  VecDestroy(&V);
  return modes;
}

TEST(ModalAnalysis, CantileverMatchesEulerBernoulli) {
  const Model model = cantilever(10, true);
  std::vector<Mode> modes = lowest_modes(model, 6);
  ASSERT_EQ(modes.size(), 6u);
  const double r = 0.15, EI = 2.06e11 * std::numbers::pi * std::pow(r, 4) / 4, rhoA = 7800 * std::numbers::pi * r * r;
  const double beta[3] = {1.875104069, 4.694091133, 7.854757438};
  // Ten elements with the linear translational mass: the error grows with the mode's waviness
  // (measured +0.1 %, +0.7 %, +3.3 %).
  const double tol[3] = {0.002, 0.01, 0.04};
  for (int k = 0; k < 3; ++k) {
    const double f = beta[k] * beta[k] / (2 * std::numbers::pi) * std::sqrt(EI / (rhoA * std::pow(15.0, 4)));
    for (int plane = 0; plane < 2; ++plane) {
      const Mode& m = modes[2 * k + plane];
      EXPECT_NEAR(m.frequency, f, tol[k] * f) << "mode " << 2 * k + plane;
      EXPECT_LT(m.residual, 1e-8);
    }
  }
  destroy_modes(modes);
}

// Rayleigh damping is proportional: every mode's ratio phi^T C phi / (2 omega phi^T M phi) is
// alpha / (2 omega) + beta omega / 2 exactly (Chopra, Dynamics of Structures, 11.4), and an
// undamped model reports zero.
TEST(ModalAnalysis, ReportsTheRayleighDampingRatioOfEveryMode) {
  for (const RayleighDamping d : {RayleighDamping{}, RayleighDamping{0.3, 2e-3}}) {
    std::vector<Mode> modes = lowest_modes(cantilever(10, true, d), 6);
    ASSERT_EQ(modes.size(), 6u);
    for (const Mode& m : modes) {
      const double expected = d.ratio(2 * std::numbers::pi * m.frequency);
      EXPECT_NEAR(m.damping_ratio, expected, 1e-8 + 1e-8 * expected) << m.frequency << " Hz";
    }
    destroy_modes(modes);
  }
}

// A free beam has six rigid-body modes at zero frequency, then its first free-free bending
// mode, (beta L)^2 = 22.3733.
TEST(ModalAnalysis, FreeBeamHasSixRigidModes) {
  const Model model = cantilever(10, false);
  std::vector<Mode> modes = lowest_modes(model, 8);
  ASSERT_EQ(modes.size(), 8u);
  for (int k = 0; k < 6; ++k) EXPECT_LT(std::abs(modes[k].omega2), 1e-6) << k;
  const double r = 0.15, EI = 2.06e11 * std::numbers::pi * std::pow(r, 4) / 4, rhoA = 7800 * std::numbers::pi * r * r;
  const double f = 22.3733 / (2 * std::numbers::pi) * std::sqrt(EI / (rhoA * std::pow(15.0, 4)));
  EXPECT_NEAR(modes[6].frequency, f, 0.01 * f);
  destroy_modes(modes);
}

}  // namespace
}  // namespace latticedyn
