# SPDX-License-Identifier: GPL-3.0-or-later
"""Helpers shared by the pvpython tests: argument parsing, plugin loading, fingerprints of outputs, and the
state-file round trip."""
import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys


def parse_arguments(extra=None):
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True, help="path to PlantMorph.so")
    parser.add_argument("--work", required=True, help="folder for files the test writes")
    for name, kwargs in (extra or []):
        parser.add_argument(name, **kwargs)
    if not any(name == "--pvpython" for name, _ in (extra or [])):
        parser.add_argument("--pvpython", default=None, help="pvpython for reloading state files (default: PATH's)")
    arguments = parser.parse_args()
    os.makedirs(arguments.work, exist_ok=True)
    return arguments


def load_plugin(path, namespace):
    from paraview.simple import LoadPlugin
    if not os.path.exists(path):
        sys.exit("plugin not found: %s (build first)" % path)
    LoadPlugin(path, remote=False, ns=namespace)


class Checks:
    """Counts failed checks so a test reports them all, then exits non-zero if any failed."""

    def __init__(self):
        self.failures = 0
        self.count = 0

    def check(self, condition, message):
        self.count += 1
        if not condition:
            self.failures += 1
            print("FAIL:", message)

    def finish(self):
        """Reports the count and exits non-zero if any check failed. Under MPI (pvbatch on several ranks) success
        returns normally, so pvbatch finalizes MPI, and failure aborts the MPI job: sys.exit or an exception on
        rank 0 would leave the other ranks waiting forever."""
        print("%d checks, %d failed" % (self.count, self.failures))
        if not self.failures:
            return
        from paraview import servermanager
        if servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions() > 1:
            sys.stdout.flush()
            from mpi4py import MPI
            MPI.COMM_WORLD.Abort(1)
        sys.exit(1)


# The options of every MPI equality test: --write-reference (the serial run writes what the others must equal) and
# --ranks (how many ranks the run is meant to have).
MPI_EQUALITY_ARGUMENTS = [("--write-reference", dict(action="store_true")), ("--ranks", dict(type=int, default=1))]


def save_reference(path, reference):
    """Writes an MPI equality test's serial reference: a dict of arrays to .npz, anything JSON holds to .json."""
    if path.endswith(".npz"):
        import numpy
        numpy.savez(path, **reference)
    else:
        with open(path, "w") as f:
            json.dump(reference, f)
    print("reference written to", path)


def load_reference(path):
    """The serial reference save_reference wrote."""
    if path.endswith(".npz"):
        import numpy
        return numpy.load(path)
    with open(path) as f:
        return json.load(f)


def check_rank_count(checks, arguments):
    """The number of ranks this pvbatch runs on, checked against --ranks."""
    from paraview import servermanager
    ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
    checks.check(ranks == arguments.ranks, "running on %d ranks (expected %d)" % (ranks, arguments.ranks))
    return ranks


def reload_in_fresh_pvpython(state, expected, expected_file, arguments, script):
    """The state-file round trip: writes `expected` (JSON) to `expected_file`, saves this session's pipeline to
    `state`, and runs `script` again in a fresh pvpython with `--load state`, whose second half loads the state and
    compares what it finds with `expected`. Returns that process's exit code (0: same outputs after loading). The
    pvpython is `arguments.pvpython` when the test has that option, else the one on PATH."""
    from paraview.simple import SaveState
    with open(expected_file, "w") as f:
        json.dump(expected, f)
    SaveState(state)
    pvpython = getattr(arguments, "pvpython", None) or shutil.which("pvpython") or "pvpython"
    command = [pvpython, os.path.abspath(script), "--plugin", arguments.plugin, "--work", arguments.work,
               "--load", state]
    if getattr(arguments, "pvpython", None):
        command += ["--pvpython", arguments.pvpython]
    sys.stdout.flush()
    return subprocess.run(command, timeout=600).returncode


def loaded_state(checks, arguments, expected_file, name, kind="filter"):
    """The second half of reload_in_fresh_pvpython's round trip, in the fresh pvpython: loads the state
    `arguments.load`, checks that it holds the proxy `name` (a `kind`, "filter" or "source", in the message) and
    returns that proxy and the description the first half wrote to `expected_file`."""
    from paraview.simple import FindSource, LoadState
    LoadState(arguments.load)
    proxy = FindSource(name)
    checks.check(proxy is not None, "the state file holds the %s '%s'" % (kind, name))
    with open(expected_file) as f:
        return proxy, json.load(f)


