// SPDX-License-Identifier: GPL-3.0-or-later
// CloudComparisonFilter against VTK's own distance filters on the same data, in the same run
// (docs/methods/comparison.md, "Performance"): 10^6 measured points against a sphere of radius 1 with about 2*10^5
// triangles (vtkSphereSource, 317 x 317), ONE poly-vertex cell each. Two clouds (argument scan): 0 = vtkPointSource's
// uniform random ball of radius 1.2 (most points far inside: the worst case of any nearest-triangle search, a point
// near the centre is almost equally far from every triangle), 1 = scan-like, points on the sphere at radius
// 1 + N(0, 0.01) in random order (what a measured leaf against its model looks like).
//
// Families (see benchmarks/README.md, "comparison_benchmark"):
//   BM_CloudComparison/points:N/threads:T   vtkCloudComparisonFilter, unsigned + signed distance + closest point,
//                                           statistics and histogram; T = 0: all cores (STDThread), 1: serial.
//   BM_CloudComparisonSymmetric/points:N    the same with Symmetric on (the reverse direction too).
//   BM_CoreQueries/scan:S/slabs:B/avx:A     the algorithm layer alone, serial: PointSurfaceDistance::BuildSurface
//                                           of the sphere and QueryMany of the 10^6 points (distance, signed
//                                           distance, closest point) with the nodes' coin bounds (slabs:1) or box
//                                           bounds only (slabs:0), the AVX traversal where the processor has AVX
//                                           (avx:1) or the SSE2 one (avx:0); counters build_s, query_s, pts_per_s
//                                           (queries).
//   BM_VtkDistancePolyData/points:N         vtkDistancePolyDataFilter (signed, one direction) on the first N points
//                                           as vertex cells (it crashes on the single poly-vertex); N is small
//                                           because it manages about 700 points/s here: extrapolate.
//   BM_VtkHausdorff/points:N                vtkHausdorffDistancePointSetFilter, point-to-cell (both directions: N
//                                           points to the sphere's triangles, the sphere's points to the N vertices).
//   BM_Accuracy                              untimed checks: our distances against brute force over all triangles on
//                                           200 points, and against vtkDistancePolyDataFilter on 2000 points.
// Counters: pts_per_s (measured points per wall second), s_per_1e6 (wall seconds per 10^6 points, extrapolated
// linearly for the VTK filters), peak memory (PeakMemory.h) against input + output bytes.
#include "../PeakMemory.h"

