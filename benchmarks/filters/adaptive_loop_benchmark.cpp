// AdaptiveLoopFilter against the alternatives, in one run (see benchmarks/README.md, "adaptive_loop_benchmark").
//
// Uniform mode (EdgeAngleThreshold 180, FlatnessThreshold 1, FeatureRule Loop: plain Loop subdivision) on
// vtkSphereSource spheres (float points and float normals, as the source makes them), for 10^3 .. 10^6 output
// triangles and 1 .. 4 levels:
//   BM_Uniform_AdaptiveLoopFilter/threads:T  the plugin's VTK filter, T threads (0 = all cores), whole RequestData
//   BM_Uniform_Core                          the algorithm layer alone, serial, on flat arrays (no VTK conversion)
//   BM_Uniform_vtkLoopSubdivisionFilter      VTK's own Loop filter (ParaView's "Loop Subdivision")
//   BM_Uniform_CGAL_Loop                     CGAL 5.5 Subdivision_method_3::Loop_subdivision on a Surface_mesh
//                                            (positions only; the mesh is built from the sphere untimed)
// Adaptive mode on a bent ginkgo blade (LeafOutlineSource, Fixed feature rule): the deviation of uniform level L
// from the level-4 uniform surface (exact point-to-triangle distances both ways, see Deviation below), and the
// adaptive settings (searched untimed, once: levels, bisection on the threshold angle, flatness rule; 288 runs,
// about 6 minutes on a loaded 2-core machine) with the fewest triangles within that deviation.
// PLANTMORPH_BLADE_SWEEP_LOG=1 prints every evaluated setting (levels, alpha = 180 - EdgeAngleThreshold,
// 1 - FlatnessThreshold, triangles, deviations) to stderr, i.e. the adaptive triangles-versus-deviation curve:
//   BM_Blade_Uniform/levels:L, BM_Blade_Adaptive/levels:L
//
// Counters: triangles (output), tri_per_s (output triangles per wall second: the filters are threaded), in_bytes /
// out_bytes (vtkPolyData::GetActualMemorySize of input / output, or the CGAL mesh's element storage), peak_bytes
// (VmHWM above the resident set before the runs, reset with `echo 5 > /proc/self/clear_refs`, as
// blade_generation_benchmark does), peak_ratio = peak_bytes / (in_bytes + out_bytes).
#include "AdaptiveLoopSubdivision.h"
#include "PointSurfaceDistance.h"
#include "vtkAdaptiveLoopFilter.h"
#include "vtkLeafOutlineSource.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkLoopSubdivisionFilter.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"

#include "PeakMemory.h"

#include <benchmark/benchmark.h>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Subdivision_method_3/subdivision_methods_3.h>
#include <CGAL/Surface_mesh.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <fstream>
#include <functional>
#include <map>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

// ---- memory (as in blade_generation_benchmark) --------------------------------------------------------------------

using plantmorph_benchmarks::PeakMemoryProbe;

void ReportTriangles(benchmark::State& state, double triangles)
{
  state.counters["triangles"] = triangles;
  state.counters["tri_per_s"] = benchmark::Counter(triangles, benchmark::Counter::kIsIterationInvariantRate);
}

double Bytes(vtkPolyData* data)
{
  return 1024.0 * static_cast<double>(data->GetActualMemorySize());
}

// ---- meshes -------------------------------------------------------------------------------------------------------

/// A sphere whose `levels`-fold Loop subdivision has about 10^exponent triangles.
vtkSmartPointer<vtkPolyData> SphereFor(int exponent, int levels)
{
  const double inputTriangles = std::pow(10.0, exponent) / std::pow(4.0, levels);
  // vtkSphereSource(theta, phi) makes 2 theta (phi - 1) triangles. Its poles have valence theta: keep that at most
  // 128, because vtkLoopSubdivisionFilter (VTK 9.2) smashes its stack at a pole of valence 354 (fixed-size stencil
  // arrays), and lengthen the sphere in phi instead.
  const int r = std::max(4, static_cast<int>(std::lround(0.5 + std::sqrt(0.25 + inputTriangles / 2.0))));
  const int theta = std::min(r, 128);
  const int phi = std::max(4, static_cast<int>(std::lround(inputTriangles / (2.0 * theta) + 1.0)));
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(theta);
  sphere->SetPhiResolution(phi);
  sphere->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(sphere->GetOutput());
  return out;
}

