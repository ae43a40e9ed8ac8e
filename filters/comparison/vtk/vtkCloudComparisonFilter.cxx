// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkCloudComparisonFilter.h"
#include "PlantMorphAlgorithmHooks.h"

#include "PlantMorphFieldData.h"
#include "PlantMorphLayer.h"
#include "PlantMorphWholeInput.h"
#include "CloudComparisonExchange.h"
#include "CloudStatistics.h"
#include "PointSurfaceDistance.h"
#include "RigidRegistration.h"

#include <plantmorph/RangeError.h>

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellType.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolygon.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using plantmorph::AddFieldValue;

vtkStandardNewMacro(vtkCloudComparisonFilter);

namespace
{
/// Triangles as point-id triples. Unset when grown and on transparent huge pages from 4 MiB (UnsetVector): 203,520
/// triangles are 4.9 MB, written on the calling thread, which with fresh 4 KiB pages took 1.2 k page faults there on
/// the first update.
using TriangleIds = plantmorph::UnsetVector<std::int64_t>;

/// Blocks of values the wrapper's own loops over the measured points split into (fixed, so results do not depend on
/// the threads).
constexpr std::size_t ScanBlock = std::size_t(1) << 16;

/// The index of the first non-finite value among `count`, or `count` when all are finite (blocks on the threads).
std::size_t FirstNonFinite(const double* values, std::size_t count)
{
  const std::size_t blocks = (count + ScanBlock - 1) / ScanBlock;
  std::vector<std::size_t> first(blocks, count);
  plantmorph::ForEachIndex(
    plantmorph::SMPFor(1), blocks,
    [&](std::size_t b) {
      const std::size_t end = std::min(count, (b + 1) * ScanBlock);
      for (std::size_t i = b * ScanBlock; i < end; ++i)
      {
        if (!std::isfinite(values[i]))
        {
          first[b] = i;
          return;
        }
      }
    },
    1);
  return first.empty() ? count : *std::min_element(first.begin(), first.end());
}

/// Per axis the minimum and minus the maximum of `count` points (flat xyz; blocks on the threads), so that one
/// minimum over MPI ranks gives both.
std::vector<double> NegatedBounds(const double* xyz, std::size_t count)
{
  const double inf = std::numeric_limits<double>::infinity();
  const std::size_t blocks = (count + ScanBlock - 1) / ScanBlock;
  std::vector<double> part(6 * blocks, inf);
  plantmorph::ForEachIndex(
    plantmorph::SMPFor(1), blocks,
    [&](std::size_t b) {
      double local[6] = { inf, inf, inf, inf, inf, inf };
      for (std::size_t i = b * ScanBlock; i < std::min(count, (b + 1) * ScanBlock); ++i)
        for (int a = 0; a < 3; ++a)
        {
          local[a] = std::min(local[a], xyz[3 * i + a]);
          local[3 + a] = std::min(local[3 + a], -xyz[3 * i + a]);
        }
      std::copy(local, local + 6, part.begin() + static_cast<std::ptrdiff_t>(6 * b));
    },
    1);
  std::vector<double> bounds(6, inf);
  for (std::size_t b = 0; b < blocks; ++b)
    for (int k = 0; k < 6; ++k)
      bounds[k] = std::min(bounds[k], part[6 * b + k]);
  return bounds;
}

/// The points of a point set as flat doubles (read in parallel; GetPoint into a local buffer is thread-safe).
std::vector<double> FlatPoints(vtkPointSet* data)
{
  const vtkIdType n = data->GetNumberOfPoints();
  std::vector<double> xyz(3 * static_cast<std::size_t>(n));
  vtkPoints* points = data->GetPoints();
  if (n == 0 || !points)
  {
    return xyz;
  }
  vtkSMPTools::For(0, n, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
    {
      points->GetPoint(i, xyz.data() + 3 * i);
    }
  });
  return xyz;
}

/// Appends the triangles of one polygon (n >= 3 point ids): fan for triangles and quads, ear cutting above.
void AppendPolygon(vtkIdType n, const vtkIdType* ids, vtkPoints* points, vtkPolygon* polygon, vtkIdList* triangleIds,
  vtkPoints* scratch, TriangleIds& triangles)
{
  if (n < 3)
  {
    return;
  }
  if (n <= 4)
  {
    for (vtkIdType k = 1; k + 1 < n; ++k)
    {
      triangles.insert(triangles.end(), { ids[0], ids[k], ids[k + 1] });
    }
    return;
  }
  polygon->PointIds->SetNumberOfIds(n);
  polygon->Points->SetNumberOfPoints(n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    polygon->PointIds->SetId(k, ids[k]);
    polygon->Points->SetPoint(k, points->GetPoint(ids[k]));
  }
  triangleIds->Reset();
  if (polygon->Triangulate(0, triangleIds, scratch) && triangleIds->GetNumberOfIds() >= 3)
  {
    for (vtkIdType k = 0; k + 2 < triangleIds->GetNumberOfIds(); k += 3)
    {
      triangles.insert(
        triangles.end(), { triangleIds->GetId(k), triangleIds->GetId(k + 1), triangleIds->GetId(k + 2) });
    }
    return;
  }
  for (vtkIdType k = 1; k + 1 < n; ++k) // degenerate polygon: a fan still covers it
  {
    triangles.insert(triangles.end(), { ids[0], ids[k], ids[k + 1] });
  }
}