#include "PointSurfaceDistance.h"
#include <plantmorph/RandomStream.h>
#include "vtkCloudComparisonFilter.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkDistancePolyDataFilter.h"
#include "vtkHausdorffDistancePointSetFilter.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSource.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkTable.h"
#include "vtkVertexGlyphFilter.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace
{
using plantmorph_benchmarks::PeakMemoryProbe;

vtkPolyData* Sphere()
{
  static vtkSmartPointer<vtkPolyData> sphere = [] {
    vtkNew<vtkSphereSource> source;
    source->SetRadius(1.0);
    source->SetThetaResolution(317);
    source->SetPhiResolution(317);
    source->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
    source->Update();
    vtkSmartPointer<vtkPolyData> out = source->GetOutput();
    return out;
  }();
  return sphere;
}

/// A scan-like cloud: 10^6 points on the unit sphere (uniform random directions) at radius 1 + N(0, 0.01), in
/// random order (no spatial coherence), one poly-vertex.
vtkSmartPointer<vtkPolyData> ScanLike()
{
  static vtkSmartPointer<vtkPolyData> scan = [] {
    plantmorph::RandomStream random(2024);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(1000000);
    for (vtkIdType i = 0; i < 1000000; ++i)
    {
      double d[3] = { random.Normal(), random.Normal(), random.Normal() };
      const double r = (1.0 + random.Normal(0.0, 0.01)) / std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      points->SetPoint(i, r * d[0], r * d[1], r * d[2]);
    }
    auto out = vtkSmartPointer<vtkPolyData>::New();
    out->SetPoints(points);
    vtkNew<vtkCellArray> verts;
    verts->InsertNextCell(1000000);
    for (vtkIdType i = 0; i < 1000000; ++i)
    {
      verts->InsertCellPoint(i);
    }
    out->SetVerts(verts);
    return out;
  }();
  return scan;
}

/// The first `count` points of one of the two 10^6-point clouds (kind 0: vtkPointSource's random ball of radius
/// 1.2; kind 1: ScanLike), as one poly-vertex (like vtkPointSource).
vtkSmartPointer<vtkPolyData> Cloud(vtkIdType count, int kind = 0)
{
  static vtkSmartPointer<vtkPolyData> ballCloud = [] {
    vtkNew<vtkPointSource> source;
    source->SetNumberOfPoints(1000000);
    source->SetRadius(1.2);
    source->SetDistributionToUniform();
    source->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
    source->Update();
    vtkSmartPointer<vtkPolyData> out = source->GetOutput();
    return out;
  }();
  vtkPolyData* ball = kind == 0 ? ballCloud.Get() : ScanLike().Get();
  if (count >= ball->GetNumberOfPoints())
  {
    return ball;
  }
  auto subset = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(count);
  for (vtkIdType i = 0; i < count; ++i)
  {
    points->SetPoint(i, ball->GetPoint(i));
  }
  subset->SetPoints(points);
  vtkNew<vtkCellArray> verts;
  verts->InsertNextCell(count);
  for (vtkIdType i = 0; i < count; ++i)
  {
    verts->InsertCellPoint(i);
  }
  subset->SetVerts(verts);
  return subset;
}

/// One vertex cell per point (what VTK's filters accept).
vtkSmartPointer<vtkPolyData> AsVertices(vtkPolyData* cloud)
{
  vtkNew<vtkVertexGlyphFilter> glyphs;
  glyphs->SetInputData(cloud);
  glyphs->Update();
  vtkSmartPointer<vtkPolyData> out = glyphs->GetOutput();
  return out;
}

double Seconds(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Report(benchmark::State& state, double points, double seconds)
{
  state.counters["pts_per_s"] = points / seconds;
  state.counters["s_per_1e6"] = seconds * 1e6 / points;
  state.counters["triangles"] = static_cast<double>(Sphere()->GetNumberOfPolys());
}

void RunOurs(benchmark::State& state, bool symmetric)
{
  const vtkIdType n = state.range(0);
  vtkSmartPointer<vtkPolyData> cloud = Cloud(n, static_cast<int>(state.range(2)));
  vtkPolyData* sphere = Sphere();
  const double inBytes = 24.0 * static_cast<double>(n + sphere->GetNumberOfPoints()) +
    12.0 * 8.0 * static_cast<double>(sphere->GetNumberOfPolys()) / 3.0 * 3.0 / 4.0; // points + ~int64 connectivity
  const double outBytes = (8.0 + 8.0 + 24.0) * static_cast<double>(n);              // Distance, SignedDistance, Closest
  PeakMemoryProbe probe;
  probe.Start();
  double total = 0.0;
  for (auto _ : state)
  {
    vtkNew<vtkCloudComparisonFilter> filter;
    filter->SetInputData(0, cloud);
    filter->SetReferenceData(sphere);
    filter->SetNumberOfThreads(static_cast<int>(state.range(1)));
    filter->SetSymmetric(symmetric);
    const auto start = std::chrono::steady_clock::now();
    filter->Update();
    const double s = Seconds(start);
    total += s;
    state.SetIterationTime(s);
    benchmark::DoNotOptimize(filter->GetOutput()->GetPointData()->GetArray("Distance"));
  }
  Report(state, static_cast<double>(n) * static_cast<double>(state.iterations()), total);
  probe.Report(state, inBytes, outBytes);
}

void BM_CloudComparison(benchmark::State& state)
{
  RunOurs(state, false);
}
BENCHMARK(BM_CloudComparison)
  ->ArgNames({ "points", "threads", "scan" })
  ->Args({ 10000, 0, 0 })
  ->Args({ 100000, 0, 0 })
  ->Args({ 1000000, 0, 0 })
  ->Args({ 1000000, 1, 0 })
  ->Args({ 10000, 0, 1 })
  ->Args({ 1000000, 0, 1 })
  ->Args({ 1000000, 1, 1 })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond)
  ->Iterations(3);

void BM_CloudComparisonSymmetric(benchmark::State& state)
{
  RunOurs(state, true);
}
BENCHMARK(BM_CloudComparisonSymmetric)
  ->ArgNames({ "points", "threads", "scan" })
  ->Args({ 1000000, 0, 1 })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1);

