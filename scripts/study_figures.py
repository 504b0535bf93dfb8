#!/usr/bin/env python3
"""Draws docs/speed_vs_accuracy.png and docs/stability.png from rov_tether_study's CSV files, and prints the
figures docs/accuracy.md quotes from STUDY_DIR/study.csv (each case's runs per method: how many failed, the
best, median and worst error of the others; the cheapest run within 1% shape and 2% tension against direct's).

usage: study_figures.py STUDY_DIR DOCS_DIR
       study_figures.py --summary STUDY_DIR     (only the printed figures: study_figures.py --summary docs)
"""
import csv
import math
import pathlib
import statistics
import sys

COLOURS = {"pbd": "tab:blue", "pbd, over-relaxation 1.8": "tab:purple", "xpbd": "tab:green",
           "lumped_mass": "tab:red", "direct": "black"}


CEILING = 10.0  # errors at or above this (1000%) are drawn as failures on the top line


def method_of(row):
    """The curve a row belongs to: pbd's over-relaxed runs are drawn apart."""
    relax = float(row.get("over_relaxation", "1") or 1)
    return row["method"] if relax == 1.0 else f"{row['method']}, over-relaxation {relax:g}"
TITLES = {
    "catenary_s8": "catenary S = 8 m (EA 1e5 N)",
    "catenary_ea100": "elastic catenary, EA = 100 N",
    "large_strain": "large strain (27%)",
    "axial_drag": "axial drag, 100 m at 1 m/s",
    "taut_string": "taut string, first mode",
    "hanging_chain": "hanging chain, period",
    "paper_experiment": "paper's 2D experiment, stretch",
    "catenary_100m": "catenary S = 8, 100 m in 1,000 segments",
}


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def error_of(row):
    """The larger of the shape and tension errors (tension may be absent)."""
    shape = float(row["shape_error"])
    tension = float(row["tension_error"]) if row["tension_error"] not in ("", "nan") else math.nan
    return shape if math.isnan(tension) else max(shape, tension)


def pareto(points):
    """Points (cost, error) not beaten in both cost and error, sorted by cost."""
    front = []
    for cost, error in sorted(points):
        if not front or error < front[-1][1]:
            front.append((cost, error))
    return front


def percent(error):
    """An error as a percentage: 2 significant digits (0.0084909 -> 0.85%), whole from 100% (1.642 -> 164%)."""
    value = 100 * error
    if 100 <= value < 1e5:
        return f"{value:.0f}%"
    return f"{value:.2g}%"


def accurate(row):
    """rov_tether_study's goal: shape within 1%, tension within 2% (or not measured)."""
    return float(row["shape_error"]) <= 0.01 and not float(row["tension_error"] or "nan") > 0.02


def summary(rows):
    """Prints each case's runs per method (the automatic choice apart): how many, how many failed (blow-up,
    non-finite, or not at rest), the best, median and worst error (worst of shape and tension) of the runs that
    did not fail; and the cheapest accurate run per method, with its cost against direct's."""
    for case in dict.fromkeys(r["scenario"] for r in rows):
        print(f"== {case}")
        mine = [r for r in rows if r["scenario"] == case and r["label"] != "auto"]
        cheapest = {}
        for method in dict.fromkeys(r["method"] for r in mine):
            runs = [r for r in mine if r["method"] == method]
            errors = [error_of(r) for r in runs if r["failed"] == "0" and math.isfinite(error_of(r))]
            line = f"   {method:<11} {len(runs):3d} runs, {len(runs) - len(errors):2d} failed"
            if errors:
                line += (f"; error of the others: best {percent(min(errors))}, median "
                         f"{percent(statistics.median(errors))}, worst {percent(max(errors))}")
            print(line)
            good = [r for r in runs if accurate(r)]
            if good:
                cheapest[method] = min(good, key=lambda r: float(r["cost_us_per_s"]))
        direct = float(cheapest["direct"]["cost_us_per_s"]) if "direct" in cheapest else math.nan
        for method, r in cheapest.items():
            cost = float(r["cost_us_per_s"])
            against = f", {cost / direct:.3g}x direct's" if math.isfinite(direct) else ""
            print(f"   cheapest within 1% shape / 2% tension: {method:<11} {cost:.0f} us/s ({r['segments']} segments, "
                  f"over-relaxation {float(r['over_relaxation']):g}){against}")


