// SPDX-License-Identifier: GPL-3.0-or-later
// wilting_convergence: the Cucumber preset's tip trajectory across leaf sizes and Resolutions (physical units: the same
// leaf at any voxel size and size; the table
// in benchmarks/README.md "wilting convergence" and docs/methods/wilting.md).
//
//   wilting_convergence [--sizes 8,20,30] [--resolutions 10,14,18,22] [--duration 10] [--legacy] [--anchor-cm 3]
//                       [--threads N] [--track FILE] [--substeps N] [--set NAME=VALUE ...]
//                       [--preset Cucumber|Tomato|Watermelon]
//
// The cucumber blade (testing/cxx/wilting/WiltingCucumberLeaf.h: LeafOutlineSource's B-spline Cucumber, midvein and
// margin regions, no VenationFilter veins) of each blade length L (cm), WiltingSimulation with the Cucumber preset,
// held as the preset holds it (3 / 22.308 of the leaf's longest side, 3 cm x L / 20.1; --anchor-cm A: A cm at every
// size, what a preset did before it held the leaf in leaf lengths), TimeStep 1/60 s, one Newton iteration, frames of 0.1 s. --legacy: the model before physical units
// (the fit's lattice values at the 20 cm leaf's Resolution 14 edge h0, stiffness scaled by h/h0 and loads by (h/h0)^3).
// Prints per run: "rises back" (the largest rise of the tip's height after its lowest point so far, / L), the lowest
// tip height / L, the tip's displacement / L at the end, the largest distance (/ L) of the tip path from the finest
// Resolution's of that size, the blow-up time, the integrator sub-steps and the wall time. --track FILE: every run's
// tip positions (cm, in the input's frame) as lines "L R t x y z". --substeps N: N integrator steps per TimeStep
// (default 0: WiltingParameters' automatic choice). --set NAME=VALUE: a Cucumber value replaced (the property names of
// examples/calibrate_wilting.py, physical units; Gravity in cm/s^2), for exploring a refit.
#include "WiltingCucumberLeaf.h"
#include "WiltingPresets.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace
{
std::vector<double> ParseList(const char* text)
{
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ','))
  {
    values.push_back(std::atof(item.c_str()));
  }
  return values;
}

/// The model before physical units: the Cucumber fit in lattice units at the 20 cm leaf's edge, rescaled by h / h0.
void MakeLegacy(plantmorph::WiltingParameters& p)
{
  const double h0 = 22.3079 / 14.0;
  for (plantmorph::WiltingMaterial& material : p.materials)
  {
    material.stiffness *= h0 / 18.0;
  }
  p.droopForce *= h0 * h0;
  p.contractionForce *= h0 * h0;
  p.units = plantmorph::WiltingUnits::Lattice;
  p.referenceVoxelSize = h0;
}
/// --set NAME=VALUE: a preset value replaced (the calibration's property names).
bool Override(const std::string& name, double value, plantmorph::WiltingParameters& p)
{
  using M = plantmorph::WiltingMaterialClass;
  double* targets[] = { &p.droopForce, &p.contractionForce, &p.loadTime, &p.contractionTime, &p.newmark.rayleighMass,
    &p.curlStrain, &p.curlTime, &p.curlRelaxation, &p.curlRelaxationTime, &p.shrinkageStrain, &p.shrinkageTime,
    &p.materials[M::WiltingBlade].stiffness, &p.materials[M::WiltingVein].stiffness,
    &p.materials[M::WiltingMargin].stiffness, &p.bladeThickness, &p.gravity };
  const char* names[] = { "DroopForce", "ContractionForce", "LoadTime", "ContractionTime", "RayleighAlpha",
    "CurlStrain", "CurlTime", "CurlRelaxation", "CurlRelaxationTime", "ShrinkageStrain", "ShrinkageTime",
    "BladeStiffness", "VeinStiffness", "MarginStiffness", "BladeThickness", "Gravity" };
  for (std::size_t k = 0; k < sizeof names / sizeof names[0]; ++k)
  {
    if (name == names[k])
    {
      *targets[k] = value;
      return true;
    }
  }
  return false;
}
} // namespace

