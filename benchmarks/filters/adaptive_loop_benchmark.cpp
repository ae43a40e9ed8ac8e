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
// from the level-4 uniform surface, and the adaptive settings (swept untimed, once) that reach that deviation with
// the fewest triangles:
//   BM_Blade_Uniform/levels:L, BM_Blade_Adaptive/levels:L
//
// Counters: triangles (output), tri_per_s (output triangles per wall second: the filters are threaded), in_bytes /
// out_bytes (vtkPolyData::GetActualMemorySize of input / output, or the CGAL mesh's element storage), peak_bytes
// (VmHWM above the resident set before the runs, reset with `echo 5 > /proc/self/clear_refs`, as
// blade_generation_benchmark does), peak_ratio = peak_bytes / (in_bytes + out_bytes).
#include "AdaptiveLoopSubdivision.h"
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
#include "vtkStaticCellLocator.h"

#include "PeakMemory.h"

#include <benchmark/benchmark.h>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Subdivision_method_3/subdivision_methods_3.h>
#include <CGAL/Surface_mesh.h>

#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <map>
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

/// The ginkgo blade (quality mesh, Resolution 24), bent into a curved surface.
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

/// Largest distance from the reference surface's points to `mesh`, and from `mesh`'s points to the reference.
double Deviation(vtkPolyData* mesh, vtkPolyData* reference, vtkStaticCellLocator* referenceLocator)
{
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(mesh);
  locator->BuildLocator();
  double worst = 0.0;
  double closest[3], d2;
  vtkIdType cell;
  int sub;
  for (vtkIdType i = 0; i < reference->GetNumberOfPoints(); ++i)
  {
    double p[3];
    reference->GetPoint(i, p);
    locator->FindClosestPoint(p, closest, cell, sub, d2);
    worst = std::max(worst, d2);
  }
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    double p[3];
    mesh->GetPoint(i, p);
    referenceLocator->FindClosestPoint(p, closest, cell, sub, d2);
    worst = std::max(worst, d2);
  }
  return std::sqrt(worst);
}

struct BladeStudy
{
  vtkSmartPointer<vtkPolyData> blade;
  std::map<int, double> uniformDeviation;       // by level
  std::map<int, vtkIdType> uniformTriangles;    // by level
  std::map<int, BladeSetting> adaptive;         // cheapest setting within the uniform deviation, by level
  std::map<int, double> adaptiveDeviation;
  std::map<int, vtkIdType> adaptiveTriangles;
};

/// Untimed, once: the reference, the uniform deviations, and a sweep of adaptive settings.
const BladeStudy& Study()
{
  static const BladeStudy study = [] {
    BladeStudy s;
    s.blade = BentBlade();
    const vtkSmartPointer<vtkPolyData> reference =
      RunFilter(s.blade, [](vtkAdaptiveLoopFilter* f) { Apply(f, BladeSetting{ 180.0, 1.0, ReferenceLevel }); });
    vtkNew<vtkStaticCellLocator> referenceLocator;
    referenceLocator->SetDataSet(reference);
    referenceLocator->BuildLocator();
    for (int level = 1; level < ReferenceLevel; ++level)
    {
      const auto uniform =
        RunFilter(s.blade, [level](vtkAdaptiveLoopFilter* f) { Apply(f, BladeSetting{ 180.0, 1.0, level }); });
      s.uniformDeviation[level] = Deviation(uniform, reference, referenceLocator);
      s.uniformTriangles[level] = uniform->GetNumberOfCells();
    }
    for (int level = 1; level < ReferenceLevel; ++level)
    {
      vtkIdType best = -1;
      for (int levels = level; levels <= ReferenceLevel; ++levels)
        for (const double angle : { 170.0, 174.0, 176.0, 177.0, 178.0, 178.5, 179.0, 179.5 })
          for (const double flatness : { 0.99, 0.995, 0.998, 0.999, 0.9995, 0.9998, 1.0 })
          {
            const BladeSetting setting{ angle, flatness, levels };
            const auto out = RunFilter(s.blade, [&setting](vtkAdaptiveLoopFilter* f) { Apply(f, setting); });
            const vtkIdType n = out->GetNumberOfCells();
            if (best >= 0 && n >= best)
              continue;
            const double deviation = Deviation(out, reference, referenceLocator);
            if (deviation <= s.uniformDeviation[level])
            {
              best = n;
              s.adaptive[level] = setting;
              s.adaptiveDeviation[level] = deviation;
              s.adaptiveTriangles[level] = n;
            }
          }
    }
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
  state.counters["deviation"] = study.uniformDeviation.at(level);
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
  state.counters["deviation"] = study.adaptiveDeviation.at(level);
  state.counters["uniform_deviation"] = study.uniformDeviation.at(level);
  state.counters["triangle_ratio"] = triangles / static_cast<double>(study.uniformTriangles.at(level));
  state.counters["angle"] = setting.angle;
  state.counters["flatness"] = setting.flatness;
  state.counters["levels"] = setting.levels;
}

BENCHMARK(BM_Blade_Uniform)->ArgName("levels")->DenseRange(1, ReferenceLevel - 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Blade_Adaptive)->ArgName("levels")->DenseRange(1, ReferenceLevel - 1)->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace

BENCHMARK_MAIN();