void AppendStrip(vtkIdType n, const vtkIdType* ids, TriangleIds& triangles)
{
  for (vtkIdType k = 0; k + 2 < n; ++k)
  {
    if (k % 2 == 0)
    {
      triangles.insert(triangles.end(), { ids[k], ids[k + 1], ids[k + 2] });
    }
    else
    {
      triangles.insert(triangles.end(), { ids[k + 1], ids[k], ids[k + 2] });
    }
  }
}

/// The polygons and strips of polygonal data as triangles.
TriangleIds PolyDataTriangles(vtkPolyData* poly)
{
  TriangleIds triangles;
  vtkNew<vtkPolygon> polygon;
  vtkNew<vtkIdList> triangleIds;
  vtkNew<vtkPoints> scratch;
  if (poly->GetPolys())
  {
    triangles.reserve(3 * static_cast<std::size_t>(poly->GetNumberOfPolys()));
    auto it = vtk::TakeSmartPointer(poly->GetPolys()->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      it->GetCurrentCell(n, ids);
      AppendPolygon(n, ids, poly->GetPoints(), polygon, triangleIds, scratch, triangles);
    }
  }
  if (poly->GetStrips())
  {
    auto it = vtk::TakeSmartPointer(poly->GetStrips()->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      it->GetCurrentCell(n, ids);
      AppendStrip(n, ids, triangles);
    }
  }
  return triangles;
}

/// The 2-D cells of a point set as triangles (empty: treat it as a point cloud).
TriangleIds Triangles(vtkPointSet* data)
{
  TriangleIds triangles;
  vtkNew<vtkPolygon> polygon;
  vtkNew<vtkIdList> triangleIds;
  vtkNew<vtkPoints> scratch;
  vtkPoints* points = data->GetPoints();
  if (auto* poly = vtkPolyData::SafeDownCast(data))
  {
    return PolyDataTriangles(poly);
  }
  vtkNew<vtkIdList> cellIds;
  for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c)
  {
    const int type = data->GetCellType(c);
    if (type != VTK_TRIANGLE && type != VTK_QUAD && type != VTK_POLYGON && type != VTK_TRIANGLE_STRIP &&
      type != VTK_PIXEL)
    {
      continue;
    }
    data->GetCellPoints(c, cellIds);
    const vtkIdType n = cellIds->GetNumberOfIds();
    const vtkIdType* ids = cellIds->GetPointer(0);
    if (type == VTK_TRIANGLE_STRIP)
    {
      AppendStrip(n, ids, triangles);
    }
    else if (type == VTK_PIXEL && n == 4)
    {
      const vtkIdType quad[4] = { ids[0], ids[1], ids[3], ids[2] };
      AppendPolygon(4, quad, points, polygon, triangleIds, scratch, triangles);
    }
    else
    {
      AppendPolygon(n, ids, points, polygon, triangleIds, scratch, triangles);
    }
  }
  return triangles;
}

void AddColumn(vtkTable* table, vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> column;
  column->SetName(name);
  column->SetNumberOfTuples(1);
  column->SetValue(0, value);
  table->AddColumn(column);
  if (fd)
  {
    AddFieldValue(fd, name, value);
  }
}

/// vtkSMPTools over blocks of at least 2048 points (a query is cheap: smaller blocks cost more than they balance).
plantmorph::ParallelFor BlockSMPFor()
{
  return plantmorph::SMPFor(2048);
}

/// Builds the distance structure over a point set (its pointCount points as flat doubles in xyz): a surface if it
/// has 2-D cells, else its points.
std::string BuildStructure(
  vtkPointSet* data, const double* xyz, std::size_t pointCount, plantmorph::PointSurfaceDistance& out)
{
  const TriangleIds triangles = Triangles(data);
  if (!triangles.empty())
  {
    return out.BuildSurface(xyz, pointCount, triangles.data(), triangles.size() / 3, BlockSMPFor());
  }
  return out.BuildCloud(xyz, pointCount, BlockSMPFor());
}
} // namespace

