# SPDX-License-Identifier: GPL-3.0-or-later
"""PlantSegmentationFilter's cost against the number of points, beside VTK and Open3D on the same points.

One plant (the accuracy benchmark's *tree*: TreeFromSketchSource, depth 3, five children per stem, 500 default
LeafOutlineSource blades 1.0 long on 125 twigs) is scanned by VirtualScanner from four positions one plant size away
with range noise 0.1 % of a leaf's length, at beam steps that give about 10^5, 3 x 10^5 and 10^6 points (in a process
of its own: the plant's surface has 7.2 M triangles). Each size is then measured in a process of its own that reads
the scan (so its peak memory is the segmentation's): the first update in the process, then a warm one (a second
filter on the same points), wall and CPU time (every thread counted), and the process's peak resident memory before
and after.

The peers, on the same points:
  * VTK's vtkPCANormalEstimation with 10 neighbours (same process): one k-nearest-neighbour covariance pass, the
    segmentation's first step alone (the filter does that pass at two scales, region growing, a geodesic graph from
    the base, the leaf instances and their tables), so the ratio says how many such passes the whole filter costs;
  * Open3D (Debian's python3-open3d, a process of its own; benchmarks/open3d_peer.py): the classical split of a
    cloud into parts as Open3D users write it, normals from 10 neighbours then DBSCAN with a radius of three beam
    spacings at the scan's distance and 10 points: the first update and a warm one, each part timed.

    pvpython benchmarks/segmentation/segmentation_speed.py --plugin build/lib/paraview-5.11/plugins/PlantMorph/PlantMorph.so
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--plugin", required=True)
parser.add_argument("--sizes", default="100000,300000,1000000", help="comma-separated target point counts")
parser.add_argument("--child", nargs="+", default=None, help=argparse.SUPPRESS)
arguments = parser.parse_args()

sys.path.insert(0, os.path.dirname(HERE))
from open3d_peer import run_open3d  # noqa: E402
from speed_runs import first_and_warm, peak_mb, vtk_first_and_warm  # noqa: E402

# The accuracy benchmark's tree (benchmarks/segmentation/segmentation_accuracy.py, PLANTS["tree"]) and its scan from
# four positions: 1,445,953 points at beams 0.05 degrees apart.
TREE = dict(Preset=0, TreeType=0, Depth=3, ChildCount=5, Ratio=0.7, Length=10.0, Radius=0.3, LeafCount=4,
            LeafScale=1.0, Sides=12)
REFERENCE_POINTS, REFERENCE_STEP = 1445953, 0.05

OPEN3D = r"""
import json, sys, time
import numpy, open3d
points = numpy.load(sys.argv[1])
radius = float(sys.argv[2])
row = {}
for run in ("first", "warm"):
    cloud = open3d.geometry.PointCloud(open3d.utility.Vector3dVector(points))
    start, cpu = time.perf_counter(), time.process_time()
    cloud.estimate_normals(open3d.geometry.KDTreeSearchParamKNN(10))
    middle, middle_cpu = time.perf_counter(), time.process_time()
    labels = numpy.asarray(cloud.cluster_dbscan(eps=radius, min_points=10))
    end, end_cpu = time.perf_counter(), time.process_time()
    row.update({run + "_normals": middle - start, run + "_dbscan": end - middle, run + "_wall": end - start,
                run + "_cpu": end_cpu - cpu})
