#!/usr/bin/env python3
"""A minimal tangling-aware planner (the paper's first use, docs/python.md): the vehicle has gone once round a
pillar and must come back to its spool; of two ways home it picks the one that leaves its tether unwrapped,
reading the topology of each candidate simulated to its end.

    python3 examples/python/choose_path.py

Each candidate is the same world (a pillar, a tether from a spool 4 m away) with the vehicle's history and then
the candidate's waypoints; the planner scores a candidate by the wrap turns left round the pillar (a tangle to
undo later), then by the largest tension on the way.
"""
import argparse
import math

import rov_tether

PILLAR = {"name": "pillar", "type": "cylinder", "position": [0.0, 0.0, 0.0], "radius": 0.3, "length": 10.0,
          "friction": 0.5}
SPOOL = [-4.0, 0.0, 0.0]
RADIUS = 1.5  # the vehicle's circle round the pillar [m]


def arc(t0, angle0, angle1, speed=1.0, steps=24):
    """Waypoints [t, x, y, z] on the circle round the pillar from angle0 to angle1 [rad] at `speed` [m/s]."""
    duration = abs(angle1 - angle0) * RADIUS / speed
    return [[t0 + duration * k / steps, RADIUS * math.cos(a), RADIUS * math.sin(a), 0.0]
            for k in range(steps + 1) for a in [angle0 + (angle1 - angle0) * k / steps]]


# History: out from beside the spool side of the pillar (angle pi) once round counter-clockwise.
HISTORY = arc(0.0, math.pi, 3.0 * math.pi)
T_END = HISTORY[-1][0]
CANDIDATES = {
    # Straight home from where it is: the shortest way, leaving the turn round the pillar.
    "straight home": [[T_END + 3.0, -3.5, 0.0, 0.0]],
    # Back round the way it came (clockwise, one turn), then home.
    "unwind first": arc(T_END, 3.0 * math.pi, math.pi)[1:] + [[T_END + 9.42 + 3.0, -3.5, 0.0, 0.0]],
}

def simulate(path):
    world = rov_tether.World({
        "params": {"noise": 0.0, "weight_in_water": 0.0, "bending_stiffness": 0.0, "cable_length": 80.0,
                   "winch_mode": "constant_tension", "target_tension": 5.0, "max_winch_speed": 3.0},
        "spool": SPOOL, "vehicle": path, "obstacles": [PILLAR], "tether_contact": True})
    tether = world.tethers[0]
    largest = 0.0
    t = 0.0
    while t < path[-1][0] + 2.0:  # to the end of the path, and 2 s to settle
        t += 0.1
        world.advance_to(t)
        largest = max(largest, max(tether.segment_tension))
    turns = next(r["value"] for r in world.topology() if r["object"] == "pillar" and r["kind"] == "wrap_turns")
    return turns, largest


def main():
    argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    scores = {}
    for name, tail in CANDIDATES.items():
        turns, largest = simulate(HISTORY + tail)
        scores[name] = (round(abs(turns)), largest)
        print("%-13s wrap turns %+.2f, largest tension %.1f N" % (name, turns, largest))
    choice = min(scores, key=scores.get)
    print("chosen: %s (it leaves %d turns round the pillar)" % (choice, scores[choice][0]))


if __name__ == "__main__":
    main()