//------------------------------------------------------------------------------
vtkCloudComparisonFilter::vtkCloudComparisonFilter()
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(3);
}

//------------------------------------------------------------------------------
void vtkCloudComparisonFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scale: " << this->Scale << "\n";
  os << indent << "Registration: " << this->Registration << "\n";
  os << indent << "RegistrationIterations: " << this->RegistrationIterations << "\n";
  os << indent << "RegistrationTolerance: " << this->RegistrationTolerance << "\n";
  os << indent << "RegistrationLandmarks: " << this->RegistrationLandmarks << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "UseMaximumDistance: " << this->UseMaximumDistance << "\n";
  os << indent << "MaximumDistance: " << this->MaximumDistance << "\n";
  os << indent << "Symmetric: " << this->Symmetric << "\n";
  os << indent << "HistogramBins: " << this->HistogramBins << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}

//------------------------------------------------------------------------------
int vtkCloudComparisonFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  (void)port;
  return 1;
}

//------------------------------------------------------------------------------
int vtkCloudComparisonFilter::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkPolyData" : "vtkTable");
  return 1;
}

namespace
{
/// Step 1 of Execute: the properties that must hold before anything is computed, and the registration settings
/// they give. The message naming the first bad property, or "".
std::string CheckProperties(vtkCloudComparisonFilter* self, plantmorph::RegistrationParameters& registration)
{
  using namespace plantmorph;
  std::ostringstream m;
  const double scale = self->GetScale(), maximumDistance = self->GetMaximumDistance();
  const int mode = self->GetRegistration(), landmarks = self->GetRegistrationLandmarks();
  if (!std::isfinite(scale) || scale <= 0.0)
  {
    m << OutOfRange("Scale", scale, "(0, inf)", "e.g. 0.1 for a scan in mm against a model in cm");
    return m.str();
  }
  if (self->GetUseMaximumDistance() && (!std::isfinite(maximumDistance) || maximumDistance < 0.0))
  {
    m << OutOfRange("MaximumDistance", maximumDistance, "[0, inf)");
    return m.str();
  }
  if (self->GetHistogramBins() < 1 || self->GetHistogramBins() > 100000)
  {
    m << OutOfRange("HistogramBins", self->GetHistogramBins(), "[1, 100000]");
    return m.str();
  }
  if (mode < vtkCloudComparisonFilter::REGISTRATION_NONE || mode > vtkCloudComparisonFilter::REGISTRATION_RIGID_SCALE)
  {
    m << OutOfRange("Registration", mode, "{0, 1, 2}", "0 none, 1 rigid, 2 rigid + uniform scale");
    return m.str();
  }
  registration.withScale = mode == vtkCloudComparisonFilter::REGISTRATION_RIGID_SCALE;
  registration.maximumIterations = self->GetRegistrationIterations();
  registration.tolerance = self->GetRegistrationTolerance();
  registration.maximumLandmarks = landmarks < 3 || landmarks > 100000000 ? 0 : landmarks;
  registration.rejectDistance = self->GetUseMaximumDistance() ? maximumDistance : -1.0;
  // Seed is ignored: the filter's registration is always the symmetric one, which subsamples by stride.
  if (mode != vtkCloudComparisonFilter::REGISTRATION_NONE)
  {
    if (registration.maximumLandmarks == 0)
    {
      m << OutOfRange("RegistrationLandmarks", landmarks, "[3, 100000000]");
      return m.str();
    }
    return ValidateRegistrationParameters(registration);
  }
  return {};
}

/// Step 2: the measured points, scaled, as flat doubles in `xyz`; every coordinate must be finite. When nothing
/// moves them (Scale 1, no registration) and the input holds them as contiguous doubles, its own array is read in
/// place; else a copy (24 bytes a point, a sixth of the filter's peak memory on 10^6 points) is made in `moved`
/// and scaled. `transform` gets the scale.
std::string ReadMeasured(vtkPointSet* measured, double scale, bool registering, std::vector<double>& moved,
  const double*& xyz, double transform[16])
{
  const vtkIdType count = measured->GetNumberOfPoints();
  auto* inputDoubles = measured->GetPoints()
    ? vtkArrayDownCast<vtkAOSDataArrayTemplate<double>>(measured->GetPoints()->GetData())
    : nullptr; // an MPI rank's empty piece
  if (inputDoubles && inputDoubles->GetNumberOfComponents() == 3 && scale == 1.0 && !registering)
  {
    xyz = inputDoubles->GetPointer(0);
  }
  else
  {
    moved = FlatPoints(measured);
    xyz = moved.data();
  }
  const std::size_t bad = FirstNonFinite(xyz, 3 * static_cast<std::size_t>(count));
  if (bad < 3 * static_cast<std::size_t>(count))
  {
    std::ostringstream m;
    m << "the Measured input's point " << bad / 3 << " has a non-finite coordinate (NaN or infinite)";
    return m.str();
  }
  const double scaling[16] = { scale, 0, 0, 0, 0, scale, 0, 0, 0, 0, scale, 0, 0, 0, 0, 1 };
  std::copy(scaling, scaling + 16, transform);
  if (scale != 1.0)
  {
    plantmorph::ApplyTransform(transform, moved.data(), moved.data(), static_cast<std::size_t>(count));
  }
  return {};
}

/// Step 3: symmetric, guarded registration of the measured points (`moved`, in place) onto the reference; the
/// registration's matrix is composed into `transform`. The error message or "".
/// The registration is fitted to `landmarks` (`landmarkCount` points: the measured points themselves when serial,
/// under MPI every rank's strided landmarks gathered, which RegisterPoints takes whole as it would have taken them
/// from all the points), then applied to this rank's `moved`.
std::string RegisterMeasured(plantmorph::RegistrationParameters registration, const std::vector<double>& referenceXYZ,
  const plantmorph::PointSurfaceDistance& referenceDistance, const plantmorph::ParallelFor& parallelFor,
  const double* landmarks, std::size_t landmarkCount, std::vector<double>& moved, double transform[16],
  plantmorph::RegistrationResult& registered)
{
  using namespace plantmorph;
  const std::size_t count = moved.size() / 3;
  // Symmetric and guarded: the reference's points take part (no collapse, in-plane sliding seen by the outline),
  // and a registration that fits worse than none is not used.
  registration.referencePoints = referenceXYZ.data();
  registration.referenceCount = referenceXYZ.size() / 3;
  registered = RegisterPoints(landmarks, landmarkCount, referenceDistance, registration, parallelFor);
  if (!registered.error.empty())
  {
    return registered.error;
  }
  ApplyTransform(registered.matrix, moved.data(), moved.data(), count);
  double total[16];
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      total[4 * r + c] = 0.0;
      for (int k = 0; k < 4; ++k)
      {
        total[4 * r + c] += registered.matrix[4 * r + k] * transform[4 * k + c];
      }
    }
  }
  std::copy(total, total + 16, transform);
  return {};
}

