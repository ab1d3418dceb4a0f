// Tests of the non-trapezoidal drives: constant, cosine step and bump, tanh step, sine, table,
// sums, validation messages and descriptions (thesis Appendix E).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/drive.hpp"
#include "drive_test_util.hpp"

namespace latticedyn {
namespace {

using test::expect_continuous_at;
using test::expect_derivatives_match_fd;
using test::sample_times;

auto as_fn(const Drive& d) {
  return [&d](double t) { return d.evaluate(t); };
}

// Expects construction to throw std::invalid_argument whose message mentions every fragment.
template <class P>
void expect_rejected(const P& params, const std::vector<std::string>& fragments) {
  try {
    (void)Drive(params);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    for (const std::string& f : fragments) {
      EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' missing from: " << msg;
    }
  }
}

TEST(Drive, DefaultAndConstant) {
  const DriveValue zero = Drive().evaluate(3.0);
  EXPECT_EQ(zero.value, 0.0);
  const Drive c(Drive::Constant{7.5});
  for (double t : {-10.0, 0.0, 1e6}) {
    const DriveValue v = c.evaluate(t);
    EXPECT_EQ(v.value, 7.5);
    EXPECT_EQ(v.rate, 0.0);
    EXPECT_EQ(v.accel, 0.0);
  }
  expect_rejected(Drive::Constant{INFINITY}, {"Constant", "value", "finite"});
}

// The thesis's example for Figures E-2 to E-4: y 10 -> 20 over [5, 15].
TEST(CosineStep, HitsEndValuesAndIsSmooth) {
  const Drive d(Drive::CosineStep{.t_start = 5.0, .t_end = 15.0, .y_start = 10.0, .y_end = 20.0});
  EXPECT_EQ(d.evaluate(0.0).value, 10.0);
  EXPECT_EQ(d.evaluate(5.0).value, 10.0);
  EXPECT_NEAR(d.evaluate(10.0).value, 15.0, 1e-14);
  EXPECT_NEAR(d.evaluate(10.0).rate, 0.5 * 10.0 * std::numbers::pi / 10.0, 1e-14);  // peak
  EXPECT_EQ(d.evaluate(15.0).value, 20.0);
  EXPECT_EQ(d.evaluate(99.0).value, 20.0);
  EXPECT_EQ(d.evaluate(99.0).rate, 0.0);
  expect_continuous_at(as_fn(d), 5.0, true);
  expect_continuous_at(as_fn(d), 15.0, true);
  expect_derivatives_match_fd(as_fn(d), sample_times(5.0, 15.0, 40, {}, 0.0), 1e-5, 1e-7);
}

TEST(CosineStep, AgreesWithThesisFormE6) {
  const double ts = 2.0, te = 4.5, ys = -1.0, ye = 3.0;
  const Drive d(Drive::CosineStep{.t_start = ts, .t_end = te, .y_start = ys, .y_end = ye});
  for (int i = 0; i < 25; ++i) {  // [ts, te): at te itself the acceleration is already 0
    const double t = ts + 0.1 * i;
    const double arg = (t - ts) * std::numbers::pi / (ts - te);
    EXPECT_NEAR(d.evaluate(t).value, 0.5 * (ys + ye) + 0.5 * (ys - ye) * std::cos(arg), 1e-14);
    EXPECT_NEAR(d.evaluate(t).rate,
                -0.5 * std::numbers::pi * (ys - ye) / (ts - te) * std::sin(arg), 1e-13);
    EXPECT_NEAR(d.evaluate(t).accel,
                -0.5 * std::numbers::pi * std::numbers::pi * (ys - ye) / ((ts - te) * (ts - te)) *
                    std::cos(arg),
                1e-13);
  }
}

TEST(CosineFull, ReachesPeakAtMidpointAndReturns) {
  const Drive d(Drive::CosineFull{.t1 = 5.0, .t2 = 15.0, .y1 = 10.0, .y2 = 20.0});
  EXPECT_EQ(d.evaluate(5.0).value, 10.0);
  EXPECT_NEAR(d.evaluate(10.0).value, 20.0, 1e-14);
  EXPECT_NEAR(d.evaluate(10.0).rate, 0.0, 1e-13);
  EXPECT_NEAR(d.evaluate(15.0 - 1e-12).value, 10.0, 1e-9);
  EXPECT_EQ(d.evaluate(15.0).value, 10.0);
  EXPECT_EQ(d.evaluate(30.0).value, 10.0);
  expect_continuous_at(as_fn(d), 5.0, true);
  expect_continuous_at(as_fn(d), 15.0, true);
  expect_derivatives_match_fd(as_fn(d), sample_times(5.0, 15.0, 40, {}, 0.0), 1e-5, 1e-7);
}

TEST(TanhStep, ValueAtEndsOfSpanAndDerivatives) {
  const double lambda = tanh_confidence_coefficient(0.99);
  const Drive::TanhStep p{.t1 = 5.0, .t2 = 15.0, .y1 = 10.0, .y2 = 20.0, .lambda = lambda};
  const Drive d(p);
  EXPECT_NEAR(d.evaluate(15.0).value, 10.0 + 10.0 * (1.0 + std::tanh(lambda)) / 2.0, 1e-13);
  EXPECT_NEAR(d.evaluate(5.0).value, 10.0 + 10.0 * (1.0 - std::tanh(lambda)) / 2.0, 1e-13);
  EXPECT_NEAR(d.evaluate(10.0).value, 15.0, 1e-14);
  EXPECT_NEAR(d.evaluate(10.0).rate, lambda * 10.0 / 10.0, 1e-14);  // E-14 at the centre
  EXPECT_NEAR(d.evaluate(1e4).value, 20.0, 1e-12);                   // asymptote
  expect_derivatives_match_fd(as_fn(d), sample_times(0.0, 20.0, 80, {}, 0.0), 1e-5, 1e-7);
}

TEST(TanhStep, ConfidenceCoefficientsOfTableE1) {
  EXPECT_EQ(tanh_confidence_coefficient(0.9), 1.4765);
  EXPECT_EQ(tanh_confidence_coefficient(0.95), 1.8368);
  EXPECT_EQ(tanh_confidence_coefficient(0.99), 2.6476);
  EXPECT_EQ(tanh_confidence_coefficient(0.995), 2.9980);
  EXPECT_EQ(tanh_confidence_coefficient(0.999), 3.8088);
  for (double c : {0.9, 0.95, 0.99, 0.995, 0.999}) {
    // The table is close to atanh(c) but not equal to it (see drive_profiles.cpp).
    EXPECT_NEAR(tanh_confidence_coefficient(c), std::atanh(c), 0.01) << c;
  }
  try {
    (void)tanh_confidence_coefficient(0.8);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("0.8"), std::string::npos) << msg;
    EXPECT_NE(msg.find("0.995"), std::string::npos) << msg;
  }
}

TEST(Sine, ValueAndDerivatives) {
  const Drive::Sine p{.amplitude = 0.3, .frequency = 1.5, .phase = 0.2, .offset = -1.0};
  const Drive d(p);
  const double w = 2.0 * std::numbers::pi * 1.5;
  EXPECT_NEAR(d.evaluate(0.7).value, -1.0 + 0.3 * std::sin(w * 0.7 + 0.2), 1e-15);
  expect_derivatives_match_fd(as_fn(d), sample_times(-1.0, 2.0, 60, {}, 0.0), 1e-6, 1e-7);
  expect_rejected(Drive::Sine{.amplitude = 1.0, .frequency = -2.0, .phase = 0.0, .offset = 0.0},
                  {"Sine", "frequency", "-2"});
}

const Drive::Table kTable{.times = {0.0, 1.0, 2.5, 3.0, 5.0},
                          .values = {0.0, 2.0, 1.0, 1.5, 4.0},
                          .zero_end_rates = true};

TEST(Table, PassesThroughPointsAndHoldsEndValues) {
  for (bool clamped : {true, false}) {
    Drive::Table p = kTable;
    p.zero_end_rates = clamped;
    const Drive d(p);
    for (std::size_t i = 0; i < p.times.size(); ++i) {
      EXPECT_EQ(d.evaluate(p.times[i]).value, p.values[i]) << i;
    }
    EXPECT_EQ(d.evaluate(-3.0).value, 0.0);
    EXPECT_EQ(d.evaluate(-3.0).rate, 0.0);
    EXPECT_EQ(d.evaluate(9.0).value, 4.0);
    EXPECT_EQ(d.evaluate(9.0).accel, 0.0);
  }
}

TEST(Table, ClampedHasZeroEndRatesNaturalHasZeroEndCurvature) {
  const Drive clamped(kTable);
  EXPECT_NEAR(clamped.evaluate(1e-12).rate, 0.0, 1e-9);
  EXPECT_NEAR(clamped.evaluate(5.0 - 1e-12).rate, 0.0, 1e-9);
  expect_continuous_at(as_fn(clamped), 0.0, true);
  expect_continuous_at(as_fn(clamped), 5.0, true);
  Drive::Table p = kTable;
  p.zero_end_rates = false;
  const Drive natural(p);
  EXPECT_NEAR(natural.evaluate(1e-12).accel, 0.0, 1e-9);
  EXPECT_NEAR(natural.evaluate(5.0 - 1e-12).accel, 0.0, 1e-9);
  EXPECT_GT(std::abs(natural.evaluate(1e-12).rate), 0.1);  // why natural tables jump in rate
}

TEST(Table, IsC2InsideAndDerivativesMatchFiniteDifferences) {
  for (bool clamped : {true, false}) {
    Drive::Table p = kTable;
    p.zero_end_rates = clamped;
    const Drive d(p);
    for (std::size_t i = 1; i + 1 < p.times.size(); ++i) {
      const double t = p.times[i];
      const DriveValue l = d.evaluate(t - 1e-10), r = d.evaluate(t + 1e-10);
      EXPECT_NEAR(l.value, r.value, 1e-8) << t;
      EXPECT_NEAR(l.rate, r.rate, 1e-8) << t;
      EXPECT_NEAR(l.accel, r.accel, 1e-7) << t;
    }
    expect_derivatives_match_fd(as_fn(d), sample_times(0.0, 5.0, 100, p.times, 1e-3), 1e-5,
                                1e-7);
  }
}

TEST(Table, InvalidTablesThrow) {
  expect_rejected(Drive::Table{.times = {0.0}, .values = {1.0}}, {"Table", "at least 2"});
  expect_rejected(Drive::Table{.times = {0.0, 1.0}, .values = {1.0}}, {"Table", "sizes"});
  expect_rejected(Drive::Table{.times = {0.0, 2.0, 2.0}, .values = {1.0, 2.0, 3.0}},
                  {"Table", "strictly increasing"});
  expect_rejected(Drive::Table{.times = {0.0, 1.0}, .values = {1.0, NAN}},
                  {"Table", "not finite"});
}

// The minimum-jerk profile y_start + (y_end - y_start)(10 s^3 - 15 s^4 + 6 s^5): end values, its
// symmetric midpoint (value halfway, peak rate 15/8 of the mean rate, no acceleration), rate and
// acceleration zero at both ends (continuous there, unlike the cosine step's acceleration), and
// derivatives that match finite differences.
TEST(QuinticStep, StartsAndStopsWithoutAcceleration) {
  const Drive d(Drive::QuinticStep{.t_start = 1.0, .t_end = 3.0, .y_start = -1.0, .y_end = 3.0});
  EXPECT_EQ(d.evaluate(0.0).value, -1.0);
  EXPECT_NEAR(d.evaluate(2.0).value, 1.0, 1e-14);
  EXPECT_NEAR(d.evaluate(2.0).rate, 15.0 / 8.0 * 4.0 / 2.0, 1e-13);
  EXPECT_NEAR(d.evaluate(2.0).accel, 0.0, 1e-13);
  EXPECT_NEAR(d.evaluate(1.5).accel, 4.0 / 4.0 * 60.0 * 0.25 * 0.75 * 0.5, 1e-13);
  EXPECT_EQ(d.evaluate(3.0).value, 3.0);
  for (double t : {1.0, 3.0}) {
    EXPECT_NEAR(d.evaluate(t).rate, 0.0, 1e-14);
    EXPECT_NEAR(d.evaluate(t).accel, 0.0, 1e-14);
    EXPECT_NEAR(d.evaluate(t - 1e-9).accel, 0.0, 1e-6);
    EXPECT_NEAR(d.evaluate(t + 1e-9).accel, 0.0, 1e-6);
  }
  expect_continuous_at(as_fn(d), 1.0, true);
  expect_continuous_at(as_fn(d), 3.0, true);
  expect_derivatives_match_fd(as_fn(d), sample_times(1.0, 3.0, 40, {}, 0.0), 1e-5, 1e-7);
  EXPECT_EQ(d.breakpoints(), (std::vector<double>{1.0, 3.0}));
  expect_rejected(Drive::QuinticStep{.t_start = 2.0, .t_end = 1.0, .y_start = 0.0, .y_end = 1.0},
                  {"QuinticStep", "t_end", "t_start"});
}

TEST(Sum, AddsItsTermsAndCopiesDeeply) {
  const Drive::Sine wobble{.amplitude = 0.1, .frequency = 2.0, .phase = 0.0, .offset = 0.0};
  const Drive::CosineStep step{.t_start = 1.0, .t_end = 3.0, .y_start = 0.0, .y_end = 2.0};
  Drive sum(Drive::Sum{{Drive::Constant{1.0}, wobble, step}});
  const Drive copy = sum;
  sum = Drive::Constant{0.0};  // reassigning the original must not touch the copy
  for (double t = 0.0; t < 4.0; t += 0.13) {
    const DriveValue a = Drive(wobble).evaluate(t), b = Drive(step).evaluate(t);
    const DriveValue s = copy.evaluate(t);
    EXPECT_DOUBLE_EQ(s.value, 1.0 + a.value + b.value);
    EXPECT_DOUBLE_EQ(s.rate, a.rate + b.rate);
    EXPECT_DOUBLE_EQ(s.accel, a.accel + b.accel);
  }
  expect_rejected(Drive::Sum{}, {"Sum", "at least one"});
}

TEST(Drive, InvalidTimeSpansThrowNamingTheParameter) {
  expect_rejected(Drive::CosineStep{.t_start = 2.0, .t_end = 2.0, .y_start = 0.0, .y_end = 1.0},
                  {"CosineStep", "t_end", "t_start"});
  expect_rejected(Drive::CosineFull{.t1 = 3.0, .t2 = 1.0, .y1 = 0.0, .y2 = 1.0},
                  {"CosineFull", "t2", "t1"});
  expect_rejected(Drive::TanhStep{.t1 = 0.0, .t2 = 1.0, .y1 = 0.0, .y2 = 1.0, .lambda = 0.0},
                  {"TanhStep", "lambda"});
  expect_rejected(Drive::TanhStep{.t1 = 1.0, .t2 = 0.5, .y1 = 0.0, .y2 = 1.0, .lambda = 2.0},
                  {"TanhStep", "t2"});
}

TEST(Drive, DescribeNamesKindAndParameters) {
  const Drive trap(Drive::TrapezoidalVelocity{.t_start = 0.0, .duration = 40.0,
                                              .accel_time = 5.0, .decel_time = 5.0,
                                              .distance = 10.0, .initial = 0.0});
  const std::string s = trap.describe();
  EXPECT_NE(s.find("trapezoidal"), std::string::npos) << s;
  EXPECT_NE(s.find("40"), std::string::npos) << s;
  EXPECT_NE(Drive(kTable).describe().find("5 points"), std::string::npos);
  const Drive sum(Drive::Sum{{Drive::Constant{2.0}, Drive::Constant{3.0}}});
  EXPECT_NE(sum.describe().find("constant 3"), std::string::npos) << sum.describe();
  EXPECT_FALSE(Drive(Drive::TanhStep{.t1 = 0, .t2 = 1, .y1 = 0, .y2 = 1, .lambda = 2})
                   .describe()
                   .empty());
}

}  // namespace
}  // namespace latticedyn

