#!/usr/bin/env python3
"""What stepping from Python costs against the C++ runner (issue 23: at most 1.2x the runner's physics time for
1,000 steps of the paper's cable), in one run:

    source catkin_build/devel/setup.bash && python3 scripts/python_overhead.py [ROUNDS]   (default 7)

The scenario: the default parameters (the paper's cable: 0.1 m segments, 10 iterations, bending on) with 10 m
deployed, the vehicle moving 3 m in 5 s: 1,000 steps of 5 ms. Each round runs rov_tether_run on it (its "simulated"
line: the time spent advancing, output excluded) and the same scenario from Python, timed around the calls that
advance it, two ways: one advance_to(5.0), and 1,000 calls of advance_to, one a step. Rounds alternate, and the
medians' ratios are printed, so the machine's load moves both sides alike.
"""
import os
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile
import time

import rov_tether

ROOT = pathlib.Path(__file__).resolve().parent.parent
RUNNER = os.environ.get("ROV_TETHER_RUN", str(ROOT / "catkin_build" / "devel" / "lib" / "rov_tether" / "rov_tether_run"))
SCENARIO = """description: "python_overhead.py: the paper's cable, 1,000 steps"
params: {cable_length: 20.0, initial_deployed_length: 10.0, winch_mode: locked}
spool: [0.0, 0.0, -1.0]
vehicle: [[0.0, 8.0, 0.0, -3.0], [5.0, 8.0, 3.0, -3.0]]
duration: 5.0
output_rate: 1.0
"""


def runner_seconds(path, out):
    printed = subprocess.run([RUNNER, str(path), "--out", str(out)], check=True, capture_output=True, text=True).stdout
    steps, seconds = re.search(r"simulated\s+[\d.]+ s in (\d+) steps, ([\d.]+) s CPU", printed).groups()
    assert int(steps) == 1000, printed
    return float(seconds)


def python_seconds(path, one_call):
    world = rov_tether.World.from_scenario(str(path))
    start = time.perf_counter()
    if one_call:
        world.advance_to(5.0)
    else:
        for k in range(1, 1001):
            world.advance_to(0.005 * k)
    return time.perf_counter() - start


def main():
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    times = {"runner": [], "one call": [], "a call a step": []}
    with tempfile.TemporaryDirectory() as work:
        path = pathlib.Path(work) / "scenario.yaml"
        path.write_text(SCENARIO)
        for _ in range(rounds):
            times["runner"].append(runner_seconds(path, pathlib.Path(work) / "out"))
            times["one call"].append(python_seconds(path, True))
            times["a call a step"].append(python_seconds(path, False))
    runner = statistics.median(times["runner"])
    print("1,000 steps of the paper's cable (median of %d rounds): rov_tether_run %.4f s" % (rounds, runner))
    for way in ("one call", "a call a step"):
        median = statistics.median(times[way])
        print("  Python, %-13s %.4f s = %.3f x the runner" % (way + ":", median, median / runner))


if __name__ == "__main__":
    main()
