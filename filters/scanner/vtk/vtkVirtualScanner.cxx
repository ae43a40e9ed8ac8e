// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkVirtualScanner.h"
#include "PlantMorphAlgorithmHooks.h"

#include "PlantMorphFieldData.h" // AdoptArray, VertexCells
#include "PlantMorphLayer.h"

#include <plantmorph/RangeError.h>
#include "VirtualScan.h"

#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCommunicator.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <limits>
#include <string>
#include <type_traits>

vtkStandardNewMacro(vtkVirtualScanner);

namespace
{
const char* const OwnArrays[] = { "Normals", "Range", "Intensity", "ScanPosition", "HitCellId", "BeamId" };
const char* const TypeNames[] = { "Terrestrial", "Line", "Depth camera" };

/// The input cell of each triangle: when every polygon is a triangle and there are no strips (the usual surface),
/// triangle t is cell first + t and nothing is stored (80 MB at 10^7 triangles); else one id per triangle.
struct TriangleCells
{
  vtkIdType first = 0;
  std::vector<vtkIdType> ids; // empty: cell first + t

  vtkIdType operator()(std::size_t t) const
  {
    return this->ids.empty() ? this->first + static_cast<vtkIdType>(t) : this->ids[t];
  }
  /// Triangle `t` (the next one) comes from `cell`.
  void Add(std::size_t t, vtkIdType cell)
  {
    if (this->ids.empty() && cell == this->first + static_cast<vtkIdType>(t))
      return;
    for (std::size_t k = this->ids.size(); k < t; ++k) // the identity so far, written out
      this->ids.push_back(this->first + static_cast<vtkIdType>(k));
    this->ids.push_back(cell);
  }
};

/// A point id as a 32-bit index; ids outside [0, n) become n, which ValidateSurface names as out of range.
std::uint32_t Index32(vtkIdType id, vtkIdType n)
{
  return static_cast<std::uint32_t>(id >= 0 && id < n ? id : n);
}

/// The input's points in double precision: its own array when it holds plain doubles (no copy), else a copy made in
/// `copy`. nullptr when there are none.
const double* DoublePoints(vtkPolyData* input, std::vector<double>& copy)
{
  const vtkIdType n = input->GetNumberOfPoints();
  auto* doubles = input->GetPoints() ? vtkDoubleArray::SafeDownCast(input->GetPoints()->GetData()) : nullptr;
  if (doubles && doubles->GetNumberOfComponents() == 3 && n > 0)
    return doubles->GetPointer(0);
  copy.resize(3 * static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
    input->GetPoint(i, &copy[3 * static_cast<std::size_t>(i)]);
  return copy.empty() ? nullptr : copy.data();
}

/// The input's polygons and strips as triangles (fans and strip triangles) of 32-bit point indices (half the memory
/// of VTK's ids; the caster needs fewer than 2^32 points anyway), each with its cell id in the input.
std::string Triangulate(
  vtkPolyData* input, const double* points, std::vector<std::uint32_t>& triangles, TriangleCells& cellOf)
{
  const vtkIdType n = input->GetNumberOfPoints();
  if (static_cast<std::uint64_t>(n) >= (std::uint64_t(1) << 32))
    return "Input: more than 2^32 - 1 points";
  vtkCellArray* polys = input->GetPolys();
  vtkCellArray* stripCells = input->GetStrips();
  // Exactly the triangles' indices: a polygon of m points makes m - 2, and so does a strip.
  triangles.reserve(static_cast<std::size_t>(std::max<vtkIdType>(0,
    3 *
      (polys->GetNumberOfConnectivityIds() - 2 * polys->GetNumberOfCells() + stripCells->GetNumberOfConnectivityIds() -
        2 * stripCells->GetNumberOfCells()))));
  cellOf.first = input->GetNumberOfVerts() + input->GetNumberOfLines();
  vtkIdType cellId = cellOf.first;
  auto polygons = vtk::TakeSmartPointer(polys->NewIterator());
  for (polygons->GoToFirstCell(); !polygons->IsDoneWithTraversal(); polygons->GoToNextCell(), ++cellId)
  {
    vtkIdType size;
    const vtkIdType* ids;
    polygons->GetCurrentCell(size, ids);
    for (vtkIdType k = 1; k + 1 < size; ++k)
    {
      cellOf.Add(triangles.size() / 3, cellId);
      triangles.insert(triangles.end(), { Index32(ids[0], n), Index32(ids[k], n), Index32(ids[k + 1], n) });
    }
  }
  auto strips = vtk::TakeSmartPointer(stripCells->NewIterator());
  for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell(), ++cellId)
  {
    vtkIdType size;
    const vtkIdType* ids;
    strips->GetCurrentCell(size, ids);
    for (vtkIdType k = 0; k + 2 < size; ++k)
    {
      cellOf.Add(triangles.size() / 3, cellId);
      if (k % 2 == 0)
        triangles.insert(triangles.end(), { Index32(ids[k], n), Index32(ids[k + 1], n), Index32(ids[k + 2], n) });
      else
        triangles.insert(triangles.end(), { Index32(ids[k + 1], n), Index32(ids[k], n), Index32(ids[k + 2], n) });
    }
  }
  return plantmorph::ValidateSurface(points, static_cast<std::size_t>(n), triangles.data(), triangles.size() / 3);
}

/// True when `name` is one of the cloud's own arrays or the ghost array: not carried from the input.
bool Reserved(const char* name)
{
  if (!name || std::strcmp(name, vtkDataSetAttributes::GhostArrayName()) == 0)
    return true;
  for (const char* ours : OwnArrays)
    if (std::strcmp(name, ours) == 0)
      return true;
  return false;
}

/// True when the input's array `array`, which needs `needed` tuples (one per cell or point), is carried to the cloud:
/// not one of ours, and not short (ShortArrays names the short ones).
bool Carried(vtkAbstractArray* array, vtkIdType needed)
{
  return array && !Reserved(array->GetName()) && array->GetNumberOfTuples() >= needed;
}

/// The input's cell and point arrays with fewer tuples than cells or points (a malformed input): named in a warning
/// and not carried to the cloud. Empty when there are none.
std::string ShortArrays(vtkPolyData* input)
{
  std::ostringstream names;
  const auto check = [&](vtkFieldData* data, vtkIdType needed, const char* kind) {
    for (int a = 0; a < data->GetNumberOfArrays(); ++a)
    {
      vtkAbstractArray* array = data->GetAbstractArray(a);
      if (array && !Reserved(array->GetName()) && !Carried(array, needed))
        names << (names.tellp() > 0 ? ", " : "") << kind << " array " << array->GetName() << " ("
              << array->GetNumberOfTuples() << " tuples for " << needed << ")";
    }
  };
  check(input->GetCellData(), input->GetNumberOfCells(), "cell");
  check(input->GetPointData(), input->GetNumberOfPoints(), "point");
  return names.str();
}

/// Arrays whose tuples threads may read and write side by side as plain memory (not bit arrays, not implicit ones).
bool Contiguous(vtkAbstractArray* array)
{
  return array->GetArrayType() == vtkAbstractArray::AoSDataArrayTemplate;
}

/// An array like `source` (type, name, components and their names) with n tuples, unset. Plain arrays get
/// CloudArray memory (huge pages for large ones: the cloud's arrays are fresh memory on every run).
vtkSmartPointer<vtkAbstractArray> LikeWithTuples(vtkAbstractArray* source, vtkIdType n)
{
  vtkSmartPointer<vtkAbstractArray> values = vtk::TakeSmartPointer(source->NewInstance());
  values->SetName(source->GetName());
  const int components = source->GetNumberOfComponents();
  values->SetNumberOfComponents(components);
  for (int c = 0; c < components; ++c)
    if (source->GetComponentName(c))
      values->SetComponentName(c, source->GetComponentName(c));
  if (Contiguous(values) && n > 0)
  {
    plantmorph::CloudArray<unsigned char> memory;
    memory.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(components * source->GetDataTypeSize()));
    values->SetVoidArray(memory.Release(), n * components, 0, vtkAbstractArray::VTK_DATA_ARRAY_FREE);
  }
  else
  {
    values->SetNumberOfTuples(n);
  }
  return values;
}

