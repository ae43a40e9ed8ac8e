// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantSegmentation.h"
#include "SegmentationSteps.h"

#include "PointGrid.h"

#include <plantmorph/RangeError.h>

#include <algorithm>
#include <cmath>
#include <map>
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
    for (std::size_t k = 0; k < ids.size(); ++k)
    {
      const auto i = static_cast<std::size_t>(ids[k]);
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