namespace latticedyn {
namespace {

// Breakpoints: where the acceleration jumps, so that an integrator can end its steps there.
TEST(Drive, BreakpointsAreWhereTheAccelerationJumps) {
  const Drive trap(Drive::TrapezoidalVelocity{.t_start = 1.0, .duration = 8.0, .accel_time = 2.0, .decel_time = 3.0,
                                              .distance = 1.0});
  EXPECT_EQ(trap.breakpoints(), (std::vector<double>{1.0, 3.0, 6.0, 9.0}));
  // The acceleration does jump at each of them (evaluate() gives the phase starting there).
  for (double t : trap.breakpoints()) EXPECT_GT(std::abs(trap.evaluate(t).accel - trap.evaluate(t - 1e-9).accel), 0.01);
  EXPECT_TRUE(Drive(Drive::Sine{.amplitude = 1.0, .frequency = 0.5}).breakpoints().empty());
  EXPECT_TRUE(Drive(Drive::Constant{2.0}).breakpoints().empty());
  EXPECT_EQ(Drive(Drive::Table{{0.0, 1.0, 2.5}, {0.0, 1.0, 0.0}}).breakpoints(), (std::vector<double>{0.0, 1.0, 2.5}));
  // A sum: the union of its terms', ascending, each once.
  const Drive sum(Drive::Sum{{Drive::CosineStep{.t_start = 0.0, .t_end = 3.0, .y_start = 0, .y_end = 1},
                              Drive::CosineStep{.t_start = 3.0, .t_end = 5.0, .y_start = 0, .y_end = 1}}});
  EXPECT_EQ(sum.breakpoints(), (std::vector<double>{0.0, 3.0, 5.0}));
}

}  // namespace
}  // namespace latticedyn
