// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkAdaptiveLoopFilter.h"
#include "PlantMorphAlgorithmHooks.h"
#include "PlantMorphFieldData.h"
#include "PlantMorphLayer.h"

#include "AdaptiveLoopSubdivision.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolygon.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTriangleStrip.h"
#include "vtkTypeInt32Array.h"

#include <plantmorph/DataContract.h>
#include <plantmorph/RangeError.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkAdaptiveLoopFilter);

namespace
{
/// Under MPI the surface is subdivided once, on rank 0, whole: pieces subdivided apart would treat their seams as
/// boundaries.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank;

/// Reads component c of every tuple of `array` into out[stride * i + offset + c] (fast paths for float and double).
void Gather(vtkDataArray* array, plantmorph::LoopArray<double>& out, int stride, int offset)
{
  const vtkIdType n = array->GetNumberOfTuples();
  const int nc = array->GetNumberOfComponents();
  if (auto* d = vtkDoubleArray::FastDownCast(array))
  {
    const double* src = d->GetPointer(0);
    vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType i = b; i < e; ++i)
        for (int c = 0; c < nc; ++c)
          out[stride * i + offset + c] = src[nc * i + c];
    });
  }
  else if (auto* f = vtkFloatArray::FastDownCast(array))
  {
    const float* src = f->GetPointer(0);
    vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType i = b; i < e; ++i)
        for (int c = 0; c < nc; ++c)
          out[stride * i + offset + c] = static_cast<double>(src[nc * i + c]);
    });
  }
  else
  {
    for (vtkIdType i = 0; i < n; ++i)
      for (int c = 0; c < nc; ++c)
        out[stride * i + offset + c] = array->GetComponent(i, c);
  }
}

/// A new array like `like` (same type, name, components) with `n` tuples from in[stride * i + offset + c]; integer
/// types are rounded and clamped to their range.
vtkSmartPointer<vtkDataArray> Scatter(
  vtkDataArray* like, const plantmorph::LoopArray<double>& in, int stride, int offset, vtkIdType n)
{
  vtkSmartPointer<vtkDataArray> array = vtk::TakeSmartPointer(like->NewInstance());
  const int nc = like->GetNumberOfComponents();
  array->SetName(like->GetName());
  array->SetNumberOfComponents(nc);
  for (int c = 0; c < nc; ++c)
    if (const char* name = like->GetComponentName(c))
      array->SetComponentName(c, name);
  array->SetNumberOfTuples(n);
  if (auto* d = vtkDoubleArray::FastDownCast(array))
  {
    double* dst = d->GetPointer(0);
    vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType i = b; i < e; ++i)
        for (int c = 0; c < nc; ++c)
          dst[nc * i + c] = in[stride * i + offset + c];
    });
  }
  else if (auto* f = vtkFloatArray::FastDownCast(array))
  {
    float* dst = f->GetPointer(0);
    vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType i = b; i < e; ++i)
        for (int c = 0; c < nc; ++c)
          dst[nc * i + c] = static_cast<float>(in[stride * i + offset + c]);
    });
  }
  else
  {
    const bool integral = array->GetDataType() != VTK_FLOAT && array->GetDataType() != VTK_DOUBLE;
    const double lo = array->GetDataTypeMin(), hi = array->GetDataTypeMax();
    for (vtkIdType i = 0; i < n; ++i)
      for (int c = 0; c < nc; ++c)
      {
        double x = in[stride * i + offset + c];
        if (integral)
          x = std::clamp(std::round(x), lo, hi);
        array->SetComponent(i, c, x);
      }
  }
  return array;
}

void AddIdList(vtkFieldData* fd, const char* name, const std::vector<std::size_t>& values)
{
  vtkNew<vtkIdTypeArray> array;
  array->SetName(name);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
    array->SetValue(static_cast<vtkIdType>(i), static_cast<vtkIdType>(values[i]));
  fd->AddArray(array);
}

/// A message: input cell `cellId` (`what`) is not a triangle and TriangulateNonTriangles is off.
std::string NotATriangle(vtkIdType cellId, const std::string& what)
{
  std::ostringstream message;
  message << "input cell " << cellId << " is " << what
          << "; AdaptiveLoopFilter subdivides triangles only: turn TriangulateNonTriangles on or apply Triangulate "
             "first";
  return message.str();
}