int main(int argc, char** argv)
{
  std::vector<double> sizes{ 8.0, 20.0, 30.0 };
  std::vector<double> resolutions{ 10, 14, 18, 22 };
  double duration = 10.0, anchorCm = 0.0;
  bool legacy = false;
  FILE* track = nullptr;
  int threads = 1, substeps = 0;
  plantmorph::WiltingPreset preset = plantmorph::WiltingPreset::Cucumber;
  std::vector<std::pair<std::string, double>> overrides;
  for (int a = 1; a < argc; ++a)
  {
    const bool more = a + 1 < argc;
    if (!std::strcmp(argv[a], "--sizes") && more)
      sizes = ParseList(argv[++a]);
    else if (!std::strcmp(argv[a], "--resolutions") && more)
      resolutions = ParseList(argv[++a]);
    else if (!std::strcmp(argv[a], "--duration") && more)
      duration = std::atof(argv[++a]);
    else if (!std::strcmp(argv[a], "--anchor-cm") && more)
      anchorCm = std::atof(argv[++a]);
    else if (!std::strcmp(argv[a], "--set") && more)
    {
      const std::string item = argv[++a];
      const std::size_t equals = item.find('=');
      overrides.emplace_back(item.substr(0, equals), std::atof(item.c_str() + equals + 1));
    }
    else if (!std::strcmp(argv[a], "--preset") && more)
    {
      // A named preset (WiltingPresetName's spelling); any other name is an error, not a silent Cucumber.
      const std::string name = argv[++a];
      int found = 0;
      for (int k = 1; k < plantmorph::WiltingPresetCount && !found; ++k)
        found = plantmorph::WiltingPresetName(static_cast<plantmorph::WiltingPreset>(k)) == name ? k : 0;
      if (!found)
      {
        std::fprintf(stderr, "--preset: unknown name %s (Cucumber, Tomato or Watermelon)\n", name.c_str());
        return 2;
      }
      preset = static_cast<plantmorph::WiltingPreset>(found);
    }
    else if (!std::strcmp(argv[a], "--substeps") && more)
      substeps = std::atoi(argv[++a]);
    else if (!std::strcmp(argv[a], "--threads") && more)
      threads = std::atoi(argv[++a]);
    else if (!std::strcmp(argv[a], "--track") && more)
      track = std::fopen(argv[++a], "w");
    else if (!std::strcmp(argv[a], "--legacy"))
      legacy = true;
    else
    {
      std::fprintf(stderr,
        "usage: %s [--sizes L,...] [--resolutions R,...] [--duration S] [--legacy] "
        "[--anchor-cm A] [--threads N] [--track FILE] [--substeps N] [--set NAME=VALUE] "
        "[--preset Cucumber|Tomato|Watermelon]\n",
        argv[0]);
      return 2;
    }
  }
  std::printf("| L (cm) | R | rises back / L | lowest / L | end (x, y, z) / L | path vs finest R / L | blow-up | "
              "sub-steps | s |\n|---|---|---|---|---|---|---|---|---|\n");
  for (double length : sizes)
  {
    const plantmorph::WiltingInput input = plantmorph::CucumberBlade(length);
    if (input.points.empty())
    {
      std::fprintf(stderr, "no leaf for L = %g\n", length);
      return 1;
    }
    std::vector<plantmorph::WiltingTipMetrics> runs;
    std::vector<std::pair<int, double>> extra; // sub-steps, seconds
    for (double r : resolutions)
    {
      plantmorph::WiltingParameters p;
      plantmorph::ApplyWiltingPreset(preset, p);
      for (const auto& [name, value] : overrides)
      {
        if (!Override(name, value, p))
        {
          std::fprintf(stderr, "--set: unknown name %s\n", name.c_str());
          return 2;
        }
      }
      if (legacy)
        MakeLegacy(p);
      p.resolution = static_cast<int>(r);
      if (anchorCm > 0.0 || legacy)
      {
        p.anchorFraction = 0.0; // a radius in cm, as before the presets held the leaf in leaf lengths
        p.anchorRadius = anchorCm > 0.0 ? anchorCm : 3.0 * length / 20.1;
      }
      if (legacy)
        p.referenceLength = 0.0; // before elastic similarity
      p.duration = duration;
      p.frameInterval = 0.1;
      p.newmark.timeStep = 1.0 / 60.0;
      p.newmark.maxIterations = 1;
      p.newmark.threads = threads;
      p.substeps = substeps;
      plantmorph::WiltingSimulation simulation;
      const auto start = std::chrono::steady_clock::now();
      std::string error = simulation.Setup(input, p);
      if (error.empty())
        error = simulation.Run();
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      runs.push_back(plantmorph::TipMetrics(simulation, length, error));
      extra.emplace_back(simulation.Substeps(), seconds);
      for (std::size_t f = 0; track && f < simulation.Frames().size(); ++f)
      {
        const plantmorph::WiltingFrame& frame = simulation.Frames()[f];
        std::fprintf(
          track, "%g %g %.4f %.6f %.6f %.6f\n", length, r, frame.time, frame.tip[0], frame.tip[1], frame.tip[2]);
      }
      if (!error.empty())
        std::fprintf(stderr, "L %g R %g: %s\n", length, r, error.c_str());
    }
    for (std::size_t k = 0; k < runs.size(); ++k)
    {
      const plantmorph::WiltingTipMetrics& m = runs[k];
      const double path = plantmorph::TrackDistance(m.track, runs.back().track);
      char blow[32] = "-";
      if (m.blowUp >= 0.0)
        std::snprintf(blow, sizeof blow, "%.1f s", m.blowUp);
      std::printf("| %g | %g | %.3f | %.3f | (%.3f, %.3f, %.3f) | %.3f | %s | %d | %.1f |\n", length, resolutions[k],
        m.risesBack, m.lowest, m.end[0], m.end[1], m.end[2], path, blow, extra[k].first, extra[k].second);
      std::fflush(stdout);
    }
  }
  if (track)
    std::fclose(track);
  return 0;
}