def check_same_properties(checks, actual, expected, same=lambda after, before: after == before):
    """One check per property of `expected["properties"]`: its value in `actual["properties"]` after loading the
    state is the same (`same(after, before)`) as before saving it."""
    for name, before in expected["properties"].items():
        after = actual["properties"][name]
        checks.check(same(after, before), "property %s: %r after loading, %r before" % (name, after, before))


def moved_copies(source, count, array, first_id, step):
    """`count` copies of `source` (a paraview.simple proxy), the k-th moved by k * `step` along x and turned by 40 k
    degrees about y, each with an integer point array `array` of value first_id + k: a stand of plants or trees for
    the MPI tests of the per-group filters."""
    from paraview.simple import Calculator, Transform
    parts = []
    for k in range(count):
        moved = Transform(Input=source)
        moved.Transform.Translate = [step * k, 0.0, 0.0]
        moved.Transform.Rotate = [0.0, 40.0 * k, 0.0]
        parts.append(Calculator(Input=moved, ResultArrayName=array, Function="%d" % (first_id + k),
                                ResultArrayType="Int"))
    return parts


def nine_leaf_herb(leaf_outline_source, tree_from_sketch_source):
    """A simulated herb of nine LeafOutlineSource blades of one size on a TreeFromSketchSource stem (the plugin's
    proxies, as load_plugin put them in the test's namespace): (the tree, its wood and leaves appended)."""
    from paraview.simple import AppendGeometry, OutputPort
    blade = leaf_outline_source()
    tree = tree_from_sketch_source(Preset="Custom", Depth=1, ChildCount=3, Ratio=0.6, Length=4.0, Radius=0.08,
                                   LeafCount=3, LeafScale=1.5, LeafAngle=50.0, Sides=12)
    tree.Leaf = OutputPort(blade, 0)
    return tree, AppendGeometry(Input=[OutputPort(tree, 0), OutputPort(tree, 2)])


