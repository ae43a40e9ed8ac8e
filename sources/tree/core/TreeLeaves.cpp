// SPDX-License-Identifier: GPL-3.0-or-later
#include "TreeLeaves.h"

#include <plantmorph/BezierCurve.h>
#include <plantmorph/MathConstants.h>
#include <plantmorph/RandomStream.h>
#include <plantmorph/RotationMinimizingFrames.h>

#include <Eigen/Geometry>

#include <cmath>
#include <set>

namespace plantmorph
{

const std::vector<Eigen::Vector2d>& WillowControlPoints()
{
  static const std::vector<Eigen::Vector2d> points = { Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.1, -0.05),
    Eigen::Vector2d(0.1, -0.4), Eigen::Vector2d(0.1, -0.8) };
  return points;
}

namespace
{
/// The leaf sizes' streams: (Seed, LeafSizeStream + leaf id), apart from the strokes' ties.
constexpr std::uint64_t LeafSizeStream = 0x4C45414653495A45ull;
} // namespace

double LeafLength(const TreeParameters& s, double t, int leafId)
{
  double length = s.leafScale * (1.0 + t * (s.leafTipScale - 1.0));
  if (s.leafScaleSpread > 0.0)
  {
    RandomStream random(s.seed, LeafSizeStream + static_cast<std::uint64_t>(leafId));
    length *= std::exp(s.leafScaleSpread * random.Normal());
  }
  return length;
}

std::string PlaceLeaves(const TreeParameters& s, Tree& tree)
{
  constexpr double Degree = Pi / 180.0;
  tree.leaves.clear();
  std::set<int> parents;
  for (const TreeBranch& b : tree.branches)
  {
    parents.insert(b.parentId);
  }
  long long twigs = 0;
  for (const TreeBranch& b : tree.branches)
  {
    twigs += parents.count(b.id) ? 0 : 1;
  }
  if (static_cast<double>(twigs) * s.leafCount > static_cast<double>(s.maxSegments))
  {
    return "the tree would have " + std::to_string(twigs * s.leafCount) +
      " leaves, more than MaxSegments = " + std::to_string(s.maxSegments) + " (lower LeafCount or the tree's size)";
  }
  for (TreeBranch& b : tree.branches)
  {
    if (parents.count(b.id))
    {
      continue;
    }
    if (s.leafType == LeafType::Willow && b.strokeIndex < 0 && b.mergedId < 0)
    {
      const Eigen::Vector3d direction = b.frame.col(1);
      Eigen::Vector3d outward = direction - direction.y() * Eigen::Vector3d::UnitY();
      outward = outward.norm() > 1e-9 ? Eigen::Vector3d(outward.normalized()) : Eigen::Vector3d(b.frame.col(0));
      std::vector<Eigen::Vector3d> controls;
      for (const Eigen::Vector2d& c : WillowControlPoints())
      {
        controls.push_back(b.centre[0] + b.length * (c.x() * outward + c.y() * Eigen::Vector3d::UnitY()));
      }
      b.centre = SampleBezier<3>(controls, s.segmentsPerBranch);
      std::vector<double> arc(b.centre.size(), 0.0);
      for (std::size_t k = 1; k < b.centre.size(); ++k)
      {
        arc[k] = arc[k - 1] + (b.centre[k] - b.centre[k - 1]).norm();
      }
      b.length = arc.back();
      b.radii.resize(b.centre.size());
      for (std::size_t k = 0; k < b.centre.size(); ++k)
      {
        b.radii[k] = b.radius + (arc[k] / b.length) * (b.radiusEnd - b.radius);
      }
      b.straight = false;
      const Eigen::Vector3d y = PolylineTangents(b.centre)[0];
      b.frame.col(1) = y;
      b.frame.col(2) = PerpendicularTo(y, b.frame.col(2));
      b.frame.col(0) = y.cross(Eigen::Vector3d(b.frame.col(2)));
    }
    for (int j = 1; j <= s.leafCount; ++j)
    {
      const double pos = s.leafType == LeafType::Sympodial ? 1.0 : (1.0 - s.leafRatio) + j * s.leafRatio / s.leafCount;
      const double rotation = PhyllotaxisAngle(j, s.phyllotaxisA, s.phyllotaxisB);
      Eigen::Vector3d point;
      Eigen::Matrix3d frame;
      double radius = 0.0;
      BranchFrameAt(b, pos, point, frame, radius);
      TreeLeaf leaf;
      leaf.branchId = b.id;
      leaf.id = static_cast<int>(tree.leaves.size());
      leaf.axes = frame * RotationY(rotation) * RotationZ(s.leafAngle);
      const bool atTip = s.leafType == LeafType::Sympodial || s.leafRatio == 0.0;
      leaf.length = LeafLength(s, atTip ? 1.0 : static_cast<double>(j) / s.leafCount, leaf.id);
      leaf.origin =
        point + radius * (frame * Eigen::Vector3d(-std::cos(rotation * Degree), 0.0, std::sin(rotation * Degree)));
      tree.leaves.push_back(leaf);
    }
  }
  return {};
}

} // namespace plantmorph