/// The Outlier point array (1 where the distance exceeds `maximumDistance`); none when it is negative (no cut-off).
void SetOutlier(vtkPointData* pd, vtkDoubleArray* distance, double maximumDistance)
{
  if (maximumDistance < 0.0)
  {
    pd->RemoveArray("Outlier");
    return;
  }
  const vtkIdType count = distance->GetNumberOfTuples();
  vtkNew<vtkUnsignedCharArray> outlier;
  outlier->SetName("Outlier");
  outlier->SetNumberOfTuples(count);
  for (vtkIdType i = 0; i < count; ++i)
  {
    outlier->SetValue(i, distance->GetValue(i) > maximumDistance ? 1 : 0);
  }
  pd->AddArray(outlier);
}

/// Step 5, output 0: the measured points (moved when scaled or registered: `moved`), one vertex each when the
/// input has no cells, with the distance arrays (`signedDistance` when the reference is a surface) and, with a
/// maximum distance, Outlier.
void FillPoints(vtkPointSet* measured, const std::vector<double>& moved, bool movedPoints, vtkDoubleArray* distance,
  vtkDoubleArray* signedDistance, vtkDoubleArray* closest, double maximumDistance, bool useMaximumDistance,
  vtkPolyData* output)
{
  const vtkIdType count = measured->GetNumberOfPoints();
  if (auto* poly = vtkPolyData::SafeDownCast(measured))
  {
    output->ShallowCopy(poly);
  }
  else
  {
    output->SetPoints(measured->GetPoints());
    output->GetPointData()->ShallowCopy(measured->GetPointData());
    output->GetFieldData()->ShallowCopy(measured->GetFieldData());
  }
  if (output->GetNumberOfCells() == 0)
  {
    output->SetVerts(plantmorph::VertexCells(count)); // a measured cloud without cells
  }
  if (movedPoints)
  {
    vtkNew<vtkDoubleArray> coordinates;
    coordinates->SetNumberOfComponents(3);
    coordinates->SetNumberOfTuples(count);
    std::copy(moved.begin(), moved.end(), coordinates->GetPointer(0));
    vtkNew<vtkPoints> points;
    points->SetData(coordinates);
    output->SetPoints(points);
  }
  vtkPointData* pd = output->GetPointData();
  pd->AddArray(distance);
  pd->SetActiveScalars("Distance");
  if (signedDistance)
  {
    pd->AddArray(signedDistance);
  }
  else
  {
    pd->RemoveArray("SignedDistance"); // a stale one from an earlier comparison would mislead
  }
  pd->AddArray(closest);
  SetOutlier(pd, distance, useMaximumDistance ? maximumDistance : -1.0);
}

