// SPDX-License-Identifier: GPL-3.0-or-later
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
// Adaptive mode on leaf blades (BladeKind: the bent ginkgo blade, paper 003's cucumber and pin oak from
// LeafOutlineSource curled by LeafCurlFilter, and the cucumber and ginkgo under FeatureRule Loop; two held-out curled
// blades, an elliptic one and the pin oak curled otherwise, not used to choose any constant): the deviation of
// uniform level L from the level-4 uniform surface (exact point-to-triangle distances both ways, see Deviation
// below; maximum and RMS), and the adaptive settings (searched untimed, once per blade: levels, bisection on the
// threshold angle with two flatness rules for the paper's DihedralAngle rule, bisection on ErrorTolerance for the
// SurfaceError and ChordError rules) with the fewest triangles within that deviation. PLANTMORPH_BLADE_SWEEP_LOG=1
// prints every evaluated setting to stderr (the triangles-versus-deviation curve); PLANTMORPH_BLADE_RULES=12 (the
// digits of the RefinementRule values) searches those rules only (default all three):
//   BM_Blade_Uniform/blade:B/levels:L, BM_Blade_Adaptive/blade:B/levels:L/rule:R/rms:C (C = 1: within the RMS)
//
// Counters: triangles (output), tri_per_s (output triangles per wall second: the filters are threaded), in_bytes /
// out_bytes (vtkPolyData::GetActualMemorySize of input / output, or the CGAL mesh's element storage), peak_bytes
// (VmHWM above the resident set before the runs, reset with `echo 5 > /proc/self/clear_refs`, as
// blade_generation_benchmark does), peak_ratio = peak_bytes / (in_bytes + out_bytes).
#include "AdaptiveLoopSubdivision.h"
#include "PointSurfaceDistance.h"
#include "vtkAdaptiveLoopFilter.h"
#include "vtkLeafCurlFilter.h"
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
  plantmorph::AdaptiveLoopParameters settings;
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
    outBytes = static_cast<double>(
      result.mesh.points.size() * 8 + result.mesh.triangles.size() * 4 + result.mesh.origin.size() * 4);
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
  return static_cast<double>(
    m.number_of_vertices() * (sizeof(Kernel::Point_3) + 4) + m.number_of_halfedges() * 16 + m.number_of_faces() * 4);
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

// ---- adaptive mode on leaf blades --------------------------------------------------------------------------------

constexpr int ReferenceLevel = 4;

enum BladeKind
{
  GinkgoBent = 0,         ///< the ginkgo blade (quality mesh, Resolution 24), z = 0.6 sin(0.8x) cos(0.5y) + 0.05x^2
  CucumberCurled = 1,     ///< paper 003's B-spline cucumber, curled 60 deg longitudinally and 40 deg transversely
  PinOakCurled = 2,       ///< paper 003's B-spline pin oak, curled 45 and -30 deg
  CucumberCurledLoop = 3, ///< the cucumber with FeatureRule Loop (margin and midvein smoothed, not fixed)
  GinkgoBentLoop = 4,     ///< the bent ginkgo with FeatureRule Loop
  // Held out: not used to choose the Chord error rule's constants, a check that they carry over (Fixed).
  EllipticCurled = 5, ///< paper 003's B-spline elliptic blade, Resolution 28, curled 50 and 35 deg
  PinOakCurledB = 6,  ///< the pin oak at Resolution 32, curled -40 and 45 deg (rolled down, bent the other way)
};
constexpr int BladeKinds = 7;

const char* BladeName(int kind)
{
  static const char* names[] = { "ginkgo_bent", "cucumber_curled", "pin_oak_curled", "cucumber_curled_loop",
    "ginkgo_bent_loop", "elliptic_curled", "pin_oak_curled_b" };
  return names[kind];
}

vtkSmartPointer<vtkPolyData> CurledBSpline(int preset, int resolution, double longitudinal, double transverse)
{
  vtkNew<vtkLeafOutlineSource> source;
  source->SetModel(vtkLeafOutlineSource::B_SPLINE);
  source->SetBSplinePreset(preset);
  source->SetResolution(resolution);
  vtkNew<vtkLeafCurlFilter> curl;
  curl->SetInputConnection(source->GetOutputPort(0));
  curl->SetLongitudinalAngle(longitudinal);
  curl->SetTransverseAngle(transverse);
  curl->Update();
  auto blade = vtkSmartPointer<vtkPolyData>::New();
  blade->DeepCopy(curl->GetOutput());
  return blade;
}

