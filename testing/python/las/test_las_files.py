# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: VirtualScanner's cloud saved as LAS through File > Save Data's writer (SaveData picks the LAS writer
by the extension) and read back by LASReader keeps its points within half the scale and its labels and scan arrays
exactly (ScanPosition, BeamId, HitCellId, Range, Intensity, Normals, and a LeafId/Organ pair added by a Calculator);
saving the read cloud again gives the same bytes (the reader keeps the scale and offset for the writer); LAS 1.2
and a chosen point format are honoured; File > Save Data lists LAS for the scan and File > Open picks LASReader; a file that is not LAS, a truncated one and a LAZ file are refused with the
field named and an empty output.

    pvpython test_las_files.py --plugin PlantMorph.so --work DIR
"""
import os
import struct

from plantmorph_testing import Checks, Messages, load_plugin, parse_arguments

arguments = parse_arguments()

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy

load_plugin(arguments.plugin, globals())
checks = Checks()


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, port)


def array(data, name):
    values = data.GetPointData().GetArray(name)
    return None if values is None else vtk_to_numpy(values)


leaf = LeafOutlineSource(Resolution=16)
scan = VirtualScanner(Input=leaf, Resolution=[60, 40])
labels = Calculator(Input=OutputPort(scan, 0), ResultArrayName="LeafId", Function="7", ResultArrayType="Int")
labels = Calculator(Input=labels, ResultArrayName="Organ", Function="2", ResultArrayType="Unsigned Char")
cloud = fetch(labels)
n = cloud.GetNumberOfPoints()
checks.check(n > 500, "the scan has points (%d)" % n)

first = os.path.join(arguments.work, "las_scan.las")
second = os.path.join(arguments.work, "las_scan_again.las")
for path in (first, second):
    if os.path.exists(path):
        os.remove(path)
# File > Save Data's list of file types for the scan (the writer factory the dialog asks) offers LAS.
offered = servermanager.vtkSMProxyManager.GetProxyManager().GetWriterFactory().GetSupportedFileTypes(labels.SMProxy)
checks.check("LAS point cloud (PlantMorph)(*.las )" in offered, "Save Data offers LAS for the scan: %s" % offered)
SaveData(first, proxy=labels)
checks.check(os.path.isfile(first), "SaveData wrote %s with the LAS writer" % first)
with open(first, "rb") as f:
    header = f.read(375)
checks.check(header[:4] == b"LASF" and header[24:26] == bytes([1, 4]), "a LAS 1.4 file")
checks.check(struct.unpack_from("<H", header, 94)[0] == 375, "its header size is 375")
checks.check(header[104] == 6, "point format 6 (the scan has no colour)")
checks.check(struct.unpack_from("<Q", header, 247)[0] == n, "its point count is the scan's")

# File > Open's choice (the reader factory, as OpenDataFile asks it): LASReader for a .las file.
opened = OpenDataFile(first)
checks.check(opened is not None and opened.GetXMLName() == "LASReader",
             "File > Open picks LASReader for .las (%s)" % (opened.GetXMLName() if opened else None))
if opened is not None:
    Delete(opened)
reader = LASReader(FileName=first)
back = fetch(reader)
checks.check(back.GetNumberOfPoints() == n, "LASReader reads %d points (%d)" % (n, back.GetNumberOfPoints()))
checks.check(back.GetNumberOfVerts() == n, "one vertex per point")
scale = vtk_to_numpy(back.GetFieldData().GetArray("PlantMorph.LASScale"))[0]
written = vtk_to_numpy(cloud.GetPoints().GetData())
read = vtk_to_numpy(back.GetPoints().GetData())
error = abs(read - written).max(axis=0)
checks.check(all(error <= 0.5 * scale * (1 + 1e-6)),
             "coordinates within half the scale %s (largest errors %s)" % (scale, error))
for name in ("ScanPosition", "BeamId", "HitCellId", "Range", "Intensity", "Normals", "LeafId", "Organ"):
    a, b = array(cloud, name), array(back, name)
    same = a is not None and b is not None and a.shape == b.shape and (a == b).all()
    checks.check(same, "%s comes back exactly" % name)
    if b is not None and a is not None:
        checks.check(back.GetPointData().GetArray(name).GetDataTypeSize() ==
                     cloud.GetPointData().GetArray(name).GetDataTypeSize(), "%s keeps its type's size" % name)

SaveData(second, proxy=reader)
with open(first, "rb") as f, open(second, "rb") as g:
    checks.check(f.read() == g.read(), "the read cloud saved again gives the same bytes")

# LAS 1.2 and a chosen format: the writer's own properties.
old = os.path.join(arguments.work, "las_scan_12.las")
SaveData(old, proxy=labels, Version=2, PointFormat=1)
with open(old, "rb") as f:
    header = f.read(227)
checks.check(header[25] == 2 and struct.unpack_from("<H", header, 94)[0] == 227 and header[104] == 1,
             "Version 1.2, point format 1, a 227-byte header")
checks.check(struct.unpack_from("<I", header, 107)[0] == n, "LAS 1.2's point count is the scan's")
back12 = fetch(LASReader(FileName=old))
checks.check((array(back12, "LeafId") == array(cloud, "LeafId")).all(), "LAS 1.2 keeps LeafId")

# Refused files: the field named, the output empty.
bad = os.path.join(arguments.work, "las_bad.las")
with open(first, "rb") as f:
    good = f.read()
cases = [(b"LASX" + good[4:], "File Signature"),
         (good[:200], "fewer than the 227"),
         (good[:-7], "Number of Point Records"),
         (good[:104] + bytes([6 | 0x80]) + good[105:], "LAZ")]
for content, named in cases:
    with open(bad, "wb") as f:
        f.write(content)
    refused = LASReader(FileName=bad)
    with Messages(refused) as messages:
        output = fetch(refused)
    checks.check(messages.said(named, "las_bad.las", kind="error"),
                 "a bad file is refused naming '%s' (%s)" % (named, messages.errors))
    checks.check(output.GetNumberOfPoints() == 0, "and the output is empty")
    Delete(refused)
checks.finish()
