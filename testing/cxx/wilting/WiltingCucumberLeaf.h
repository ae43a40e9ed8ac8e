// SPDX-License-Identifier: GPL-3.0-or-later
// The cucumber blade of paper 001's measurement, as LeafOutlineSource builds it (B-spline Cucumber preset, 7 control
// points per margin, quality mesh of Resolution 30), scaled to a blade length (20.1 cm: the measured leaf, 22.1 cm
// wide), with its LeafUV and its midvein and margin Region, and the palmate veins examples/calibrate_wilting.py
// grows on it (VenationFilter Custom, Palmate, PalmateEnds "Along the far edge": its vein nodes appended with Region
// min(VeinOrder, 3), as WiltingSimulator's Veins input adds them), as a WiltingInput; and the tip metrics of a run.
// Shared by the convergence test (WiltingConvergenceTest.cpp) and benchmarks/wilting_convergence.cpp (header-only:
// both link PlantMorphLeaf, PlantMorphVenation and PlantMorphWilting).
#pragma once

#include "BSplineLeaf.h"
#include "VenationGrowth.h"
#include "WiltingSimulation.h"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

namespace plantmorph
{

/// `in` (a blade with LeafUV) with the palmate veins examples/calibrate_wilting.py grows on the cucumber blade
/// (VenationFilter Custom, Palmate, ForkLevels 1, PalmateEnds "Along the far edge") appended as points with Region
/// min(VeinOrder, 3), as WiltingSimulator's Veins input adds them; empty points on failure.
inline WiltingInput WithPalmateVeins(WiltingInput in)
{
  VenationParameters venation; // VenationFilter's Custom defaults, with the fit's fork
  venation.pattern = VenationPattern::Palmate;
  venation.palmateFan = false;
  venation.forkLevels = 1;
  std::vector<Eigen::Vector3d> blade = in.points;
  std::vector<Eigen::Vector2d> uv = in.leafUV;
  bool flat = true;
  const VenationBlade plane{ VenationWorkingPlane(blade, uv, in.triangles, flat), uv, in.triangles };
  VenationResult result;
  if (!GrowVenation(plane, venation, result).empty())
  {
    return WiltingInput();
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t n = 0; n < result.nodes.size(); ++n)
  {
    const auto& t = in.triangles[static_cast<std::size_t>(result.location[n].triangle)];
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
    {
      x += result.location[n].weights[k] * blade[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])];
    }
    in.points.push_back(x);
    in.regions.push_back(std::min(result.order[n], 3));
    in.leafUV.emplace_back(nan, nan);
  }
  return in;
}

/// The blade of length `length` (width 22.1 / 20.1 of it, or `width` when that is > 0), with its veins unless
/// `veins` is false; empty points on failure.
inline WiltingInput CucumberBlade(double length, bool veins = true, double width = 0.0)
{
  WiltingInput in;
  const BSplineLeafParameters controls =
    MakeBSplinePreset(BSplinePreset::Cucumber, length, width > 0.0 ? width : length * 22.1 / 20.1, 7);
  LeafMeshParameters settings;
  settings.resolution = 30;
  settings.quality = true;
  LeafGeometry leaf;
  if (!BuildBSplineLeaf(controls, settings, leaf).empty())
  {
    return in;
  }
  for (std::size_t p = 0; p < leaf.blade.points.size(); ++p)
  {
    const double z = leaf.z.empty() ? 0.0 : leaf.z[p];
    in.points.emplace_back(leaf.blade.points[p][0], leaf.blade.points[p][1], z);
  }
  in.triangles = leaf.blade.triangles;
  in.regions = leaf.blade.region;
  in.leafUV = leaf.blade.uv;
  return veins ? WithPalmateVeins(in) : in;
}

/// A run's tip metrics, lengths over the blade length L: the largest rise of the tip's height after its lowest
/// point so far ("rises back"), its lowest height, its position at the end, and the time of a blow-up (-1: none).
struct WiltingTipMetrics
{
  double risesBack = 0.0;
  double lowest = 0.0;
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
  double blowUp = -1.0;
  std::string message;
  std::vector<Eigen::Vector3d> track;              ///< the tip's displacement / L per frame
  Eigen::Vector3d start = Eigen::Vector3d::Zero(); ///< the tip's position at t = 0 (cm)
};

inline WiltingTipMetrics TipMetrics(const WiltingSimulation& simulation, double length, const std::string& error)
{
  WiltingTipMetrics m;
  const std::vector<WiltingFrame>& frames = simulation.Frames();
  if (frames.empty())
  {
    return m;
  }
  const Eigen::Vector3d start = frames.front().tip;
  m.start = start;
  double lowest = start[2];
  for (const WiltingFrame& frame : frames)
  {
    lowest = std::min(lowest, frame.tip[2]);
    m.risesBack = std::max(m.risesBack, (frame.tip[2] - lowest) / length);
    m.track.push_back((frame.tip - start) / length);
  }
  m.lowest = (lowest - start[2]) / length;
  m.end = m.track.back();
  m.message = error;
  if (!error.empty())
  {
    m.blowUp = frames.back().time;
  }
  return m;
}

/// The largest distance between two tracks' common frames (leaf lengths).
inline double TrackDistance(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b)
{
  double d = 0.0;
  for (std::size_t f = 0; f < std::min(a.size(), b.size()); ++f)
  {
    d = std::max(d, (a[f] - b[f]).norm());
  }
  return d;
}

} // namespace plantmorph