/// values[i] = source[from(i)] for the n tuples, `from` giving tuple indices in [0, source's tuple count): threaded
/// as plain bytes when both are plain arrays, else serial through VTK.
template <class From>
void GatherTuples(vtkAbstractArray* source, vtkAbstractArray* values, vtkIdType n, const From& from)
{
  if (Contiguous(source) && Contiguous(values))
  {
    const auto bytes = static_cast<std::size_t>(source->GetNumberOfComponents() * source->GetDataTypeSize());
    const auto* in = static_cast<const unsigned char*>(source->GetVoidPointer(0));
    auto* out = static_cast<unsigned char*>(values->GetVoidPointer(0));
    vtkSMPTools::For(0, n, [&](vtkIdType begin, vtkIdType end) {
      for (vtkIdType i = begin; i < end; ++i)
        std::memcpy(out + static_cast<std::size_t>(i) * bytes, in + static_cast<std::size_t>(from(i)) * bytes, bytes);
    });
    return;
  }
  if (n == 0) // strings, variants, bits
    return;
  vtkNew<vtkIdList> fromIds, toIds;
  fromIds->SetNumberOfIds(n);
  toIds->SetNumberOfIds(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    fromIds->SetId(i, from(i));
    toIds->SetId(i, i);
  }
  values->InsertTuples(toIds, fromIds, source);
}

