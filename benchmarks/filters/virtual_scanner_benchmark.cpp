// VirtualScanner's ray casting against VTK's locators on the same scene and beams, in the same run (docs/methods/virtual-scanner.md,
// issue 24). Scene: a sphere of radius 1 (vtkSphereSource, R x R, about 2 R^2 triangles: 10^4 ... 10^6), scanned
// by a terrestrial scanner 3 away over a 45 x 45 degree field (about 60% of the beams hit), its step giving 10^5 or
// 10^6 beams. Nearest hit per beam in every family.
//
//   BM_ScannerBuild/tris:N                 TriangleBVH::Build alone (binned SAH), serial; counter tris_per_s.
//   BM_ScannerCast/tris:N/beams:B/threads:T CastBeams (pattern, BVH traversal, watertight test, normals, intensity,
//                                          compaction), T threads (std::thread pieces through ParallelFor).
//   BM_VtkOBBTree/tris:N                   vtkOBBTree::IntersectWithLine (the nearest hit) on 200 beams spread
//                                          over the 10^5-beam scan, serial, one iteration (it manages a few hundred
//                                          beams per second); the tree built untimed.
//   BM_VtkStaticCellLocator/tris:N         vtkStaticCellLocator::IntersectWithLine, 2000 such beams, serial.
//   BM_Embree/tris:N/beams:B               Embree 3 (libembree-dev, single precision, when installed): the scene
//                                          committed untimed on a one-thread device, then the same beams made by
//                                          the same pattern, rtcIntersect1 each (nearest hit), serial; no normals
//                                          or compaction, so it does a little less than BM_ScannerCast.
// Rates: per CPU second of the benchmark's thread for the serial families (fair on a loaded machine), per wall
// second for threads:2 (the casting threads are not the benchmark's own).
// Counters: beams_per_s (beams per wall second), hits (returns, to check all families see the same scene), peak
// memory (PeakMemory.h) of the timed runs, and build_s (the hierarchy's or locator's build, untimed runs).
#include "../PeakMemory.h"

#include "ScanPattern.h"
#include "TriangleBVH.h"
#include "VirtualScan.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkGenericCell.h"
#include "vtkNew.h"
#include "vtkOBBTree.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkStaticCellLocator.h"

#include <benchmark/benchmark.h>

#ifdef PLANTMORPH_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <thread>
#include <vector>

