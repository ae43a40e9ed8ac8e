# SPDX-License-Identifier: GPL-3.0-or-later
"""TreeFitFilter's cost against the number of points, beside VTK's vtkStatisticalOutlierRemoval on the same points.

One tree (the accuracy benchmark's mono-large: TreeFromSketchSource's monopodial template, 12 m, depth 2, eight
children per stem, seated tubes of 32 sides, no leaves) is scanned by VirtualScanner from four terrestrial stations
1.2 tree heights away with 3 mm range noise, at beam steps that give about 10^5, 3 x 10^5 and 10^6 points. Each size
runs in a process of its own (so its peak memory is its own): the fit's first update in the process, then a warm one
(a second filter on the same points), wall and CPU time (every thread counted), and the process's peak resident
memory before and after the fits. The peer, in the same process and on the same points, is VTK's statistical outlier
removal with 10 neighbours: one k-nearest-neighbour pass over the cloud, which is the fit's step 2 alone (the fit
does that pass, a neighbour graph, geodesic distances, a skeleton and a robust cylinder fit per segment), so the
ratio says how many such passes the whole fit costs.

    pvpython benchmarks/fit/tree_fit_speed.py --plugin build/lib/paraview-5.11/plugins/PlantMorph/PlantMorph.so
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--plugin", required=True)
parser.add_argument("--sizes", default="100000,300000,1000000", help="comma-separated target point counts")
parser.add_argument("--child", type=int, default=None, help=argparse.SUPPRESS)
arguments = parser.parse_args()

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from speed_runs import first_and_warm, peak_mb, vtk_first_and_warm  # noqa: E402

REFERENCE_POINTS = 831495  # mono-large's points at beams 1.2 cm apart (the accuracy benchmark's scan)
REFERENCE_STEP = 0.012


def child(target):
    from paraview import simple, servermanager
    from vtkmodules.vtkFiltersPoints import vtkStatisticalOutlierRemoval
    simple.LoadPlugin(arguments.plugin, ns=globals())
    TreeFromSketchSource, VirtualScanner = globals()["TreeFromSketchSource"], globals()["VirtualScanner"]
    TreeFitFilter, Delete = globals()["TreeFitFilter"], simple.Delete
    tree = TreeFromSketchSource(Preset="Custom", Leaves=0, Sides=32, Joints="Seated tubes", TreeType="Monopodial",
                                Length=12.0, Radius=0.3, Depth=2, ChildCount=8)
    tree.UpdatePipeline()
    bounds = tree.GetDataInformation().GetBounds()
    low, height = bounds[2], bounds[3] - bounds[2]
    distance = max(8.0, 1.2 * height)
    positions = []
    for k in range(4):
        a = 2 * math.pi * (k + 0.125) / 4
        positions += [distance * math.cos(a), low + 1.5, distance * math.sin(a)]
    field = 2 * math.degrees(math.atan(0.6 * height / distance)) + 10
    spacing = REFERENCE_STEP * math.sqrt(REFERENCE_POINTS / target)
    scanner = VirtualScanner(Input=tree, ScannerType="Terrestrial", Positions=positions,
                             LookAt=[0.0, low + 0.5 * height, 0.0], Up=[0, 1, 0], HorizontalFieldOfView=field,
                             VerticalFieldOfView=field, AngularStep=math.degrees(spacing / distance),
                             RangeNoise=0.003, Seed=1, MaximumBeams=4e8)
    scanner.UpdatePipeline()
    cloud = servermanager.Fetch(scanner)
    row = dict(points=cloud.GetNumberOfPoints(), beam_cm=100 * spacing, peak_before_mb=peak_mb())

    def check(fit, row):
        table = servermanager.Fetch(fit, idx=2)
        row["fit_ok"] = table.GetNumberOfRows() == 1 and table.GetValueByName(0, "TotalVolume").ToDouble() > 0

    first_and_warm(row, "fit", lambda: TreeFitFilter(Input=scanner, UpAxis="Y"), check, Delete)
    vtk_first_and_warm(row, "peer", vtkStatisticalOutlierRemoval, cloud)
    print("ROW " + json.dumps(row), flush=True)


if arguments.child is not None:
    child(arguments.child)
    sys.exit(0)

PVPYTHON = shutil.which("pvpython") or "pvpython"  # sys.executable is not pvpython under pvpython
print("| points | beams (cm) | fit first: wall / CPU (s) | fit warm | per 10^6 points (warm wall) | "
      "VTK outlier removal first / warm wall (s) | fit / VTK (warm wall) | peak memory before -> after (MB) |")
print("|---|---|---|---|---|---|---|---|")
for target in (int(s) for s in arguments.sizes.split(",")):
    output = subprocess.run([PVPYTHON, os.path.abspath(__file__), "--plugin", arguments.plugin, "--child", str(target)],
                            capture_output=True, text=True)
    rows = [line[4:] for line in output.stdout.splitlines() if line.startswith("ROW ")]
    if not rows:
        print(f"{target}: failed\n{output.stdout[-2000:]}\n{output.stderr[-2000:]}")
        continue
    r = json.loads(rows[0])
    per = r["fit_warm_wall"] / r["points"] * 1e6
    print(f"| {r['points']} | {r['beam_cm']:.2f} | {r['fit_first_wall']:.2f} / {r['fit_first_cpu']:.2f} | "
          f"{r['fit_warm_wall']:.2f} / {r['fit_warm_cpu']:.2f} | {per:.2f} | {r['peer_first_wall']:.2f} / "
          f"{r['peer_warm_wall']:.2f} | {r['fit_warm_wall'] / r['peer_warm_wall']:.1f}x | "
          f"{r['peak_before_mb']:.0f} -> {r['peak_after_warm_mb']:.0f}{'' if r['fit_ok'] else ' (fit FAILED)'} |",
          flush=True)