plantmorph::AdaptiveLoopMesh FlatArrays(vtkPolyData* data)
{
  plantmorph::AdaptiveLoopMesh mesh;
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    double p[3];
    data->GetPoint(i, p);
    mesh.points.insert(mesh.points.end(), p, p + 3);
  }
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c)
  {
    data->GetCellPoints(c, ids);
    for (int k = 0; k < 3; ++k)
      mesh.triangles.push_back(static_cast<int>(ids->GetId(k)));
  }
  return mesh;
}

SurfaceMesh ToSurfaceMesh(vtkPolyData* data)
{
  SurfaceMesh mesh;
  std::vector<SurfaceMesh::Vertex_index> vertices;
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    double p[3];
    data->GetPoint(i, p);
    vertices.push_back(mesh.add_vertex(Kernel::Point_3(p[0], p[1], p[2])));
  }
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c)
  {
    data->GetCellPoints(c, ids);
    mesh.add_face(vertices[ids->GetId(0)], vertices[ids->GetId(1)], vertices[ids->GetId(2)]);
  }
  return mesh;
}

vtkSmartPointer<vtkPolyData> RunFilter(vtkPolyData* input, const std::function<void(vtkAdaptiveLoopFilter*)>& set)
{
  vtkNew<vtkAdaptiveLoopFilter> filter;
  filter->SetInputData(input);
  set(filter);
  filter->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}

void Uniform(vtkAdaptiveLoopFilter* f, int levels)
{
  f->SetMaximumLevel(levels);
  f->SetEdgeAngleThreshold(180.0);
  f->SetFlatnessThreshold(1.0);
  f->SetFeatureRule(vtkAdaptiveLoopFilter::LOOP);
}

// ---- uniform mode -------------------------------------------------------------------------------------------------

void BM_Uniform_AdaptiveLoopFilter(benchmark::State& state)
{
  const int exponent = static_cast<int>(state.range(0)), levels = static_cast<int>(state.range(1));
  const int threads = static_cast<int>(state.range(2));
  const vtkSmartPointer<vtkPolyData> sphere = SphereFor(exponent, levels);
  double triangles = 0.0, outBytes = 0.0;
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    vtkSmartPointer<vtkPolyData> out = RunFilter(sphere, [&](vtkAdaptiveLoopFilter* f) {
      Uniform(f, levels);
      f->SetNumberOfThreads(threads);
    });
    triangles = static_cast<double>(out->GetNumberOfCells());
    outBytes = Bytes(out);
  }
  ReportTriangles(state, triangles);
  memory.Report(state, Bytes(sphere), outBytes);
}

void BM_Uniform_Core(benchmark::State& state)
{
  const int exponent = static_cast<int>(state.range(0)), levels = static_cast<int>(state.range(1));
  const plantmorph::AdaptiveLoopMesh mesh = FlatArrays(SphereFor(exponent, levels));
  plantmorph::AdaptiveLoopSettings settings;
  settings.edgeAngleThreshold = 180.0;
  settings.flatnessThreshold = 1.0;
  settings.featureRule = plantmorph::FeatureRule::Loop;
  settings.maximumLevel = levels;
  double triangles = 0.0, outBytes = 0.0;
  const double inBytes = static_cast<double>(mesh.points.size() * 8 + mesh.triangles.size() * 4);
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    plantmorph::AdaptiveLoopResult result = plantmorph::AdaptiveLoopSubdivide(mesh, settings);
    triangles = static_cast<double>(result.mesh.NumberOfTriangles());
    outBytes = static_cast<double>(result.mesh.points.size() * 8 + result.mesh.triangles.size() * 4 +
      result.mesh.origin.size() * 4);
    benchmark::DoNotOptimize(result.mesh.points.data());
  }
  ReportTriangles(state, triangles);
  memory.Report(state, inBytes, outBytes);
}

void BM_Uniform_vtkLoopSubdivisionFilter(benchmark::State& state)
{
  const int exponent = static_cast<int>(state.range(0)), levels = static_cast<int>(state.range(1));
  const vtkSmartPointer<vtkPolyData> sphere = SphereFor(exponent, levels);
  double triangles = 0.0, outBytes = 0.0;
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    vtkNew<vtkLoopSubdivisionFilter> loop;
    loop->SetInputData(sphere);
    loop->SetNumberOfSubdivisions(levels);
    loop->Update();
    triangles = static_cast<double>(loop->GetOutput()->GetNumberOfCells());
    outBytes = Bytes(loop->GetOutput());
  }
  ReportTriangles(state, triangles);
  memory.Report(state, Bytes(sphere), outBytes);
}