vtkSmartPointer<vtkPolyData> MakeBlade(int kind)
{
  if (kind == CucumberCurled || kind == CucumberCurledLoop)
    return CurledBSpline(2, 24, 60.0, 40.0);
  if (kind == PinOakCurled)
    return CurledBSpline(3, 40, 45.0, -30.0);
  if (kind == EllipticCurled)
    return CurledBSpline(1, 28, 50.0, 35.0);
  if (kind == PinOakCurledB)
    return CurledBSpline(3, 32, -40.0, 45.0);
  vtkNew<vtkLeafOutlineSource> source;
  // Paper 000's ginkgo at b_y = 5: a blade 5 (1.6 + 0.05 sin(-1.5)) = 7.75 long (Length is the blade's length, base to
  // apex), the size the bend below and the README's measured ratios are for.
  source->SetLength(5.0 * (1.6 + 0.05 * std::sin(-1.5)));
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

int BladeFeatureRule(int kind)
{
  return (kind == CucumberCurledLoop || kind == GinkgoBentLoop) ? vtkAdaptiveLoopFilter::LOOP
                                                                : vtkAdaptiveLoopFilter::FIXED;
}

struct BladeSetting
{
  int rule = vtkAdaptiveLoopFilter::DIHEDRAL_ANGLE;
  double angle = 180.0;
  double flatness = 1.0;
  double tolerance = 0.0;
  int levels = 1;
  int featureRule = vtkAdaptiveLoopFilter::FIXED;
};

void Apply(vtkAdaptiveLoopFilter* f, const BladeSetting& s)
{
  f->SetMaximumLevel(s.levels);
  f->SetRefinementRule(s.rule);
  f->SetEdgeAngleThreshold(s.angle);
  f->SetFlatnessThreshold(s.flatness);
  f->SetErrorTolerance(s.tolerance);
  f->SetFeatureRule(s.featureRule);
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

  /// Exact distances from `other`'s points to this surface.
  std::vector<double> DistancesFrom(const Surface& other) const
  {
    std::vector<double> d(other.NumberOfPoints());
    this->distance.QueryMany(other.points.data(), d.size(), d.data(), nullptr, nullptr, nullptr);
    return d;
  }
};

/// Deviation of a mesh M from the reference (uniform level-4) surface S: both one-sided maxima of exact
/// point-to-triangle distances, from M's points to S ("to") and from S's points to M ("from", which sees the chords
/// of triangles left too large). The study's deviation is the larger of the two: a vertex-sampled Hausdorff
/// distance (S is 16x finer than any compared mesh's input and its vertices sample it densely). `rms` is the root
/// mean square of the "from" distances (S's points sample the surface nearly uniformly by area).
struct Deviation
{
  double to = 0.0;
  double from = 0.0;
  double rms = 0.0;
  double Max() const { return std::max(this->to, this->from); }
};

Deviation Measure(vtkPolyData* mesh, const Surface& reference)
{
  const Surface surface(mesh);
  const std::vector<double> to = reference.DistancesFrom(surface);
  const std::vector<double> from = surface.DistancesFrom(reference);
  Deviation d;
  d.to = to.empty() ? 0.0 : *std::max_element(to.begin(), to.end());
  d.from = from.empty() ? 0.0 : *std::max_element(from.begin(), from.end());
  double sum = 0.0;
  for (double x : from)
    sum += x * x;
  d.rms = from.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(from.size()));
  return d;
}

struct Best
{
  BladeSetting setting;
  Deviation deviation;
  vtkIdType triangles = -1;
};

struct BladeStudy
{
  vtkSmartPointer<vtkPolyData> blade;
  double length = 1.0;                       // bounding-box diagonal
  std::map<int, Deviation> uniformDeviation; // by level
  std::map<int, vtkIdType> uniformTriangles; // by level
  // cheapest setting within uniform level L's maximum deviation ([0]) or RMS deviation ([1]), by rule, by level
  std::map<int, std::map<int, Best>> best[2];
  int evaluations = 0;
  double seconds = 0.0;
};