/// True when the input's point array `source` is carried to the cloud at the hits (InterpolatePointArrays): not
/// named like ours or like a cell array, and with a tuple per point.
bool Interpolated(vtkPolyData* input, vtkDataArray* source)
{
  return Carried(source, input->GetNumberOfPoints()) && !input->GetCellData()->GetAbstractArray(source->GetName());
}

/// True when some point array of the input is carried (the scan then keeps each hit's barycentric coordinates).
bool AnyInterpolated(vtkPolyData* input)
{
  for (int a = 0; a < input->GetPointData()->GetNumberOfArrays(); ++a)
    if (Interpolated(input, input->GetPointData()->GetArray(a)))
      return true;
  return false;
}

/// A floating-point point array at the hits: each hit's triangle corners (`corner(i, k)`) weighted by its
/// barycentric coordinates (exact on the triangle hit). Threaded when both arrays are plain memory.
template <class Corner>
void InterpolateFloating(
  const plantmorph::ScanPoints& scan, vtkDataArray* source, vtkDataArray* values, vtkIdType n, const Corner& corner)
{
  const int components = source->GetNumberOfComponents();
  const auto weights = [&](vtkIdType i, double w[3]) {
    w[1] = scan.barycentric[2 * i];
    w[2] = scan.barycentric[2 * i + 1];
    w[0] = 1.0 - w[1] - w[2];
  };
  if (Contiguous(values) && Contiguous(source))
  {
    const auto plain = [&](auto* in, auto* out) { // the same type: float or double
      vtkSMPTools::For(0, n, [&](vtkIdType begin, vtkIdType end) {
        for (vtkIdType i = begin; i < end; ++i)
        {
          double w[3];
          weights(i, w);
          const auto* a = in + components * corner(i, 0);
          const auto* b = in + components * corner(i, 1);
          const auto* c = in + components * corner(i, 2);
          for (int k = 0; k < components; ++k)
            out[components * i + k] = static_cast<std::remove_reference_t<decltype(*out)>>(
              w[0] * static_cast<double>(a[k]) + w[1] * static_cast<double>(b[k]) + w[2] * static_cast<double>(c[k]));
        }
      });
    };
    if (source->GetDataType() == VTK_FLOAT)
      plain(static_cast<const float*>(source->GetVoidPointer(0)), static_cast<float*>(values->GetVoidPointer(0)));
    else
      plain(static_cast<const double*>(source->GetVoidPointer(0)), static_cast<double*>(values->GetVoidPointer(0)));
    return;
  }
  for (vtkIdType i = 0; i < n; ++i) // not plain memory: serial, through VTK
  {
    double w[3];
    weights(i, w);
    for (int c = 0; c < components; ++c)
      values->SetComponent(i, c,
        w[0] * source->GetComponent(corner(i, 0), c) + w[1] * source->GetComponent(corner(i, 1), c) +
          w[2] * source->GetComponent(corner(i, 2), c));
  }
}

