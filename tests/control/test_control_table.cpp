// The control table of thesis 6.4: 20 resampled points plus 5 steady points at each end, equal
// spacing, the trajectory's values at the resampled times, and a spline drive through it that
// starts and ends at rest.
#include "control/control_table.hpp"
#include "core/drive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace latticedyn {
namespace {

TEST(ControlTable, ResamplesAndAddsSteadyPoints) {
  std::vector<double> t, a, b;
  for (int k = 0; k <= 400; ++k) {  // 40 s at 0.1 s, as Table 8-2
    t.push_back(0.1 * k);
    a.push_back(10.0 + 0.01 * k * k / 40.0);
    b.push_back(50.0 - std::sin(0.1 * k / 40.0 * M_PI / 2) * 8.0);
  }
  const ControlTable c = make_control_table(t, {a, b}, 20, 5);
  ASSERT_EQ(c.times.size(), 30u);
  ASSERT_EQ(c.values.size(), 2u);
  EXPECT_DOUBLE_EQ(c.spacing, 40.0 / 19);
  EXPECT_DOUBLE_EQ(c.lead_time, 5 * 40.0 / 19);
  for (std::size_t i = 1; i < c.times.size(); ++i) EXPECT_NEAR(c.times[i] - c.times[i - 1], c.spacing, 1e-12);
  for (int i = 0; i <= 5; ++i) {
    EXPECT_DOUBLE_EQ(c.values[0][i], a.front());
    EXPECT_DOUBLE_EQ(c.values[1][29 - i], b.back());
  }
  // A resampled point between two trajectory instants: linear interpolation of the neighbours.
  const double at = 7 * c.spacing;  // sample 7, table index 12
  const int k = static_cast<int>(at / 0.1);
  const double w = (at - t[k]) / 0.1;
  EXPECT_NEAR(c.values[0][12], (1 - w) * a[k] + w * a[k + 1], 1e-12);
}

TEST(ControlTable, SplineDriveThroughItStartsAndEndsAtRest) {
  std::vector<double> t{0, 1, 2, 3, 4}, v{0, 1, 4, 9, 16};
  const ControlTable c = make_control_table(t, {v}, 5, 5);
  const Drive d = Drive::Table{c.times, c.values[0], true};
  EXPECT_NEAR(d.evaluate(0.0).rate, 0.0, 1e-12);
  EXPECT_NEAR(d.evaluate(c.times.back()).rate, 0.0, 1e-12);
  EXPECT_NEAR(d.evaluate(c.lead_time + 2.0).value, 4.0, 1e-12);  // passes through the samples
}

TEST(ControlTable, RejectsUnusableInput) {
  const std::vector<double> t{0, 1, 1}, v{0, 1, 2};
  EXPECT_THROW(make_control_table(t, {v}, 20, 5), std::invalid_argument);
  const std::vector<double> t2{0, 1, 2};
  EXPECT_THROW(make_control_table(t2, {v}, 1, 5), std::invalid_argument);
  EXPECT_THROW(make_control_table(t2, {std::vector<double>{1, 2}}, 20, 5), std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
