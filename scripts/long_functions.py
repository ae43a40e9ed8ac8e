#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Lists the C++ functions longer than a limit (200 lines; 60 in the VTK wrappers), tests and benchmarks excluded.

Two limits: --limit (default 200) for every function, and --wrapper-limit (default 60) for the functions of the VTK
layer, the files under a `vtk/` folder (every method's `<method>/vtk/` and the shared `common/vtk/`): a wrapper
reads properties, converts and calls its algorithm through small named functions, its mathematics lives in core/.

A function's length runs from the first line of its signature to its closing brace, as `ctags` start and end lines
do. The scan is a brace counter over the tracked .h/.cpp/.cxx files with comments, string and character literals
and preprocessor lines blanked out: a `{` at namespace or class scope opens a function body when the text before it
(since the previous `;`, `{` or `}`) holds a parameter list and is not a type, namespace, enum or initializer
(`= {`). Everything inside a function body (lambdas, local classes) counts toward that function.

Exit status 1 when a function is over its limit and not on the allow-list (ALLOWED, empty: every method is split),
0 otherwise. Usage: long_functions.py [--limit N] [--wrapper-limit N] [repository root]; ctest runs it as
repo.function_length. With --limit below the wrapper limit, the lower one holds in the wrappers too.
"""
import argparse
import os
import re
import subprocess
import sys

# "path:function" entries exempt from the limits. Empty on purpose: no function over its limit.
ALLOWED = set()

EXCLUDED_PREFIXES = ("testing/", "benchmarks/")
SOURCE = re.compile(r"\.(h|hpp|cpp|cxx)$")
WRAPPER = re.compile(r"(^|/)vtk/")  # the VTK layer: <method>/vtk/ and common/vtk/
TYPE_HEADER = re.compile(r"\b(namespace|class|struct|union|enum)\b|^\s*extern\s*\"C\"")


def blank(text):
    """Comments, literals and preprocessor lines replaced by spaces; newlines kept so line numbers stay right."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#":
            # A preprocessor directive, with its continuation lines.
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        if c == "\n":
            out.append(c)
            line_start = True
            i += 1
            continue
        if not c.isspace():
            line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:end]))
            i = end
            continue
        raw = re.match(r'R"([^(\s]*)\(', text[i:i + 20])
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = ")" + raw.group(1) + '"'
            end = text.find(close, i + raw.end())
            end = n if end < 0 else end + len(close)
            out.append('""' + "".join(ch if ch == "\n" else " " for ch in text[i + 2:end]))
            i = end
            continue
        if c in "\"'":
            # A digit separator (1'000'000) is not a character literal.
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(c + " " * (min(j, n) - i - 1) + (c if j < n else ""))
            i = j + 1
            continue
        out.append(c)
        i += 1
    return "".join(out)


def functions(text):
    """(name, first line, last line) of every function body at namespace or class scope."""
    code = blank(text)
    found = []
    stack = []  # "scope" (namespace, class, extern "C") or "body" (function body or initializer)
    header_start = 0
    line = 1
    line_of = []  # line number of each character
    for ch in code:
        line_of.append(line)
        if ch == "\n":
            line += 1
    for i, ch in enumerate(code):
        in_scope = all(kind == "scope" for kind, _, _ in stack)
        if ch == "{":
            if not in_scope:
                stack.append(("block", None, None))
            else:
                header = code[header_start:i]
                if TYPE_HEADER.search(header) and "(" not in header.split("{")[0].split(":")[0]:
                    stack.append(("scope", None, None))
                elif ")" in header and not re.search(r"(?<![=!<>])=(?!=)", header.split("(")[0]):
                    first = header_start + (len(header) - len(header.lstrip()))
                    name = re.findall(r"([~\w:]+)\s*\(", header)
                    stack.append(("function", name[0] if name else "?", line_of[first]))
                else:
                    stack.append(("block", None, None))
            header_start = i + 1
        elif ch == "}":
            if stack:
                kind, name, first = stack.pop()
                if kind == "function":
                    found.append((name, first, line_of[i]))
            header_start = i + 1
        elif ch == ";" and in_scope:
            header_start = i + 1
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("root", nargs="?", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    parser.add_argument("--limit", type=int, default=200)
    parser.add_argument("--wrapper-limit", type=int, default=60)
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    try:
        files = subprocess.run(["git", "-C", root, "ls-files"], check=True, capture_output=True, text=True).stdout
        paths = files.split()
    except (OSError, subprocess.CalledProcessError):
        paths = [os.path.relpath(os.path.join(d, f), root) for d, _, fs in os.walk(root) for f in fs]
    long_ones = []
    for path in sorted(paths):
        if not SOURCE.search(path) or path.startswith(EXCLUDED_PREFIXES):
            continue
        with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
            text = f.read()
        limit = min(args.limit, args.wrapper_limit) if WRAPPER.search(path) else args.limit
        for name, first, last in functions(text):
            length = last - first + 1
            if length > limit and "%s:%s" % (path, name) not in ALLOWED:
                long_ones.append((length, path, first, name))
    for length, path, first, name in sorted(long_ones, reverse=True):
        print("%5d lines  %s:%d  %s" % (length, path, first, name))
    limits = "%d lines, %d in the VTK wrappers (*/vtk/)" % (args.limit, min(args.limit, args.wrapper_limit))
    if long_ones:
        print("%d function(s) over %s (tests and benchmarks excluded)" % (len(long_ones), limits))
        return 1
    print("no function over %s (tests and benchmarks excluded)" % limits)
    return 0


if __name__ == "__main__":
    sys.exit(main())
