#!/usr/bin/env bash
# How much the wrap scenarios' outcomes depend on rounding: runs scenarios/pillar_wrap.yaml and
# scenarios/pillar_wrap_dynamic.yaml (the latter written at every step) with `drag` moved by a few parts in
# 1e7 (0.9 as shipped), and prints each run's deployed length at the end, its largest tension at the vehicle,
# the steps at which pillar_wrap's spool segment pulled harder than the winch's stall pull (7.5 N) as state.csv
# reports it, the steps at which its drum was back-driven (its pay-out speed jumping past what the drive's
# acceleration limit allows: a pull past the stall pull in one of the step's contact sub-steps, which the
# reported tension, the last sub-step's, may not show) and, for the dynamic vehicle, the largest single-step
# pull on it. Both are written at every step (output_rate 200 Hz, copies of the scenarios). A change that only rounds differently
# (another order of operations in the solver) moves these runs as much as such a nudge does: a cable wound
# round a pillar with friction, held by a constant-tension winch, is chaotic.
#   bash scripts/contact_sensitivity.sh        (builds the runner if needed)
#   RUN=path/to/rov_tether_run bash scripts/contact_sensitivity.sh   (another build's runner, as it is)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$here/.." && pwd)"
if [ -z "${RUN:-}" ]; then
  source "$here/setup.sh" >/dev/null
  build_target rov_tether_run >/dev/null
  RUN="$BUILD_DIR/devel/lib/rov_tether/rov_tether_run"
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for name in pillar_wrap pillar_wrap_dynamic; do
  sed -e 's/^output_rate:.*/output_rate: 200.0/' -e "s|\.\./config/|$ROOT/config/|" \
    "$ROOT/scenarios/$name.yaml" >"$work/$name.yaml"
done
for drag in 0.8999998 0.8999999 0.9 0.9000001 0.9000002; do
  "$RUN" "$work/pillar_wrap.yaml" --set drag=$drag --out "$work/kinematic" >"$work/kinematic.txt"
  "$RUN" "$work/pillar_wrap_dynamic.yaml" --set drag=$drag --out "$work/dynamic" >"$work/dynamic.txt"
  /usr/bin/python3 - "$drag" "$work" <<'PYTHON'
import csv, re, sys
drag, work = sys.argv[1], sys.argv[2]
def summary(name):
    text = open("%s/%s.txt" % (work, name)).read()
    end = re.search(r"deployed length start [\d.]+ m, end ([\d.]+) m", text).group(1)
    at_vehicle = re.search(r"max (\S+) N at the vehicle", text).group(1)
    return end, at_vehicle
k_end, k_pull = summary("kinematic")
d_end, d_pull = summary("dynamic")
rows = list(csv.DictReader(open(work + "/kinematic/state.csv")))
spool = [float(r["tension_spool"]) for r in rows]
stalls = [t for t in spool if t > 7.5]
# The pay-out speed over each 5 ms row. The drive's 1 m/s^2 limit lets it rise 0.005 m/s a step; a rise of more
# than ten times that is the drum back-driven at its stall pull. The spool tension a row reports is the last
# contact sub-step's, so a slip in an earlier sub-step can show 0 N there.
speed = [(float(b["deployed_length"]) - float(a["deployed_length"])) / (float(b["t"]) - float(a["t"]))
         for a, b in zip(rows, rows[1:])]
slips = [(float(rows[i + 2]["t"]), b - a) for i, (a, b) in enumerate(zip(speed, speed[1:])) if b - a > 0.05]
pulls = [float(r["tether_tension"]) for r in csv.DictReader(open(work + "/dynamic/vehicle.csv"))]
largest = sorted(slips, key=lambda slip: -slip[1])[:2]
print("drag %s: pillar_wrap %s m out at the end, max %s N at the vehicle, spool segment above the stall pull at "
      "%d steps (at most %.1f N), drum back-driven at %d steps (largest: %s); pillar_wrap_dynamic %s m out, max %s N "
      "at the vehicle, largest single-step pull %.0f N"
      % (drag, k_end, k_pull, len(stalls), max(spool), len(slips),
         ", ".join("+%.2f m/s at %.3f s" % (jump, t) for t, jump in largest) or "none", d_end, d_pull, max(pulls)))
PYTHON
done