// The searches, for every target level L (uniform level L's deviation), with adaptive runs of L .. min(L + 2, 4)
// levels:
// - DihedralAngle (the paper's rules): a bisection on alpha = 180 - EdgeAngleThreshold (an edge splits where its
//   triangles' normals differ by more than alpha) in log10(alpha) over [AlphaLow, AlphaHigh] degrees, AngleSteps
//   halvings (3.7% resolution); FlatnessThreshold 1 (every vertex moves) or lambda = cos(alpha) (a vertex whose
//   triangles' normals lie within about alpha of its normal stays). An earlier search also tried cos(c alpha) for
//   c = 0.5 and 2: no better.
// - SurfaceError and ChordError: a bisection on log10(ErrorTolerance / L0) over [1e-7, 1e-1], ToleranceSteps
//   halvings, L0 the blade's bounding-box diagonal.
// The cost grows as the deviation falls, so the bisection keeps the largest threshold within the target; every
// evaluated setting within the target competes for the fewest triangles.
constexpr double AlphaLow = 1e-3;
constexpr double AlphaHigh = 10.0;
constexpr int AngleSteps = 8;
constexpr double FlatnessFactors[] = { 0.0, 1.0 }; // 0: lambda = 1
constexpr double ToleranceLow = 1e-7;
constexpr double ToleranceHigh = 1e-1;
constexpr int ToleranceSteps = 10;