/// The input's point arrays at the hits, for those not named like ours or like a carried cell array: floating-point
/// arrays interpolated with the hit's barycentric weights (LeafUV, TCoords: exact on the triangle hit), integer
/// arrays (labels) taken from the triangle's vertex nearest the hit. Threaded over the points.
std::vector<vtkSmartPointer<vtkAbstractArray>> InterpolatePointArrays(
  const plantmorph::ScanPoints& scan, const std::vector<std::uint32_t>& triangles, vtkPolyData* input)
{
  const auto n = static_cast<vtkIdType>(scan.Size());
  std::vector<vtkSmartPointer<vtkAbstractArray>> interpolated;
  vtkPointData* in = input->GetPointData();
  const auto corner = [&](vtkIdType i, int k) {
    return static_cast<vtkIdType>(triangles[3 * static_cast<std::size_t>(scan.triangle[i]) + k]);
  };
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* source = in->GetArray(a);
    if (!Interpolated(input, source))
      continue;
    vtkSmartPointer<vtkDataArray> values = vtkDataArray::SafeDownCast(LikeWithTuples(source, n));
    if (source->GetDataType() != VTK_FLOAT && source->GetDataType() != VTK_DOUBLE)
    {
      GatherTuples(source, values, n, [&](vtkIdType i) {
        const double u = scan.barycentric[2 * i], v = scan.barycentric[2 * i + 1], w = 1.0 - u - v;
        return corner(i, w >= u && w >= v ? 0 : (u >= v ? 1 : 2));
      });
    }
    else
    {
      InterpolateFloating(scan, source, values, n, corner);
    }
    interpolated.emplace_back(values);
  }
  return interpolated;
}

/// Port 0: the cloud with its arrays, the hit cells' arrays and the input's point arrays at the hits. The scan's
/// arrays become the output's (adopted, not copied: `scan` is left empty); the triangle indices become the hit cells'
/// ids in place. Each point is written by one thread only, so the output does not depend on the threads.
void WriteCloud(plantmorph::ScanPoints& scan, const TriangleCells& cellOf, const std::vector<std::uint32_t>& triangles,
  vtkPolyData* input, vtkPolyData* cloud)
{
  const auto n = static_cast<vtkIdType>(scan.Size());
  const std::vector<vtkSmartPointer<vtkAbstractArray>> interpolated = InterpolatePointArrays(scan, triangles, input);
  long long* cell = scan.triangle.data();
  vtkSMPTools::For(0, n, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
      cell[i] = cellOf(static_cast<std::size_t>(cell[i]));
  });
  vtkNew<vtkPoints> points;
  points->SetData(plantmorph::AdoptArray<vtkDoubleArray>(scan.points, 3, nullptr));
  cloud->SetPoints(points);
  cloud->SetVerts(plantmorph::VertexCells(n));
  vtkPointData* pd = cloud->GetPointData();
  pd->SetNormals(plantmorph::AdoptArray<vtkFloatArray>(scan.normals, 3, "Normals"));
  pd->AddArray(plantmorph::AdoptArray<vtkDoubleArray>(scan.range, 1, "Range"));
  pd->AddArray(plantmorph::AdoptArray<vtkDoubleArray>(scan.intensity, 1, "Intensity"));
  pd->AddArray(plantmorph::AdoptArray<vtkIntArray>(scan.pose, 1, "ScanPosition"));
  pd->AddArray(plantmorph::AdoptArray<vtkIdTypeArray>(scan.triangle, 1, "HitCellId"));
  pd->AddArray(plantmorph::AdoptArray<vtkIdTypeArray>(scan.beam, 1, "BeamId"));
  pd->SetActiveScalars("Range");
  vtkCellData* cd = input->GetCellData();
  for (int a = 0; a < cd->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* source = cd->GetAbstractArray(a);
    if (!Carried(source, input->GetNumberOfCells()))
      continue;
    vtkSmartPointer<vtkAbstractArray> carried = LikeWithTuples(source, n);
    GatherTuples(source, carried, n, [cell](vtkIdType i) { return static_cast<vtkIdType>(cell[i]); });
    pd->AddArray(carried);
  }
  for (const auto& values : interpolated)
    pd->AddArray(values);
}

