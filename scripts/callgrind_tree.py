"""Reading callgrind_annotate's caller tree (--tree=caller --inclusive=yes): the instructions of a function, per
call from a given caller. Shared by scripts/vehicle_overhead.sh and scripts/sections_overhead.sh."""
import re

# A function compiled as clones (target_clones) is named once a clone, "... [clone .avx2]": the tag stays in
# the name, so that the clones do not overwrite each other.
ARC = re.compile(r"^\s*([\d,]+) \(\s*[\d.]+%\)\s+([<*])\s+(.*?(?: \[clone [^\]]*\])?)(?: \(([\d,]+)x\))? \[")


def functions(path):
    """{callee: (inclusive instructions, {caller: (instructions, calls)})} from callgrind_annotate's caller tree."""
    found, callers = {}, {}
    for line in open(path):
        m = ARC.match(line)
        if not m:
            if not line.strip():
                callers = {}
            continue
        count, kind, name, calls = int(m.group(1).replace(",", "")), m.group(2), m.group(3), m.group(4)
        if kind == "<":
            callers[name] = (count, int(calls.replace(",", "")) if calls else 0)
        else:
            found[name] = (count, callers)
            callers = {}
    return found


def one(functions_, suffix):
    return [v for k, v in functions_.items() if k.endswith(suffix)]


def per_step(found, benchmark):
    """Instructions of one Tether::step() called from the benchmark function `benchmark`'s loop, and how many."""
    (inclusive, callers), = one(found, "rov_tether::Tether::step()")
    (count, calls), = [v for k, v in callers.items() if benchmark in k]
    return count / calls, calls