/// Untimed, once per blade: the reference, the uniform deviations, and the adaptive searches.
const BladeStudy& Study(int kind)
{
  static std::map<int, BladeStudy> studies;
  if (studies.count(kind))
    return studies.at(kind);
  const auto started = std::chrono::steady_clock::now();
  BladeStudy& s = studies[kind];
  s.blade = MakeBlade(kind);
  s.length = std::sqrt(s.blade->GetLength2());
  const int featureRule = BladeFeatureRule(kind);
  const auto uniform = [featureRule](int levels) {
    BladeSetting u;
    u.levels = levels;
    u.featureRule = featureRule;
    return u;
  };
  const Surface reference(RunFilter(s.blade, [&](vtkAdaptiveLoopFilter* f) { Apply(f, uniform(ReferenceLevel)); }));
  for (int level = 0; level < ReferenceLevel; ++level)
  {
    const auto out = RunFilter(s.blade, [&](vtkAdaptiveLoopFilter* f) { Apply(f, uniform(level)); });
    s.uniformDeviation[level] = Measure(out, reference);
    s.uniformTriangles[level] = out->GetNumberOfCells();
  }
  const bool log = std::getenv("PLANTMORPH_BLADE_SWEEP_LOG") != nullptr;
  // PLANTMORPH_BLADE_RULES: the digits of the rules to search (default all).
  const char* rules = std::getenv("PLANTMORPH_BLADE_RULES");
  const auto searched = [rules](int rule) {
    return rules == nullptr || std::string(rules).find(static_cast<char>('0' + rule)) != std::string::npos;
  };
  const bool dihedral = searched(vtkAdaptiveLoopFilter::DIHEDRAL_ANGLE);
  for (int level = 1; level < ReferenceLevel; ++level)
  {
    const Deviation target = s.uniformDeviation[level];
    const auto evaluate = [&](const BladeSetting& setting) {
      const auto out = RunFilter(s.blade, [&setting](vtkAdaptiveLoopFilter* f) { Apply(f, setting); });
      const vtkIdType n = out->GetNumberOfCells();
      const Deviation deviation = out->GetNumberOfCells() > 0 ? Measure(out, reference) : Deviation{ 1e9, 1e9, 1e9 };
      ++s.evaluations;
      const bool within[2] = { deviation.Max() <= target.Max(), deviation.rms <= target.rms };
      if (log)
        std::fprintf(stderr,
          "%s target L%d %.4g/%.4g: rule %d levels %d alpha %.5f 1-flatness %.3g tol %.4g -> %lld triangles "
          "(%.3f of uniform), to %.4g from %.4g rms %.4g%s%s\n",
          BladeName(kind), level, target.Max(), target.rms, setting.rule, setting.levels, 180.0 - setting.angle,
          1.0 - setting.flatness, setting.tolerance, static_cast<long long>(n),
          static_cast<double>(n) / static_cast<double>(s.uniformTriangles[level]), deviation.to, deviation.from,
          deviation.rms, within[0] ? " within-max" : "", within[1] ? " within-rms" : "");
      for (int c = 0; c < 2; ++c)
      {
        Best& b = s.best[c][setting.rule][level];
        if (within[c] && (b.triangles < 0 || n < b.triangles))
          b = Best{ setting, deviation, n };
      }
      return within[0];
    };
    for (int levels = level; levels <= std::min(level + 2, ReferenceLevel); ++levels)
    {
      if (dihedral)
        for (const double factor : FlatnessFactors)
        {
          const auto setting = [&](double alpha) {
            BladeSetting b = uniform(levels);
            b.angle = 180.0 - alpha;
            b.flatness = factor > 0.0 ? std::cos(factor * alpha * 3.14159265358979323846 / 180.0) : 1.0;
            return b;
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
      for (const int rule : { vtkAdaptiveLoopFilter::SURFACE_ERROR, vtkAdaptiveLoopFilter::CHORD_ERROR })
      {
        if (!searched(rule))
          continue;
        const auto setting = [&](double relative) {
          BladeSetting b = uniform(levels);
          b.rule = rule;
          b.tolerance = relative * s.length;
          return b;
        };
        double low = std::log10(ToleranceLow), high = std::log10(ToleranceHigh);
        if (!evaluate(setting(ToleranceLow)))
          continue;
        for (int step = 0; step < ToleranceSteps; ++step)
        {
          const double mid = 0.5 * (low + high);
          (evaluate(setting(std::pow(10.0, mid))) ? low : high) = mid;
        }
      }
    }
  }
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return s;
}

void BM_Blade_Uniform(benchmark::State& state)
{
  const int kind = static_cast<int>(state.range(0));
  const int level = static_cast<int>(state.range(1));
  const BladeStudy& study = Study(kind);
  BladeSetting setting;
  setting.levels = level;
  setting.featureRule = BladeFeatureRule(kind);
  double triangles = 0.0;
  for (auto _ : state)
  {
    const auto out = RunFilter(study.blade, [&](vtkAdaptiveLoopFilter* f) { Apply(f, setting); });
    triangles = static_cast<double>(out->GetNumberOfCells());
  }
  ReportTriangles(state, triangles);
  state.SetLabel(BladeName(kind));
  state.counters["deviation"] = study.uniformDeviation.at(level).Max();
  state.counters["deviation_to"] = study.uniformDeviation.at(level).to;
  state.counters["deviation_from"] = study.uniformDeviation.at(level).from;
  state.counters["deviation_rms"] = study.uniformDeviation.at(level).rms;
  state.counters["input_triangles"] = static_cast<double>(study.blade->GetNumberOfCells());
  state.counters["blade_diagonal"] = study.length;
}

/// range(2): the refinement rule; range(3): 0 = within the maximum deviation, 1 = within the RMS deviation.
void BM_Blade_Adaptive(benchmark::State& state)
{
  const int kind = static_cast<int>(state.range(0));
  const int level = static_cast<int>(state.range(1));
  const int rule = static_cast<int>(state.range(2));
  const int criterion = static_cast<int>(state.range(3));
  const BladeStudy& study = Study(kind);
  const auto& byRule = study.best[criterion];
  if (!byRule.count(rule) || !byRule.at(rule).count(level))
  {
    state.SkipWithError("no adaptive setting reached the uniform deviation");
    return;
  }
  const Best& best = byRule.at(rule).at(level);
  double triangles = 0.0;
  for (auto _ : state)
  {
    const auto out = RunFilter(study.blade, [&best](vtkAdaptiveLoopFilter* f) { Apply(f, best.setting); });
    triangles = static_cast<double>(out->GetNumberOfCells());
  }
  ReportTriangles(state, triangles);
  state.SetLabel(BladeName(kind));
  state.counters["deviation"] = best.deviation.Max();
  state.counters["deviation_to"] = best.deviation.to;
  state.counters["deviation_from"] = best.deviation.from;
  state.counters["deviation_rms"] = best.deviation.rms;
  state.counters["uniform_deviation"] = study.uniformDeviation.at(level).Max();
  state.counters["uniform_rms"] = study.uniformDeviation.at(level).rms;
  state.counters["triangle_ratio"] = triangles / static_cast<double>(study.uniformTriangles.at(level));
  state.counters["alpha"] = 180.0 - best.setting.angle;
  state.counters["flatness_1m"] = 1.0 - best.setting.flatness;
  state.counters["tolerance"] = best.setting.tolerance;
  state.counters["levels"] = best.setting.levels;
  state.counters["sweep_runs"] = study.evaluations;
  state.counters["sweep_s"] = study.seconds;
}

BENCHMARK(BM_Blade_Uniform)
  ->ArgNames({ "blade", "levels" })
  ->ArgsProduct(
    { benchmark::CreateDenseRange(0, BladeKinds - 1, 1), benchmark::CreateDenseRange(1, ReferenceLevel - 1, 1) })
  ->Unit(benchmark::kMillisecond)
  ->UseRealTime();
BENCHMARK(BM_Blade_Adaptive)
  ->ArgNames({ "blade", "levels", "rule", "rms" })
  ->ArgsProduct({ benchmark::CreateDenseRange(0, BladeKinds - 1, 1),
    benchmark::CreateDenseRange(1, ReferenceLevel - 1, 1), { 0, 1, 2 }, { 0, 1 } })
  ->Unit(benchmark::kMillisecond)
  ->UseRealTime();

} // namespace

BENCHMARK_MAIN();