/// Appends triangle (a, b, c) of input cell `cellId`.
void AddTriangle(plantmorph::AdaptiveLoopMesh& mesh, std::vector<vtkIdType>& cellOf, vtkIdType cellId, vtkIdType a,
  vtkIdType b, vtkIdType c)
{
  mesh.triangles.insert(mesh.triangles.end(), { static_cast<int>(a), static_cast<int>(b), static_cast<int>(c) });
  cellOf.push_back(cellId);
}

/// Polygons that are all triangles, straight from the connectivity array, in parallel.
void ReadOnlyTriangles(
  vtkCellArray* polys, vtkIdType polyStart, plantmorph::AdaptiveLoopMesh& mesh, std::vector<vtkIdType>& cellOf)
{
  const vtkIdType nPolys = polys->GetNumberOfCells();
  mesh.triangles.resize(3 * static_cast<std::size_t>(nPolys));
  cellOf.resize(static_cast<std::size_t>(nPolys));
  vtkDataArray* connectivity = polys->GetConnectivityArray();
  vtkSMPTools::For(0, nPolys, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i)
    {
      for (int c = 0; c < 3; ++c)
        mesh.triangles[3 * i + c] = static_cast<int>(connectivity->GetComponent(3 * i + c, 0));
      cellOf[i] = polyStart + i;
    }
  });
}

/// Polygons of any size: triangles as they are, larger ones triangulated (or refused), smaller ones skipped.
std::string ReadPolygons(vtkPolyData* input, vtkIdType polyStart, bool triangulate, plantmorph::AdaptiveLoopMesh& mesh,
  std::vector<vtkIdType>& cellOf)
{
  vtkNew<vtkPolygon> polygon;
  vtkNew<vtkIdList> local;
  auto it = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType npts;
    const vtkIdType* pts;
    it->GetCurrentCell(npts, pts);
    const vtkIdType cellId = polyStart + it->GetCurrentCellId();
    if (npts < 3)
      continue; // a polygon of fewer than three points has no area: skipped
    if (npts == 3)
    {
      AddTriangle(mesh, cellOf, cellId, pts[0], pts[1], pts[2]);
      continue;
    }
    if (!triangulate)
      return NotATriangle(cellId, "a polygon with " + std::to_string(npts) + " points");
    polygon->Initialize(static_cast<int>(npts), pts, input->GetPoints());
    local->Reset();
    polygon->Triangulate(local);
    for (vtkIdType k = 0; k + 2 < local->GetNumberOfIds(); k += 3)
      AddTriangle(mesh, cellOf, cellId, pts[local->GetId(k)], pts[local->GetId(k + 1)], pts[local->GetId(k + 2)]);
  }
  return {};
}

/// Triangle strips decomposed into their triangles (or refused), the zero-area turning triangles skipped.
std::string ReadStrips(vtkPolyData* input, vtkIdType stripStart, bool triangulate, plantmorph::AdaptiveLoopMesh& mesh,
  std::vector<vtkIdType>& cellOf)
{
  vtkCellArray* strips = input->GetStrips();
  if (!strips || strips->GetNumberOfCells() == 0)
    return {};
  if (!triangulate)
    return NotATriangle(stripStart, "a triangle strip");
  vtkNew<vtkCellArray> triangles;
  auto it = vtk::TakeSmartPointer(strips->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType npts;
    const vtkIdType* pts;
    it->GetCurrentCell(npts, pts);
    triangles->Reset();
    vtkTriangleStrip::DecomposeStrip(static_cast<int>(npts), pts, triangles);
    vtkIdType tn;
    const vtkIdType* tp;
    for (triangles->InitTraversal(); triangles->GetNextCell(tn, tp);)
    {
      if (tn != 3 || tp[0] == tp[1] || tp[1] == tp[2] || tp[0] == tp[2])
        continue; // strips repeat points to turn: skip those zero-area triangles
      AddTriangle(mesh, cellOf, stripStart + it->GetCurrentCellId(), tp[0], tp[1], tp[2]);
    }
  }
  return {};
}