namespace
{
using plantmorph_benchmarks::PeakMemoryProbe;

struct Scene
{
  vtkSmartPointer<vtkPolyData> polyData;
  std::vector<double> points;
  std::vector<std::int64_t> triangles;
};

/// The sphere with about `triangles` triangles (cached per size).
const Scene& Sphere(std::int64_t triangles)
{
  static std::map<std::int64_t, Scene> cache;
  auto it = cache.find(triangles);
  if (it != cache.end())
    return it->second;
  const int r = static_cast<int>(std::lround(std::sqrt(triangles / 2.0))) + 1;
  vtkNew<vtkSphereSource> source;
  source->SetRadius(1.0);
  source->SetThetaResolution(r);
  source->SetPhiResolution(r);
  source->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  source->Update();
  Scene scene;
  scene.polyData = source->GetOutput();
  const vtkIdType n = scene.polyData->GetNumberOfPoints();
  scene.points.resize(3 * static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
    scene.polyData->GetPoint(i, &scene.points[3 * static_cast<std::size_t>(i)]);
  auto cells = vtk::TakeSmartPointer(scene.polyData->GetPolys()->NewIterator());
  for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell())
  {
    vtkIdType size;
    const vtkIdType* ids;
    cells->GetCurrentCell(size, ids);
    scene.triangles.insert(scene.triangles.end(), { ids[0], ids[1], ids[2] });
  }
  return cache.emplace(triangles, std::move(scene)).first->second;
}

/// The scan: a terrestrial scanner 3 from the centre, 45 x 45 degrees, about `beams` beams.
plantmorph::ScannerParameters Scan(std::int64_t beams)
{
  plantmorph::ScannerParameters p;
  p.positions = { plantmorph::Vec3{ 0.1, -3.0, 0.2 } };
  p.lookAt = { 0.0, 0.0, 0.0 };
  p.horizontalFieldOfView = 45;
  p.verticalFieldOfView = 45;
  p.angularStep = 45.0 / (std::sqrt(static_cast<double>(beams)) - 1.0);
  p.maximumRange = 10.0;
  return p;
}

plantmorph::ParallelFor Threads(int threads)
{
  if (threads <= 1)
    return plantmorph::SerialFor;
  return [threads](std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
      pool.emplace_back([&, t] { body(n * t / threads, n * (t + 1) / threads); });
    for (auto& thread : pool)
      thread.join();
  };
}

void BM_ScannerBuild(benchmark::State& state)
{
  const Scene& scene = Sphere(state.range(0));
  PeakMemoryProbe memory;
  memory.Start();
  plantmorph::TriangleBVH bvh;
  for (auto _ : state)
  {
    bvh.Build(scene.points, scene.triangles);
    benchmark::DoNotOptimize(bvh.NodeCount());
  }
  const double tris = static_cast<double>(scene.triangles.size() / 3);
  state.counters["tris"] = tris;
  state.counters["tris_per_s"] = benchmark::Counter(tris, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["bvh_bytes"] = plantmorph_benchmarks::Bytes(static_cast<double>(bvh.MemoryBytes()));
  memory.Report(state, static_cast<double>(scene.points.size() * 8 + scene.triangles.size() * 8));
}

void BM_ScannerCast(benchmark::State& state)
{
  const Scene& scene = Sphere(state.range(0));
  const plantmorph::ScannerParameters p = Scan(state.range(1));
  plantmorph::BeamPattern pattern;
  if (!pattern.Setup(p).empty())
  {
    state.SkipWithError("pattern");
    return;
  }
  plantmorph::TriangleBVH bvh;
  const auto start = std::chrono::steady_clock::now();
  bvh.Build(scene.points, scene.triangles);
  const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const plantmorph::ParallelFor parallel = Threads(static_cast<int>(state.range(2)));
  PeakMemoryProbe memory;
  memory.Start();
  plantmorph::ScanPoints out;
  for (auto _ : state)
  {
    plantmorph::CastBeams(p, pattern, scene.points, scene.triangles, bvh, out, parallel);
    benchmark::DoNotOptimize(out.points.data());
  }
  state.counters["tris"] = static_cast<double>(scene.triangles.size() / 3);
  state.counters["beams"] = static_cast<double>(pattern.BeamCount());
  state.counters["hits"] = static_cast<double>(out.Size());
  state.counters["build_s"] = build;
  state.counters["beams_per_s"] =
    benchmark::Counter(static_cast<double>(pattern.BeamCount()), benchmark::Counter::kIsIterationInvariantRate);
  memory.Report(state, 0.0, static_cast<double>(out.Size() * (8 * 10 + 8 * 3)));
}

/// The first `count` beams of the 10^5-beam scan as line segments (start, end at MaximumRange).
std::vector<double> Segments(std::size_t count)
{
  const plantmorph::ScannerParameters p = Scan(100000);
  plantmorph::BeamPattern pattern;
  pattern.Setup(p);
  std::vector<double> segments;
  // Spread over the whole field: every k-th beam.
  const std::uint64_t stride = pattern.BeamCount() / count;
  for (std::size_t i = 0; i < count; ++i)
  {
    double o[3], d[3];
    std::int64_t pose;
    pattern.Beam(i * stride, o, d, pose);
    segments.insert(segments.end(), { o[0], o[1], o[2], o[0] + 10 * d[0], o[1] + 10 * d[1], o[2] + 10 * d[2] });
  }
  return segments;
}

template <typename Locator>
void RunVtk(benchmark::State& state, Locator* locator, std::size_t count)
{
  const Scene& scene = Sphere(state.range(0));
  locator->SetDataSet(scene.polyData);
  const auto start = std::chrono::steady_clock::now();
  locator->BuildLocator();
  const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::vector<double> segments = Segments(count);
  PeakMemoryProbe memory;
  memory.Start();
  vtkNew<vtkGenericCell> cell;
  std::size_t hits = 0;
  for (auto _ : state)
  {
    hits = 0;
    for (std::size_t i = 0; i < count; ++i)
    {
      double t, x[3], pcoords[3];
      int subId;
      vtkIdType cellId = -1;
      double a[3] = { segments[6 * i], segments[6 * i + 1], segments[6 * i + 2] };
      double b[3] = { segments[6 * i + 3], segments[6 * i + 4], segments[6 * i + 5] };
      if (locator->IntersectWithLine(a, b, 0.0, t, x, pcoords, subId, cellId, cell))
        ++hits;
    }
  }
  state.counters["tris"] = static_cast<double>(scene.triangles.size() / 3);
  state.counters["beams"] = static_cast<double>(count);
  state.counters["hits"] = static_cast<double>(hits);
  state.counters["build_s"] = build;
  state.counters["beams_per_s"] = benchmark::Counter(static_cast<double>(count), benchmark::Counter::kIsIterationInvariantRate);
  memory.Report(state);
}

void BM_VtkOBBTree(benchmark::State& state)
{
  vtkNew<vtkOBBTree> tree;
  RunVtk(state, tree.Get(), 200);
}

void BM_VtkStaticCellLocator(benchmark::State& state)
{
  vtkNew<vtkStaticCellLocator> locator;
  RunVtk(state, locator.Get(), 2000);
}
#ifdef PLANTMORPH_HAVE_EMBREE
void BM_Embree(benchmark::State& state)
{
  const Scene& scene = Sphere(state.range(0));
  const plantmorph::ScannerParameters p = Scan(state.range(1));
  plantmorph::BeamPattern pattern;
  pattern.Setup(p);
  RTCDevice device = rtcNewDevice("threads=1");
  RTCScene rtc = rtcNewScene(device);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const std::size_t nv = scene.points.size() / 3, nt = scene.triangles.size() / 3;
  auto* vertices = static_cast<float*>(
    rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
  auto* indices = static_cast<unsigned*>(
    rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
  for (std::size_t i = 0; i < 3 * nv; ++i)
    vertices[i] = static_cast<float>(scene.points[i]);
  for (std::size_t i = 0; i < 3 * nt; ++i)
    indices[i] = static_cast<unsigned>(scene.triangles[i]);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(rtc, geometry);
  rtcReleaseGeometry(geometry);
  const auto start = std::chrono::steady_clock::now();
  rtcCommitScene(rtc);
  const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  PeakMemoryProbe memory;
  memory.Start();
  std::size_t hits = 0;
  for (auto _ : state)
  {
    hits = 0;
    for (std::uint64_t b = 0; b < pattern.BeamCount(); ++b)
    {
      double o[3], d[3];
      std::int64_t pose;
      pattern.Beam(b, o, d, pose);
      RTCRayHit ray;
      ray.ray.org_x = static_cast<float>(o[0]);
      ray.ray.org_y = static_cast<float>(o[1]);
      ray.ray.org_z = static_cast<float>(o[2]);
      ray.ray.dir_x = static_cast<float>(d[0]);
      ray.ray.dir_y = static_cast<float>(d[1]);
      ray.ray.dir_z = static_cast<float>(d[2]);
      ray.ray.tnear = 0.0f;
      ray.ray.tfar = static_cast<float>(p.maximumRange);
      ray.ray.time = 0.0f;
      ray.ray.mask = 0xFFFFFFFFu;
      ray.ray.id = 0;
      ray.ray.flags = 0;
      ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(rtc, &context, &ray);
      hits += ray.hit.geomID != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
    }
  }
  state.counters["tris"] = static_cast<double>(nt);
  state.counters["beams"] = static_cast<double>(pattern.BeamCount());
  state.counters["hits"] = static_cast<double>(hits);
  state.counters["build_s"] = build;
  state.counters["beams_per_s"] =
    benchmark::Counter(static_cast<double>(pattern.BeamCount()), benchmark::Counter::kIsIterationInvariantRate);
  memory.Report(state);
  rtcReleaseScene(rtc);
  rtcReleaseDevice(device);
}
BENCHMARK(BM_Embree)
  ->ArgNames({ "tris", "beams" })
  ->ArgsProduct({ { 10000, 100000, 1000000 }, { 100000, 1000000 } })
  ->Unit(benchmark::kMillisecond);
#endif
} // namespace

BENCHMARK(BM_ScannerBuild)->ArgName("tris")->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ScannerCast)
  ->ArgNames({ "tris", "beams", "threads" })
  ->ArgsProduct({ { 10000, 100000, 1000000 }, { 100000, 1000000 }, { 1 } })
  ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ScannerCast)
  ->ArgNames({ "tris", "beams", "threads" })
  ->ArgsProduct({ { 10000, 100000, 1000000 }, { 100000, 1000000 }, { 2 } })
  ->Unit(benchmark::kMillisecond)
  ->UseRealTime();
BENCHMARK(BM_VtkOBBTree)->ArgName("tris")->Arg(10000)->Arg(100000)->Arg(1000000)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VtkStaticCellLocator)
  ->ArgName("tris")
  ->Arg(10000)
  ->Arg(100000)
  ->Arg(1000000)
  ->Iterations(1)
  ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