double MeshBytes(const SurfaceMesh& m)
{
  // Surface_mesh storage: per vertex a point and a halfedge index, per halfedge 4 indices, per face 1 index.
  return static_cast<double>(m.number_of_vertices() * (sizeof(Kernel::Point_3) + 4) + m.number_of_halfedges() * 16 +
    m.number_of_faces() * 4);
}

void BM_Uniform_CGAL_Loop(benchmark::State& state)
{
  const int exponent = static_cast<int>(state.range(0)), levels = static_cast<int>(state.range(1));
  const SurfaceMesh input = ToSurfaceMesh(SphereFor(exponent, levels));
  double triangles = 0.0, outBytes = 0.0;
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    state.PauseTiming();
    SurfaceMesh mesh = input;
    state.ResumeTiming();
    CGAL::Subdivision_method_3::Loop_subdivision(mesh, CGAL::parameters::number_of_iterations(levels));
    triangles = static_cast<double>(mesh.number_of_faces());
    outBytes = MeshBytes(mesh);
  }
  ReportTriangles(state, triangles);
  memory.Report(state, MeshBytes(input), outBytes);
}

void UniformArguments(benchmark::internal::Benchmark* b, bool withThreads)
{
  b->ArgNames(withThreads ? std::vector<std::string>{ "tri_exp", "levels", "threads" }
                          : std::vector<std::string>{ "tri_exp", "levels" });
  for (int levels = 1; levels <= 4; ++levels)
    for (int exponent = 3; exponent <= 6; ++exponent)
    {
      if (std::pow(10.0, exponent) / std::pow(4.0, levels) < 24.0)
        continue; // the input would be smaller than the coarsest sphere
      if (withThreads)
      {
        b->Args({ exponent, levels, 0 });
        if (exponent == 6)
          b->Args({ exponent, levels, 1 });
      }
      else
        b->Args({ exponent, levels });
    }
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.2);
}

BENCHMARK(BM_Uniform_AdaptiveLoopFilter)->Apply([](benchmark::internal::Benchmark* b) { UniformArguments(b, true); });
BENCHMARK(BM_Uniform_Core)->Apply([](benchmark::internal::Benchmark* b) { UniformArguments(b, false); });
BENCHMARK(BM_Uniform_vtkLoopSubdivisionFilter)->Apply([](benchmark::internal::Benchmark* b) {
  UniformArguments(b, false);
});
BENCHMARK(BM_Uniform_CGAL_Loop)->Apply([](benchmark::internal::Benchmark* b) { UniformArguments(b, false); });

// ---- adaptive mode on a leaf blade --------------------------------------------------------------------------------

constexpr int ReferenceLevel = 4;

/// The ginkgo blade (quality mesh, Resolution 24, 2,340 triangles), bent into a curved surface.
vtkSmartPointer<vtkPolyData> BentBlade()
{
  vtkNew<vtkLeafOutlineSource> source;
  source->SetResolution(24);
  source->Update();
  auto blade = vtkSmartPointer<vtkPolyData>::New();
  blade->DeepCopy(source->GetOutput(0));
  for (vtkIdType i = 0; i < blade->GetNumberOfPoints(); ++i)
  {
    double p[3];
    blade->GetPoint(i, p);
    p[2] = 0.6 * std::sin(0.8 * p[0]) * std::cos(0.5 * p[1]) + 0.05 * p[0] * p[0];
    blade->GetPoints()->SetPoint(i, p);
  }
  return blade;
}

struct BladeSetting
{
  double angle = 180.0;
  double flatness = 1.0;
  int levels = 1;
};

void Apply(vtkAdaptiveLoopFilter* f, const BladeSetting& s)
{
  f->SetMaximumLevel(s.levels);
  f->SetEdgeAngleThreshold(s.angle);
  f->SetFlatnessThreshold(s.flatness);
  f->SetFeatureRule(vtkAdaptiveLoopFilter::FIXED);
}

/// A triangle surface on flat arrays, and its exact point-to-surface distance structure (BVH).
struct Surface
{
  std::vector<double> points;
  std::vector<std::int64_t> triangles;
  plantmorph::PointSurfaceDistance distance;