/// Field data of output 0: the total transform and, when registering, the registration's numbers.
void FillTransform(const double transform[16], const plantmorph::RegistrationResult* registered, vtkFieldData* fd)
{
  vtkNew<vtkDoubleArray> matrix;
  matrix->SetName("PlantMorph.MeasuredTransform");
  matrix->SetNumberOfComponents(16);
  matrix->SetNumberOfTuples(1);
  matrix->SetTypedTuple(0, transform);
  fd->AddArray(matrix);
  if (registered)
  {
    AddFieldValue(fd, "PlantMorph.RegistrationScale", registered->scale);
    AddFieldValue(fd, "PlantMorph.RegistrationIterations", registered->iterations);
    AddFieldValue(fd, "PlantMorph.RegistrationConverged", registered->converged ? 1.0 : 0.0);
    AddFieldValue(fd, "PlantMorph.RegistrationRMS", registered->rms);
    AddFieldValue(fd, "PlantMorph.RegistrationSymmetricBefore", registered->symmetricBefore);
    AddFieldValue(fd, "PlantMorph.RegistrationSymmetricAfter", registered->symmetricAfter);
    AddFieldValue(fd, "PlantMorph.RegistrationRejected", registered->worse ? 1.0 : 0.0);
  }
}

/// Output 2 (and field data): statistics of the distances, and of the reverse ones when `reverse` is given.
void FillStatistics(const plantmorph::DistanceStatistics& s, double cutOff, bool surface,
  const std::vector<double>* reverse, vtkTable* statistics, vtkFieldData* fd)
{
  using namespace plantmorph;
  AddColumn(statistics, fd, "Count", static_cast<double>(s.count));
  AddColumn(statistics, fd, "Outliers", static_cast<double>(s.outliers));
  AddColumn(statistics, fd, "Minimum", s.minimum);
  AddColumn(statistics, fd, "Maximum", s.maximum);
  AddColumn(statistics, fd, "Mean", s.mean);
  AddColumn(statistics, fd, "StandardDeviation", s.standardDeviation);
  AddColumn(statistics, fd, "RMS", s.rms);
  AddColumn(statistics, fd, "Percentile50", s.p50);
  AddColumn(statistics, fd, "Percentile68", s.p68);
  AddColumn(statistics, fd, "Percentile75", s.p75);
  AddColumn(statistics, fd, "Percentile95", s.p95);
  AddColumn(statistics, fd, "Percentile99", s.p99);
  AddColumn(statistics, fd, "Hausdorff", s.maximum);
  AddColumn(statistics, fd, "ReferenceIsSurface", surface ? 1.0 : 0.0);
  if (reverse)
  {
    const DistanceStatistics r = ComputeDistanceStatistics(reverse->data(), reverse->size(), cutOff);
    AddColumn(statistics, fd, "ReverseCount", static_cast<double>(r.count));
    AddColumn(statistics, fd, "ReverseMean", r.mean);
    AddColumn(statistics, fd, "ReverseHausdorff", r.maximum);
    AddColumn(statistics, fd, "SymmetricHausdorff", std::max(s.maximum, r.maximum));
    AddColumn(statistics, fd, "Chamfer", 0.5 * (s.mean + r.mean));
  }
}

/// Output 1: the histogram of the distances (`counted`: the statistics' count, for the fractions).
void FillHistogram(const plantmorph::DistanceHistogram& h, std::size_t counted, vtkTable* histogram)
{
  const vtkIdType n = static_cast<vtkIdType>(h.count.size());
  vtkNew<vtkDoubleArray> centers;
  centers->SetName("bin_extents");
  vtkNew<vtkIdTypeArray> values;
  values->SetName("bin_values");
  vtkNew<vtkDoubleArray> starts;
  starts->SetName("BinStart");
  vtkNew<vtkDoubleArray> ends;
  ends->SetName("BinEnd");
  vtkNew<vtkDoubleArray> fraction;
  fraction->SetName("Fraction");
  for (vtkDataArray* a : { static_cast<vtkDataArray*>(centers), static_cast<vtkDataArray*>(values),
         static_cast<vtkDataArray*>(starts), static_cast<vtkDataArray*>(ends), static_cast<vtkDataArray*>(fraction) })
  {
    a->SetNumberOfTuples(n);
  }
  for (vtkIdType b = 0; b < n; ++b)
  {
    centers->SetValue(b, h.binCenter[b]);
    values->SetValue(b, static_cast<vtkIdType>(h.count[b]));
    starts->SetValue(b, h.binStart[b]);
    ends->SetValue(b, h.binEnd[b]);
    fraction->SetValue(b, counted ? static_cast<double>(h.count[b]) / static_cast<double>(counted) : 0.0);
  }
  histogram->AddColumn(centers);
  histogram->AddColumn(values);
  histogram->AddColumn(starts);
  histogram->AddColumn(ends);
  histogram->AddColumn(fraction);
}