/// The input's polygons and strips as triangles, each remembering its input cell in `cellOf` (cell ids count verts,
/// lines, polys, strips in that order); "" or why the input cannot be subdivided.
std::string ReadTriangles(
  vtkPolyData* input, bool triangulate, plantmorph::AdaptiveLoopMesh& mesh, std::vector<vtkIdType>& cellOf)
{
  const vtkIdType polyStart = input->GetNumberOfVerts() + input->GetNumberOfLines();
  vtkCellArray* polys = input->GetPolys();
  const vtkIdType nPolys = polys ? polys->GetNumberOfCells() : 0;
  if (nPolys > 0 && polys->IsHomogeneous() == 3)
  {
    ReadOnlyTriangles(polys, polyStart, mesh, cellOf);
  }
  else if (nPolys > 0)
  {
    if (std::string error = ReadPolygons(input, polyStart, triangulate, mesh, cellOf); !error.empty())
      return error;
  }
  return ReadStrips(input, polyStart + nPolys, triangulate, mesh, cellOf);
}

/// The numeric point arrays passed through the subdivision, and Region (kept apart: propagated, not interpolated).
struct PointArrays
{
  vtkDataArray* regionArray = nullptr;
  std::vector<vtkDataArray*> attributeArrays;
  std::vector<int> attributeOffsets;
};

/// Points, Region and every other point array (interleaved into one attribute block) into `mesh`.
PointArrays ReadPoints(vtkPolyData* input, plantmorph::AdaptiveLoopMesh& mesh)
{
  const vtkIdType nPoints = input->GetNumberOfPoints();
  PointArrays read;
  vtkDataArray*& regionArray = read.regionArray;
  std::vector<vtkDataArray*>& attributeArrays = read.attributeArrays;
  std::vector<int>& attributeOffsets = read.attributeOffsets;
  mesh.points.resize(3 * static_cast<std::size_t>(nPoints));
  Gather(input->GetPoints()->GetData(), mesh.points, 3, 0);
  vtkPointData* inPD = input->GetPointData();
  for (int a = 0; a < inPD->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = inPD->GetArray(a);
    if (!array)
      continue; // string and other non-numeric arrays are not passed
    const char* name = array->GetName();
    if (name && std::string(name) == plantmorph::arrays::Region && array->GetNumberOfComponents() == 1 && !regionArray)
    {
      regionArray = array;
      continue;
    }
    attributeArrays.push_back(array);
    attributeOffsets.push_back(mesh.attributeComponents);
    mesh.attributeComponents += array->GetNumberOfComponents();
  }
  mesh.attributes.resize(static_cast<std::size_t>(mesh.attributeComponents) * nPoints);
  for (std::size_t a = 0; a < attributeArrays.size(); ++a)
    Gather(attributeArrays[a], mesh.attributes, mesh.attributeComponents, attributeOffsets[a]);
  if (regionArray)
  {
    mesh.region.resize(static_cast<std::size_t>(nPoints));
    for (vtkIdType i = 0; i < nPoints; ++i)
      mesh.region[i] = static_cast<int>(std::lround(regionArray->GetComponent(i, 0)));
  }
  return read;
}

/// The input's lines as feature edges.
void ReadLineFeatures(vtkPolyData* input, plantmorph::AdaptiveLoopMesh& mesh)
{
  auto it = vtk::TakeSmartPointer(input->GetLines()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType npts;
    const vtkIdType* pts;
    it->GetCurrentCell(npts, pts);
    for (vtkIdType k = 0; k + 1 < npts; ++k)
      if (pts[k] != pts[k + 1])
        mesh.featureEdges.push_back({ static_cast<int>(pts[k]), static_cast<int>(pts[k + 1]) });
  }
}