  explicit Surface(vtkPolyData* data)
  {
    const vtkIdType n = data->GetNumberOfPoints();
    this->points.resize(3 * static_cast<std::size_t>(n));
    for (vtkIdType i = 0; i < n; ++i)
      data->GetPoint(i, this->points.data() + 3 * i);
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c)
    {
      data->GetCellPoints(c, ids);
      for (int k = 0; k < 3; ++k)
        this->triangles.push_back(ids->GetId(k));
    }
    const std::string error = this->distance.BuildSurface(
      this->points.data(), static_cast<std::size_t>(n), this->triangles.data(), this->triangles.size() / 3);
    if (!error.empty())
      throw std::runtime_error("blade study: " + error);
  }

  std::size_t NumberOfPoints() const { return this->points.size() / 3; }

  /// The largest exact distance from `other`'s points to this surface.
  double MaxDistanceFrom(const Surface& other) const
  {
    std::vector<double> d(other.NumberOfPoints());
    this->distance.QueryMany(other.points.data(), d.size(), d.data(), nullptr, nullptr, nullptr);
    return d.empty() ? 0.0 : *std::max_element(d.begin(), d.end());
  }
};

/// Deviation of a mesh from the reference (uniform level-4) surface S: both one-sided maxima of exact
/// point-to-triangle distances, from the mesh's points to S ("to") and from S's points to the mesh ("from", which
/// sees the chords of triangles left too large). The study's deviation is the larger of the two: a vertex-sampled
/// Hausdorff distance (S is 16x finer than any compared mesh's input and its vertices sample it densely).
struct Deviation
{
  double to = 0.0;
  double from = 0.0;
  double Max() const { return std::max(this->to, this->from); }
};

Deviation Measure(vtkPolyData* mesh, const Surface& reference)
{
  const Surface surface(mesh);
  return { reference.MaxDistanceFrom(surface), surface.MaxDistanceFrom(reference) };
}

struct BladeStudy
{
  vtkSmartPointer<vtkPolyData> blade;
  std::map<int, Deviation> uniformDeviation;    // by level
  std::map<int, vtkIdType> uniformTriangles;    // by level
  std::map<int, BladeSetting> adaptive;         // cheapest setting within the uniform deviation, by level
  std::map<int, Deviation> adaptiveDeviation;
  std::map<int, vtkIdType> adaptiveTriangles;
  int evaluations = 0;
  double seconds = 0.0;
};

// The sweep: for every target level L, adaptive runs of L .. min(L + 2, ReferenceLevel) levels, and for each a
// bisection on the threshold angle alpha = 180 - EdgeAngleThreshold (an edge splits where its triangles' normals
// differ by more than alpha) in log10(alpha) over [AlphaLow, AlphaHigh] degrees, AngleSteps halvings (resolution
// 3.7% in alpha): the triangle count falls as alpha grows, the deviation rises. FlatnessThreshold is either 1
// (every vertex moves) or tied to alpha, lambda = cos(c * alpha) for c in FlatnessFactors: a vertex whose
// triangles' normals all lie within about c * alpha of its normal keeps its place, the vertex twin of the edge
// rule (a vertex that keeps moving on an unrefined neighbourhood is smoothed again at every level and drifts from
// the uniform surface). Every evaluated setting within the target competes for the fewest triangles.
constexpr double AlphaLow = 1e-3;
constexpr double AlphaHigh = 10.0;
constexpr int AngleSteps = 8;
constexpr double FlatnessFactors[] = { 0.0, 0.5, 1.0, 2.0 }; // 0: lambda = 1

