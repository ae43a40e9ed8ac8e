#include "vtkVirtualScanner.h"
#include "PlantMorphAlgorithmHooks.h"

#include "PlantMorphFieldData.h"
#include "PlantMorphWholeInput.h"

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
#include <sstream>
#include <string>

vtkStandardNewMacro(vtkVirtualScanner);

namespace
{
const char* const OwnArrays[] = { "Normals", "Range", "Intensity", "ScanPosition", "HitCellId", "BeamId" };
const char* const TypeNames[] = { "Terrestrial", "Line", "Depth camera" };

/// The input's polygons and strips as triangles (fans and strip triangles), each with its cell id in the input.
std::string Triangulate(
  vtkPolyData* input, std::vector<double>& points, std::vector<std::int64_t>& triangles, std::vector<vtkIdType>& cellOf)
{
  const vtkIdType n = input->GetNumberOfPoints();
  points.resize(3 * static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
    input->GetPoint(i, &points[3 * static_cast<std::size_t>(i)]);
  vtkIdType cellId = input->GetNumberOfVerts() + input->GetNumberOfLines();
  auto polygons = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  for (polygons->GoToFirstCell(); !polygons->IsDoneWithTraversal(); polygons->GoToNextCell(), ++cellId)
  {
    vtkIdType size;
    const vtkIdType* ids;
    polygons->GetCurrentCell(size, ids);
    for (vtkIdType k = 1; k + 1 < size; ++k)
    {
      triangles.insert(triangles.end(), { ids[0], ids[k], ids[k + 1] });
      cellOf.push_back(cellId);
    }
  }
  auto strips = vtk::TakeSmartPointer(input->GetStrips()->NewIterator());
  for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell(), ++cellId)
  {
    vtkIdType size;
    const vtkIdType* ids;
    strips->GetCurrentCell(size, ids);
    for (vtkIdType k = 0; k + 2 < size; ++k)
    {
      if (k % 2 == 0)
        triangles.insert(triangles.end(), { ids[k], ids[k + 1], ids[k + 2] });
      else
        triangles.insert(triangles.end(), { ids[k + 1], ids[k], ids[k + 2] });
      cellOf.push_back(cellId);
    }
  }
  return plantmorph::ValidateSurface(points, triangles);
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

/// Arrays whose tuples threads may write side by side (plain arrays of values; not bit arrays, not implicit ones).
bool Contiguous(vtkAbstractArray* array)
{
  return array->GetArrayType() == vtkAbstractArray::AoSDataArrayTemplate;
}

/// An empty array like `source` (type, name, components and their names) with n tuples.
vtkSmartPointer<vtkAbstractArray> LikeWithTuples(vtkAbstractArray* source, vtkIdType n)
{
  vtkSmartPointer<vtkAbstractArray> values = vtk::TakeSmartPointer(source->NewInstance());
  values->SetName(source->GetName());
  values->SetNumberOfComponents(source->GetNumberOfComponents());
  for (int c = 0; c < source->GetNumberOfComponents(); ++c)
    if (source->GetComponentName(c))
      values->SetComponentName(c, source->GetComponentName(c));
  values->SetNumberOfTuples(n);
  return values;
}

/// Port 0: the cloud with its arrays and the hit cells' arrays. One threaded pass writes every array, sized once,
/// through raw pointers (each point i is written by one thread only, so the output does not depend on the threads).
void WriteCloud(
  const plantmorph::ScanPoints& scan, const std::vector<vtkIdType>& cellOf, vtkPolyData* input, vtkPolyData* cloud)
{
  const auto n = static_cast<vtkIdType>(scan.Size());
  vtkNew<vtkDoubleArray> xyz;
  xyz->SetNumberOfComponents(3);
  xyz->SetNumberOfTuples(n);
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(n);
  vtkNew<vtkDoubleArray> range, intensity;
  range->SetName("Range");
  range->SetNumberOfTuples(n);
  intensity->SetName("Intensity");
  intensity->SetNumberOfTuples(n);
  vtkNew<vtkIntArray> pose;
  pose->SetName("ScanPosition");
  pose->SetNumberOfTuples(n);
  vtkNew<vtkIdTypeArray> hitCell, beam, offsets, connectivity;
  hitCell->SetName("HitCellId");
  hitCell->SetNumberOfTuples(n);
  beam->SetName("BeamId");
  beam->SetNumberOfTuples(n);
  offsets->SetNumberOfTuples(n + 1);
  connectivity->SetNumberOfTuples(n);
  double* x = xyz->GetPointer(0);
  float* normal = normals->GetPointer(0);
  double *r = range->GetPointer(0), *in = intensity->GetPointer(0);
  int* ps = pose->GetPointer(0);
  vtkIdType *cell = hitCell->GetPointer(0), *b = beam->GetPointer(0), *off = offsets->GetPointer(0),
            *conn = connectivity->GetPointer(0);
  vtkSMPTools::For(0, n, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
    {
      const auto s = static_cast<std::size_t>(i);
      for (std::size_t k = 0; k < 3; ++k)
      {
        x[3 * s + k] = scan.points[3 * s + k];
        normal[3 * s + k] = static_cast<float>(scan.normals[3 * s + k]);
      }
      r[s] = scan.range[s];
      in[s] = scan.intensity[s];
      ps[s] = static_cast<int>(scan.pose[s]);
      cell[s] = cellOf[static_cast<std::size_t>(scan.triangle[s])];
      b[s] = static_cast<vtkIdType>(scan.beam[s]);
      off[s] = i;
      conn[s] = i;
    }
  });
  off[n] = n;
  vtkNew<vtkPoints> points;
  points->SetData(xyz);
  vtkNew<vtkCellArray> verts;
  verts->SetData(offsets, connectivity);
  cloud->SetPoints(points);
  cloud->SetVerts(verts);
  vtkPointData* pd = cloud->GetPointData();
  pd->SetNormals(normals);
  pd->AddArray(range);
  pd->AddArray(intensity);
  pd->AddArray(pose);
  pd->AddArray(hitCell);
  pd->AddArray(beam);
  pd->SetActiveScalars("Range");
  vtkCellData* cd = input->GetCellData();
  for (int a = 0; a < cd->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* source = cd->GetAbstractArray(a);
    if (!source || Reserved(source->GetName()))
      continue;
    vtkSmartPointer<vtkAbstractArray> carried = LikeWithTuples(source, n);
    auto* data = vtkDataArray::SafeDownCast(carried);
    if (data && Contiguous(carried)) // numbers: copied in parallel, tuple by tuple
    {
      vtkSMPTools::For(0, n, [&](vtkIdType begin, vtkIdType end) {
        for (vtkIdType i = begin; i < end; ++i)
          data->SetTuple(i, cell[i], source);
      });
    }
    else if (n > 0) // strings, variants, bits: serial
    {
      vtkNew<vtkIdList> from, to;
      from->SetNumberOfIds(n);
      to->SetNumberOfIds(n);
      for (vtkIdType i = 0; i < n; ++i)
      {
        from->SetId(i, cell[i]);
        to->SetId(i, i);
      }
      carried->InsertTuples(to, from, source);
    }
    pd->AddArray(carried);
  }
}

/// The input's point arrays at the hits, for those not named like ours or like a carried cell array: floating-point
/// arrays interpolated with the hit's barycentric weights (LeafUV, TCoords: exact on the triangle hit), integer
/// arrays (labels) taken from the triangle's vertex nearest the hit. Threaded over the points.
void InterpolatePointArrays(const plantmorph::ScanPoints& scan, const std::vector<std::int64_t>& triangles,
  vtkPolyData* input, vtkPolyData* cloud)
{
  const auto n = static_cast<vtkIdType>(scan.Size());
  vtkPointData* in = input->GetPointData();
  vtkPointData* pd = cloud->GetPointData();
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* source = in->GetArray(a);
    if (!source || Reserved(source->GetName()) || pd->GetAbstractArray(source->GetName()))
      continue;
    vtkSmartPointer<vtkDataArray> values = vtkDataArray::SafeDownCast(LikeWithTuples(source, n));
    const int components = source->GetNumberOfComponents();
    const bool real = source->GetDataType() == VTK_FLOAT || source->GetDataType() == VTK_DOUBLE;
    const auto interpolate = [&](vtkIdType begin, vtkIdType end) {
      for (vtkIdType i = begin; i < end; ++i)
      {
        const auto s = static_cast<std::size_t>(i);
        const std::int64_t* t = &triangles[3 * static_cast<std::size_t>(scan.triangle[s])];
        const double u = scan.barycentric[2 * s], v = scan.barycentric[2 * s + 1];
        const double w[3] = { 1.0 - u - v, u, v };
        if (!real)
        {
          const int k = w[0] >= w[1] && w[0] >= w[2] ? 0 : (w[1] >= w[2] ? 1 : 2);
          values->SetTuple(i, static_cast<vtkIdType>(t[k]), source);
          continue;
        }
        for (int c = 0; c < components; ++c)
        {
          values->SetComponent(i, c,
            w[0] * source->GetComponent(static_cast<vtkIdType>(t[0]), c) +
              w[1] * source->GetComponent(static_cast<vtkIdType>(t[1]), c) +
              w[2] * source->GetComponent(static_cast<vtkIdType>(t[2]), c));
        }
      }
    };
    if (Contiguous(values) && Contiguous(source))
      vtkSMPTools::For(0, n, interpolate);
    else
      interpolate(0, n);
    pd->AddArray(values);
  }
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
  std::vector<double> points;
  std::vector<std::int64_t> triangles;
  std::vector<vtkIdType> cellOf;
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
int vtkVirtualScanner::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkVirtualScanner::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* original = input;
  vtkPolyData* cloud = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* setup = vtkPolyData::GetData(outputVector, 1);
  if (!input || !cloud || !setup)
  {
    return 0;
  }
  cloud->Initialize();
  setup->Initialize();
  // Under MPI the whole surface (gathered on rank 0 if it was split over ranks) is replicated on every rank, and
  // each rank casts its consecutive share of the beams: the ranks' pieces in rank order are the serial cloud.
  vtkSmartPointer<vtkPolyData> whole = plantmorph::GatherOnFirstRank(input);
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int ranks = controller ? controller->GetNumberOfProcesses() : 1;
  const int rank = controller ? controller->GetLocalProcessId() : 0;
  if (ranks > 1)
  {
    vtkNew<vtkPolyData> replica;
    if (rank == 0)
    {
      replica->ShallowCopy(whole);
    }
    controller->Broadcast(replica, 0);
    whole = replica.Get();
  }
  input = whole.Get();
  auto fail = [&](const std::string& message) {
    if (rank == 0) // every rank finds the same error: report it once
    {
      vtkErrorMacro(<< message);
    }
    cloud->Initialize();
    setup->Initialize();
    return 1;
  };