/// The reverse direction: every reference point's distance to the measured data, as a surface if it has 2-D
/// cells, else its points. Under MPI each rank measures to its own piece (as a surface when any rank's piece has
/// 2-D cells, as serially the whole would be) and the minimum over the ranks is taken. The error message or "".
std::string ReverseDistances(vtkMultiProcessController* controller, vtkPointSet* measured, const double* xyz,
  std::size_t count, const std::vector<double>& referenceXYZ, const plantmorph::ParallelFor& parallelFor,
  std::vector<double>& reverse)
{
  using namespace plantmorph;
  const TriangleIds triangles = count ? Triangles(measured) : TriangleIds();
  const bool surface = plantmorph::AnyRank(controller, !triangles.empty());
  reverse.assign(referenceXYZ.size() / 3, std::numeric_limits<double>::infinity());
  std::string error;
  if (count > 0 && (!surface || !triangles.empty()))
  {
    PointSurfaceDistance measuredDistance;
    error = surface ? measuredDistance.BuildSurface(xyz, count, triangles.data(), triangles.size() / 3, BlockSMPFor())
                    : measuredDistance.BuildCloud(xyz, count, BlockSMPFor());
    if (error.empty())
    {
      measuredDistance.QueryMany(
        referenceXYZ.data(), reverse.size(), reverse.data(), nullptr, nullptr, nullptr, parallelFor);
    }
  }
  if (plantmorph::AnyRank(controller, !error.empty()))
  {
    return error.empty() ? std::string("(failed on another MPI rank)") : error;
  }
  cloudmpi::MinimumOverRanks(controller, reverse);
  return {};
}
} // namespace

