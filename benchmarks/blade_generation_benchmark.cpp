// SPDX-License-Identifier: GPL-3.0-or-later
// Blade generation cost versus Resolution: the whole plantmorph::BuildDeformedRectangleLeaf call for the ginkgo
// preset (b_y = 5), in quality mode (CGAL Delaunay refinement) and paper mode (plain constrained Delaunay of the
// boundary samples), next to CGAL alone on the very same boundary as the baseline to compare with.
//
// Families (argument: Resolution, segments along the midvein):
//   BM_BladeQuality      BuildDeformedRectangleLeaf, quality = true  (~4*R^2 triangles: 1e3 .. 1e6)
//   BM_BladePaper        BuildDeformedRectangleLeaf, quality = false (linear in R: far fewer triangles)
//   BM_CgalRefineSameBoundary  CGAL alone: spatially sorted CDT of the same outline and midvein + the same
//                        Delaunay_mesher_no_edge_refinement_2 criteria (B = 0.125, max edge = midvein spacing),
//                        one-shot refine_mesh(); no sampling, validation, LeafUV or output copy. A lower bound
//                        for BM_BladeQuality.
//   BM_CgalCdtSameBoundary     CGAL alone: spatially sorted CDT of the same outline + domain marking. A lower bound
//                        for BM_BladePaper.
//   BM_SpaceCurveIntegration   Model B's outline: Frenet-Serret integration of a half-margin (paper 002 Fig. 5),
//                        R + 1 samples, RK45 at 1e-10.
//   BM_SpaceCurveLeaf    Model B's whole leaf (Fig. 5): integration, mirror, midvein, strips, normals.
//   BM_PalmateLeafQuality      Model B's palmate leaf (Fig. 8, 5 lobes, quality mode).
//   BM_BSplineLeafQuality      Model C's whole leaf (pin oak, quality mode).
//
// Counters:
//   triangles     triangles of the blade (in the domain, for the CGAL families)
//   tri_per_s     triangles per CPU second
//   s_per_tri     CPU seconds per triangle (printed with SI prefix: 1.5u = 1.5 microseconds)
//   out_bytes     bytes of the output mesh: size() of blade.points, uv, region and triangles (not capacity, not
//                 tcoords/margins); 0 for the CGAL families, which copy nothing out
//   peak_bytes    peak resident memory the measured runs added above the resident set just before them
//   peak_ratio    peak_bytes / out_bytes
//   vm_hwm        the process's VmHWM (peak resident set) over the measured runs, absolute
//
// How the per-run peak is measured: before the timed loop (untimed) malloc_trim(0) hands freed heap pages back to
// the kernel, the baseline VmRSS is read, and writing "5" to /proc/self/clear_refs resets VmHWM to the current
// resident set (Linux >= 4.0). After the loop VmHWM is read again: peak_bytes = VmHWM - baseline, the most memory
// resident at any moment of those runs. Several iterations reuse the same freed heap, so this is the peak of one
// run. If clear_refs cannot be written, the counter peak_reset is 0 and vm_hwm is the whole process's peak so far.
//
// Timing: the rates use process CPU time (user + system, so page faults count), not wall time, because the code is
// single-threaded and a shared 2-core machine inflates wall time; both columns are printed. Small sizes repeat for
// at least 0.2 s of CPU time; sizes slower than that run once (one iteration is then the whole measurement).

#include "BSplineLeaf.h"
#include "DeformedRectangleLeaf.h"
#include "DeformedRectangleModel.h"
#include "DeformedRectanglePresets.h"
#include "LeafGeometry.h"
#include "SpaceCurvePresets.h"

#include "PeakMemory.h"