/// Port 1: the set-up as lines, with the pose of each.
void WriteSetup(const plantmorph::BeamPattern& pattern, double length, vtkPolyData* setup)
{
  std::vector<double> segments;
  std::vector<std::int64_t> poses;
  pattern.SetupLines(length, 200, segments, poses);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> pose;
  pose->SetName("ScanPosition");
  for (std::size_t i = 0; i < poses.size(); ++i)
  {
    const vtkIdType a = points->InsertNextPoint(&segments[6 * i]);
    const vtkIdType b = points->InsertNextPoint(&segments[6 * i + 3]);
    const vtkIdType ids[2] = { a, b };
    lines->InsertNextCell(2, ids);
    pose->InsertNextValue(static_cast<int>(poses[i]));
  }
  setup->SetPoints(points);
  setup->SetLines(lines);
  setup->GetCellData()->AddArray(pose);
}
} // namespace

//------------------------------------------------------------------------------
struct vtkVirtualScanner::PreparedSurface
{
  const vtkPolyData* input = nullptr; // identity only, never dereferenced
  vtkMTimeType time = 0;
  std::vector<std::uint32_t> triangles; // for the point arrays at the hits; the points are the caster's copy only
  TriangleCells cellOf;
  plantmorph::RayCaster caster;
};

namespace
{
/// The kept surfaces of every filter, released by an exit handler: a filter still alive when the process ends
/// (ParaView deletes its proxies in its static destructors) would otherwise release its Embree device after
/// Embree's thread pool is gone, which aborts or hangs.
struct KeptSurfaces
{
  std::mutex lock;
  std::vector<std::weak_ptr<vtkVirtualScanner::PreparedSurface>> all;
};

KeptSurfaces& Kept()
{
  static KeptSurfaces* kept = new KeptSurfaces; // never destroyed: the exit handler may run after statics
  return *kept;
}

void ReleaseKeptSurfaces()
{
  std::lock_guard<std::mutex> guard(Kept().lock);
  for (auto& weak : Kept().all)
  {
    if (auto prepared = weak.lock())
    {
      prepared->caster.Clear();
    }
  }
  Kept().all.clear();
}

void Keep(const std::shared_ptr<vtkVirtualScanner::PreparedSurface>& prepared)
{
  static std::once_flag once;
  std::call_once(once, [] { std::atexit(ReleaseKeptSurfaces); });
  std::lock_guard<std::mutex> guard(Kept().lock);
  auto& all = Kept().all;
  all.erase(std::remove_if(all.begin(), all.end(), [](const auto& w) { return w.expired(); }), all.end());
  all.push_back(prepared);
}
} // namespace

