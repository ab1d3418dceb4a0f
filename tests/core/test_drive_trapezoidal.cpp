// Tests of the trapezoidal velocity drive (thesis eq. 8-3, E-1..E-5), including the thesis's
// example s0 = 10, t0 = 40, t1 = t3 = 5, and a sum of stages as in section 8.3.2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/drive.hpp"
#include "drive_test_util.hpp"

namespace latticedyn {
namespace {

using test::expect_continuous_at;
using test::expect_derivatives_match_fd;
using test::sample_times;

const Drive::TrapezoidalVelocity kThesisExample{
    .t_start = 0.0, .duration = 40.0, .accel_time = 5.0, .decel_time = 5.0, .distance = 10.0,
    .initial = 0.0};

// Shifted, asymmetric, backwards: exercises every parameter.
const Drive::TrapezoidalVelocity kGeneral{
    .t_start = 3.0, .duration = 20.0, .accel_time = 4.0, .decel_time = 7.0, .distance = -6.0,
    .initial = 2.0};

TEST(TrapezoidalVelocity, ThesisExampleValues) {
  const Drive d(kThesisExample);
  const double a1 = 2.0 * 10.0 / (5.0 * (80.0 - 10.0));  // E-5: 4/70 m/s^2
  const double vmax = a1 * 5.0;
  const double s1 = 0.5 * a1 * 25.0;
  const TrapezoidalKinematics k = trapezoidal_kinematics(kThesisExample);
  EXPECT_NEAR(k.accel, a1, 1e-15);
  EXPECT_NEAR(k.decel, -a1, 1e-15);  // symmetric phases
  EXPECT_NEAR(k.peak_rate, vmax, 1e-15);
  EXPECT_EQ(d.evaluate(-1.0).value, 0.0);
  EXPECT_NEAR(d.evaluate(2.0).value, 0.5 * a1 * 4.0, 1e-14);
  EXPECT_NEAR(d.evaluate(2.0).accel, a1, 1e-15);
  EXPECT_NEAR(d.evaluate(20.0).value, s1 + vmax * 15.0, 1e-13);
  EXPECT_NEAR(d.evaluate(20.0).value, 5.0, 1e-13);  // symmetric profile: half way at half time
  EXPECT_NEAR(d.evaluate(20.0).rate, vmax, 1e-15);
  EXPECT_NEAR(d.evaluate(38.0).value, 10.0 - 0.5 * a1 * 4.0, 1e-13);
  EXPECT_NEAR(d.evaluate(38.0).accel, -a1, 1e-15);
  EXPECT_EQ(d.evaluate(40.0).value, 10.0);
  EXPECT_EQ(d.evaluate(55.0).value, 10.0);
  EXPECT_EQ(d.evaluate(55.0).rate, 0.0);
}

TEST(TrapezoidalVelocity, ReachesInitialPlusDistance) {
  const Drive d(kGeneral);
  EXPECT_EQ(d.evaluate(kGeneral.t_start).value, kGeneral.initial);
  EXPECT_DOUBLE_EQ(d.evaluate(kGeneral.t_start + kGeneral.duration).value,
                   kGeneral.initial + kGeneral.distance);
  EXPECT_NEAR(d.evaluate(kGeneral.t_start + kGeneral.duration - 1e-9).value,
              kGeneral.initial + kGeneral.distance, 1e-12);
  EXPECT_EQ(d.evaluate(1e3).value, kGeneral.initial + kGeneral.distance);
}

TEST(TrapezoidalVelocity, ValueAndRateContinuousAtPhaseBoundaries) {
  for (const auto& p : {kThesisExample, kGeneral}) {
    const Drive d(p);
    const auto f = [&d](double t) { return d.evaluate(t); };
    for (double b : {p.t_start, p.t_start + p.accel_time,
                     p.t_start + p.duration - p.decel_time, p.t_start + p.duration}) {
      expect_continuous_at(f, b, true);
    }
  }
}

TEST(TrapezoidalVelocity, AccelerationIsRightContinuousAtPhaseBoundaries) {
  // Like eq. 8-3's half-open intervals: the phase starting at a boundary gives its acceleration.
  const Drive d(kThesisExample);
  const TrapezoidalKinematics k = trapezoidal_kinematics(kThesisExample);
  EXPECT_EQ(d.evaluate(0.0).accel, k.accel);
  EXPECT_EQ(d.evaluate(5.0).accel, 0.0);
  EXPECT_EQ(d.evaluate(35.0).accel, k.decel);
  EXPECT_EQ(d.evaluate(40.0).accel, 0.0);
}

TEST(TrapezoidalVelocity, PeakRateIsA1TimesT1) {
  const Drive d(kGeneral);
  const TrapezoidalKinematics k = trapezoidal_kinematics(kGeneral);
  EXPECT_DOUBLE_EQ(k.peak_rate, k.accel * kGeneral.accel_time);
  EXPECT_DOUBLE_EQ(k.peak_rate, -k.decel * kGeneral.decel_time);  // E-3: v_max + a3 t3 = 0
  double extreme = 0.0;  // distance < 0 here, so the peak rate is the most negative one
  for (double t = 0.0; t < 30.0; t += 0.01) extreme = std::min(extreme, d.evaluate(t).rate);
  EXPECT_NEAR(extreme, k.peak_rate, 1e-12);
  EXPECT_NEAR(d.evaluate(kGeneral.t_start + 6.0).rate, k.peak_rate, 1e-15);
}

TEST(TrapezoidalVelocity, DerivativesMatchFiniteDifferences) {
  const Drive d(kGeneral);
  const auto times = sample_times(0.0, 30.0, 150, {3.0, 7.0, 16.0, 23.0}, 1e-3);
  expect_derivatives_match_fd([&d](double t) { return d.evaluate(t); }, times, 1e-5, 1e-7);
}

TEST(TrapezoidalVelocity, TriangularProfileWithoutCoastPhase) {
  const Drive::TrapezoidalVelocity p{.t_start = 0.0, .duration = 10.0, .accel_time = 4.0,
                                     .decel_time = 6.0, .distance = 5.0, .initial = 0.0};
  const Drive d(p);
  const auto f = [&d](double t) { return d.evaluate(t); };
  expect_continuous_at(f, 4.0, true);
  EXPECT_DOUBLE_EQ(d.evaluate(10.0).value, 5.0);
  EXPECT_NEAR(d.evaluate(4.0).rate, trapezoidal_kinematics(p).peak_rate, 1e-15);
}

TEST(TrapezoidalVelocity, InvalidParametersThrow) {
  auto with = [](auto change) {
    Drive::TrapezoidalVelocity p = kThesisExample;
    change(p);
    return p;
  };
  EXPECT_THROW((void)Drive(with([](auto& p) { p.accel_time = 0.0; })), std::invalid_argument);
  EXPECT_THROW((void)Drive(with([](auto& p) { p.decel_time = -1.0; })), std::invalid_argument);
  EXPECT_THROW((void)Drive(with([](auto& p) { p.duration = 9.0; })), std::invalid_argument);
  EXPECT_THROW((void)Drive(with([](auto& p) { p.distance = NAN; })), std::invalid_argument);
  try {
    (void)Drive(with([](auto& p) { p.duration = 9.0; }));
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("TrapezoidalVelocity"), std::string::npos) << msg;
    EXPECT_NE(msg.find("duration"), std::string::npos) << msg;
  }
}

TEST(TrapezoidalVelocity, SumOfStagesAddsLikeTheCraneMotion) {
  // Lifting, then luffing back part of the way: two stages of one coordinate, as in 8.3.2.
  const Drive::TrapezoidalVelocity lift{.t_start = 0.0, .duration = 10.0, .accel_time = 2.0,
                                        .decel_time = 2.0, .distance = 4.0, .initial = 53.9937};
  const Drive::TrapezoidalVelocity lower{.t_start = 12.0, .duration = 8.0, .accel_time = 3.0,
                                         .decel_time = 1.0, .distance = -1.5, .initial = 0.0};
  const Drive sum(Drive::Sum{{lift, lower}});
  const Drive a(lift), b(lower);
  for (double t = -1.0; t < 25.0; t += 0.37) {
    const DriveValue s = sum.evaluate(t), va = a.evaluate(t), vb = b.evaluate(t);
    EXPECT_DOUBLE_EQ(s.value, va.value + vb.value) << t;
    EXPECT_DOUBLE_EQ(s.rate, va.rate + vb.rate) << t;
    EXPECT_DOUBLE_EQ(s.accel, va.accel + vb.accel) << t;
  }
  EXPECT_NEAR(sum.evaluate(30.0).value, 53.9937 + 4.0 - 1.5, 1e-12);
}

}  // namespace
}  // namespace latticedyn
