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
#include <cstring>
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

/// Port 0: the cloud with its arrays and the hit cells' arrays.
void WriteCloud(
  const plantmorph::ScanPoints& scan, const std::vector<vtkIdType>& cellOf, vtkPolyData* input, vtkPolyData* cloud)
{
  const auto n = static_cast<vtkIdType>(scan.Size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
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
  vtkNew<vtkIdTypeArray> hitCell, beam;
  hitCell->SetName("HitCellId");
  hitCell->SetNumberOfTuples(n);
  beam->SetName("BeamId");
  beam->SetNumberOfTuples(n);
  vtkNew<vtkIdList> from, to;
  from->SetNumberOfIds(n);
  to->SetNumberOfIds(n);
  vtkNew<vtkCellArray> verts;
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(n + 1);
  connectivity->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const auto s = static_cast<std::size_t>(i);
    points->SetPoint(i, &scan.points[3 * s]);
    normals->SetTuple3(i, scan.normals[3 * s], scan.normals[3 * s + 1], scan.normals[3 * s + 2]);
    range->SetValue(i, scan.range[s]);
    intensity->SetValue(i, scan.intensity[s]);
    pose->SetValue(i, static_cast<int>(scan.pose[s]));
    const vtkIdType cell = cellOf[static_cast<std::size_t>(scan.triangle[s])];
    hitCell->SetValue(i, cell);
    beam->SetValue(i, static_cast<vtkIdType>(scan.beam[s]));
    from->SetId(i, cell);
    to->SetId(i, i);
    offsets->SetValue(i, i);
    connectivity->SetValue(i, i);
  }
  offsets->SetValue(n, n);
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
    const char* name = source ? source->GetName() : nullptr;
    if (!name || std::strcmp(name, vtkDataSetAttributes::GhostArrayName()) == 0)
      continue;
    bool own = false;
    for (const char* ours : OwnArrays)
      own = own || std::strcmp(name, ours) == 0;
    if (own)
      continue;
    vtkSmartPointer<vtkAbstractArray> carried = vtk::TakeSmartPointer(source->NewInstance());
    carried->SetName(name);
    carried->SetNumberOfComponents(source->GetNumberOfComponents());
    for (int c = 0; c < source->GetNumberOfComponents(); ++c)
      if (source->GetComponentName(c))
        carried->SetComponentName(c, source->GetComponentName(c));
    carried->SetNumberOfTuples(n);
    if (n > 0)
      carried->InsertTuples(to, from, source);
    pd->AddArray(carried);
  }
}

/// The input's point arrays at the hits, for those not named like ours or like a carried cell array: floating-point
/// arrays interpolated with the hit's barycentric weights (LeafUV, TCoords: exact on the triangle hit), integer
/// arrays (labels) taken from the triangle's vertex nearest the hit.
void InterpolatePointArrays(const plantmorph::ScanPoints& scan, const std::vector<std::int64_t>& triangles,
  vtkPolyData* input, vtkPolyData* cloud)
{
  const auto n = static_cast<vtkIdType>(scan.Size());
  vtkPointData* in = input->GetPointData();
  vtkPointData* pd = cloud->GetPointData();
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* source = in->GetArray(a);
    const char* name = source ? source->GetName() : nullptr;
    if (!name || std::strcmp(name, vtkDataSetAttributes::GhostArrayName()) == 0 || pd->GetAbstractArray(name))
      continue;
    bool own = false;
    for (const char* ours : OwnArrays)
      own = own || std::strcmp(name, ours) == 0;
    if (own)
      continue;
    vtkSmartPointer<vtkDataArray> values = vtk::TakeSmartPointer(source->NewInstance());
    values->SetName(name);
    const int components = source->GetNumberOfComponents();
    values->SetNumberOfComponents(components);
    values->SetNumberOfTuples(n);
    const bool real = source->GetDataType() == VTK_FLOAT || source->GetDataType() == VTK_DOUBLE;
    for (vtkIdType i = 0; i < n; ++i)
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

  std::vector<double> points;
  std::vector<std::int64_t> triangles;
  std::vector<vtkIdType> cellOf;
  error = Triangulate(input, points, triangles, cellOf);
  if (!error.empty())
  {
    return fail(error);
  }
  plantmorph::RayCaster caster;
  error = caster.Build(points, triangles);
  if (!error.empty())
  {
    return fail(error);
  }
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
  });
  if (!error.empty())
  {
    return fail(error);
  }
  WriteCloud(scan, cellOf, input, cloud);
  InterpolatePointArrays(scan, triangles, input, cloud);
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