/// Untimed, once: the reference, the uniform deviations, and the adaptive search.
const BladeStudy& Study()
{
  static const BladeStudy study = [] {
    const auto started = std::chrono::steady_clock::now();
    BladeStudy s;
    s.blade = BentBlade();
    const Surface reference(
      RunFilter(s.blade, [](vtkAdaptiveLoopFilter* f) { Apply(f, BladeSetting{ 180.0, 1.0, ReferenceLevel }); }));
    for (int level = 1; level < ReferenceLevel; ++level)
    {
      const auto uniform =
        RunFilter(s.blade, [level](vtkAdaptiveLoopFilter* f) { Apply(f, BladeSetting{ 180.0, 1.0, level }); });
      s.uniformDeviation[level] = Measure(uniform, reference);
      s.uniformTriangles[level] = uniform->GetNumberOfCells();
    }
    for (int level = 1; level < ReferenceLevel; ++level)
    {
      const double target = s.uniformDeviation[level].Max();
      vtkIdType best = -1;
      const auto evaluate = [&](const BladeSetting& setting) {
        const auto out = RunFilter(s.blade, [&setting](vtkAdaptiveLoopFilter* f) { Apply(f, setting); });
        const vtkIdType n = out->GetNumberOfCells();
        const Deviation deviation = Measure(out, reference);
        ++s.evaluations;
        const bool within = deviation.Max() <= target;
        if (std::getenv("PLANTMORPH_BLADE_SWEEP_LOG"))
          std::fprintf(stderr,
            "target L%d %.4g: levels %d alpha %.5f 1-flatness %.3g -> %lld triangles, to %.4g from %.4g%s\n", level,
            target, setting.levels, 180.0 - setting.angle, 1.0 - setting.flatness, static_cast<long long>(n),
            deviation.to, deviation.from, within ? " within" : "");
        if (within && (best < 0 || n < best))
        {
          best = n;
          s.adaptive[level] = setting;
          s.adaptiveDeviation[level] = deviation;
          s.adaptiveTriangles[level] = n;
        }
        return within;
      };
      for (int levels = level; levels <= std::min(level + 2, ReferenceLevel); ++levels)
        for (const double factor : FlatnessFactors)
        {
          const auto setting = [levels, factor](double alpha) {
            const double flatness = factor > 0.0 ? std::cos(factor * alpha * 3.14159265358979323846 / 180.0) : 1.0;
            return BladeSetting{ 180.0 - alpha, flatness, levels };
          };
          double low = std::log10(AlphaLow), high = std::log10(AlphaHigh); // low: within, high: not (assumed)
          if (!evaluate(setting(AlphaLow)))
            continue; // even the finest threshold misses the target with these levels and this flatness rule
          for (int step = 0; step < AngleSteps; ++step)
          {
            const double mid = 0.5 * (low + high);
            (evaluate(setting(std::pow(10.0, mid))) ? low : high) = mid;
          }
        }
    }
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return s;
  }();
  return study;
}

void BM_Blade_Uniform(benchmark::State& state)
{
  const int level = static_cast<int>(state.range(0));
  const BladeStudy& study = Study();
  double triangles = 0.0;
  for (auto _ : state)
  {
    const auto out =
      RunFilter(study.blade, [level](vtkAdaptiveLoopFilter* f) { Apply(f, BladeSetting{ 180.0, 1.0, level }); });
    triangles = static_cast<double>(out->GetNumberOfCells());
  }
  ReportTriangles(state, triangles);
  state.counters["deviation"] = study.uniformDeviation.at(level).Max();
  state.counters["deviation_to"] = study.uniformDeviation.at(level).to;
  state.counters["deviation_from"] = study.uniformDeviation.at(level).from;
  state.counters["input_triangles"] = static_cast<double>(study.blade->GetNumberOfCells());
}

void BM_Blade_Adaptive(benchmark::State& state)
{
  const int level = static_cast<int>(state.range(0));
  const BladeStudy& study = Study();
  if (!study.adaptive.count(level))
  {
    state.SkipWithError("no adaptive setting reached the uniform deviation");
    return;
  }
  const BladeSetting setting = study.adaptive.at(level);
  double triangles = 0.0;
  for (auto _ : state)
  {
    const auto out = RunFilter(study.blade, [&setting](vtkAdaptiveLoopFilter* f) { Apply(f, setting); });
    triangles = static_cast<double>(out->GetNumberOfCells());
  }
  ReportTriangles(state, triangles);
  state.counters["deviation"] = study.adaptiveDeviation.at(level).Max();
  state.counters["deviation_to"] = study.adaptiveDeviation.at(level).to;
  state.counters["deviation_from"] = study.adaptiveDeviation.at(level).from;
  state.counters["uniform_deviation"] = study.uniformDeviation.at(level).Max();
  state.counters["triangle_ratio"] = triangles / static_cast<double>(study.uniformTriangles.at(level));
  state.counters["angle"] = setting.angle;
  state.counters["alpha"] = 180.0 - setting.angle;
  state.counters["flatness_1m"] = 1.0 - setting.flatness;
  state.counters["levels"] = setting.levels;
  state.counters["sweep_runs"] = study.evaluations;
  state.counters["sweep_s"] = study.seconds;
}

BENCHMARK(BM_Blade_Uniform)->ArgName("levels")->DenseRange(1, ReferenceLevel - 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Blade_Adaptive)->ArgName("levels")->DenseRange(1, ReferenceLevel - 1)->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace

BENCHMARK_MAIN();
