"""latticedyn from Python: the crane of Appendix D with its drives set by this script (the same
maneuver as hoist_and_slew.cpp): statics, then 40 s sampled every 0.1 s, the hoisting rope paid in
for 20 s and a quarter turn of slewing in 30 s; prints the load's path and the steps per second.

    PYTHONPATH=build/python /usr/bin/python3 examples/api/hoist_and_slew.py [examples/api/crane_external.yaml]
"""
import math
import sys
import time

import latticedyn


def main():
    model = sys.argv[1] if len(sys.argv) > 1 else "examples/api/crane_external.yaml"
    crane = latticedyn.Simulator(model)
    crane.solve_statics()
    slew_acceleration = (math.pi / 2) / (15.0 * 15.0)
    print(f"{'t [s]':>6} {'x [m]':>9} {'y [m]':>9} {'z [m]':>9} {'rope [kN]':>10}")
    start = time.perf_counter()
    for k in range(400):
        if k == 0:
            crane.set_drive_rate("hoisting", -0.25)
            crane.set_drive_acceleration("slewing", slew_acceleration)
        if k == 150:
            crane.set_drive_acceleration("slewing", -slew_acceleration)
        if k == 200:
            crane.set_drive_rate("hoisting", 0.0)
        if k == 300:
            crane.set_drive_rate("slewing", 0.0)
        crane.advance(0.1)
        if (k + 1) % 50 == 0:
            x, y, z = crane.joint_position("load.1")
            rope = crane.axial_forces("hoisting_rope").max() / 1e3
            print(f"{crane.time:6.1f} {x:9.3f} {y:9.3f} {z:9.3f} {rope:10.1f}")
    wall = time.perf_counter() - start
    print(f"{crane.steps} steps to t = {crane.time:g} s in {wall:.2f} s: {crane.steps / wall:.0f} steps/s, "
          f"{crane.time / wall:.0f} x real time")


if __name__ == "__main__":
    main()
