#!/usr/bin/env python3
"""Writes the three files generated from the parameter table (parameterInfo() in src/core/parameter_table.cpp):
cfg/Tether.cfg (kept executable: dynamic_reconfigure runs it when the package is configured), config/default.yaml,
and the README's parameter table (section "## Parameters", from the line "| name | type" to the next blank line;
the rest of the README is left as it is). Each is what `rov_tether_run --parameters=cfg|yaml|markdown` prints.
Usage:
  /usr/bin/python3 scripts/generate_parameters.py [path/to/rov_tether_run]
Test ParamTable.GeneratedFilesAreTheCommittedOnes fails until the committed files are the generated ones.

Why the generator is the runner and not a script reading a dump: the table, the defaults (TetherParams) and the
number format (formatParamValue, which the loaders read back) are C++; the test compares in-process, with no
second program or file format to keep in step."""
import os
import pathlib
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
runner = sys.argv[1] if len(sys.argv) > 1 else str(root / "catkin_build/devel/lib/rov_tether/rov_tether_run")


def generated(form):
    return subprocess.run([runner, "--parameters=" + form], check=True, capture_output=True, text=True).stdout


def write(relative, text, executable=False):
    path = root / relative
    changed = not path.exists() or path.read_text(encoding="utf-8") != text
    if changed:
        path.write_text(text, encoding="utf-8")
    if executable:
        os.chmod(path, 0o755)
    print(f"{relative}: {'rewritten' if changed else 'unchanged'}")


write("cfg/Tether.cfg", generated("cfg"), executable=True)
write("config/default.yaml", generated("yaml"))
table = generated("markdown").strip("\n")
readme = (root / "README.md").read_text(encoding="utf-8")
start = readme.index("| name | type", readme.index("## Parameters"))
end = readme.index("\n\n", start)
write("README.md", readme[:start] + table + readme[end:])
