#!/usr/bin/env python3
"""Sums gtest/rostest JUnit XML results in a folder; prints "N passed, N failed" last.

Exit code 1 when a case failed or no case ran at all (an empty suite must not look green).
"""
import pathlib
import sys
import xml.etree.ElementTree as ET


def result_files(folder: pathlib.Path):
    """Every JUnit file, except rostest's wrapper (one case per launch file) when the test node's own
    rosunit-*.xml is beside it: the wrapper then repeats what the test node reported."""
    for path in sorted(folder.rglob("*.xml")):
        if path.name.startswith("rostest-") and any(path.parent.glob("rosunit-*.xml")):
            continue
        yield path


def main(folder: str) -> int:
    passed = failed = skipped = 0
    for path in result_files(pathlib.Path(folder)):
        for case in ET.parse(path).getroot().iter("testcase"):
            if case.find("failure") is not None or case.find("error") is not None:
                failed += 1
                print(f"FAILED: {case.get('classname')}.{case.get('name')} ({path.name})")
            elif case.find("skipped") is not None or case.get("status") == "notrun":
                skipped += 1
            else:
                passed += 1
    tail = f", {skipped} skipped" if skipped else ""
    print(f"{passed} passed, {failed} failed{tail}")
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