/// The sphere's points and triangles as the core's flat arrays.
struct FlatSurface
{
  std::vector<double> points;
  std::vector<std::int64_t> triangles;
};

const FlatSurface& SphereArrays()
{
  static const FlatSurface flat = [] {
    FlatSurface out;
    vtkPolyData* sphere = Sphere();
    out.points.resize(3 * static_cast<std::size_t>(sphere->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < sphere->GetNumberOfPoints(); ++i)
    {
      sphere->GetPoint(i, out.points.data() + 3 * i);
    }
    auto it = vtk::TakeSmartPointer(sphere->GetPolys()->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      it->GetCurrentCell(n, ids);
      out.triangles.insert(out.triangles.end(), { ids[0], ids[1], ids[2] });
    }
    return out;
  }();
  return flat;
}

/// The algorithm layer alone, serial: BuildSurface of the sphere (once per iteration), then QueryMany of the 10^6
/// points with slab bounds on (slabs:1) or box bounds only (slabs:0), AVX (avx:1, where the processor has it) or
/// SSE2 (avx:0). Counters: build_s, query_s, pts_per_s of the queries alone.
void BM_CoreQueries(benchmark::State& state)
{
  const FlatSurface& sphere = SphereArrays();
  vtkPolyData* cloud = Cloud(1000000, static_cast<int>(state.range(0)));
  std::vector<double> xyz(3 * static_cast<std::size_t>(cloud->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < cloud->GetNumberOfPoints(); ++i)
  {
    cloud->GetPoint(i, xyz.data() + 3 * i);
  }
  const std::size_t n = xyz.size() / 3;
  std::vector<double> distance(n);
  std::vector<double> signedDistance(n);
  std::vector<double> closest(3 * n);
  double build = 0.0;
  double query = 0.0;
  for (auto _ : state)
  {
    plantmorph::PointSurfaceDistance core;
    core.SetSlabBounds(state.range(1) != 0);
    core.SetAvx(state.range(2) != 0);
    auto start = std::chrono::steady_clock::now();
    core.BuildSurface(
      sphere.points.data(), sphere.points.size() / 3, sphere.triangles.data(), sphere.triangles.size() / 3);
    const double b = Seconds(start);
    start = std::chrono::steady_clock::now();
    core.QueryMany(xyz.data(), n, distance.data(), signedDistance.data(), closest.data(), nullptr);
    const double q = Seconds(start);
    build += b;
    query += q;
    state.SetIterationTime(b + q);
    benchmark::DoNotOptimize(distance.data());
  }
  const double iterations = static_cast<double>(state.iterations());
  state.counters["build_s"] = build / iterations;
  state.counters["query_s"] = query / iterations;
  state.counters["pts_per_s"] = static_cast<double>(n) * iterations / query;
}
BENCHMARK(BM_CoreQueries)
  ->ArgNames({ "scan", "slabs", "avx" })
  ->Args({ 0, 1, 1 })
  ->Args({ 1, 1, 1 })
  ->Args({ 0, 1, 0 })
  ->Args({ 1, 1, 0 })
  ->Args({ 0, 0, 1 })
  ->Args({ 1, 0, 1 })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1);

/// Times one of VTK's filters on the first state.range(0) points of a cloud (state.range(1): 0 ball, 1 scan-like) as
/// vertex cells against the sphere; `configure` sets the filter up.
template <typename Filter, typename Configure>
void TimeVtkFilter(benchmark::State& state, Configure configure)
{
  vtkSmartPointer<vtkPolyData> cloud = AsVertices(Cloud(state.range(0), static_cast<int>(state.range(1))));
  double total = 0.0;
  for (auto _ : state)
  {
    vtkNew<Filter> filter;
    filter->SetInputData(0, cloud);
    filter->SetInputData(1, Sphere());
    configure(filter.Get());
    const auto start = std::chrono::steady_clock::now();
    filter->Update();
    const double s = Seconds(start);
    total += s;
    state.SetIterationTime(s);
  }
  Report(state, static_cast<double>(state.range(0)) * static_cast<double>(state.iterations()), total);
}

void BM_VtkDistancePolyData(benchmark::State& state)
{
  TimeVtkFilter<vtkDistancePolyDataFilter>(state, [](vtkDistancePolyDataFilter* filter) {
    filter->SignedDistanceOn();
    filter->ComputeSecondDistanceOff();
  });
}
BENCHMARK(BM_VtkDistancePolyData)
  ->ArgNames({ "points", "scan" })
  ->Args({ 1000, 0 })
  ->Args({ 1000, 1 })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1);