def speed_vs_accuracy(rows, docs):
    import matplotlib.pyplot as plt  # only for the figures: the summary needs no matplotlib

    cases = list(dict.fromkeys(r["scenario"] for r in rows))
    columns = 4
    lines = math.ceil(len(cases) / columns)
    fig, axes = plt.subplots(lines, columns, figsize=(4.2 * columns, 3.6 * lines))
    axes = axes.flatten()
    for ax, case in zip(axes, cases):
        everything = []
        for method, colour in COLOURS.items():
            mine = [r for r in rows if r["scenario"] == case and method_of(r) == method and r["label"] != "auto"]
            points = [(float(r["cost_us_per_s"]), error_of(r)) for r in mine
                      if r["failed"] == "0" and math.isfinite(error_of(r)) and 0 < error_of(r) < CEILING]
            # Failed or diverged runs (blow-up reported, not at rest, error beyond 1000%) on the top line.
            failed = [float(r["cost_us_per_s"]) for r in mine
                      if r["failed"] == "1" or not math.isfinite(error_of(r)) or error_of(r) >= CEILING]
            if failed:
                ax.scatter(failed, [CEILING] * len(failed), marker="x", s=18, color=colour, alpha=0.6)
            if not points:
                continue
            everything += points
            ax.scatter(*zip(*points), s=10, color=colour, alpha=0.35)
            front = pareto(points)
            ax.step(*zip(*front), where="post", color=colour, label=method, linewidth=1.6)
        overall = pareto(everything)
        if overall:
            ax.plot(*zip(*overall), "k--", linewidth=0.8, label="Pareto front (all)")
        auto = [(float(r["cost_us_per_s"]), error_of(r)) for r in rows if r["scenario"] == case and r["label"] == "auto"]
        if auto:
            ax.scatter(*zip(*auto), marker="*", s=140, color="gold", edgecolor="k", zorder=5,
                       label="auto segment_length + iterations")
        ax.axhline(0.01, color="grey", linewidth=0.6, linestyle=":")
        ax.axhline(CEILING, color="grey", linewidth=0.6)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(TITLES.get(case, case), fontsize=10)
        ax.set_xlabel("CPU per simulated second [us]")
        ax.set_ylabel("relative error (worst of shape, tension)")
        ax.grid(True, which="major", alpha=0.3)
    for ax in axes[len(cases):]:
        ax.axis("off")
    handles, labels = axes[0].get_legend_handles_labels()
    if len(cases) < len(axes):
        axes[-1].legend(handles, labels, loc="center", fontsize=10)
        bottom = 0.0
    else:  # every panel holds a case: the legend goes under them in one row
        fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=10)
        bottom = 0.05
    fig.suptitle("Speed against accuracy: each point one method x resolution x effort; lines: Pareto fronts; "
                 "dotted: 1 %; x on the top line: failed (blow-up, not at rest, error >= 1000 %)", fontsize=11)
    fig.tight_layout(rect=(0.0, bottom, 1.0, 1.0))
    fig.savefig(docs / "speed_vs_accuracy.png", dpi=90)
    plt.close(fig)


def stability(rows, docs):
    import matplotlib.pyplot as plt
    methods = list(dict.fromkeys(r["method"] for r in rows))
    fig, axes = plt.subplots(2, len(methods), figsize=(4.6 * len(methods), 7.5), squeeze=False)
    for column, method in enumerate(methods):
        mine = [r for r in rows if r["method"] == method]
        for line, (axis, fixed, label) in enumerate(
                [("stiffness", ("speed", 1.0), "EA [N] (vehicle at 1 m/s)"),
                 ("speed", ("stiffness", 1e5), "vehicle speed [m/s] (EA = 1e5 N)")]):
            ax = axes[line][column]
            chosen = [r for r in mine if float(r[fixed[0]]) == fixed[1]]
            for bounded, marker, colour, name in [("1", "o", "tab:green", "bounded"), ("0", "x", "tab:red", "fails")]:
                pts = [(float(r["time_step"]), float(r[axis])) for r in chosen if r["bounded"] == bounded]
                if pts:
                    ax.scatter(*zip(*pts), marker=marker, color=colour, label=name, s=30)
            steps = sorted({float(r["time_step"]) for r in mine})
            if axis == "stiffness":
                # dt_crit = dL / sqrt(EA / mu), dL = 0.5 m, mu = 0.4 kg/m: EA = mu (dL / dt)^2.
                ea = [0.4 * (0.5 / dt) ** 2 for dt in steps]
                ax.plot(steps, ea, "k--", label="explicit limit dt = dL / sqrt(EA / mu)")
                values = [float(r[axis]) for r in chosen]
                ax.set_ylim(min(values) / 3, max(values) * 3)
            else:
                ax.axvline(0.5 / math.sqrt(1e5 / 0.4), color="k", linestyle="--", label="explicit limit at EA = 1e5 N")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("time step [s]")
            ax.set_ylabel(label)
            ax.set_title(method, fontsize=10)
            ax.legend(fontsize=7, loc="lower left")
    fig.suptitle("Stability map: a vehicle pulls a 0.5 m-segment cable (mu 0.4 kg/m) for 2 s; "
                 "bounded = no blow-up reported, strain < 1", fontsize=10)
    fig.tight_layout()
    fig.savefig(docs / "stability.png", dpi=90)
    plt.close(fig)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    if sys.argv[1] == "--summary":
        summary(read(pathlib.Path(sys.argv[2]) / "study.csv"))
        return
    import matplotlib

    matplotlib.use("Agg")
    study_dir = pathlib.Path(sys.argv[1])
    docs = pathlib.Path(sys.argv[2])
    docs.mkdir(parents=True, exist_ok=True)
    summary(read(study_dir / "study.csv"))
    speed_vs_accuracy(read(study_dir / "study.csv"), docs)
    stability(read(study_dir / "stability.csv"), docs)
    print(f"wrote {docs / 'speed_vs_accuracy.png'} and {docs / 'stability.png'}")


if __name__ == "__main__":
    main()