def true_leaf_areas(leaves):
    """Per LeafId, the area of TreeFromSketchSource's leaf output `leaves` (a fetched vtkPolyData of triangles)."""
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    points = vtk_to_numpy(leaves.GetPoints().GetData())
    cells = vtk_to_numpy(leaves.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    a, b, c = points[cells[:, 0]], points[cells[:, 1]], points[cells[:, 2]]
    return numpy.bincount(vtk_to_numpy(leaves.GetCellData().GetArray("LeafId")),
                          weights=0.5 * numpy.linalg.norm(numpy.cross(b - a, c - a), axis=1))


def scan_around(virtual_scanner, plant, count, angular_step, range_noise, seed, maximum_range=None):
    """A scan of `plant` (a paraview.simple proxy, Y up) by `virtual_scanner` (the plugin's VirtualScanner, as
    load_plugin put it in the test's namespace) from `count` positions evenly round it (the first at 0.3 radians),
    each a plant size (its bounds' largest extent) from its centre and 0.3 of that above, looking at the centre with
    an 80-degree field of view; `maximum_range` in plant sizes (the scanner's default when None)."""
    import math
    from paraview import servermanager
    plant.UpdatePipeline()
    b = servermanager.Fetch(plant).GetBounds()
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
    positions = []
    for k in range(count):
        angle = 2 * math.pi * k / count + 0.3
        positions += [centre[0] + size * math.cos(angle), centre[1] + 0.3 * size, centre[2] + size * math.sin(angle)]
    scanner = virtual_scanner(Input=plant, Positions=positions, LookAt=centre, Up=[0, 1, 0], HorizontalFieldOfView=80,
                              VerticalFieldOfView=80, AngularStep=angular_step, RangeNoise=range_noise, Seed=seed)
    if maximum_range is not None:
        scanner.MaximumRange = maximum_range * size
    return scanner


def leaf_instances_against_truth(labels, truth):
    """PlantSegmentationFilter's leaf instances (`labels`: its output's point data) against a VirtualScanner scan's
    truth (`truth`: the scan's point data, Organ and LeafId): the instance ids found, those holding mostly points
    that are not leaf, and how many instances match a true leaf at point IoU above 0.5."""
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    leaf = vtk_to_numpy(labels.GetArray("LeafId"))
    true_organ = vtk_to_numpy(truth.GetArray("Organ"))
    true_leaf = numpy.where(true_organ == 1, vtk_to_numpy(truth.GetArray("LeafId")), -1)
    found = sorted(set(leaf[leaf >= 0].tolist()))
    wood_instances = [k for k in found
                      if 2 * numpy.count_nonzero((leaf == k) & (true_organ != 1)) > numpy.count_nonzero(leaf == k)]
    matched = 0
    for k in found:
        ids, counts = numpy.unique(true_leaf[leaf == k], return_counts=True)
        best = counts.argmax()
        union = numpy.count_nonzero(leaf == k) + numpy.count_nonzero(true_leaf == ids[best]) - counts[best]
        matched += int(ids[best] >= 0 and counts[best] / union > 0.5)
    return found, wood_instances, matched


def organ_iou(labels, truth, organ):
    """The point IoU of `organ` (0 wood, 1 leaf) between PlantSegmentationFilter's labels and a scan's truth (the two
    outputs' point data, as leaf_instances_against_truth)."""
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    found = vtk_to_numpy(labels.GetArray("Organ")) == organ
    true = vtk_to_numpy(truth.GetArray("Organ")) == organ
    return numpy.count_nonzero(found & true) / max(1, numpy.count_nonzero(found | true))


def benchmark_tree_instances(names, positions, range_noise):
    """The tree of the segmentation accuracy benchmark (125 twigs, 500 blades 1.0 long, tubes of 12 sides) scanned
    from `positions` positions at `range_noise` (the benchmark's scan, point for point) and segmented by
    PlantSegmentationFilter (UpAxis Y): leaf_instances_against_truth of its labels, then the wood's and the leaves'
    point IoU (organ_iou, a tuple). `names`: the test's namespace, where load_plugin put the plugin's proxies."""
    from paraview import servermanager
    from paraview.simple import AppendGeometry, OutputPort
    tree = names["TreeFromSketchSource"](Preset=0, TreeType=0, Depth=3, ChildCount=5, Ratio=0.7, Length=10.0,
                                         Radius=0.3, LeafCount=4, LeafScale=1.0, Sides=12)
    tree.Leaf = OutputPort(names["LeafOutlineSource"](), 0)
    plant = AppendGeometry(Input=[OutputPort(tree, 0), OutputPort(tree, 2)])
    scan = scan_around(names["VirtualScanner"], plant, positions, 0.05, range_noise, 1, maximum_range=5)
    segmentation = names["PlantSegmentationFilter"](Input=scan, UpAxis="Y")
    segmentation.UpdatePipeline()
    labels, truth = servermanager.Fetch(segmentation).GetPointData(), servermanager.Fetch(scan).GetPointData()
    found, wood_instances, matched = leaf_instances_against_truth(labels, truth)
    return found, wood_instances, matched, (organ_iou(labels, truth, 0), organ_iou(labels, truth, 1))


def sorted_point_rows(data, arrays):
    """Every point of `data` as a row (x, y, z, then the one-component point `arrays`), the rows sorted: an MPI
    run's outputs appended over the ranks do not keep the serial order."""
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    columns = [vtk_to_numpy(data.GetPoints().GetData()).astype(numpy.float64)]
    for name in arrays:
        columns.append(vtk_to_numpy(data.GetPointData().GetArray(name)).astype(numpy.float64).reshape(-1, 1))
    rows = numpy.hstack(columns)
    return rows[numpy.lexsort(rows.T[::-1])]


def fingerprint(dataset):
    """A SHA-256 of everything a source or filter computes: points, every point and cell array (by name), every cell
    array's connectivity, and for tables every column; equal fingerprints mean bit-identical outputs. Field data is
    left out (it holds parameters, not results)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    digest = hashlib.sha256()

    def add_array(array):
        digest.update(str(array.GetName()).encode())
        if array.IsA("vtkDataArray"):
            digest.update(vtk_to_numpy(array).tobytes())
        else:
            digest.update("\x1f".join(str(array.GetVariantValue(i)) for i in range(array.GetNumberOfValues()))
                          .encode())

    def add_arrays(attributes):
        arrays = [attributes.GetAbstractArray(i) for i in range(attributes.GetNumberOfArrays())]
        for array in sorted(arrays, key=lambda a: str(a.GetName())):
            add_array(array)

    if dataset.IsA("vtkTable"):
        add_arrays(dataset.GetRowData())
        return digest.hexdigest()
    if dataset.GetNumberOfPoints():
        digest.update(vtk_to_numpy(dataset.GetPoints().GetData()).tobytes())
    add_arrays(dataset.GetPointData())
    add_arrays(dataset.GetCellData())
    if dataset.IsA("vtkPolyData"):
        # As 64-bit ids: a cell array may store 32-bit ids, and MPI transfers come back as 64-bit ones.
        for cells in (dataset.GetVerts(), dataset.GetLines(), dataset.GetPolys(), dataset.GetStrips()):
            if cells.GetNumberOfCells():
                digest.update(vtk_to_numpy(cells.GetConnectivityArray()).astype("int64").tobytes())
                digest.update(vtk_to_numpy(cells.GetOffsetsArray()).astype("int64").tobytes())
    return digest.hexdigest()


class Messages:
    """Collects the VTK errors and warnings the given proxies' algorithms report while the `with` block runs
    (pvpython's built-in session: the algorithms live in this process). `errors` and `warnings` are their texts."""

    def __init__(self, *proxies):
        self.proxies = proxies
        self.errors = []
        self.warnings = []
        self._observers = []

    def __enter__(self):
        from vtkmodules.util.misc import calldata_type
        from vtkmodules.util.vtkConstants import VTK_STRING
        from vtkmodules.vtkCommonCore import vtkCommand

        @calldata_type(VTK_STRING)
        def collect(caller, event, text):
            (self.errors if event == "ErrorEvent" else self.warnings).append(str(text))

        self._callback = collect
        for proxy in self.proxies:
            algorithm = proxy.GetClientSideObject()
            for event in (vtkCommand.ErrorEvent, vtkCommand.WarningEvent):
                self._observers.append((algorithm, algorithm.AddObserver(event, collect)))
        return self

    def __exit__(self, *exception):
        for algorithm, tag in self._observers:
            algorithm.RemoveObserver(tag)
        self._observers = []
        return False

    def said(self, *words, kind="any"):
        """True when one error (kind "error"), warning ("warning") or either holds every word."""
        texts = {"error": self.errors, "warning": self.warnings}.get(kind, self.errors + self.warnings)
        return any(all(word in text for word in words) for text in texts)


def skeleton_truth(skeleton, bounds):
    """What a TreeFromSketchSource tree is, from its Skeleton port (`skeleton`, polylines with Radius, ParentId and
    BranchId) and its surface's bounds (Y up): total volume (the frusta between skeleton points, m3), DBH (twice the
    trunk's radius 1.3 m above the base), height (the surface's Y extent) and the number of first-order branches (the
    lines whose parent is the trunk)."""
    import math
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    points = vtk_to_numpy(skeleton.GetPoints().GetData()).astype(float)
    radius = vtk_to_numpy(skeleton.GetPointData().GetArray("Radius")).astype(float)
    offsets = vtk_to_numpy(skeleton.GetLines().GetOffsetsArray())
    connectivity = vtk_to_numpy(skeleton.GetLines().GetConnectivityArray())
    parents = vtk_to_numpy(skeleton.GetCellData().GetArray("ParentId"))
    branch_ids = vtk_to_numpy(skeleton.GetCellData().GetArray("BranchId"))
    volume, trunk = 0.0, None
    for c in range(len(offsets) - 1):
        ids = connectivity[offsets[c]:offsets[c + 1]]
        p, r = points[ids], radius[ids]
        seg = numpy.linalg.norm(numpy.diff(p, axis=0), axis=1)
        volume += float(numpy.sum(math.pi / 3 * seg * (r[:-1] ** 2 + r[:-1] * r[1:] + r[1:] ** 2)))
        if parents[c] < 0:
            trunk = (p, r, branch_ids[c])
    return dict(volume=volume, dbh=2 * float(numpy.interp(1.3 + bounds[2], trunk[0][:, 1], trunk[1])),
                height=bounds[3] - bounds[2], first_order=int(numpy.sum(parents == trunk[2])))
