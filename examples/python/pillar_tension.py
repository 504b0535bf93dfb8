#!/usr/bin/env python3
"""Drives a tether twice around a pillar (scenarios/pillar_wrap.yaml) and plots the tension at the vehicle and at
the spool, and the wrap turns the topology reads, against time (docs/python.md).

    python3 examples/python/pillar_tension.py [--out DIR]     # writes DIR/pillar_tension.png (default: .)

The winch holds 5 N at the spool; the tension at the vehicle jumps as the tether catches and slips on the
pillar (friction 0.5), and the wrap turns count +1 per circle, counter-clockwise seen from above.
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # headless: the figure goes to a file
import matplotlib.pyplot as plt

import rov_tether

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=".", help="directory for pillar_tension.png")
    out = pathlib.Path(parser.parse_args().out)
    out.mkdir(parents=True, exist_ok=True)

    world = rov_tether.World.from_scenario(str(ROOT / "scenarios" / "pillar_wrap.yaml"))
    tether = world.tether("tether")
    times, vehicle, spool, turns = [], [], [], []
    for k in range(201):  # 0 to 20 s every 0.1 s
        world.advance_to(0.1 * k)
        topology = {(r["object"], r["kind"]): r["value"] for r in world.topology()}
        times.append(world.time)
        vehicle.append(tether.tension_vehicle)
        spool.append(tether.tension_spool)
        turns.append(topology[("pillar", "wrap_turns")])

    figure, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    top.plot(times, vehicle, label="at the vehicle")
    top.plot(times, spool, label="at the spool")
    top.set_ylabel("tension [N]")
    top.legend()
    bottom.plot(times, turns)
    bottom.set_ylabel("wrap turns round the pillar")
    bottom.set_xlabel("time [s]")
    figure.tight_layout()
    figure.savefig(out / "pillar_tension.png", dpi=80)
    print("after %.1f s: %.2f wrap turns, %.1f N at the vehicle, %.1f N at the spool; wrote %s"
          % (times[-1], turns[-1], vehicle[-1], spool[-1], out / "pillar_tension.png"))


if __name__ == "__main__":
    main()