//------------------------------------------------------------------------------
namespace
{
/// Under MPI the measured points stay on their ranks, each rank comparing its own; the reference (small) is
/// replicated on every rank (CloudComparisonExchange.h).
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::DataParallel;

/// Collective: stops every rank together when `error` is not empty on some rank; the rank that found it says why.
void StopTogether(const plantmorph::Run& run, vtkMultiProcessController* controller, const std::string& error,
  const std::string& prefix)
{
  if (!plantmorph::AnyRank(controller, !error.empty()))
  {
    return;
  }
  if (!error.empty())
  {
    run.FailHere(prefix + error);
  }
  run.Stop();
}

/// Collective: stops every rank together when the user pressed Abort on any.
void StopIfAnyAborted(vtkAlgorithm* self, const plantmorph::Run& run, vtkMultiProcessController* controller)
{
  if (plantmorph::AnyRank(controller, self->GetAbortExecute() != 0))
  {
    run.Stop();
  }
}

/// The measured points as compared: read and scaled (ReadMeasured), then registered (RegisterMeasured).
struct MeasuredPoints
{
  bool registering = false;
  std::vector<double> moved;
  const double* xyz = nullptr;
  double transform[16];
  plantmorph::RegistrationResult registered;
};

/// The reference: its points as flat doubles and its distance structure.
struct Reference
{
  std::vector<double> xyz;
  plantmorph::PointSurfaceDistance distance;
};

/// Step 3: the registration, fitted to the whole cloud's landmarks (the same on every rank), applied to this rank's
/// points.
void Register(const plantmorph::Run& run, vtkMultiProcessController* controller,
  const plantmorph::cloudmpi::PointLayout& layout, const plantmorph::RegistrationParameters& registration,
  const Reference& reference, const plantmorph::ParallelFor& parallelFor, MeasuredPoints& m)
{
  using namespace plantmorph;
  const std::vector<double> gathered = controller
    ? cloudmpi::Landmarks(controller, layout, m.moved.data(), registration.maximumLandmarks)
    : std::vector<double>();
  const std::vector<double>& landmarks = controller ? gathered : m.moved;
  const std::string error = RegisterMeasured(registration, reference.xyz, reference.distance, parallelFor,
    landmarks.data(), landmarks.size() / 3, m.moved, m.transform, m.registered);
  if (!error.empty())
  {
    run.Fail("Registration: " + error);
  }
  if (!m.registered.warning.empty()) // a worse fit refused, or measured points that cannot determine a transform
  {
    run.Warn("Registration: " + m.registered.warning);
  }
}

/// The distance arrays of output 0.
struct Distances
{
  vtkSmartPointer<vtkDoubleArray> distance;
  vtkSmartPointer<vtkDoubleArray> signedDistance;
  vtkSmartPointer<vtkDoubleArray> closest;
};

/// Step 4: the measured points' distances to the reference, one QueryMany over all of them (one Morton order: the
/// most coherent), reporting progress between its blocks. The results go into CloudArrays (unset, on huge pages:
/// the queries write them scattered over the arrays, and with 4 KiB pages each first write to a page faulted, 8.7 k
/// faults on 10^6 points), which the outputs then adopt without a copy.
void QueryDistances(vtkAlgorithm* self, const plantmorph::PointSurfaceDistance& reference, const double* xyz,
  vtkIdType count, const plantmorph::ParallelFor& parallelFor, Distances& d)
{
  const bool surface = reference.IsSurface();
  const std::size_t n = static_cast<std::size_t>(count);
  plantmorph::CloudArray<double> distance, signedDistance, closest;
  distance.resize(n);
  signedDistance.resize(surface ? n : 0);
  closest.resize(3 * n);
  if (count > 0)
  {
    reference.QueryMany(xyz, n, distance.data(), surface ? signedDistance.data() : nullptr, closest.data(), nullptr,
      parallelFor, plantmorph::Progress(self, 0.3, 0.9));
  }
  d.distance = plantmorph::AdoptArray<vtkDoubleArray>(distance, 1, "Distance");
  d.signedDistance = plantmorph::AdoptArray<vtkDoubleArray>(signedDistance, 1, "SignedDistance");
  d.closest = plantmorph::AdoptArray<vtkDoubleArray>(closest, 3, "ClosestPoint");
}

/// Step 5, the outputs: each rank's points; the statistics and histogram of all ranks' distances (collective; the
/// tables on rank 0, the field data on every rank).
void WriteOutputs(vtkCloudComparisonFilter* self, const plantmorph::Run& run, vtkMultiProcessController* controller,
  vtkPointSet* measured, const MeasuredPoints& m, Distances& d, bool surface, const std::vector<double>& reverse)
{
  using namespace plantmorph;
  const double cutOff = self->GetUseMaximumDistance() ? self->GetMaximumDistance() : -1.0;
  const std::size_t count = static_cast<std::size_t>(measured->GetNumberOfPoints());
  vtkPolyData* output = run.Output<vtkPolyData>(0);
  vtkTable* histogram = run.Output<vtkTable>(1);
  vtkTable* statistics = run.Output<vtkTable>(2);
  FillPoints(measured, m.moved, self->GetScale() != 1.0 || m.registering, d.distance,
    surface ? d.signedDistance.Get() : nullptr, d.closest, self->GetMaximumDistance(),
    self->GetUseMaximumDistance() != 0, output);
  vtkFieldData* fd = output->GetFieldData();
  FillTransform(m.transform, m.registering ? &m.registered : nullptr, fd);
  // The statistics' two parts (sums; percentiles) at once, and the histogram's blocks, one a thread: the serial
  // tail of the update.
  const DistanceStatistics s = cloudmpi::Statistics(controller, d.distance->GetPointer(0), count, cutOff, SMPFor(1));
  FillStatistics(s, cutOff, surface, self->GetSymmetric() ? &reverse : nullptr, statistics, fd);
  FillHistogram(cloudmpi::Histogram(controller, d.distance->GetPointer(0), count,
                  static_cast<std::size_t>(self->GetHistogramBins()), cutOff, s, SMPFor(1)),
    s.count, histogram);
  if (!IsFirstRank())
  {
    statistics->Initialize(); // one row in all, rank 0's
    histogram->Initialize();
  }
}

/// Size ratio beyond which the two inputs are taken for a unit mismatch.
constexpr double UnitMismatchRatio = 5.0;

/// Warns when the measured points (after Scale) and the reference differ in size (their bounding boxes' diagonals)
/// by more than UnitMismatchRatio times: a scan in mm against a model in cm with the wrong Scale gives distances
/// that are all about the larger size. Collective under MPI (the measured bounds are reduced over the ranks).
void WarnIfSizesDiffer(const plantmorph::Run& run, vtkMultiProcessController* controller, const double* xyz,
  vtkIdType count, const std::vector<double>& reference, double scale)
{
  std::vector<double> bounds = NegatedBounds(xyz, static_cast<std::size_t>(count));
  plantmorph::cloudmpi::MinimumOverRanks(controller, bounds);
  const std::vector<double> own = NegatedBounds(reference.data(), reference.size() / 3);
  double measuredSize = 0.0, referenceSize = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    measuredSize += (bounds[3 + a] + bounds[a]) * (bounds[3 + a] + bounds[a]);
    referenceSize += (own[3 + a] + own[a]) * (own[3 + a] + own[a]);
  }
  measuredSize = std::sqrt(measuredSize);
  referenceSize = std::sqrt(referenceSize);
  const double ratio = std::max(measuredSize, referenceSize) / std::min(measuredSize, referenceSize);
  if (std::isfinite(measuredSize) && std::isfinite(referenceSize) && measuredSize > 0.0 && referenceSize > 0.0 &&
    ratio > UnitMismatchRatio)
  {
    std::ostringstream message;
    message.precision(4);
    message << "the Measured points (after Scale = " << scale << ") span " << measuredSize
            << " (bounding-box diagonal) and the Reference " << referenceSize << ": " << ratio
            << " times apart in size, more than " << UnitMismatchRatio
            << ". A unit mismatch? Set Scale to bring the measured points into the reference's unit (e.g. 0.1 for a "
               "scan in mm against a model in cm); the distances below mostly measure the difference in size";
    run.Warn(message.str());
  }
}