row["clusters"] = int(labels.max()) + 1
print(json.dumps(row))
"""


def scanned_tree(simple, plugin, step):
    leaf = plugin["LeafOutlineSource"]()
    tree = plugin["TreeFromSketchSource"](**TREE)
    tree.Leaf = simple.OutputPort(leaf, 0)
    plant = simple.AppendGeometry(Input=[simple.OutputPort(tree, 0), simple.OutputPort(tree, 2)])
    plant.UpdatePipeline()
    b = plant.GetDataInformation().GetBounds()
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
    places = []
    for k in range(4):
        angle = 2 * math.pi * k / 4 + 0.3
        places += [centre[0] + size * math.cos(angle), centre[1] + 0.3 * size, centre[2] + size * math.sin(angle)]
    scanner = plugin["VirtualScanner"](Input=plant, Positions=places, LookAt=centre, Up=[0, 1, 0],
                                       HorizontalFieldOfView=80, VerticalFieldOfView=80, AngularStep=step,
                                       RangeNoise=0.001, Seed=1, MaximumRange=5 * size, MaximumBeams=4e8)
    scanner.UpdatePipeline()
    return scanner, size


def scan_child(target, path):
    """Scans the tree at the beam step that gives about `target` points and writes the cloud to `path` (a process of
    its own: the plant's surface, 7.2 M triangles, would otherwise set the measuring process's peak memory)."""
    from paraview import simple
    simple.LoadPlugin(arguments.plugin)  # its proxies join paraview.simple's namespace
    step = REFERENCE_STEP * math.sqrt(REFERENCE_POINTS / target)
    scanner, size = scanned_tree(simple, vars(simple), step)
    simple.SaveData(path, proxy=scanner)
    print("SCAN " + json.dumps(dict(step=step, size=size)), flush=True)


def child(path, step, size):
    from paraview import simple, servermanager
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkFiltersPoints import vtkPCANormalEstimation
    simple.LoadPlugin(arguments.plugin)
    plugin = vars(simple)
    scanner = simple.XMLPolyDataReader(FileName=[path])
    scanner.UpdatePipeline()
    cloud = servermanager.Fetch(scanner)
    row = dict(points=cloud.GetNumberOfPoints(), peak_before_mb=peak_mb())

    def check(segmentation, row):
        plant = servermanager.Fetch(segmentation, idx=2)
        row["leaves"] = plant.GetValueByName(0, "LeafCount").ToInt() if plant.GetNumberOfRows() == 1 else -1

    first_and_warm(row, "seg", lambda: plugin["PlantSegmentationFilter"](Input=scanner, UpAxis=1), check,
                   simple.Delete)
    vtk_first_and_warm(row, "vtk", vtkPCANormalEstimation, cloud)
    import numpy
    points = path + ".npy"
    numpy.save(points, vtk_to_numpy(cloud.GetPoints().GetData()).astype(numpy.float64))
    # three beam spacings at the scan's distance (one plant size): DBSCAN's radius joins a surface's neighbours
    reply = run_open3d(OPEN3D, points, repr(3 * size * math.radians(step)), label="open3d")
    row["open3d"] = reply
    print("ROW " + json.dumps(row), flush=True)


if arguments.child is not None:
    if arguments.child[0] == "scan":
        scan_child(int(arguments.child[1]), arguments.child[2])
    else:
        child(arguments.child[1], float(arguments.child[2]), float(arguments.child[3]))
    sys.exit(0)


def run_child(*words):
    """Runs this script in a child pvpython with `--child words` and returns its stdout lines."""
    output = subprocess.run([PVPYTHON, os.path.abspath(__file__), "--plugin", arguments.plugin, "--child"] +
                            [str(word) for word in words], capture_output=True, text=True)
    return output.stdout.splitlines(), output.stdout[-2000:] + output.stderr[-2000:]


PVPYTHON = shutil.which("pvpython") or "pvpython"  # sys.executable is not pvpython under pvpython
print("| points | segmentation first: wall / CPU (s) | warm | per 10^6 points (warm wall) | leaves found | "
      "VTK PCA normals first / warm (s) | ours / VTK (warm) | Open3D normals + DBSCAN first / warm (s) | "
      "ours / Open3D (warm) | peak memory before -> after (MB) |")
print("|---|---|---|---|---|---|---|---|---|---|")
folder = tempfile.TemporaryDirectory()
for target in (int(s) for s in arguments.sizes.split(",")):
    path = os.path.join(folder.name, "scan_%d.vtp" % target)
    lines, tail = run_child("scan", target, path)
    scans = [json.loads(line[5:]) for line in lines if line.startswith("SCAN ")]
    lines, tail = run_child("fit", path, scans[0]["step"], scans[0]["size"]) if scans else ([], tail)
    rows = [line[4:] for line in lines if line.startswith("ROW ")]
    if not rows:
        print(f"{target}: failed\n{tail}")
        continue
    r = json.loads(rows[0])
    o = r["open3d"]
    peer = (f"{o['first_wall']:.2f} / {o['warm_wall']:.2f} (normals {o['warm_normals']:.2f}, DBSCAN "
            f"{o['warm_dbscan']:.2f}; {o['clusters']} parts) | {r['seg_warm_wall'] / o['warm_wall']:.2f}x"
            if o else "not run | -")
    print(f"| {r['points']} | {r['seg_first_wall']:.2f} / {r['seg_first_cpu']:.2f} | "
          f"{r['seg_warm_wall']:.2f} / {r['seg_warm_cpu']:.2f} | {r['seg_warm_wall'] / r['points'] * 1e6:.2f} | "
          f"{r['leaves']} | {r['vtk_first_wall']:.2f} / {r['vtk_warm_wall']:.2f} | "
          f"{r['seg_warm_wall'] / r['vtk_warm_wall']:.2f}x | {peer} | "
          f"{r['peak_before_mb']:.0f} -> {r['peak_after_warm_mb']:.0f} |", flush=True)
