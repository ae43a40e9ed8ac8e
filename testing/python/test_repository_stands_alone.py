# SPDX-License-Identifier: GPL-3.0-or-later
"""The repository stands alone: no tracked file reads or names the team's workbench folder beside the clone.

Everything a user needs (measured data in data/, references in docs/references.md, method notes in docs/methods/)
is in the repository; a path into the workbench works only on the developers' own machines. This test lists the
tracked files (git ls-files) and fails naming every file and line that mentions the workbench: the parent-directory
form, or its data, spec, seeds or hooks folders, or its building notes. Outside a git checkout (a source tarball)
there is no list of tracked files: the test is then skipped (exit code 77, ctest's SKIP_RETURN_CODE).

    python3 test_repository_stands_alone.py --source-dir .
"""
import argparse
import os
import re
import subprocess
import sys

SKIP = 77

# Built from pieces so that this file does not match itself.
WORKBENCH = "sha" + "red"
PATTERN = re.compile(
    r"(\.\./+%s\b|/work/%s\b|\b%s/+(data|spec|seeds|hooks|BUILDING-NOTES)\b)" % (WORKBENCH, WORKBENCH, WORKBENCH))


def tracked_files(source_dir):
    """The tracked files (paths relative to source_dir), or None when source_dir is not a git checkout."""
    try:
        top = subprocess.run(["git", "-C", source_dir, "rev-parse", "--show-toplevel"], capture_output=True,
                             text=True, check=False)
    except OSError:  # no git installed
        return None
    if top.returncode != 0 or os.path.realpath(top.stdout.strip()) != os.path.realpath(source_dir):
        return None
    listing = subprocess.run(["git", "-C", source_dir, "ls-files", "-z"], capture_output=True, check=True)
    return [name for name in listing.stdout.decode("utf-8", "surrogateescape").split("\0") if name]


def offending_lines(path):
    """(line number, line) for every line of the file at path that names the workbench."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError:  # listed but absent (deleted in the work tree, an unchecked-out LFS file)
        return []
    text = data.decode("utf-8", "replace")
    return [(number, line.strip()) for number, line in enumerate(text.splitlines(), 1) if PATTERN.search(line)]


def check_pattern():
    """The pattern finds the forms it must and leaves ordinary uses of the word alone (a guard that cannot fail is
    no guard)."""
    must = ["../" + WORKBENCH + "/data/x.csv", "../../" + WORKBENCH, WORKBENCH + "/spec/04-wilting.md",
            "see " + WORKBENCH + "/data/leaf-clouds", "/work/" + WORKBENCH + "/seeds", "..//" + WORKBENCH]
    must_not = ["std::" + WORKBENCH + "_ptr", "a " + WORKBENCH + " node", WORKBENCH + " by leaves and trees",
                "BUILD_" + WORKBENCH.upper() + "_LIBS", "make_" + WORKBENCH + "<int>"]
    wrong = [s for s in must if not PATTERN.search(s)] + [s for s in must_not if PATTERN.search(s)]
    if wrong:
        print("FAIL: the pattern misjudges %r" % wrong)
    return not wrong


def main():
    if not check_pattern():
        return 1
    parser = argparse.ArgumentParser()
    parser.add_argument("--source-dir", required=True, help="the repository's top folder")
    arguments = parser.parse_args()
    source_dir = os.path.abspath(arguments.source_dir)
    files = tracked_files(source_dir)
    if files is None:
        print("SKIP: %s is not a git checkout, so there is no list of tracked files to check" % source_dir)
        return SKIP
    if not files:
        print("FAIL: git ls-files listed no file in %s" % source_dir)
        return 1
    failures = []
    for name in files:
        for number, line in offending_lines(os.path.join(source_dir, name)):
            failures.append("%s:%d: %s" % (name, number, line[:160]))
    if failures:
        print("FAIL: %d line(s) of tracked files name the team's workbench folder beside the clone; the repository"
              " must stand alone (data/, docs/references.md, docs/methods/):" % len(failures))
        print("\n".join(failures))
        return 1
    print("OK: none of %d tracked files names the workbench folder" % len(files))
    return 0


if __name__ == "__main__":
    sys.exit(main())