//------------------------------------------------------------------------------
vtkVirtualScanner::vtkVirtualScanner()
{
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
void vtkVirtualScanner::ClearPositions()
{
  this->PositionsElementCount = -1;
  if (!this->Positions.empty())
  {
    this->Positions.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkVirtualScanner::AddPosition(double x, double y, double z)
{
  this->Positions.insert(this->Positions.end(), { x, y, z });
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkVirtualScanner::SetPositionsElementCount(int count)
{
  if (count != this->PositionsElementCount)
  {
    this->PositionsElementCount = count;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkVirtualScanner::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
namespace
{
/// Under MPI the whole surface (gathered on rank 0 if it was split over ranks) is replicated on every rank, and each
/// rank casts its consecutive share of the beams: the ranks' pieces in rank order are the serial cloud.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::DataParallel;

/// The global controller and this rank (serial: null, 0 of 1).
struct Ranks
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  int count = controller ? controller->GetNumberOfProcesses() : 1;
  int rank = controller ? controller->GetLocalProcessId() : 0;
};

/// The field data of the cloud (totals over the ranks, which every rank holds) and, on rank 0, the set-up port.
void WriteTotals(vtkVirtualScanner* self, const Ranks& ranks, const plantmorph::ScannerParameters& p,
  const plantmorph::BeamPattern& pattern, std::size_t dropped, vtkPolyData* cloud, vtkPolyData* setup)
{
  double local[2] = { static_cast<double>(cloud->GetNumberOfPoints()), static_cast<double>(dropped) };
  double total[2] = { local[0], local[1] };
  if (ranks.count > 1)
  {
    ranks.controller->AllReduce(local, total, 2, vtkCommunicator::SUM_OP);
  }
  plantmorph::FieldRecord record;
  record.Add("Beams", static_cast<double>(pattern.BeamCount()));
  record.Add("Returns", total[0]);
  record.Add("Dropped", total[1]);
  record.Add("Seed", self->GetSeed());
  record.Add("ScannerType", std::string(TypeNames[self->GetScannerType()]));
  record.WriteTo(cloud);
  const double dx = p.lookAt[0] - p.positions[0][0], dy = p.lookAt[1] - p.positions[0][1],
               dz = p.lookAt[2] - p.positions[0][2];
  if (ranks.rank == 0) // the set-up once
  {
    WriteSetup(pattern, std::sqrt(dx * dx + dy * dy + dz * dz), setup);
  }
}
} // namespace

namespace
{
/// The bytes the output adds to each point of the scan's cloud: its vertex cell (32-bit offset and connectivity)
/// and the input's arrays carried to it (cell arrays at the hit cells, point arrays at the hits).
std::size_t CarriedBytesPerPoint(vtkPolyData* input)
{
  std::size_t bytes = 2 * sizeof(std::int32_t);
  vtkCellData* cd = input->GetCellData();
  for (int a = 0; a < cd->GetNumberOfArrays(); ++a)
    if (vtkAbstractArray* array = cd->GetAbstractArray(a))
      if (Carried(array, input->GetNumberOfCells()))
        bytes += static_cast<std::size_t>(array->GetNumberOfComponents() * array->GetDataTypeSize());
  vtkPointData* pd = input->GetPointData();
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
    if (vtkDataArray* array = pd->GetArray(a))
      if (Interpolated(input, array))
        bytes += static_cast<std::size_t>(array->GetNumberOfComponents() * array->GetDataTypeSize());
  return bytes;
}

/// Casts this rank's beams [first, end) into `cloud` (port 0) on every core: refused first when its cloud clearly
/// cannot fit in memory; memory that runs out while casting or writing the output is an error naming the
/// properties that set the beam count, agreed by every rank. Returns the beams that hit but were dropped.
std::uint64_t ScanShare(plantmorph::Run& run, vtkAlgorithm* self, const plantmorph::ScannerParameters& p,
  const plantmorph::BeamPattern& pattern, const vtkVirtualScanner::PreparedSurface& prepared, vtkPolyData* input,
  std::uint64_t first, std::uint64_t end, vtkPolyData* cloud);
} // namespace

//------------------------------------------------------------------------------
int vtkVirtualScanner::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(
    this, Policy, "the scan", request, inputVector, outputVector, [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
std::string vtkVirtualScanner::ReadParameters(plantmorph::ScannerParameters& p) const
{
  if (this->ScannerType < 0 || this->ScannerType > 2)
  {
    return plantmorph::OutOfRange(
      "ScannerType", this->ScannerType, "{0, 1, 2}", "0 Terrestrial, 1 Line, 2 Depth camera");
  }
  if (this->LineMotion < 0 || this->LineMotion > 1)
  {
    return plantmorph::OutOfRange("LineMotion", this->LineMotion, "{0, 1}", "0 Path, 1 Turntable");
  }
  if (!(this->MaximumBeams >= 1.0 && this->MaximumBeams <= 4e9))
  {
    return plantmorph::OutOfRange("MaximumBeams", this->MaximumBeams, "[1, 4e9]");
  }
  if (this->Seed < 0 || this->Seed > 1000000)
  {
    return plantmorph::OutOfRange("Seed", this->Seed, "[0, 1000000]");
  }
  if (this->PositionsElementCount >= 0 &&
    static_cast<std::size_t>(this->PositionsElementCount) != this->Positions.size())
  {
    // ParaView pushed only the whole rows: a partial row means the list is not rows of x, y, z.
    return plantmorph::OutOfRange("Positions", std::to_string(this->PositionsElementCount) + " numbers",
      "{3, 6, 9, ...}", "rows of x, y, z; the last row has " + std::to_string(this->PositionsElementCount % 3));
  }
  p.type = static_cast<plantmorph::ScannerType>(this->ScannerType);
  p.positions.clear();
  for (std::size_t i = 0; i + 2 < this->Positions.size(); i += 3)
    p.positions.push_back({ this->Positions[i], this->Positions[i + 1], this->Positions[i + 2] });
  p.lookAt = { this->LookAt[0], this->LookAt[1], this->LookAt[2] };
  p.up = { this->Up[0], this->Up[1], this->Up[2] };
  p.horizontalFieldOfView = this->HorizontalFieldOfView;
  p.verticalFieldOfView = this->VerticalFieldOfView;
  p.angularStep = this->AngularStep;
  p.resolution[0] = this->Resolution[0];
  p.resolution[1] = this->Resolution[1];
  p.lineMotion = static_cast<plantmorph::LineMotion>(this->LineMotion);
  p.lineSpacing = this->LineSpacing;
  p.turntableSteps = this->TurntableSteps;
  p.turntableAxis = { this->TurntableAxis[0], this->TurntableAxis[1], this->TurntableAxis[2] };
  p.rangeNoise = this->RangeNoise;
  p.angularJitter = this->AngularJitter;
  p.dropoutProbability = this->DropoutProbability;
  p.maximumRange = this->MaximumRange;
  p.intensityFalloff = this->IntensityFalloff;
  p.seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(this->Seed));
  p.maximumBeams = static_cast<std::uint64_t>(this->MaximumBeams);
  return {};
}

//------------------------------------------------------------------------------
void vtkVirtualScanner::Prepare(plantmorph::Run& run, vtkPolyData* original, vtkPolyData* input, int ranks)
{
  // The triangulation and the caster's build, unless the same input (unchanged) was prepared by the last run.
  const vtkMTimeType inputTime = original->GetMTime();
  if (this->Prepared && ranks == 1 && this->Prepared->input == original && this->Prepared->time == inputTime)
  {
    return;
  }
  this->Prepared.reset(); // its memory first
  run.Building("the ray caster of the surface");
  auto prepared = std::make_shared<PreparedSurface>();
  std::vector<double> copy; // only when the input's points are not plain doubles
  const double* points = DoublePoints(input, copy);
  run.Check(Triangulate(input, points, prepared->triangles, prepared->cellOf));
  run.Check(prepared->caster.Build(points, static_cast<std::size_t>(input->GetNumberOfPoints()),
    prepared->triangles.data(), prepared->triangles.size() / 3, plantmorph::RayCasterParameters{}));
  prepared->input = original;
  prepared->time = inputTime;
  this->Prepared = prepared;
  Keep(prepared);
}

//------------------------------------------------------------------------------
void vtkVirtualScanner::Execute(plantmorph::Run& run)
{
  vtkPolyData* original = run.Input<vtkPolyData>(0);
  const vtkSmartPointer<vtkPolyData> whole = run.Replicated(original); // collective
  vtkPolyData* input = whole.Get();
  const Ranks ranks;
  // The parameters first, with the beam budget: nothing is built or cast when they fail. Every rank finds the same
  // errors (the surface is replicated): said once.
  plantmorph::ScannerParameters p;
  run.Check(this->ReadParameters(p));
  plantmorph::BeamPattern pattern;
  run.Check(pattern.Setup(p));
  this->Prepare(run, original, input, ranks.count);
  const std::string shortArrays = ShortArrays(input);
  if (!shortArrays.empty())
  {
    run.Warn("Input: not carried to the cloud, fewer tuples than the input has cells or points: " + shortArrays);
  }
  this->UpdateProgress(0.1);
  const std::uint64_t beams = pattern.BeamCount();
  const auto share = [&](int r) {
    // beams <= 4e9 (AbsoluteMaximumBeams), so beams * rank fits in 64 bits for any rank count MPI runs.
    return beams * static_cast<std::uint64_t>(r) / static_cast<std::uint64_t>(ranks.count);
  };
  vtkPolyData* cloud = run.Output<vtkPolyData>(0);
  const std::uint64_t dropped =
    ScanShare(run, this, p, pattern, *this->Prepared, input, share(ranks.rank), share(ranks.rank + 1), cloud);
  WriteTotals(this, ranks, p, pattern, dropped, cloud, run.Output<vtkPolyData>(1));
  if (ranks.count > 1) // rebuilt every run under MPI: not kept
  {
    this->Prepared.reset();
  }
  this->UpdateProgress(1.0);
}

//------------------------------------------------------------------------------
namespace
{
std::uint64_t ScanShare(plantmorph::Run& run, vtkAlgorithm* self, const plantmorph::ScannerParameters& p,
  const plantmorph::BeamPattern& pattern, const vtkVirtualScanner::PreparedSurface& prepared, vtkPolyData* input,
  std::uint64_t first, std::uint64_t end, vtkPolyData* cloud)
{
  run.Building("the scanned cloud (its size is set by MaximumBeams, " + plantmorph::BeamCountProperties(p) + ")");
  plantmorph::ScanPoints scan;
  scan.withBarycentric = AnyInterpolated(input);
  const std::size_t extra = CarriedBytesPerPoint(input);
  const std::string tooLarge = plantmorph::CheckCloudMemory(
    p, pattern, prepared.caster, scan.withBarycentric, extra, plantmorph::AvailableMemory(), first, end);
  run.StopIfAnyRankFailed(run.AnyRank(!tooLarge.empty()), tooLarge);
  std::string error;
  // Every core (RunThreaded replaces a Sequential backend by STDThread); the output does not depend on the threads.
  run.Threaded(0, [&]() {
    error = plantmorph::CastBeams(
      p, pattern, prepared.caster, scan, plantmorph::SMPFor(2), plantmorph::Progress(self, 0.1, 0.9), first, end);
    if (!error.empty())
      return;
    const double points = static_cast<double>(scan.Size());
    try
    {
      WriteCloud(scan, prepared.cellOf, prepared.triangles, input, cloud); // on the same threads
    }
    catch (const std::bad_alloc&)
    {
      cloud->Initialize();
      std::ostringstream message;
      message << "MaximumBeams / " << plantmorph::BeamCountProperties(p) << ": out of memory writing the output of "
              << points << " points ("
              << (points * static_cast<double>(plantmorph::CloudBytesPerPoint(scan.withBarycentric) + extra) / 1e9)
              << " GB with the scan's arrays); cast fewer beams";
      error = message.str();
    }
  });
  run.StopIfAnyRankFailed(run.AnyRank(!error.empty()), error);
  return scan.dropped;
}
} // namespace

//------------------------------------------------------------------------------
void vtkVirtualScanner::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ScannerType: " << this->ScannerType << "\n";
  os << indent << "Positions: " << this->GetNumberOfPositions() << "\n";
  os << indent << "LookAt: " << this->LookAt[0] << " " << this->LookAt[1] << " " << this->LookAt[2] << "\n";
  os << indent << "FieldOfView: " << this->HorizontalFieldOfView << " x " << this->VerticalFieldOfView << "\n";
  os << indent << "AngularStep: " << this->AngularStep << "\n";
  os << indent << "Resolution: " << this->Resolution[0] << " x " << this->Resolution[1] << "\n";
  os << indent << "LineMotion: " << this->LineMotion << "\n";
  os << indent << "RangeNoise: " << this->RangeNoise << "\n";
  os << indent << "DropoutProbability: " << this->DropoutProbability << "\n";
  os << indent << "MaximumRange: " << this->MaximumRange << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "MaximumBeams: " << this->MaximumBeams << "\n";
}
