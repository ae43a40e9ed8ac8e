# SPDX-License-Identifier: GPL-3.0-or-later
"""pvbatch under MPI: TreeFromSketchSource made by pieces (one per rank) gives the serial tree.

Each rank builds its piece of the branches (sources/tree/tubes/BranchPieces.h); gathered, the Branches and Leaves outputs
must hold the serial run's triangles exactly once: compared as a sorted set of triangles written out by their
corners' exact coordinates, Normals and TCoords with the cell arrays (BranchId, ParentId, Depth), so point ids and
cell order may differ but not one bit of a triangle. The Skeleton is whole on rank 0. On 2 and 4 ranks every rank
really holds a part (ProcessIdScalars), none all of it. Trees: Table 1 templates welded and seated with leaf quads,
a stroke tree (a stroke file) and a forest (a second trunk merged from another source's Skeleton, split by tree).
Run once serially with --write-reference (pvpython), then as `mpirun -np N pvbatch test_mpi_tree_pieces.py ...
--ranks N`."""
import hashlib
import os

from plantmorph_testing import (check_rank_count, Checks, fingerprint, load_plugin, load_reference,
                               MPI_EQUALITY_ARGUMENTS, parse_arguments, save_reference)

arguments = parse_arguments(MPI_EQUALITY_ARGUMENTS)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())

# The sample strokes of testing/cxx/tree/TreeTestStrokes.h.
STROKES = [[(0, 0), (0.2, 3), (-0.1, 6), (0.1, 9), (0, 12)], [(0.3, 6), (1.5, 7.5), (3, 8.2), (4, 10)],
           [(-0.2, 4), (-1, 5), (-2.5, 5.5), (-3.5, 7), (-4, 8)], [(2.0, 7.8), (2.2, 9), (2.1, 10.5)]]
stroke_file = os.path.join(arguments.work, "mpi_tree_strokes.csv")
if arguments.write_reference:
    with open(stroke_file, "w") as f:
        f.write("stroke_id,x,y\n")
        for k, line in enumerate(STROKES):
            for x, y in line:
                f.write("%d,%r,%r\n" % (k, float(x), float(y)))

second = TreeFromSketchSource(Preset=2, Depth=2, Leaves=0)
TREES = {
    "template_welded": TreeFromSketchSource(Preset=1, Depth=3, Leaves=1, LeafCount=2),
    "template_seated": TreeFromSketchSource(Preset=2, Depth=3, Joints=1, Leaves=1),
    "strokes": TreeFromSketchSource(Mode="Strokes", StrokeFile=stroke_file, Leaves=0),
    "forest": TreeFromSketchSource(Preset=2, Depth=2, Leaves=0, MergeTree=OutputPort(second, 1),
                                   MergeParentBranch=-1, MergeOffset=[30.0, 0.0, 0.0], MergeScale=1.0),
}


def triangle_rows(data):
    """One row per polygon: its corners rotated to put the smallest (x, y, z, normal, TCoords) first, orientation
    kept, then its cell arrays; the rows sorted. Exact values: no rounding."""
    polys = data.GetPolys()
    offsets = vtk_to_numpy(polys.GetOffsetsArray())
    connectivity = vtk_to_numpy(polys.GetConnectivityArray())
    sizes = numpy.diff(offsets)
    corners = int(sizes.max()) if len(sizes) else 3
    if not numpy.all(sizes == corners):
        raise ValueError("polygons of several sizes")
    ids = connectivity.reshape(-1, corners)
    point_data = [vtk_to_numpy(data.GetPoints().GetData()).astype(numpy.float64)]
    for name in ("Normals", "TCoords"):
        array = data.GetPointData().GetArray(name)
        point_data.append(vtk_to_numpy(array).astype(numpy.float64).reshape(data.GetNumberOfPoints(), -1))
    values = numpy.hstack(point_data)[ids]  # polygons x corners x values
    # Rotate each polygon so its lexicographically smallest corner comes first.
    keys = [tuple(map(tuple, polygon)) for polygon in values]
    first = [min(range(corners), key=lambda k, p=p: p[k]) for p in keys]
    rotated = numpy.array([numpy.roll(values[i], -first[i], axis=0) for i in range(len(values))])
    cell = [vtk_to_numpy(data.GetCellData().GetArray(name)).astype(numpy.float64).reshape(-1, 1)
            for name in ("BranchId", "ParentId", "Depth") if data.GetCellData().GetArray(name) is not None]
    rows = numpy.hstack([rotated.reshape(len(values), -1)] + cell)
    return rows[numpy.lexsort(rows.T[::-1])]


def digest(data):
    rows = triangle_rows(data)
    return {"polygons": int(rows.shape[0]), "sha256": hashlib.sha256(numpy.ascontiguousarray(rows).tobytes()).hexdigest()}


reference_file = os.path.join(arguments.work, "mpi_tree_pieces_reference.json")
if arguments.write_reference:
    reference = {}
    for name, tree in TREES.items():
        reference[name] = {"branches": digest(servermanager.Fetch(tree, idx=0)),
                           "skeleton": fingerprint(servermanager.Fetch(tree, idx=1))}
        leaves = servermanager.Fetch(tree, idx=2)
        reference[name]["leaves"] = digest(leaves) if leaves.GetNumberOfCells() else None
    save_reference(reference_file, reference)
    raise SystemExit(0)

checks = Checks()
ranks = check_rank_count(checks, arguments)
reference = load_reference(reference_file)
for name, tree in TREES.items():
    serial = reference[name]
    branches = digest(servermanager.Fetch(tree, idx=0))
    checks.check(branches == serial["branches"], "%s: the %d ranks' branch triangles are the serial ones, each once: "
                 "%s, serially %s" % (name, ranks, branches, serial["branches"]))
    skeleton = servermanager.Fetch(tree, idx=1)
    checks.check(fingerprint(skeleton) == serial["skeleton"], "%s: the skeleton is the serial one, once" % name)
    if serial["leaves"] is not None:
        leaves = digest(servermanager.Fetch(tree, idx=2))
        checks.check(leaves == serial["leaves"], "%s: the leaves are the serial ones, each once: %s, serially %s" % (
            name, leaves, serial["leaves"]))
    # Every rank holds a part of the branches, none all of them (the tree is really split).
    owners = servermanager.Fetch(ProcessIdScalars(Input=OutputPort(tree, 0)))
    process = vtk_to_numpy(owners.GetPointData().GetArray("ProcessId"))
    per_rank = numpy.bincount(process.astype(int), minlength=ranks)
    checks.check(len(per_rank) == ranks and (ranks == 1 or (per_rank.min() > 0 and per_rank.max() < len(process))),
                 "%s: points per rank %s" % (name, per_rank.tolist()))
checks.finish()