#include <benchmark/benchmark.h>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <malloc.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace
{
constexpr double GinkgoLength = 5.0;
constexpr double ShapeBound = 0.125; // BladeMeshParameters' default, as the plugin uses it
constexpr double MinSeconds = 0.2;

// Quality mode makes ~4*R^2 triangles: 16 -> ~1e3, 512 -> ~1e6, in steps of sqrt(2) (twice the triangles).
const std::vector<int64_t> Resolutions = { 16, 23, 32, 45, 64, 91, 128, 181, 256, 362, 512 };
// Paper mode is cheap, so it also runs up to the property's maximum (4000).
const std::vector<int64_t> PaperOnlyResolutions = { 1024, 2048, 4000 };

using plantmorph_benchmarks::PeakMemoryProbe;

void ReportTriangles(benchmark::State& state, std::size_t triangles)
{
  const double t = static_cast<double>(triangles);
  state.counters["triangles"] = t;
  state.counters["tri_per_s"] = benchmark::Counter(t, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["s_per_tri"] =
    benchmark::Counter(t, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

double OutputBytes(const plantmorph::BladeMesh& blade)
{
  return static_cast<double>(blade.points.size() * sizeof(blade.points[0]) + blade.uv.size() * sizeof(blade.uv[0]) +
    blade.region.size() * sizeof(blade.region[0]) + blade.triangles.size() * sizeof(blade.triangles[0]));
}

// ---- the plugin's blade generation -------------------------------------------------------------------------------

/// Times `build(leaf)` (which returns an error message or "") and reports triangles, rates and peak memory.
template <typename Build>
void MeasureLeaf(benchmark::State& state, Build&& build)
{
  std::size_t triangles = 0;
  double outputBytes = 0.0;
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    plantmorph::LeafGeometry leaf;
    std::string error = build(leaf);
    benchmark::DoNotOptimize(error);
    benchmark::DoNotOptimize(leaf.blade.triangles.data());
    benchmark::ClobberMemory();
    if (!error.empty())
    {
      state.SkipWithError(error.c_str());
      break;
    }
    triangles = leaf.blade.triangles.size();
    outputBytes = OutputBytes(leaf.blade);
  }
  memory.Report(state, 0.0, outputBytes);
  ReportTriangles(state, triangles);
}

void RunBlade(benchmark::State& state, bool quality)
{
  const plantmorph::DeformedRectangleParameters parameters =
    plantmorph::MakeDeformedRectanglePreset(plantmorph::DeformedRectanglePreset::Ginkgo, GinkgoLength);
  plantmorph::LeafMeshParameters settings;
  settings.resolution = static_cast<int>(state.range(0));
  settings.quality = quality;
  MeasureLeaf(state,
    [&](plantmorph::LeafGeometry& leaf) { return plantmorph::BuildDeformedRectangleLeaf(parameters, settings, leaf); });
}

void BM_BladeQuality(benchmark::State& state)
{
  RunBlade(state, true);
}

void BM_BladePaper(benchmark::State& state)
{
  RunBlade(state, false);
}

// ---- CGAL alone on the same boundary -----------------------------------------------------------------------------

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using DataStructure = CGAL::Triangulation_data_structure_2<CGAL::Delaunay_mesh_vertex_base_2<Kernel>,
  CGAL::Delaunay_mesh_face_base_2<Kernel>>;
using Triangulation = CGAL::Constrained_Delaunay_triangulation_2<Kernel, DataStructure, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Triangulation>;
using Mesher = CGAL::Delaunay_mesher_no_edge_refinement_2<Triangulation, Criteria>;

/// The outline the plugin meshes at a resolution (its samples, the boundary loop and midvein as index pairs) and its
/// quality-mode size bound.
struct SameBoundary
{
  std::vector<Kernel::Point_2> points;
  std::vector<std::pair<std::size_t, std::size_t>> segments;
  double maxEdgeLength = 0.0;
  std::string error;
};

const SameBoundary& BoundaryAt(int resolution)
{
  static std::map<int, SameBoundary> cache;
  auto found = cache.find(resolution);
  if (found != cache.end())
    return found->second;
  SameBoundary& boundary = cache[resolution];

  const plantmorph::DeformedRectangleParameters parameters =
    plantmorph::MakeDeformedRectanglePreset(plantmorph::DeformedRectanglePreset::Ginkgo, GinkgoLength);
  // Paper mode adds no Steiner point: the blade's points are exactly the outline samples (midvein first), the same
  // ones quality mode starts from.
  plantmorph::LeafMeshParameters settings;
  settings.resolution = resolution;
  settings.quality = false;
  plantmorph::LeafGeometry leaf;
  boundary.error = plantmorph::BuildDeformedRectangleLeaf(parameters, settings, leaf);
  if (!boundary.error.empty())
    return boundary;
  for (const Eigen::Vector2d& p : leaf.blade.points)
    boundary.points.emplace_back(p.x(), p.y());
  // As the plugin builds it: up the right margin, down the left one (counter-clockwise), closed.
  std::vector<int> loop(leaf.rightMargin.begin(), leaf.rightMargin.end() - 1);
  loop.insert(loop.end(), leaf.leftMargin.rbegin(), leaf.leftMargin.rend() - 1);
  for (std::size_t i = 0; i < loop.size(); ++i)
    boundary.segments.emplace_back(loop[i], loop[(i + 1) % loop.size()]);
  for (std::size_t i = 0; i + 1 < leaf.midvein.size(); ++i)
    boundary.segments.emplace_back(leaf.midvein[i], leaf.midvein[i + 1]);

  // The plugin's size bound: midvein arc length / Resolution.
  const plantmorph::DeformedRectangleModel model(parameters);
  boundary.maxEdgeLength =
    plantmorph::CurveLength([&](double v) { return model.Evaluate(0.0, v); }, 0.0, 1.0) / resolution;
  return boundary;
}

void RunCgal(benchmark::State& state, bool refine)
{
  const SameBoundary& boundary = BoundaryAt(static_cast<int>(state.range(0)));
  if (!boundary.error.empty())
  {
    state.SkipWithError(boundary.error.c_str());
    return;
  }
  std::size_t triangles = 0;
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    Triangulation cdt;
    cdt.insert_constraints(
      boundary.points.begin(), boundary.points.end(), boundary.segments.begin(), boundary.segments.end());
    Mesher mesher(cdt, Criteria(ShapeBound, refine ? boundary.maxEdgeLength : 0.0));
    mesher.clear_seeds(); // CGAL 5.5 leaves seeds_mark uninitialised otherwise (see BladeMesher.cpp)
    mesher.init();        // marks the faces inside the outline
    if (refine)
      mesher.refine_mesh();
    std::size_t count = 0;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
      count += f->is_in_domain() ? 1 : 0;
    benchmark::DoNotOptimize(count);
    triangles = count;
  }
  memory.Report(state, 0.0);
  ReportTriangles(state, triangles);
}

void BM_CgalRefineSameBoundary(benchmark::State& state)
{
  RunCgal(state, true);
}

void BM_CgalCdtSameBoundary(benchmark::State& state)
{
  RunCgal(state, false);
}

// ---- Models B and C ------------------------------------------------------------------------------------------------

/// Model B's outline alone: the Frenet-Serret integration of one half-margin (paper 002 Fig. 5, with torsion) at
/// R + 1 samples, RK45 to 1e-10.
void BM_SpaceCurveIntegration(benchmark::State& state)
{
  const plantmorph::SpaceCurveParameters parameters =
    plantmorph::MakeSpaceCurvePreset(plantmorph::SpaceCurvePreset::Figure5, 5.0);
  std::size_t samples = 0;
  for (auto _ : state)
  {
    std::vector<plantmorph::FrenetFrame> frames;
    std::string error = plantmorph::IntegrateHalfMargin(parameters, static_cast<int>(state.range(0)), frames);
    benchmark::DoNotOptimize(frames.data());
    if (!error.empty())
    {
      state.SkipWithError(error.c_str());
      break;
    }
    samples = frames.size();
  }
  state.counters["samples"] = static_cast<double>(samples);
  state.counters["samples_per_s"] =
    benchmark::Counter(static_cast<double>(samples), benchmark::Counter::kIsIterationInvariantRate);
}

/// Model B's whole leaf: integration, mirror, midvein, strips of 6 columns a half, normals.
void BM_SpaceCurveLeaf(benchmark::State& state)
{
  const plantmorph::SpaceCurveParameters parameters =
    plantmorph::MakeSpaceCurvePreset(plantmorph::SpaceCurvePreset::Figure5, 5.0);
  plantmorph::SpaceCurveMeshParameters settings;
  settings.resolution = static_cast<int>(state.range(0));
  MeasureLeaf(
    state, [&](plantmorph::LeafGeometry& leaf) { return plantmorph::BuildSpaceCurveLeaf(parameters, settings, leaf); });
}

/// Palmate leaf (paper 002 Fig. 8, 5 lobes, quality mode): five lobes integrated, their union (CGAL Boolean
/// operations, exact), CGAL meshing with the lobes' midveins as constraints, mean-value LeafUV per sector.
void BM_PalmateLeafQuality(benchmark::State& state)
{
  const plantmorph::SpaceCurveParameters parameters =
    plantmorph::MakeSpaceCurvePreset(plantmorph::SpaceCurvePreset::Figure8FiveLobes, 5.0);
  plantmorph::SpaceCurveMeshParameters settings;
  settings.resolution = static_cast<int>(state.range(0));
  MeasureLeaf(
    state, [&](plantmorph::LeafGeometry& leaf) { return plantmorph::BuildSpaceCurveLeaf(parameters, settings, leaf); });
}

/// Model C's whole leaf (pin oak preset, quality mode): spline interpolation, sampling, CGAL meshing, MVC LeafUV.
void BM_BSplineLeafQuality(benchmark::State& state)
{
  const plantmorph::BSplineLeafParameters parameters =
    plantmorph::MakeBSplinePreset(plantmorph::BSplinePreset::PinOak, 8.0, 7.0, 7);
  plantmorph::LeafMeshParameters settings;
  settings.resolution = static_cast<int>(state.range(0));
  MeasureLeaf(
    state, [&](plantmorph::LeafGeometry& leaf) { return plantmorph::BuildBSplineLeaf(parameters, settings, leaf); });
}

void Register(const char* name, void (*function)(benchmark::State&), const std::vector<int64_t>& resolutions)
{
  benchmark::internal::Benchmark* b = benchmark::RegisterBenchmark(name, function);
  b->ArgName("resolution")->Unit(benchmark::kMillisecond)->MinTime(MinSeconds);
  for (int64_t resolution : resolutions)
    b->Arg(resolution);
}
} // namespace

int main(int argc, char** argv)
{
  std::vector<int64_t> paperResolutions = Resolutions;
  paperResolutions.insert(paperResolutions.end(), PaperOnlyResolutions.begin(), PaperOnlyResolutions.end());
  // Each plugin family is followed by its CGAL-alone baseline on the same boundary.
  Register("BM_BladeQuality", BM_BladeQuality, Resolutions);
  Register("BM_CgalRefineSameBoundary", BM_CgalRefineSameBoundary, Resolutions);
  Register("BM_BladePaper", BM_BladePaper, paperResolutions);
  Register("BM_CgalCdtSameBoundary", BM_CgalCdtSameBoundary, paperResolutions);
  Register("BM_SpaceCurveIntegration", BM_SpaceCurveIntegration, { 64, 256, 1024, 4000 });
  Register("BM_SpaceCurveLeaf", BM_SpaceCurveLeaf, { 64, 256, 1024, 4000 });
  Register("BM_PalmateLeafQuality", BM_PalmateLeafQuality, { 16, 32, 64, 128, 256 });
  Register("BM_BSplineLeafQuality", BM_BSplineLeafQuality, { 16, 32, 64, 128, 256, 512 });

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  benchmark::AddCustomContext("preset", "Ginkgo, b_y = 5");
  benchmark::AddCustomContext(
    "peak_memory", "malloc_trim(0), baseline VmRSS, echo 5 > /proc/self/clear_refs, run, VmHWM - baseline");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
