#!/usr/bin/env python3
"""The scenario runner's start-up (issue 24: a 0.01 s scenario in at most 10 ms of CPU): runs
rov_tether_run on a 0.01 s scenario (two steps) RUNS times and prints the mean CPU time (user + system) per
run, the shared libraries it loads (ldd), the dynamic loader's own time (LD_DEBUG=statistics) and which
libraries' symbols it binds at load (LD_DEBUG=bindings: Debian builds its libraries with BIND_NOW, so every
symbol a library uses is looked up at start-up, used or not). Usage, after a build (scripts/setup.sh or scripts/test.sh):

  /usr/bin/python3 scripts/runner_startup.py [BUILD_DIR] [RUNS]     (default catkin_build, 20 runs)
"""
import collections
import os
import re
import resource
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENARIO = """description: "two steps: the runner's start-up and nothing else"
params: {}
spool: [0.0, 0.0, 0.0]
vehicle:
  - [0.0, 2.0, 0.0, -1.0]
  - [0.01, 2.0, 0.0, -1.0]
duration: 0.01
"""


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "catkin_build")
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    runner = os.path.join(build, "devel", "lib", "rov_tether", "rov_tether_run")
    libraries = subprocess.run(["ldd", runner], check=True, capture_output=True, text=True).stdout.count("=>")
    with tempfile.TemporaryDirectory() as work:
        scenario = os.path.join(work, "short.yaml")
        with open(scenario, "w") as f:
            f.write(SCENARIO)
        subprocess.run([runner, scenario, "--out", os.path.join(work, "warm")], check=True, stdout=subprocess.DEVNULL)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        for i in range(runs):
            subprocess.run([runner, scenario, "--out", os.path.join(work, "out%d" % i)], check=True,
                           stdout=subprocess.DEVNULL)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        user = (after.ru_utime - before.ru_utime) / runs
        system = (after.ru_stime - before.ru_stime) / runs
        print("rov_tether_run on a 0.01 s scenario: %.1f ms CPU per run (user %.1f, system %.1f; mean of %d runs); "
              "%d shared libraries loaded" % (1e3 * (user + system), 1e3 * user, 1e3 * system, runs, libraries))
        for what in ("statistics", "bindings"):
            debug = subprocess.run([runner, scenario, "--out", os.path.join(work, what)], check=True, text=True,
                                   capture_output=True, env=dict(os.environ, LD_DEBUG=what)).stderr
            if what == "statistics":
                total = re.search(r"total startup time in dynamic loader: (\d+) cycles", debug)
                relocation = re.search(r"time needed for relocation: (\d+) cycles", debug)
                print("the dynamic loader: %s cycles, of which relocation %s" % (total.group(1), relocation.group(1)))
            else:
                bound = collections.Counter(os.path.basename(m) for m in re.findall(r"binding file (\S+) ", debug))
                print("symbols bound at start-up: %d; most by %s" % (sum(bound.values()), ", ".join(
                    "%s %d" % (name, count) for name, count in bound.most_common(6))))


if __name__ == "__main__":
    main()