/// The comparison (on the threads RunThreaded gives). Under MPI (controller not null) every step runs on every
/// rank, each on its own measured points; the steps that may fail on one rank only are followed by a collective
/// check, so that all ranks stop together (the failing rank says why).
void Compare(vtkCloudComparisonFilter* self, const plantmorph::Run& run, vtkPointSet* measured, vtkPointSet* reference)
{
  using namespace plantmorph;
  vtkMultiProcessController* controller = cloudmpi::Parallel();
  RegistrationParameters registration;
  run.Check(CheckProperties(self, registration)); // the same on every rank, as is the replicated reference
  if (!reference || reference->GetNumberOfPoints() == 0)
  {
    run.Fail("the Reference input (port 1) is missing or has no point: connect a surface (polygons) or a point set to "
             "compare the Measured points with");
  }
  const vtkIdType count = measured->GetNumberOfPoints();
  const cloudmpi::PointLayout layout = cloudmpi::Layout(controller, static_cast<std::uint64_t>(count));
  if (layout.total == 0)
  {
    run.Warn("the Input (Measured points, port 0) is empty (no points): nothing to compare, the outputs are empty");
    return;
  }
  MeasuredPoints m;
  m.registering = self->GetRegistration() != vtkCloudComparisonFilter::REGISTRATION_NONE;
  StopTogether(
    run, controller, ReadMeasured(measured, self->GetScale(), m.registering, m.moved, m.xyz, m.transform), "");
  self->UpdateProgress(0.05);
  Reference ref;
  ref.xyz = FlatPoints(reference);
  WarnIfSizesDiffer(run, controller, m.xyz, count, ref.xyz, self->GetScale());
  const std::string built = BuildStructure(reference, ref.xyz.data(), ref.xyz.size() / 3, ref.distance);
  if (!built.empty())
  {
    run.Fail("Reference input: " + built);
  }
  self->UpdateProgress(0.15);
  StopIfAnyAborted(self, run, controller);
  const ParallelFor parallelFor = BlockSMPFor();
  if (m.registering)
  {
    Register(run, controller, layout, registration, ref, parallelFor, m);
  }
  self->UpdateProgress(0.3);
  StopIfAnyAborted(self, run, controller);
  Distances d;
  QueryDistances(self, ref.distance, m.xyz, count, parallelFor, d);
  StopIfAnyAborted(self, run, controller);
  const bool surface = ref.distance.IsSurface();
  ref.distance = PointSurfaceDistance(); // not needed any more: its memory back before what follows
  std::vector<double> reverse;
  if (self->GetSymmetric())
  {
    StopTogether(run, controller,
      ReverseDistances(controller, measured, m.xyz, static_cast<std::size_t>(count), ref.xyz, parallelFor, reverse),
      "Measured input (reverse direction): ");
  }
  self->UpdateProgress(0.95);
  WriteOutputs(self, run, controller, measured, m, d, surface, reverse);
  self->UpdateProgress(1.0);
}
} // namespace

//------------------------------------------------------------------------------
int vtkCloudComparisonFilter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the cloud comparison", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkCloudComparisonFilter::Execute(plantmorph::Run& run)
{
  vtkPointSet* measured = run.Input<vtkPointSet>(0);
  if (!measured)
  {
    return;
  }
  if (this->NumberOfThreads < 0 || this->NumberOfThreads > 256)
  {
    run.Fail(plantmorph::OutOfRange("NumberOfThreads", this->NumberOfThreads, "[0, 256]", "0: all cores"));
  }
  // The reference (small) gathered and broadcast, so every rank holds it whole (collective).
  const vtkSmartPointer<vtkPointSet> reference =
    plantmorph::cloudmpi::Replicate(plantmorph::cloudmpi::Parallel(), run.Input<vtkPointSet>(1));
  run.Threaded(this->NumberOfThreads, [&]() { Compare(this, run, measured, reference); });
}
