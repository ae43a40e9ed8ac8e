// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantSegmentation.h"
#include "SegmentationSteps.h"

#include "PointGrid.h"

#include <plantmorph/RangeError.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

namespace plantmorph
{

std::string ValidateSegmentationParameters(const SegmentationParameters& p)
{
  std::string error = p.upAxis >= 0 && p.upAxis <= 2 ? "" : OutOfRange("UpAxis", p.upAxis, "{0, 1, 2}", "X, Y, Z");
  const auto check = [&](bool ok, const char* name, double value, const char* range) {
    if (error.empty() && !ok)
      error = OutOfRange(name, value, range);
  };
  check(std::isfinite(p.featureScale) && p.featureScale >= 2.0 && p.featureScale <= 50.0, "FeatureScale",
    p.featureScale, "[2, 50]");
  check(std::isfinite(p.linkScale) && p.linkScale >= 1.5 && p.linkScale <= 20.0, "LinkScale", p.linkScale, "[1.5, 20]");
  check(std::isfinite(p.normalAngle) && p.normalAngle > 0.0 && p.normalAngle < 90.0, "NormalAngle", p.normalAngle,
    "(0, 90)");
  check(std::isfinite(p.creaseVariation) && p.creaseVariation > 0.0 && p.creaseVariation < 1.0, "CreaseVariation",
    p.creaseVariation, "(0, 1)");
  check(std::isfinite(p.sheetCoherence) && p.sheetCoherence > 0.0 && p.sheetCoherence < 1.0, "SheetCoherence",
    p.sheetCoherence, "(0, 1)");
  check(std::isfinite(p.maximumLeafElongation) && p.maximumLeafElongation >= 1.0 && p.maximumLeafElongation <= 1000.0,
    "MaximumLeafElongation", p.maximumLeafElongation, "[1, 1000]");
  check(p.minimumLeafPoints >= 1 && p.minimumLeafPoints <= 1000000000, "MinimumLeafPoints", p.minimumLeafPoints,
    "[1, 1e9]");
  return error;
}

namespace
{
/// The plants' point ids, in ascending plant id; an error for a non-finite coordinate.
std::string GroupPlants(
  const std::vector<Eigen::Vector3d>& points, const std::vector<int>& plantOf, std::map<int, std::vector<int>>& plants)
{
  if (!plantOf.empty() && plantOf.size() != points.size())
    return "the plant ids (" + std::to_string(plantOf.size()) + ") are not one per point (" +
      std::to_string(points.size()) + ")";
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    if (!points[i].allFinite())
    {
      std::ostringstream message;
      message << "point " << i << " has a non-finite coordinate (" << points[i].x() << ", " << points[i].y() << ", "
              << points[i].z() << "): remove NaN and infinite points first";
      return message.str();
    }
    plants[plantOf.empty() ? 0 : plantOf[i]].push_back(static_cast<int>(i));
  }
  return {};
}

/// The centroids of `points[ids]` per cube of side `cell` (cubes in key order), and (when `cubeOf` is given) each
/// id's cube in that list.
std::vector<Eigen::Vector3d> CubeCentroids(const std::vector<Eigen::Vector3d>& points,
  const std::vector<std::size_t>& ids, double cell, std::vector<int>* cubeOf = nullptr)
{
  std::map<std::array<std::int64_t, 3>, std::pair<Eigen::Vector3d, int>> cubes;
  std::vector<std::array<std::int64_t, 3>> keys(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k)
  {
    const Eigen::Vector3d& p = points[ids[k]];
    for (int c = 0; c < 3; ++c)
      keys[k][c] = static_cast<std::int64_t>(std::floor(p[c] / cell));
    auto& cube = cubes.try_emplace(keys[k], Eigen::Vector3d::Zero(), 0).first->second;
    cube.first += p;
    ++cube.second;
  }
  std::vector<Eigen::Vector3d> centroids;
  for (auto& [key, cube] : cubes)
  {
    centroids.push_back(cube.first / cube.second);
    cube.second = static_cast<int>(centroids.size()) - 1; // from here on: the cube's index
  }
  if (cubeOf)
  {
    cubeOf->resize(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k)
      (*cubeOf)[k] = cubes.at(keys[k]).second;
  }
  return centroids;
}

/// A plant's wood points (Organ 0): their indices, and a grid of them in cubes of side `cell` (none when the plant
/// has no wood or `cell` is not positive); the same of its petioles' points (Organ 2). WoodDistances and
/// PlaceLeafBases search the same grids.
struct PlantWood
{
  std::vector<std::size_t> ids, petiole;
  std::optional<PointGrid> grid, petioleGrid;
};
PlantWood WoodOf(
  const std::vector<Eigen::Vector3d>& points, const std::vector<int>& organ, double cell, const ParallelFor& parallel)
{
  PlantWood wood;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (organ[i] == OrganWood)
      wood.ids.push_back(i);
    else if (organ[i] == OrganPetiole)
      wood.petiole.push_back(i);
  if (wood.ids.empty() || !(cell > 0.0))
    return wood;
  const auto gridOf = [&](const std::vector<std::size_t>& ids) {
    std::vector<Eigen::Vector3d> at(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k)
      at[k] = points[ids[k]];
    return PointGrid(at, cell, parallel);
  };
  wood.grid.emplace(gridOf(wood.ids));
  if (!wood.petiole.empty())
    wood.petioleGrid.emplace(gridOf(wood.petiole));
  return wood;
}

/// Each point's distance to what its plant's leaves grow from, the nearest wood or petiole point (0 on them, Organ
/// 0 and 2; a blade on a petiole meets the petiole, not the twig): exact within `near`; beyond it the distance of
/// the centroid of the point's cube of side `near` to the nearest centroid of the wood's and petioles' cubes (off
/// by at most a few `near`: what tells a leaf's base end from its apex end is the difference between a twig's
/// touch and a leaf's length), never under `near`. `wood` is the plant's (WoodOf), its grids in cubes of side
/// `near`. NaN everywhere on a plant without wood.
std::vector<double> WoodDistances(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& organ,
  const PlantWood& wood, double near, const ParallelFor& parallel)
{
  std::vector<double> distance(points.size(), std::numeric_limits<double>::quiet_NaN());
  if (!wood.grid)
    return distance;
  ForEachIndex(parallel, points.size(), [&](std::size_t i) {
    if (organ[i] == OrganWood || organ[i] == OrganPetiole)
    {
      distance[i] = 0.0;
      return;
    }
    double least = std::numeric_limits<double>::infinity();
    for (const std::optional<PointGrid>* grid : { &wood.grid, &wood.petioleGrid })
      if (*grid)
      {
        const auto nearest = (*grid)->Nearest(points[i], 1, -1, near);
        if (!nearest.empty())
          least = std::min(least, nearest.front().first);
      }
    distance[i] = std::isfinite(least) ? std::sqrt(least) : -1.0; // -1: farther than `near`
  });
  std::vector<std::size_t> far;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (distance[i] < 0.0)
      far.push_back(i);
  std::vector<int> farCube;
  const std::vector<Eigen::Vector3d> farCentres = CubeCentroids(points, far, near, &farCube);
  std::vector<std::size_t> attach = wood.ids;
  attach.insert(attach.end(), wood.petiole.begin(), wood.petiole.end());
  const std::vector<Eigen::Vector3d> woodCentres = CubeCentroids(points, attach, near);
  const PointGrid coarse(woodCentres, WoodDistanceCoarseCell * near, parallel);
  std::vector<double> cubeDistance(farCentres.size());
  ForEachIndex(parallel, farCentres.size(),
    [&](std::size_t c) { cubeDistance[c] = std::sqrt(coarse.Nearest(farCentres[c], 1).front().first); });
  for (std::size_t k = 0; k < far.size(); ++k)
    distance[far[k]] = std::max(near, cubeDistance[static_cast<std::size_t>(farCube[k])]);
  return distance;
}

/// Each leaf's base (the leaves table's Base, with its Branch and BaseGap from the wood point nearest it): the leaf's
/// point of the least LeafBaseScore (WoodDistance - LeafBaseCentreWeight x its distance from the leaf's centre), the
/// point nearest the wood among those far from the middle of the leaf. A leaf grows from its twig at one end, but its
/// margin can touch other wood, or lie nearer the twig beyond its base than its base does. Leaves whose petiole was
/// found keep the petiole's junction; a plant without wood keeps the bases of the link graph. `wood` is the plant's
/// (WoodOf).
void PlaceLeafBases(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& woodDistance,
  const PlantWood& wood, segmentation::PlantLabels& labels)
{
  const std::size_t leaves = labels.leaves.size();
  std::vector<int> best(leaves, -1);
  std::vector<double> score(leaves, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const int l = labels.leaf[i];
    if (l < 0 || !(woodDistance[i] >= 0.0))
      continue;
    const auto li = static_cast<std::size_t>(l);
    const double here = LeafBaseScore(woodDistance[i], (points[i] - labels.leaves[li].centre).norm());
    if (here < score[li])
    {
      score[li] = here;
      best[li] = static_cast<int>(i);
    }
  }
  if (!wood.grid)
    return;
  for (std::size_t li = 0; li < leaves; ++li)
  {
    SegmentedLeaf& leaf = labels.leaves[li];
    if (best[li] < 0 || leaf.petioleLength > 0.0)
      continue;
    leaf.base = points[static_cast<std::size_t>(best[li])];
    const auto nearest = wood.grid->Nearest(leaf.base, 1);
    const std::size_t woodPoint = wood.ids[static_cast<std::size_t>(nearest.front().second)];
    leaf.baseGap = std::sqrt(nearest.front().first);
    if (woodPoint < labels.woodSegment.size())
      leaf.branch = labels.woodSegment[woodPoint];
  }
}
} // namespace

