// latticedyn's facade (api/simulator.hpp) driving the Appendix D crane from a program: the static
// equilibrium, then 40 s sampled every 0.1 s in which the program pays in the hoisting rope and
// slews the crane by a quarter turn in 30 s with a bang-bang acceleration, printing the load's path.
//   hoist_and_slew [examples/api/crane_external.yaml] [PETSc options]
#include "api/simulator.hpp"

#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>

int main(int argc, char** argv) {
  latticedyn::Runtime runtime(&argc, &argv);
  const char* model = argc > 1 && argv[1][0] != '-' ? argv[1] : "examples/api/crane_external.yaml";
  try {
    latticedyn::Simulator crane = latticedyn::Simulator::load(model);
    crane.solve_statics();
    // A quarter turn in 30 s: accelerate for 15 s, decelerate for 15 s.
    const double slew_acceleration = (std::numbers::pi / 2) / (15.0 * 15.0);
    std::printf("%6s %9s %9s %9s %12s %10s %9s\n", "t [s]", "x [m]", "y [m]", "z [m]", "rope [kN]", "slew [rad]",
                "hoist [m]");
    for (int k = 0; k < 400; ++k) {
      const double t = 0.1 * k;
      if (k == 0) crane.set_drive_rate("hoisting", -0.25);  // pay in 5 m in 20 s
      if (k == 200) crane.set_drive_rate("hoisting", 0.0);
      if (k == 0) crane.set_drive_acceleration("slewing", slew_acceleration);
      if (k == 150) crane.set_drive_acceleration("slewing", -slew_acceleration);
      if (k == 300) crane.set_drive_rate("slewing", 0.0);
      crane.advance(0.1);
      if ((k + 1) % 20 == 0) {
        const latticedyn::Vec3 load = crane.joint_position("load.1");
        double rope = 0.0;
        for (double f : crane.axial_forces("hoisting_rope")) rope = std::max(rope, f);
        std::printf("%6.1f %9.3f %9.3f %9.3f %12.1f %10.4f %9.3f\n", t + 0.1, load.x(), load.y(), load.z(),
                    rope / 1e3, crane.drive("slewing").value, crane.drive("hoisting").value);
      }
    }
    std::printf("%ld steps to t = %g s\n", crane.steps(), crane.time());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hoist_and_slew: %s\n", e.what());
    return 1;
  }
  return 0;
}
