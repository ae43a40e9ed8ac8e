# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: VirtualScanner under a memory limit says what it needed instead of ending the process.

A scanner inside a sphere with MaximumBeams = 4e9 and about 1e8 beams that all hit used to end pvpython with
"terminate called after throwing an instance of 'std::bad_alloc'" (SIGABRT) under `ulimit -v`. Each case runs in a
child pvpython whose address space is limited (resource.setrlimit RLIMIT_AS, set once the plugin is loaded, to what
it maps then plus HEADROOM): the child must exit normally, and
  * a scan whose cloud clearly cannot fit (1e8 points, about 7 GB, against 2 GB) is refused before casting, with an
    error naming MaximumBeams and the properties that set the beam count (AngularStep, the fields of view) and the
    memory it needed, and empty outputs;
  * a scan that fits under the same limit (2.6e5 beams) is not refused.

    pvpython test_scanner_memory.py --plugin PlantMorph.so --work DIR --pvpython PVPYTHON
"""
import json
import os
import resource
import subprocess
import sys

from plantmorph_testing import Checks, parse_arguments

arguments = parse_arguments([("--pvpython", dict(default=None)), ("--child", dict(default=None))])
HEADROOM = 2 * 1024 ** 3
CASES = {"too_big": 0.025, "fits": 0.5}  # AngularStep over a full sphere: 1.04e8 and 2.6e5 beams


def child(case):
    """Runs in the limited process: prints one JSON line with what the scan gave."""
    from paraview.simple import Sphere
    from paraview import servermanager
    from plantmorph_testing import Messages, load_plugin
    load_plugin(arguments.plugin, globals())
    VirtualScanner = globals()["VirtualScanner"]
    sphere = Sphere(Radius=2.0, ThetaResolution=32, PhiResolution=32)
    scanner = VirtualScanner(Input=sphere, Positions=[0, 0, 0], LookAt=[1, 0, 0], HorizontalFieldOfView=360,
                             VerticalFieldOfView=180, AngularStep=CASES[case], MaximumBeams=4e9)
    sphere.UpdatePipeline()
    with open("/proc/self/statm") as statm:
        mapped = int(statm.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    resource.setrlimit(resource.RLIMIT_AS, (mapped + HEADROOM, resource.RLIM_INFINITY))
    with Messages(scanner) as messages:
        scanner.UpdatePipeline()
        points = [servermanager.Fetch(scanner, idx=port).GetNumberOfPoints() for port in (0, 1)]
    print("RESULT " + json.dumps({"errors": messages.errors, "points": points}))
    sys.stdout.flush()


if arguments.child:
    child(arguments.child)
    sys.exit(0)

checks = Checks()
pvpython = arguments.pvpython or "pvpython"
results = {}
for case in CASES:
    run = subprocess.run([pvpython, os.path.abspath(__file__), "--plugin", arguments.plugin, "--work", arguments.work,
                          "--child", case], capture_output=True, text=True, timeout=600)
    checks.check(run.returncode == 0, "%s: the limited process exits normally (code %d, not a signal): %s" %
                 (case, run.returncode, run.stderr[-2000:]))
    checks.check("terminate called" not in run.stderr, "%s: no std::terminate" % case)
    lines = [line for line in run.stdout.splitlines() if line.startswith("RESULT ")]
    checks.check(len(lines) == 1, "%s: the child reports its scan %s" % (case, run.stdout[-2000:]))
    results[case] = json.loads(lines[0][len("RESULT "):]) if lines else {"errors": ["(none)"], "points": [-1, -1]}

big = results["too_big"]
text = " ".join(big["errors"])
for word in ("MaximumBeams", "AngularStep", "HorizontalFieldOfView", "VerticalFieldOfView", " GB ", "needs",
             "can still allocate"):
    checks.check(word in text, "1e8 beams under a 2 GB limit: the error says %r: %s" % (word, text))
checks.check(big["points"] == [0, 0], "... and both outputs are empty %s" % big["points"])
fits = results["fits"]
print("the refusal: " + text)
checks.check(not fits["errors"] and fits["points"][0] > 0.99 * 720 * 360,
             "2.6e5 beams under the same limit: (nearly) every beam returns, no error %s %s" % (fits["errors"], fits["points"]))
checks.finish()
