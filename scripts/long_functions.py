#!/usr/bin/env python3
"""List the C++ functions in src/ that are longer than N lines (default 80).

Crude on purpose: it strips comments, string and character literals, then
matches braces. A block counts as a function body when the text before its
`{` (back to the previous `;`, `{` or `}`) ends in a parameter list `)`,
optionally followed by qualifiers (const, noexcept, override, a trailing
return type, a constructor's initialiser list), and the block sits in a
namespace or class scope, not inside another function (so lambdas and
control blocks count towards their enclosing function). Macros, templates
with braces in default arguments and other oddities may fool it. The length
is the count of lines from the line holding the name to the closing `}`.

Usage: scripts/long_functions.py [N] [DIR ...]   (DIR defaults to src/)
"""
import os
import re
import sys

CONTROL = {"if", "for", "while", "switch", "catch", "do", "else", "return", "sizeof"}
SCOPE_RE = re.compile(r"\b(namespace|class|struct|union|enum)\b")
# Qualifiers allowed between the closing ')' of the parameter list and '{'.
TAIL_RE = re.compile(
    r"\)\s*(?:const\s*|noexcept(?:\s*\([^()]*\))?\s*|override\s*|final\s*|mutable\s*|"
    r"->\s*[\w:<>,\s*&]+?\s*)*$"
)
NAME_RE = re.compile(r"([~\w:]+|operator\s*\S+)\s*\($")


def strip(text):
    """Blank out comments and literals, keeping newlines so line numbers hold."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = ")" + m.group(1) + '"'
            j = text.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                out.append(" ")  # digit separator 1'000
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + " " * (j - i - 2) + c if j - i >= 2 else c)
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def function_name(header):
    """The function's name if `header` (text before a '{') is a function definition, else None."""
    header = header.strip()
    if SCOPE_RE.search(header.split("(")[0]) or header.startswith("#"):
        return None
    # A constructor's initialiser list: cut at the ':' that follows the parameter list.
    depth, cut = 0, None
    for k, ch in enumerate(header):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                rest = header[k + 1 :].lstrip()
                if rest.startswith(":") and not rest.startswith("::"):
                    cut = k + 1
                    break
    if cut is not None:
        header = header[:cut]
    if not TAIL_RE.search(header):
        return None
    # Find the '(' matching the last ')' of the parameter list.
    end = header.rfind(")")
    depth = 0
    for k in range(end, -1, -1):
        if header[k] == ")":
            depth += 1
        elif header[k] == "(":
            depth -= 1
            if depth == 0:
                m = NAME_RE.search(header[: k + 1])
                if not m:
                    return None
                name = m.group(1)
                if name.split("::")[-1] in CONTROL or name.endswith("]"):
                    return None
                return name
    return None


def functions(path):
    """Yield (name, first_line, length) for each function body in the file."""
    with open(path, encoding="utf-8", errors="replace") as f:
        text = strip(f.read())
    stack = []  # one entry per open brace: "func", "scope" or "inner"
    start = 0  # where the current statement's text starts
    for i, ch in enumerate(text):
        if ch == "{":
            inside_function = any(kind[0] == "func" for kind in stack)
            header = text[start:i]
            name = None if inside_function else function_name(header)
            if name:
                offset = len(header) - len(header.lstrip())
                first = text.count("\n", 0, start + offset + header.lstrip().find(name.split("::")[0])) + 1
                stack.append(("func", name, first))
            elif inside_function:
                stack.append(("inner",))
            else:
                stack.append(("scope",))
            start = i + 1
        elif ch == "}":
            if stack:
                kind = stack.pop()
                if kind[0] == "func":
                    last = text.count("\n", 0, i) + 1
                    yield kind[1], kind[2], last - kind[2] + 1
            start = i + 1
        elif ch == ";":
            start = i + 1


def main(argv):
    limit = 80
    dirs = []
    for arg in argv[1:]:
        if arg.isdigit():
            limit = int(arg)
        else:
            dirs.append(arg)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    dirs = dirs or [os.path.join(root, "src")]
    rows = []
    for d in dirs:
        for dirpath, _, names in os.walk(d):
            for fname in sorted(names):
                if fname.endswith((".cpp", ".hpp", ".h", ".cc")):
                    path = os.path.join(dirpath, fname)
                    for name, first, length in functions(path):
                        if length > limit:
                            rows.append((length, os.path.relpath(path, root), first, name))
    rows.sort(key=lambda r: (-r[0], r[1], r[2]))
    for length, path, first, name in rows:
        print(f"{length:5d}  {path}:{first}  {name}")
    print(f"{len(rows)} functions over {limit} lines")


if __name__ == "__main__":
    main(sys.argv)