/// The output's points, in the input's precision: double points adopt the core's array (no copy), float ones are
/// converted.
void WritePoints(vtkPolyData* input, plantmorph::AdaptiveLoopMesh& out, vtkIdType nOutPoints, vtkPolyData* output)
{
  vtkNew<vtkPoints> points;
  vtkDataArray* inData = input->GetPoints()->GetData();
  if (input->GetPoints()->GetDataType() == VTK_DOUBLE)
  {
    points->SetData(plantmorph::AdoptArray<vtkDoubleArray>(out.points, 3, inData->GetName()));
  }
  else
  {
    points->SetDataType(VTK_FLOAT);
    vtkSmartPointer<vtkDataArray> data = Scatter(points->GetData(), out.points, 3, 0, nOutPoints);
    data->SetName(inData->GetName());
    points->SetData(data);
  }
  plantmorph::LoopArray<double>().swap(out.points);
  output->SetPoints(points);
}

/// The output's triangles, 32-bit connectivity.
void WriteTriangles(plantmorph::AdaptiveLoopMesh& out, vtkIdType nOutTriangles, vtkPolyData* output)
{
  vtkNew<vtkTypeInt32Array> offsets;
  offsets->SetNumberOfValues(nOutTriangles + 1);
  vtkTypeInt32* o = offsets->GetPointer(0);
  vtkSMPTools::For(0, nOutTriangles + 1, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i)
      o[i] = static_cast<vtkTypeInt32>(3 * i);
  });
  // The connectivity is the core's triangle array, adopted (no copy).
  vtkSmartPointer<vtkTypeInt32Array> connectivity =
    plantmorph::AdoptArray<vtkTypeInt32Array>(out.triangles, 1, nullptr);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  output->SetPolys(cells);
}

/// Point data: interpolated arrays, active normals renormalised, Region propagated; active attributes kept.
void WritePointData(vtkPolyData* input, const PointArrays& read, plantmorph::AdaptiveLoopMesh& out,
  vtkIdType nOutPoints, vtkPolyData* output)
{
  vtkPointData* inPD = input->GetPointData();
  vtkPointData* outPD = output->GetPointData();
  vtkDataArray* inNormals = inPD->GetNormals();
  for (std::size_t a = 0; a < read.attributeArrays.size(); ++a)
  {
    vtkDataArray* in = read.attributeArrays[a];
    if (in == inNormals && inNormals->GetNumberOfComponents() == 3)
      plantmorph::NormalizeAttributeVectors(out, read.attributeOffsets[a], plantmorph::SMPFor());
    if (read.attributeArrays.size() == 1 && vtkDoubleArray::FastDownCast(in))
    {
      // The one double array is the attribute block itself: adopted (no copy), named like the input's.
      vtkSmartPointer<vtkDoubleArray> array =
        plantmorph::AdoptArray<vtkDoubleArray>(out.attributes, out.attributeComponents, in->GetName());
      for (int c = 0; c < in->GetNumberOfComponents(); ++c)
        if (const char* name = in->GetComponentName(c))
          array->SetComponentName(c, name);
      outPD->AddArray(array);
      continue;
    }
    outPD->AddArray(Scatter(in, out.attributes, out.attributeComponents, read.attributeOffsets[a], nOutPoints));
  }
  plantmorph::LoopArray<double>().swap(out.attributes);
  if (read.regionArray)
  {
    vtkSmartPointer<vtkDataArray> region = vtk::TakeSmartPointer(read.regionArray->NewInstance());
    region->SetName(read.regionArray->GetName());
    region->SetNumberOfComponents(1);
    region->SetNumberOfTuples(nOutPoints);
    for (vtkIdType i = 0; i < nOutPoints; ++i)
      region->SetComponent(i, 0, out.region[i]);
    outPD->AddArray(region);
  }
  for (int attribute = 0; attribute < vtkDataSetAttributes::NUM_ATTRIBUTES; ++attribute)
    if (vtkDataArray* active = inPD->GetAttribute(attribute))
      if (active->GetName())
        outPD->SetActiveAttribute(active->GetName(), attribute);
}