void BM_VtkHausdorff(benchmark::State& state)
{
  TimeVtkFilter<vtkHausdorffDistancePointSetFilter>(
    state, [](vtkHausdorffDistancePointSetFilter* filter) { filter->SetTargetDistanceMethodToPointToCell(); });
}
BENCHMARK(BM_VtkHausdorff)
  ->ArgNames({ "points", "scan" })
  ->Args({ 10000, 0 })
  ->Args({ 10000, 1 })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1);

/// Independent brute force: exact distance to every triangle (projection if inside, else the nearest edge).
double BruteForce(vtkPolyData* surface, const double p[3])
{
  double best = std::numeric_limits<double>::infinity();
  vtkPoints* pts = surface->GetPoints();
  auto it = vtk::TakeSmartPointer(surface->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    it->GetCurrentCell(n, ids);
    double a[3], b[3], c[3], closest[3];
    pts->GetPoint(ids[0], a);
    pts->GetPoint(ids[1], b);
    pts->GetPoint(ids[2], c);
    plantmorph::TriangleFeature feature;
    int index = 0;
    plantmorph::ClosestPointOnTriangle(p, a, b, c, closest, feature, index);
    best = std::min(best,
      std::sqrt((p[0] - closest[0]) * (p[0] - closest[0]) + (p[1] - closest[1]) * (p[1] - closest[1]) +
        (p[2] - closest[2]) * (p[2] - closest[2])));
  }
  return best;
}

void BM_Accuracy(benchmark::State& state)
{
  vtkSmartPointer<vtkPolyData> cloud = Cloud(1000000);
  vtkNew<vtkCloudComparisonFilter> filter;
  filter->SetInputData(0, cloud);
  filter->SetReferenceData(Sphere());
  filter->Update();
  vtkDataArray* ours = filter->GetOutput()->GetPointData()->GetArray("Distance");
  double bruteError = 0.0;
  double vtkError = 0.0;
  for (auto _ : state)
  {
    for (vtkIdType i = 0; i < 1000000; i += 5000) // 200 points spread over the cloud
    {
      double p[3];
      cloud->GetPoint(i, p);
      bruteError = std::max(bruteError, std::fabs(BruteForce(Sphere(), p) - ours->GetTuple1(i)));
    }
    vtkNew<vtkDistancePolyDataFilter> reference;
    reference->SetInputData(0, AsVertices(Cloud(2000)));
    reference->SetInputData(1, Sphere());
    reference->ComputeSecondDistanceOff();
    reference->Update();
    vtkDataArray* theirs = reference->GetOutput()->GetPointData()->GetArray("Distance");
    for (vtkIdType i = 0; i < 2000; ++i)
    {
      vtkError = std::max(vtkError, std::fabs(std::fabs(theirs->GetTuple1(i)) - ours->GetTuple1(i)));
    }
  }
  state.counters["max_err_brute"] = bruteError;
  state.counters["max_err_vtk"] = vtkError;
}
BENCHMARK(BM_Accuracy)->Iterations(1)->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
