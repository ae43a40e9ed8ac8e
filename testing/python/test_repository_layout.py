# SPDX-License-Identifier: GPL-3.0-or-later
"""The repository keeps the layout its design fixes, and the rules a newcomer can rely on.

Checks over the tracked files (git ls-files), each failure naming the file:
- the top level holds CMakeLists.txt, README.md, LICENSE, CONTRIBUTING.md, CHANGELOG.md and the folders sources/,
  filters/, xml/, common/, paraview_plugin/, testing/;
- every proxy's server-manager XML lies in xml/, one proxy per file, the file named after its proxy;
- every method folder (sources/<method>/, filters/<method>/) has its thin VTK layer in vtk/ (with vtk.module) and
  its algorithm folders hold no VTK header;
- no folder holds more than 12 C++ files;
- every source file carries its SPDX licence line near the top;
- no tracked file refers to the project's tracker by number (the word for a tracker entry and a number): a reader
  has no such tracker, the text says the reason itself.
Outside a git checkout the test is skipped (exit code 77).

    python3 test_repository_layout.py --source-dir .
"""
import argparse
import collections
import os
import re
import sys
import xml.etree.ElementTree as ElementTree

from test_repository_stands_alone import SKIP, tracked_files

TOP_FILES = ["CMakeLists.txt", "README.md", "LICENSE", "CONTRIBUTING.md", "CHANGELOG.md"]
TOP_FOLDERS = ["sources", "filters", "xml", "common", "paraview_plugin", "testing"]
CXX = re.compile(r"\.(h|hpp|cpp|cxx|inc)$")
SPDX = "SPDX-License-Identifier: GPL-3.0-or-later"
# Files that take the SPDX line: C++, Python, shell, CMake, the proxy XML.
LICENSED = re.compile(r"(\.(h|hpp|cpp|cxx|inc|py|sh|cmake|xml)|(^|/)CMakeLists\.txt)$")
# A tracker reference: the word and a number, built from pieces so this file does not match itself.
TRACKER = re.compile(r"(\b[Ii]|(?<=[a-z])I)ssues?[\s_]*#?[0-9]+" + "")
PROXY_TAGS = ("SourceProxy", "Proxy", "ReaderFactory", "WriterProxy", "PSWriterProxy")
MAX_CXX_PER_FOLDER = 12


def check_patterns():
    """The patterns find what they must and leave ordinary text alone (a guard that cannot fail is no guard)."""
    word = "iss" + "ue"  # in pieces, so that this file does not match itself
    must = ["see %s 24" % word, "%s 3:" % word.capitalize(), "%ss 21 and 22" % word, "%s #7" % word,
            "Of%s25Build" % word.capitalize(), "%s_12" % word]
    wrong = [s for s in must if not TRACKER.search(s)]
    must_not = ["no %s here" % word, "%ss remain" % word, "t%s 3D" % word, "%s-free" % word]
    wrong += [s for s in must_not if TRACKER.search(s)]
    wrong += [s for s in ["a/b/Foo.cxx", "CMakeLists.txt", "x/y.py", "xml/A.xml"] if not LICENSED.search(s)]
    wrong += [s for s in ["README.md", "a.png", "vtk.module", "x.pvsm"] if LICENSED.search(s)]
    if wrong:
        print("FAIL: the patterns misjudge %r" % wrong)
    return not wrong


def read(source_dir, name):
    try:
        with open(os.path.join(source_dir, name), "rb") as f:
            return f.read().decode("utf-8", "replace")
    except OSError:  # listed but absent in the work tree
        return None


def top_level(files):
    tops = {name.split("/", 1)[0] for name in files}
    return ["top level: %s is missing" % t for t in TOP_FILES + TOP_FOLDERS if t not in tops]


def proxy_xml(source_dir, files):
    failures = []
    for name in files:
        if not name.endswith(".xml"):
            continue
        text = read(source_dir, name)
        if text is None or "<ServerManagerConfiguration" not in text:
            continue
        if os.path.dirname(name) != "xml":
            failures.append("%s: a proxy's XML outside xml/" % name)
            continue
        try:
            root = ElementTree.fromstring(text)
        except ElementTree.ParseError as error:
            failures.append("%s: not well-formed XML (%s)" % (name, error))
            continue
        proxies = [p.get("name") for group in root.iter("ProxyGroup") for p in group if p.tag in PROXY_TAGS]
        stem = os.path.splitext(os.path.basename(name))[0]
        if proxies != [stem]:
            failures.append("%s: holds proxies %s; one proxy per file, named as the file" % (name, proxies))
    return failures


def method_folders(source_dir, files):
    failures = []
    methods = collections.defaultdict(set)
    for name in files:
        parts = name.split("/")
        if parts[0] in ("sources", "filters") and len(parts) >= 4:
            methods["/".join(parts[:2])].add(parts[2])
    for method, subfolders in sorted(methods.items()):
        if "vtk/vtk.module" not in {n[len(method) + 1:] for n in files if n.startswith(method + "/vtk/")}:
            failures.append("%s: no vtk/vtk.module (each method has its thin VTK layer in vtk/)" % method)
        if not subfolders - {"vtk"}:
            failures.append("%s: no algorithm folder beside vtk/ (core/)" % method)
    for name in files:
        parts = name.split("/")
        if (parts[0] in ("sources", "filters") and len(parts) >= 4 and parts[2] != "vtk" or
                parts[:2] in (["common", "src"], ["common", "include"])) and CXX.search(name):
            text = read(source_dir, name) or ""
            if re.search(r'^\s*#\s*include\s*[<"]vtk', text, re.M):
                failures.append("%s: the algorithm layer includes a VTK header" % name)
    return failures


def folder_sizes(files):
    counts = collections.Counter(os.path.dirname(n) for n in files if CXX.search(n))
    return ["%s: %d C++ files (at most %d a folder)" % (d, c, MAX_CXX_PER_FOLDER)
            for d, c in sorted(counts.items()) if c > MAX_CXX_PER_FOLDER]


def text_rules(source_dir, files):
    failures = []
    for name in files:
        if name.startswith("data/") or name.endswith((".png", ".jpg", ".pvsm", ".vtp")):
            continue
        text = read(source_dir, name)
        if text is None:
            continue
        if LICENSED.search(name) and SPDX not in "\n".join(text.splitlines()[:3]):
            failures.append("%s: no '%s' line in its first lines" % (name, SPDX))
        for number, line in enumerate(text.splitlines(), 1):
            if TRACKER.search(line):
                failures.append("%s:%d: names a tracker entry instead of the reason: %s" % (name, number,
                                                                                           line.strip()[:120]))
    return failures


def main():
    if not check_patterns():
        return 1
    parser = argparse.ArgumentParser()
    parser.add_argument("--source-dir", required=True, help="the repository's top folder")
    source_dir = os.path.abspath(parser.parse_args().source_dir)
    files = tracked_files(source_dir)
    if files is None:
        print("SKIP: %s is not a git checkout, so there is no list of tracked files to check" % source_dir)
        return SKIP
    failures = (top_level(files) + proxy_xml(source_dir, files) + method_folders(source_dir, files) +
                folder_sizes(files) + text_rules(source_dir, files))
    if failures:
        print("FAIL: %d problem(s) with the repository's layout and rules:" % len(failures))
        print("\n".join(failures))
        return 1
    print("OK: %d tracked files follow the layout (sources/, filters/, xml/) and its rules" % len(files))
    return 0


if __name__ == "__main__":
    sys.exit(main())