/// Cell data: each triangle takes its input cell's tuple.
void WriteCellData(vtkPolyData* input, const std::vector<vtkIdType>& cellOf, const plantmorph::AdaptiveLoopMesh& out,
  vtkIdType nOutTriangles, vtkPolyData* output)
{
  vtkCellData* inCD = input->GetCellData();
  if (inCD->GetNumberOfArrays() > 0)
  {
    vtkNew<vtkIdList> sourceIds;
    sourceIds->SetNumberOfIds(nOutTriangles);
    for (vtkIdType i = 0; i < nOutTriangles; ++i)
      sourceIds->SetId(i, cellOf[out.origin[i]]);
    vtkCellData* outCD = output->GetCellData();
    for (int a = 0; a < inCD->GetNumberOfArrays(); ++a)
    {
      vtkAbstractArray* in = inCD->GetAbstractArray(a);
      vtkSmartPointer<vtkAbstractArray> array = vtk::TakeSmartPointer(in->NewInstance());
      array->SetName(in->GetName());
      array->SetNumberOfComponents(in->GetNumberOfComponents());
      array->SetNumberOfTuples(nOutTriangles);
      in->GetTuples(sourceIds, array);
      outCD->AddArray(array);
    }
    for (int attribute = 0; attribute < vtkDataSetAttributes::NUM_ATTRIBUTES; ++attribute)
      if (vtkAbstractArray* active = inCD->GetAbstractAttribute(attribute))
        if (active->GetName())
          outCD->SetActiveAttribute(active->GetName(), attribute);
  }
}
} // namespace

//------------------------------------------------------------------------------
vtkAdaptiveLoopFilter::vtkAdaptiveLoopFilter() = default;

//------------------------------------------------------------------------------
void vtkAdaptiveLoopFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumLevel: " << this->MaximumLevel << "\n";
  os << indent << "EdgeAngleThreshold: " << this->EdgeAngleThreshold << "\n";
  os << indent << "FlatnessThreshold: " << this->FlatnessThreshold << "\n";
  os << indent << "FeatureRule: " << this->FeatureRule << "\n";
  os << indent << "RefinementRule: " << this->RefinementRule << "\n";
  os << indent << "ErrorTolerance: " << this->ErrorTolerance << "\n";
  os << indent << "MidveinFeatures: " << this->MidveinFeatures << "\n";
  os << indent << "LineFeatures: " << this->LineFeatures << "\n";
  os << indent << "TriangulateNonTriangles: " << this->TriangulateNonTriangles << "\n";
  os << indent << "MaximumTriangles: " << this->MaximumTriangles << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}

//------------------------------------------------------------------------------
int vtkAdaptiveLoopFilter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the subdivided surface", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkAdaptiveLoopFilter::Execute(plantmorph::Run& run)
{
  vtkPolyData* input = run.Input<vtkPolyData>(0);
  vtkPolyData* output = run.Output<vtkPolyData>(0);
  if (!input)
  {
    return;
  }
  if (this->NumberOfThreads < 0 || this->NumberOfThreads > 256)
  {
    run.Fail(plantmorph::OutOfRange("NumberOfThreads", this->NumberOfThreads, "[0, 256]", "0: all cores"));
  }
  if (input->GetNumberOfPoints() == 0)
  {
    run.Warn("the Input is empty (no points): nothing to subdivide, the output is empty");
    return;
  }
  // Small outputs run serially: starting threads costs more than the work (about 1 ms against 0.4 ms for 1e4
  // output triangles on the benchmark machine).
  const double estimate = static_cast<double>(input->GetNumberOfPolys() + input->GetNumberOfStrips()) *
    std::pow(4.0, std::clamp(this->MaximumLevel, 0, 10));
  std::string error;
  bool aborted = false;
  run.Threaded(estimate < 2e5 ? 1 : this->NumberOfThreads, [&]() { error = this->Subdivide(input, output, aborted); });
  run.Check(error);
  if (aborted)
  {
    run.Stop();
  }
}

//------------------------------------------------------------------------------
std::string vtkAdaptiveLoopFilter::MakeSettings(plantmorph::AdaptiveLoopParameters& settings)
{
  settings.maximumLevel = this->MaximumLevel;
  settings.edgeAngleThreshold = this->EdgeAngleThreshold;
  settings.flatnessThreshold = this->FlatnessThreshold;
  settings.featureRule = static_cast<plantmorph::FeatureRule>(this->FeatureRule);
  settings.refinementRule = static_cast<plantmorph::RefinementRule>(this->RefinementRule);
  settings.errorTolerance = this->ErrorTolerance;
  settings.midveinIsFeature = this->MidveinFeatures != 0;
  if (this->MaximumTriangles < 1 ||
    static_cast<std::size_t>(this->MaximumTriangles) > plantmorph::MaxAdaptiveLoopTriangles)
  {
    return plantmorph::OutOfRange(
      "MaximumTriangles", this->MaximumTriangles, "[1, " + std::to_string(plantmorph::MaxAdaptiveLoopTriangles) + "]");
  }
  settings.maximumTriangles = static_cast<std::size_t>(this->MaximumTriangles);
  return plantmorph::ValidateAdaptiveLoopParameters(settings);
}

