// SPDX-License-Identifier: GPL-3.0-or-later
#include "TreeTemplate.h"

#include "TreeLeaves.h"
#include "TreeMerge.h"
#include "TreeStrokes.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RangeError.h>
#include <plantmorph/RotationMinimizingFrames.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace plantmorph
{

namespace
{
constexpr double Degree = Pi / 180.0;

bool InRange(double v, double low, double high, bool lowOpen = false)
{
  return std::isfinite(v) && (lowOpen ? v > low : v >= low) && v <= high;
}

std::string RangeError(const char* name, double value, const char* range)
{
  return OutOfRange(name, value, range);
}
} // namespace

std::string TreeParameters::Validate() const
{
  if (static_cast<int>(this->mode) < 0 || static_cast<int>(this->mode) > 2)
    return RangeError("Mode", static_cast<int>(this->mode), "{0 Template, 1 Strokes, 2 Template and strokes}");
  if (static_cast<int>(this->type) < 0 || static_cast<int>(this->type) > 1)
    return RangeError("TreeType", static_cast<int>(this->type), "{0 Monopodial, 1 Sympodial}");
  if (!InRange(this->length, 0.0, 1e6, true))
    return RangeError("Length", this->length, "(0, 1e6]");
  if (!InRange(this->radius, 0.0, 1e5, true))
    return RangeError("Radius", this->radius, "(0, 1e5]");
  if (this->depth < 0 || this->depth > 20)
    return RangeError("Depth", this->depth, "[0, 20]");
  if (this->phyllotaxisA < 1 || this->phyllotaxisA > 1000)
    return RangeError("PhyllotaxisA", this->phyllotaxisA, "[1, 1000]");
  if (this->phyllotaxisB < 1 || this->phyllotaxisB > 1000)
    return RangeError("PhyllotaxisB", this->phyllotaxisB, "[1, 1000]");
  if (this->childCount < 1 || this->childCount > 1000)
    return RangeError("ChildCount", this->childCount, "[1, 1000]");
  if (!InRange(this->ratio, 0.0, 1.0))
    return RangeError("Ratio", this->ratio, "[0, 1]");
  if (!InRange(this->lengthScale, 0.0, 10.0, true))
    return RangeError("LengthScale", this->lengthScale, "(0, 10]");
  if (!InRange(this->monopodialAngle, 0.0, 180.0))
    return RangeError("MonopodialAngle", this->monopodialAngle, "[0, 180]");
  if (!InRange(this->sympodialAngle, 0.0, 180.0))
    return RangeError("SympodialAngle", this->sympodialAngle, "[0, 180]");
  if (this->segmentsPerBranch < 1 || this->segmentsPerBranch > 10000)
    return RangeError("SegmentsPerBranch", this->segmentsPerBranch, "[1, 10000]");
  if (!InRange(this->twigScale, 0.0, 10.0, true))
    return RangeError("TwigScale", this->twigScale, "(0, 10]");
  if (this->sides < 3 || this->sides > 256)
    return RangeError("Sides", this->sides, "[3, 256]");
  if (this->maxSegments < 1 || this->maxSegments > 1000000000LL)
    return RangeError("MaxSegments", static_cast<double>(this->maxSegments), "[1, 1e9]");
  if (this->strokeControlPoints < 2 || this->strokeControlPoints > 64)
    return RangeError("StrokeControlPoints", this->strokeControlPoints, "[2, 64]");
  if (!std::isfinite(this->strokeLengthRatio) || this->strokeLengthRatio > 100.0)
    return RangeError("StrokeLengthRatio", this->strokeLengthRatio, "(0, 100], or <= 0 for the type's 0.6 / 0.8");
  if (this->strokeSubtreeDepth < 0 || this->strokeSubtreeDepth > 20)
    return RangeError("StrokeSubtreeDepth", this->strokeSubtreeDepth, "[0, 20]");
  if (static_cast<int>(this->leafType) < 0 || static_cast<int>(this->leafType) > 2)
    return RangeError("LeafType", static_cast<int>(this->leafType), "{0 Monopodial, 1 Sympodial, 2 Willow}");
  if (this->leafCount < 0 || this->leafCount > 1000)
    return RangeError("LeafCount", this->leafCount, "[0, 1000]");
  if (!InRange(this->leafRatio, 0.0, 1.0))
    return RangeError("LeafRatio", this->leafRatio, "[0, 1]");
  if (!InRange(this->leafScale, 0.0, 1e5, true))
    return RangeError("LeafScale", this->leafScale, "(0, 1e5]");
  if (!InRange(this->leafAngle, 0.0, 180.0))
    return RangeError("LeafAngle", this->leafAngle, "[0, 180]");
  if (!InRange(this->leafTipScale, 0.0, 10.0, true))
    return RangeError("LeafTipScale", this->leafTipScale, "(0, 10]");
  if (!InRange(this->leafScaleSpread, 0.0, 1.0))
    return RangeError("LeafScaleSpread", this->leafScaleSpread, "[0, 1]");
  if (this->mergeParent < -1)
    return RangeError("MergeParentBranch", this->mergeParent, "[-1, 2147483647] (-1: a second trunk)");
  if (!InRange(this->mergeU, 0.0, 1.0))
    return RangeError("MergeU", this->mergeU, "[0, 1]");
  if (!InRange(this->mergeAngle, 0.0, 180.0))
    return RangeError("MergeAngle", this->mergeAngle, "[0, 180]");
  if (!InRange(this->mergeRotation, -1e6, 1e6))
    return RangeError("MergeRotation", this->mergeRotation, "[-1e6, 1e6]");
  if (!InRange(this->mergeScale, 0.0, 1e6, true))
    return RangeError("MergeScale", this->mergeScale, "(0, 1e6]");
  if (!this->mergeOffset.allFinite() || this->mergeOffset.cwiseAbs().maxCoeff() > 1e9)
    return RangeError("MergeOffset", this->mergeOffset.cwiseAbs().maxCoeff(), "[-1e9, 1e9] in each coordinate");
  for (const auto& [id, o] : this->overrides)
  {
    std::ostringstream where;
    where << "BranchOverrides row of branch " << id << ": ";
    if (!std::isnan(o.length) && !InRange(o.length, 0.0, 1e6, true))
      return where.str() + RangeError("length", o.length, "(0, 1e6] or NaN (keep)");
    if (!std::isnan(o.radius) && !InRange(o.radius, 0.0, 1e5, true))
      return where.str() + RangeError("radius", o.radius, "(0, 1e5] or NaN (keep)");
    if (!std::isnan(o.u) && !InRange(o.u, 0.0, 1.0))
      return where.str() + RangeError("u", o.u, "[0, 1] or NaN (keep)");
    if (!std::isnan(o.angle) && !InRange(o.angle, 0.0, 180.0))
      return where.str() + RangeError("angle", o.angle, "[0, 180] or NaN (keep)");
    if (!std::isnan(o.rotation) && !InRange(o.rotation, -1e6, 1e6))
      return where.str() + RangeError("rotation_angle", o.rotation, "[-1e6, 1e6] or NaN (keep)");
  }
  return {};
}

void ApplyTreePreset(int preset, TreeParameters& s)
{
  switch (preset)
  {
    case 1:
      s.type = TreeType::Monopodial, s.depth = 4, s.ratio = 0.7, s.length = 12.0, s.radius = 0.4;
      s.phyllotaxisA = 3, s.phyllotaxisB = 8, s.childCount = 8;
      break;
    case 2:
      s.type = TreeType::Sympodial, s.depth = 6, s.ratio = 0.0, s.length = 5.0, s.radius = 0.4;
      s.phyllotaxisA = 1, s.phyllotaxisB = 3, s.childCount = 3;
      break;
    case 3:
      s.type = TreeType::Monopodial, s.depth = 4, s.ratio = 1.0, s.length = 12.0, s.radius = 0.4;
      s.phyllotaxisA = 5, s.phyllotaxisB = 8, s.childCount = 10;
      break;
    default:
      break;
  }
}

const char* TreePresetName(int preset)
{
  switch (preset)
  {
    case 1:
      return "Table 1 left: monopodial 3/8";
    case 2:
      return "Table 1 middle: sympodial 1/3";
    case 3:
      return "Table 1 right: monopodial 5/8";
    default:
      return "Custom";
  }
}

long long Tree::SegmentCount() const
{
  long long count = 0;
  for (const TreeBranch& b : this->branches)
  {
    count += static_cast<long long>(b.centre.size()) - 1;
  }
  return count;
}

long long SubtreeSize(int childCount, int levels)
{
  const long long cap = 1LL << 62;
  long long total = 1, power = 1;
  for (int l = 1; l <= levels; ++l)
  {
    power = power > cap / std::max(childCount, 1) ? cap : power * childCount;
    total = std::min(cap, total + power);
  }
  return total;
}

double PhyllotaxisAngle(long long i, int a, int b)
{
  const long long r = ((i % b) * a) % b;
  return static_cast<double>(r) * 360.0 / b;
}

Eigen::Matrix3d RotationY(double degrees)
{
  const double c = std::cos(degrees * Degree), s = std::sin(degrees * Degree);
  Eigen::Matrix3d m;
  m << c, 0, s, 0, 1, 0, -s, 0, c;
  return m;
}

Eigen::Matrix3d RotationZ(double degrees)
{
  const double c = std::cos(degrees * Degree), s = std::sin(degrees * Degree);
  Eigen::Matrix3d m;
  m << c, -s, 0, s, c, 0, 0, 0, 1;
  return m;
}

void BranchFrameAt(const TreeBranch& b, double pos, Eigen::Vector3d& point, Eigen::Matrix3d& frame, double& radius)
{
  pos = std::clamp(pos, 0.0, 1.0);
  const std::size_t n = b.centre.size();
  if (n < 2)
  {
    point = n ? b.centre[0] : Eigen::Vector3d::Zero();
    frame = b.frame;
    radius = b.radius;
    return;
  }
  if (b.straight)
  {
    point = b.centre.front() + pos * (b.centre.back() - b.centre.front());
    frame = b.frame;
    radius = b.radius + pos * (b.radiusEnd - b.radius);
    return;
  }
  // Arc-length position, then the segment holding it.
  std::vector<double> s(n, 0.0);
  for (std::size_t k = 1; k < n; ++k)
  {
    s[k] = s[k - 1] + (b.centre[k] - b.centre[k - 1]).norm();
  }
  const double target = pos * s.back();
  std::size_t k = static_cast<std::size_t>(std::upper_bound(s.begin(), s.end(), target) - s.begin());
  k = std::clamp<std::size_t>(k, 1, n - 1) - 1;
  const double width = s[k + 1] - s[k];
  const double f = width > 0.0 ? (target - s[k]) / width : 0.0;
  point = b.centre[k] + f * (b.centre[k + 1] - b.centre[k]);
  radius = b.radii[k] + f * (b.radii[k + 1] - b.radii[k]);
  const std::vector<OrthonormalFrame> frames =
    RotationMinimizingFrames(b.centre, PolylineTangents(b.centre), b.frame.col(0));
  const Eigen::Vector3d d = (b.centre[k + 1] - b.centre[k]).norm() > 0.0
    ? Eigen::Vector3d((b.centre[k + 1] - b.centre[k]).normalized())
    : frames[k].tangent;
  const Eigen::Matrix3d turn = Eigen::Quaterniond::FromTwoVectors(frames[k].tangent, d).toRotationMatrix();
  frame.col(0) = turn * frames[k].normal;
  frame.col(1) = d;
  frame.col(2) = frame.col(0).cross(d).normalized();
  frame.col(0) = d.cross(frame.col(2)).normalized();
}

Eigen::Vector3d ChildBase(const Eigen::Vector3d& axisPoint, const Eigen::Matrix3d& parentFrame, double parentRadius,
  double angle, double rotation)
{
  if (!(std::sin(angle * Degree) > 1e-9))
  {
    return axisPoint;
  }
  const Eigen::Vector3d outward =
    parentFrame * Eigen::Vector3d(-std::cos(rotation * Degree), 0.0, std::sin(rotation * Degree));
  return axisPoint + parentRadius * outward;
}

std::vector<TubeInput> TreeTubeInputs(const Tree& tree)
{
  std::map<int, std::int64_t> index;
  std::vector<TubeInput> tubes(tree.branches.size());
  for (std::size_t t = 0; t < tree.branches.size(); ++t)
  {
    const TreeBranch& b = tree.branches[t];
    index[b.id] = static_cast<std::int64_t>(t);
    tubes[t].centre = b.centre;
    tubes[t].radii = b.radii;
    tubes[t].normal = b.frame.col(0);
    const auto parent = index.find(b.parentId);
    tubes[t].parent = parent == index.end() ? -1 : parent->second;
  }
  return tubes;
}

void MakeStraightBranch(const TreeParameters& settings, const Eigen::Vector3d& base, TreeBranch& b)
{
  const int segments = settings.segmentsPerBranch;
  const Eigen::Vector3d direction = b.frame.col(1);
  b.centre.resize(static_cast<std::size_t>(segments) + 1);
  b.radii.resize(b.centre.size());
  for (int k = 0; k <= segments; ++k)
  {
    const double f = static_cast<double>(k) / segments;
    b.centre[static_cast<std::size_t>(k)] = base + (f * b.length) * direction;
    b.radii[static_cast<std::size_t>(k)] = b.radius + f * (b.radiusEnd - b.radius);
  }
  b.centre.back() = base + b.length * direction;
  b.straight = true;
}

namespace
{
double EndRadius(const TreeParameters& s, double radius)
{
  return s.type == TreeType::Monopodial ? 0.0 : radius / std::sqrt(static_cast<double>(s.childCount));
}

void ApplyOverride(const TreeParameters& s, TreeBranch& b)
{
  const auto found = s.overrides.find(b.id);
  if (found == s.overrides.end())
  {
    return;
  }
  const BranchOverride& o = found->second;
  if (!std::isnan(o.length))
    b.length = o.length;
  if (!std::isnan(o.radius))
    b.radius = o.radius;
  if (!std::isnan(o.u))
    b.position = o.u;
  if (!std::isnan(o.angle))
    b.angle = o.angle;
  if (!std::isnan(o.rotation))
    b.rotation = o.rotation;
}

void GrowRecursive(const TreeParameters& s, std::size_t index, Tree& tree)
{
  const int levels = tree.branches[index].level;
  if (levels <= 0)
  {
    return;
  }
  const int c = s.childCount;
  const long long block = SubtreeSize(c, levels - 1);
  for (int i = 1; i <= c; ++i)
  {
    const TreeBranch& parent = tree.branches[index];
    TreeBranch child;
    child.id = static_cast<int>(parent.id + 1 + (i - 1) * block);
    if (s.deletedBranches.count(child.id))
    {
      continue;
    }
    child.parentId = parent.id;
    child.depth = parent.depth + 1;
    child.level = levels - 1;
    child.childIndex = i;
    child.strokeIndex = -1;
    child.position = (1.0 - s.ratio) + i * s.ratio / c;
    const double pos = child.position;
    if (s.type == TreeType::Monopodial)
    {
      child.length = parent.length * (1.0 - 0.618 * pos);
      child.radius = parent.radius * (1.0 - 0.618 * pos);
    }
    else
    {
      child.length = parent.length * s.lengthScale;
      child.radius = parent.radius + pos * (parent.radiusEnd - parent.radius);
    }
    if (child.level == 0)
    {
      child.length *= s.twigScale;
    }
    child.angle = s.Angle();
    child.rotation = PhyllotaxisAngle(i, s.phyllotaxisA, s.phyllotaxisB);
    ApplyOverride(s, child);
    child.radiusEnd = EndRadius(s, child.radius);

    Eigen::Vector3d axisPoint;
    Eigen::Matrix3d parentFrame;
    double parentRadius = 0.0;
    BranchFrameAt(parent, child.position, axisPoint, parentFrame, parentRadius);
    child.frame = parentFrame * RotationY(child.rotation) * RotationZ(child.angle);
    MakeStraightBranch(s, ChildBase(axisPoint, parentFrame, parentRadius, child.angle, child.rotation), child);
    tree.branches.push_back(std::move(child));
    GrowRecursive(s, tree.branches.size() - 1, tree);
  }
}
} // namespace

void GrowTemplateChildren(const TreeParameters& settings, std::size_t index, Tree& tree)
{
  GrowRecursive(settings, index, tree);
}

std::string BuildTree(
  const TreeParameters& settings, const std::vector<std::vector<Eigen::Vector3d>>& strokes, Tree& tree)
{
  return BuildTree(settings, strokes, nullptr, tree);
}

std::string BuildTree(const TreeParameters& settings, const std::vector<std::vector<Eigen::Vector3d>>& strokes,
  const std::vector<SkeletonBranch>* second, Tree& tree)
{
  tree = Tree();
  std::string error = settings.Validate();
  if (!error.empty())
  {
    return error;
  }
  // Memory budget, from closed forms before anything is allocated.
  const double segments = static_cast<double>(settings.segmentsPerBranch);
  double estimate = 0.0;
  if (settings.mode != TreeMode::Strokes)
  {
    estimate += static_cast<double>(SubtreeSize(settings.childCount, settings.depth)) * segments;
  }
  if (settings.mode != TreeMode::Template)
  {
    const int levels = settings.strokesOnly ? 0 : settings.strokeSubtreeDepth;
    estimate += static_cast<double>(strokes.size()) * static_cast<double>(SubtreeSize(settings.childCount, levels)) *
      (segments + 2.0);
  }
  if (second)
  {
    for (const SkeletonBranch& b : *second)
    {
      estimate += static_cast<double>(b.centre.size());
    }
  }
  if (estimate > static_cast<double>(settings.maxSegments))
  {
    std::ostringstream out;
    out << "the tree would have about " << estimate << " segments, more than MaxSegments = " << settings.maxSegments
        << " (lower Depth, ChildCount, StrokeSubtreeDepth or SegmentsPerBranch, or raise MaxSegments)";
    return out.str();
  }

  if (settings.mode != TreeMode::Strokes && !settings.deletedBranches.count(0))
  {
    TreeBranch trunk;
    trunk.id = 0;
    trunk.level = settings.depth;
    trunk.length = settings.length;
    trunk.radius = settings.radius;
    if (trunk.level == 0)
    {
      trunk.length *= settings.twigScale;
    }
    ApplyOverride(settings, trunk);
    trunk.radiusEnd = EndRadius(settings, trunk.radius);
    MakeStraightBranch(settings, Eigen::Vector3d::Zero(), trunk);
    tree.branches.push_back(std::move(trunk));
    GrowTemplateChildren(settings, 0, tree);
  }
  if (settings.mode != TreeMode::Template)
  {
    error = AddStrokes(settings, strokes, tree);
    if (!error.empty())
    {
      tree = Tree();
      return error;
    }
  }
  if (second && !second->empty())
  {
    error = MergeTree(settings, strokes.size(), *second, tree);
    if (!error.empty())
    {
      tree = Tree();
      return error;
    }
  }
  if (settings.leaves)
  {
    error = PlaceLeaves(settings, tree);
    if (!error.empty())
    {
      tree = Tree();
      return error;
    }
  }
  return {};
}

} // namespace plantmorph
