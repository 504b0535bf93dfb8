#!/usr/bin/env python3
"""Draws the figures of the README, docs/runner.md and docs/model.md from rov_tether_run output (state.csv / shape.csv).

usage: figures.py OUT_DIR DOCS_DIR
OUT_DIR holds one sub-folder per run, as written by scripts/figures.sh.
"""
import csv
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def shapes(run_dir):
    """{t: [(x, y, z, tension), ...]} from shape.csv."""
    result = {}
    for row in read(run_dir / "shape.csv"):
        t = float(row["t"])
        tension = float(row["tension"]) if row["tension"] else math.nan
        result.setdefault(t, []).append((float(row["x"]), float(row["y"]), float(row["z"]), tension))
    return result


def payout(out, docs):
    """The pay-out scenario with its brake winch (direct), against the paper's strain rule (pbd)."""
    runs = {name: read(out / name / "state.csv") for name in ("payout", "payout_strain")}
    shape = shapes(out / "payout")
    t = [float(r["t"]) for r in runs["payout"]]
    distance = [math.dist(shape[time][0][:3], shape[time][-1][:3]) for time in t]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    labels = {"payout": "brake 2 N (direct)", "payout_strain": "paper's strain rule (pbd, winch_mode strain)"}
    styles = {"payout": dict(color="tab:blue"), "payout_strain": dict(color="tab:orange", alpha=0.8)}
    for name, state in runs.items():
        times = [float(r["t"]) for r in state]
        top.plot(times, [float(r["deployed_length"]) for r in state], label="deployed, " + labels[name], **styles[name])
        bottom.plot(times, [float(r["tension_vehicle"]) for r in state], label=labels[name], **styles[name])
    top.plot(t, distance, "--", color="black", label="spool-vehicle distance")
    top.set_ylabel("m")
    top.legend(loc="upper left", fontsize=8)
    top.set_title("scenarios/spool_payout.yaml: out 8 m at 0.5 m/s, around, back")
    bottom.set_ylabel("tension at vehicle [N]")
    bottom.set_xlabel("t [s]")
    bottom.set_yscale("symlog", linthresh=1.0)
    bottom.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(docs / "spool_payout.png", dpi=100)

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for time in (0.0, 8.0, 16.0, 24.0, 32.0, 42.0):
        pts = shape[time]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], ".-", markersize=2, label=f"t = {time:g} s")
    ax.plot([0], [0], "ks", label="spool")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title("Cable seen from above during the pay-out scenario")
    fig.tight_layout()
    fig.savefig(docs / "spool_payout_shapes.png", dpi=100)


def paper_2d(out, docs):
    fig, axes = plt.subplots(1, 3, figsize=(12, 4), sharey=True)
    for ax, (name, title) in zip(axes, [("drag_1", "drag 1.0 (no damping)"), ("drag_098", "drag 0.98 (paper Fig. 9)"),
                                        ("drag_09", "drag 0.9 (paper Fig. 10)")]):
        shape = shapes(out / name)
        for time in (0.0, 0.6, 1.0, 2.0, 4.0, 16.0):
            pts = shape[min(shape, key=lambda s: abs(s - time))]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], label=f"t = {time:g} s")
        ax.set_title(title)
        ax.set_xlabel("x [m]")
        ax.set_aspect("equal")
    axes[0].set_ylabel("y [m]")
    axes[0].legend(fontsize=7)
    fig.suptitle("scenarios/paper_2d_experiment.yaml: end (0,0,0) -> (3,3,2) in 0.6 s, other end pinned at (10,0,0)")
    fig.tight_layout()
    fig.savefig(docs / "paper_2d_damping.png", dpi=100)

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, (name, title) in zip(axes, [("noise", "noise 0.0005 m (memory loss)"), ("no_noise", "noise 0 (frozen)")]):
        shape = shapes(out / name)
        for time in (4.0, 8.0, 16.0):
            pts = shape[min(shape, key=lambda s: abs(s - time))]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], label=f"t = {time:g} s")
        ax.set_title(title)
        ax.set_xlabel("x [m]")
        ax.set_aspect("equal")
        ax.legend(fontsize=8)
    axes[0].set_ylabel("y [m]")
    fig.suptitle("Paper Fig. 11: shapes after settling, drag 0.9, bending off")
    fig.tight_layout()
    fig.savefig(docs / "paper_fig11_noise.png", dpi=100)


def lazy_wave(out, docs):
    """The lazy wave from a boat: the cable seen from the side (x, z) as the vehicle drives out and back."""
    shape = shapes(out / "lazy_wave")
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for time in (10.0, 20.0, 30.0, 50.0):
        pts = shape[time]
        ax.plot([p[0] for p in pts], [p[2] for p in pts], ".-", markersize=2, label=f"t = {time:g} s")
    ax.axhline(0.0, color="tab:blue", linewidth=0.8, linestyle="--", label="water surface")
    ax.axhline(-16.0, color="saddlebrown", linewidth=1.5, label="seabed")
    ax.plot([0], [1.5], "ks", label="spool (on deck)")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title("scenarios/lazy_wave.yaml: floats hold the tether off the seabed")
    fig.tight_layout()
    fig.savefig(docs / "images" / "lazy_wave.png", dpi=100)


def main():
    out, docs = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    docs.mkdir(parents=True, exist_ok=True)
    payout(out, docs)
    paper_2d(out, docs)
    lazy_wave(out, docs)
    print(f"figures written to {docs}")


if __name__ == "__main__":
    main()
