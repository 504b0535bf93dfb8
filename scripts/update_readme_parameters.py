#!/usr/bin/env python3
"""Replaces the README's parameter table (section "## Parameters", from the line "| name | type" to the
next blank line) with the one the parameter table generates (`rov_tether_run --parameters`). Usage:
  /usr/bin/python3 scripts/update_readme_parameters.py [path/to/rov_tether_run]
Test ParamTable.ReadmeTableIsTheGeneratedOne fails until the README holds the generated table."""
import pathlib
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
runner = sys.argv[1] if len(sys.argv) > 1 else str(root / "catkin_build/devel/lib/rov_tether/rov_tether_run")
table = subprocess.run([runner, "--parameters"], check=True, capture_output=True, text=True).stdout.strip("\n")
readme_path = root / "README.md"
readme = readme_path.read_text(encoding="utf-8")
section = readme.index("## Parameters")
start = readme.index("| name | type", section)
end = readme.index("\n\n", start)
readme_path.write_text(readme[:start] + table + readme[end:], encoding="utf-8")
print(f"README.md: parameter table replaced ({table.count(chr(10)) + 1} lines)")