  // The parameters first, with the beam budget: nothing is built or cast when they fail.
  plantmorph::ScannerParameters p;
  if (this->ScannerType < 0 || this->ScannerType > 2)
  {
    std::ostringstream message;
    message << plantmorph::OutOfRange(
      "ScannerType", this->ScannerType, "{0, 1, 2}", "0 Terrestrial, 1 Line, 2 Depth camera");
    return fail(message.str());
  }
  if (this->LineMotion < 0 || this->LineMotion > 1)
  {
    std::ostringstream message;
    message << plantmorph::OutOfRange("LineMotion", this->LineMotion, "{0, 1}", "0 Path, 1 Turntable");
    return fail(message.str());
  }
  if (!(this->MaximumBeams >= 1.0 && this->MaximumBeams <= 4e9))
  {
    std::ostringstream message;
    message << plantmorph::OutOfRange("MaximumBeams", this->MaximumBeams, "[1, 4e9]");
    return fail(message.str());
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
  plantmorph::BeamPattern pattern;
  std::string error = pattern.Setup(p);
  if (!error.empty())
  {
    return fail(error);
  }

  // The triangulation and the caster's build, unless the same input (unchanged) was prepared by the last run.
  const vtkMTimeType inputTime = original->GetMTime();
  if (!this->Prepared || ranks > 1 || this->Prepared->input != original || this->Prepared->time != inputTime)
  {
    this->Prepared.reset(); // its memory first
    auto prepared = std::make_shared<PreparedSurface>();
    error = Triangulate(input, prepared->points, prepared->triangles, prepared->cellOf);
    if (error.empty())
    {
      error = prepared->caster.Build(prepared->points, prepared->triangles);
    }
    if (!error.empty())
    {
      return fail(error);
    }
    prepared->input = original;
    prepared->time = inputTime;
    this->Prepared = prepared;
    Keep(prepared);
  }
  const std::vector<double>& points = this->Prepared->points;
  const std::vector<std::int64_t>& triangles = this->Prepared->triangles;
  const std::vector<vtkIdType>& cellOf = this->Prepared->cellOf;
  const plantmorph::RayCaster& caster = this->Prepared->caster;
  this->UpdateProgress(0.1);
  plantmorph::ScanPoints scan;
  const std::uint64_t beams = pattern.BeamCount();
  const auto share = [&](int r) {
    // beams <= 4e9 (AbsoluteMaximumBeams), so beams * rank fits in 64 bits for any rank count MPI runs.
    return beams * static_cast<std::uint64_t>(r) / static_cast<std::uint64_t>(ranks);
  };
  // Every core: ParaView's default Sequential SMP backend (Debian's) is replaced by STDThread for the cast, as
  // CloudComparisonFilter does; the output does not depend on the thread count.
  const std::string current = vtkSMPTools::GetBackend() ? vtkSMPTools::GetBackend() : "Sequential";
  const std::string backend = current == "Sequential" ? "STDThread" : current;
  vtkSMPTools::LocalScope(vtkSMPTools::Config{ 0, backend, false }, [&]() {
    error = plantmorph::CastBeams(p, pattern, points, triangles, caster, scan, plantmorph::SMPFor(2),
      plantmorph::Progress(this, 0.1, 0.9), share(rank), share(rank + 1));
    if (error.empty()) // the output stage on the same threads
    {
      WriteCloud(scan, cellOf, input, cloud);
      InterpolatePointArrays(scan, triangles, input, cloud);
    }
  });
  if (!error.empty())
  {
    return fail(error);
  }
  // Totals over the ranks in field data (every rank holds them).
  double local[2] = { static_cast<double>(scan.Size()), static_cast<double>(scan.dropped) };
  double total[2] = { local[0], local[1] };
  if (ranks > 1)
  {
    controller->AllReduce(local, total, 2, vtkCommunicator::SUM_OP);
  }
  vtkFieldData* fd = cloud->GetFieldData();
  plantmorph::AddFieldValue(fd, "PlantMorph.Beams", static_cast<double>(beams));
  plantmorph::AddFieldValue(fd, "PlantMorph.Returns", total[0]);
  plantmorph::AddFieldValue(fd, "PlantMorph.Dropped", total[1]);
  plantmorph::AddFieldValue(fd, "PlantMorph.Seed", this->Seed);
  plantmorph::AddFieldString(fd, "PlantMorph.ScannerType", TypeNames[this->ScannerType]);
  const double dx = p.lookAt[0] - p.positions[0][0], dy = p.lookAt[1] - p.positions[0][1],
               dz = p.lookAt[2] - p.positions[0][2];
  if (rank == 0) // the set-up once
  {
    WriteSetup(pattern, std::sqrt(dx * dx + dy * dy + dz * dz), setup);
  }
  if (ranks > 1) // rebuilt every run under MPI: not kept
  {
    this->Prepared.reset();
  }
  this->UpdateProgress(1.0);
  return 1;
}

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