namespace
{
/// The input as the core's mesh: triangles (each remembering its input cell in `cellOf`), points and their arrays
/// (`read`), and the lines as feature edges when `lineFeatures`; "" or why it cannot be subdivided.
std::string ReadMesh(vtkPolyData* input, bool triangulate, bool lineFeatures, plantmorph::AdaptiveLoopMesh& mesh,
  std::vector<vtkIdType>& cellOf, PointArrays& read)
{
  const vtkIdType nPoints = input->GetNumberOfPoints();
  if (std::string error = ReadTriangles(input, triangulate, mesh, cellOf); !error.empty())
    return error;
  std::ostringstream message;
  if (mesh.triangles.empty())
    message << "the input has " << nPoints
            << " points but no polygons or triangle strips: AdaptiveLoopFilter needs a triangle surface";
  else if (nPoints >= std::numeric_limits<int>::max() / 2)
    message << "the input has " << nPoints << " points; at most " << std::numeric_limits<int>::max() / 2
            << " are supported";
  if (message.tellp() > 0)
    return message.str();
  read = ReadPoints(input, mesh);
  if (lineFeatures && input->GetNumberOfLines() > 0)
    ReadLineFeatures(input, mesh);
  return {};
}

/// The subdivided mesh into `output` with the input's arrays carried over, and the counts per level.
void WriteMesh(vtkAlgorithm* self, vtkPolyData* input, const PointArrays& read, const std::vector<vtkIdType>& cellOf,
  plantmorph::AdaptiveLoopResult& result, vtkPolyData* output)
{
  // Each writer frees the mesh's part it has written.
  plantmorph::AdaptiveLoopMesh& out = result.mesh;
  const vtkIdType nOutPoints = static_cast<vtkIdType>(out.NumberOfPoints());
  const vtkIdType nOutTriangles = static_cast<vtkIdType>(out.NumberOfTriangles());
  WritePoints(input, out, nOutPoints, output);
  WriteTriangles(out, nOutTriangles, output);
  WritePointData(input, read, out, nOutPoints, output);
  self->UpdateProgress(0.95);
  WriteCellData(input, cellOf, out, nOutTriangles, output);
  // Field data: the input's, and the counts per level.
  output->GetFieldData()->PassData(input->GetFieldData());
  AddIdList(output->GetFieldData(), "AdaptiveLoop.TrianglesPerLevel", result.trianglesPerLevel);
  AddIdList(output->GetFieldData(), "AdaptiveLoop.PointsPerLevel", result.pointsPerLevel);
}
} // namespace

//------------------------------------------------------------------------------
std::string vtkAdaptiveLoopFilter::Subdivide(vtkPolyData* input, vtkPolyData* output, bool& aborted)
{
  plantmorph::AdaptiveLoopParameters settings;
  plantmorph::AdaptiveLoopMesh mesh;
  std::vector<vtkIdType> cellOf;
  PointArrays read;
  std::string error = this->MakeSettings(settings);
  if (error.empty())
    error = ReadMesh(input, this->TriangulateNonTriangles, this->LineFeatures, mesh, cellOf, read);
  if (!error.empty())
    return error;
  this->UpdateProgress(0.05);
  settings.parallelFor = plantmorph::SMPFor();
  settings.progress = plantmorph::Progress(this, 0.05, 0.85);
  plantmorph::AdaptiveLoopResult result = plantmorph::AdaptiveLoopSubdivide(std::move(mesh), settings);
  aborted = result.aborted;
  if (!result.error.empty() || result.aborted)
    return result.error;
  WriteMesh(this, input, read, cellOf, result, output);
  this->UpdateProgress(1.0);
  return {};
}