SegmentationResult SegmentPlants(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& plantOf,
  const SegmentationParameters& parameters, const ParallelFor& parallel)
{
  SegmentationResult result;
  result.error = ValidateSegmentationParameters(parameters);
  if (result.error.empty() && points.empty())
    result.error = "the input has no points";
  std::map<int, std::vector<int>> plants;
  if (result.error.empty())
    result.error = GroupPlants(points, plantOf, plants);
  if (!result.error.empty())
    return result;
  result.organ.assign(points.size(), OrganWood);
  result.leafId.assign(points.size(), -1);
  result.confidence.assign(points.size(), 0.0);
  result.woodDistance.assign(points.size(), 0.0);
  int nextLeaf = 0;
  for (const auto& [plantId, ids] : plants)
  {
    std::vector<Eigen::Vector3d> own(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k)
      own[k] = points[static_cast<std::size_t>(ids[k])];
    segmentation::PlantLabels labels;
    const std::string error = segmentation::SegmentPlant(own, parameters, parallel, labels);
    if (!error.empty())
    {
      SegmentationResult failed;
      failed.error = (plants.size() > 1 ? "plant " + std::to_string(plantId) + ": " : std::string()) + error;
      return failed;
    }
    const double near = WoodDistanceReach * parameters.featureScale * labels.plant.spacing;
    const PlantWood wood = WoodOf(own, labels.organ, near, parallel);
    const std::vector<double> woodDistance = WoodDistances(own, labels.organ, wood, near, parallel);
    PlaceLeafBases(own, woodDistance, wood, labels);
    for (std::size_t k = 0; k < ids.size(); ++k)
    {
      const auto i = static_cast<std::size_t>(ids[k]);
      result.woodDistance[i] = woodDistance[k];
      result.organ[i] = labels.organ[k];
      result.leafId[i] = labels.leaf[k] >= 0 ? nextLeaf + labels.leaf[k] : -1;
      result.confidence[i] = labels.confidence[k];
    }
    for (SegmentedLeaf leaf : labels.leaves)
    {
      leaf.leafId += nextLeaf;
      leaf.plantId = plantId;
      result.leaves.push_back(leaf);
    }
    nextLeaf += static_cast<int>(labels.leaves.size());
    labels.plant.plantId = plantId;
    result.plants.push_back(labels.plant);
  }
  return result;
}

} // namespace plantmorph
