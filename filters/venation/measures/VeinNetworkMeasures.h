// SPDX-License-Identifier: GPL-3.0-or-later
// The measures plant scientists report for a vein network (docs/methods/venation.md "Statistics"; LEAF GUI,
// phenoVein, Green & Losada 2023), computed from the network alone, so they apply to any VenationResult.
//
// - Lengths: total vein length, length per VeinOrder, and VLA (vein length per blade area; in mm/mm^2 when the
//   leaf is in mm, in 1/cm when in cm).
// - Areoles: the bounded faces (of non-zero area) of the planar graph of the veins alone (regions enclosed by veins only; a region
//   that a vein ending on the margin leaves open is not one): count, mean, median, coefficient of variation
//   (population standard deviation over the mean) of their areas, and the sorted areas (for a histogram). A vein
//   loop lying inside an areole without touching it is not subtracted from it.
// - Loopiness: total length of a minimum spanning forest of the network (Kruskal) over the total length: 1 for a
//   tree, lower the more loops.
// - Branch points (nodes where three or more vein segments meet) and free ends (nodes with one segment, not on the
//   margin), absolute and per blade area.
// - Mean width per order: the length-weighted mean of the segments' widths (each the mean of its two nodes').
// - MeasureVenation: the same for a network GrowVenation grew, on its blade (area and margin from the blade), and
//   MakeAreoleHistogram: the areole-area distribution in equal bins (VenationFilter's two table ports).
//
// Plain C++17 + Eigen, no VTK.
#pragma once

#include "VenationBlade.h"
#include "VenationGrowth.h"

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace plantmorph
{

struct VeinNetworkMeasures
{
  double bladeArea = 0.0;
  double totalLength = 0.0;
  double vla = 0.0;                      ///< vein length per blade area
  double length[VeinOrderCount] = {};    ///< per VeinOrder (index 0 unused)
  double meanWidth[VeinOrderCount] = {}; ///< length-weighted, per VeinOrder; 0 where an order has no vein
  std::size_t areoles = 0;
  double areoleMean = 0.0, areoleMedian = 0.0, areoleCV = 0.0;
  std::vector<double> areoleAreas; ///< sorted ascending
  double spanningLength = 0.0;     ///< minimum spanning forest length
  double loopiness = 1.0;          ///< spanningLength / totalLength
  std::size_t branchPoints = 0, freeEnds = 0;
  double branchPointsPerArea = 0.0, freeEndsPerArea = 0.0;
};

/// Measures `veins` on a blade of area `bladeArea` whose margin is the closed polygon `margin` (vein ends within
/// `tolerance` of it are not free ends; may be empty: then every end is free). Empty on success, else a message.
std::string MeasureVeinNetwork(const VenationResult& veins, double bladeArea,
  const std::vector<Eigen::Vector2d>& margin, double tolerance, VeinNetworkMeasures& measures);

/// Measures the network `veins` that GrowVenation grew on `blade`, in the blade's working plane: the blade's area
/// and its outer boundary loop as the margin (vein ends within 1e-6 leaf lengths of it are not free ends; a hole's
/// edge is not margin). This is what VenationFilter reports. Empty on success, else a message.
std::string MeasureVenation(const VenationBlade& blade, const VenationResult& veins, VeinNetworkMeasures& measures);

/// A histogram of areole areas: `lower[b]`, `upper[b]` the edges of bin b, `count[b]` the areas in [lower, upper)
/// (the last bin holds its upper edge too).
struct AreoleHistogram
{
  std::vector<double> lower, upper;
  std::vector<std::size_t> count;
};

/// `bins` equal bins from the smallest to the largest of `areas` (any order), so the counts sum to areas.size();
/// when every area is the same the bins span [a, a (1 + 1e-6)]. No bins when `areas` is empty or `bins` < 1.
AreoleHistogram MakeAreoleHistogram(const std::vector<double>& areas, int bins);

} // namespace plantmorph
