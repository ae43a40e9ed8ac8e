// SPDX-License-Identifier: GPL-3.0-or-later
#include "TreeStrokes.h"

#include "StrokeSegmentGrid.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/BezierCurve.h>
#include <plantmorph/RandomStream.h>
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

std::string StrokeError(std::size_t k, const std::string& what)
{
  std::ostringstream out;
  out << "Strokes input, stroke " << k << ": " << what;
  return out.str();
}
} // namespace

double PointSegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double& mu)
{
  const Eigen::Vector2d ab = b - a, ap = p - a, bp = p - b;
  if (ap.dot(ab) <= 0.0)
  {
    mu = 0.0;
    return ap.norm();
  }
  if (bp.dot(-ab) <= 0.0)
  {
    mu = 1.0;
    return bp.norm();
  }
  mu = ap.dot(ab) / ab.squaredNorm();
  const double along = ap.dot(ab) / ab.norm();
  return std::sqrt(std::max(0.0, ap.squaredNorm() - along * along));
}

double SignedSegmentAngle(const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  const double c = std::clamp(a.dot(b) / (a.norm() * b.norm()), -1.0, 1.0);
  const double angle = std::acos(c) * 180.0 / Pi;
  const double crossZ = b.x() * a.y() - b.y() * a.x(); // (b x a).e_z
  return crossZ > 0.0 ? angle : -angle;
}

double LiftedLength(const std::vector<Eigen::Vector2d>& q, double theta)
{
  const double c = std::cos(theta);
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < q.size(); ++i)
  {
    const double dx = q[i + 1].x() - q[i].x(), dy = q[i + 1].y() - q[i].y();
    total += std::sqrt(dx * dx / (c * c) + dy * dy);
  }
  return total;
}

namespace
{
/// The strokes checked: at least one, each of two or more finite points and a positive length in the image.
std::string ValidateStrokes(const std::vector<std::vector<Eigen::Vector3d>>& strokes)
{
  if (strokes.empty())
  {
    return "Strokes input: no strokes (Mode Strokes and 'Template and strokes' need polylines on the Strokes input "
           "or a StrokeFile)";
  }
  for (std::size_t k = 0; k < strokes.size(); ++k)
  {
    const auto& stroke = strokes[k];
    if (stroke.size() < 2)
    {
      return StrokeError(k, "has " + std::to_string(stroke.size()) + " point(s); a stroke needs at least 2");
    }
    double length = 0.0;
    for (std::size_t i = 0; i < stroke.size(); ++i)
    {
      if (!std::isfinite(stroke[i].x()) || !std::isfinite(stroke[i].y()))
      {
        return StrokeError(k, "point " + std::to_string(i) + " is not finite (NaN or infinite x or y)");
      }
      if (i > 0)
      {
        length += (stroke[i].head<2>() - stroke[i - 1].head<2>()).norm();
      }
    }
    if (!(length > 0.0) || !std::isfinite(length))
    {
      return StrokeError(k, "has zero length in the image plane (all its points coincide)");
    }
  }

  return {};
}

/// A point of an existing branch's centre line: segment `segment` of branch `branch`, at `mu` along it.
struct Candidate
{
  std::size_t branch, segment;
  double mu;
};

/// Eq. (2): the existing branch segments nearest to `p` in the image plane (all of them on an exact tie), at `best`.
std::vector<Candidate> NearestSegments(const Tree& tree, const Eigen::Vector2d& p, double& best)
{
  std::vector<Candidate> nearest;
  best = std::numeric_limits<double>::infinity();
  const double tolerance = 1e-12 * (1.0 + p.norm());
  for (std::size_t bi = 0; bi < tree.branches.size(); ++bi)
  {
    const TreeBranch& b = tree.branches[bi];
    for (std::size_t j = 0; j + 1 < b.centre.size(); ++j)
    {
      double mu = 0.0;
      const double d = PointSegmentDistance(p, b.centre[j].head<2>(), b.centre[j + 1].head<2>(), mu);
      if (d < best - tolerance)
      {
        best = d;
        nearest.clear();
      }
      if (d <= best + tolerance)
      {
        nearest.push_back({ bi, j, mu });
      }
    }
  }
  return nearest;
}

/// NearestSegments through the grid: the same candidates in the same order and the same `best`. The grid gives the
/// smallest distance D and the branches within D + 4 tol; their segments are searched in (branch, segment) order.
/// When every segment within D + 4 tol is within D + tol, the exhaustive search keeps exactly those (its running
/// best is the first one's distance, and nothing farther than D + 4 tol enters or resets it); otherwise (near-ties
/// at the 1e-12 scale that its order decides) the exhaustive search itself answers.
std::vector<Candidate> NearestSegmentsIndexed(
  const Tree& tree, StrokeSegmentGrid& grid, const Eigen::Vector2d& p, double& best)
{
  const double tolerance = 1e-12 * (1.0 + p.norm());
  double low = 0.0;
  std::vector<std::size_t> branches;
  if (!grid.Nearest(p, 4.0 * tolerance, low, branches))
  {
    return NearestSegments(tree, p, best);
  }
  std::vector<Candidate> nearest;
  for (std::size_t bi : branches)
  {
    const TreeBranch& b = tree.branches[bi];
    for (std::size_t j = 0; j + 1 < b.centre.size(); ++j)
    {
      double mu = 0.0;
      const double d = PointSegmentDistance(p, b.centre[j].head<2>(), b.centre[j + 1].head<2>(), mu);
      if (d <= low + 4.0 * tolerance)
      {
        if (d > low + tolerance)
        {
          return NearestSegments(tree, p, best);
        }
        best = nearest.empty() ? d : best;
        nearest.push_back({ bi, j, mu });
      }
    }
  }
  if (nearest.empty())
  {
    return NearestSegments(tree, p, best);
  }
  return nearest;
}

/// Registers every segment of branch `bi` in the grid.
void AddToGrid(const Tree& tree, std::size_t bi, StrokeSegmentGrid& grid)
{
  const TreeBranch& b = tree.branches[bi];
  for (std::size_t j = 0; j + 1 < b.centre.size(); ++j)
  {
    grid.Add(bi, b.centre[j].head<2>(), b.centre[j + 1].head<2>());
  }
}

/// A grid over the tree's segments, sized for the strokes to come.
StrokeSegmentGrid MakeGrid(
  const TreeParameters& s, const std::vector<std::vector<Eigen::Vector3d>>& strokes, const Tree& tree)
{
  std::vector<Eigen::Vector2d> points;
  std::size_t segments = 0;
  for (const auto& stroke : strokes)
  {
    for (const auto& x : stroke)
    {
      points.push_back(x.head<2>());
    }
  }
  for (const auto& b : tree.branches)
  {
    for (const auto& x : b.centre)
    {
      points.push_back(x.head<2>());
    }
    segments += b.centre.size();
  }
  segments += strokes.size() * static_cast<std::size_t>(std::max(1, s.segmentsPerBranch));
  StrokeSegmentGrid grid(points, segments);
  for (std::size_t bi = 0; bi < tree.branches.size(); ++bi)
  {
    AddToGrid(tree, bi, grid);
  }
  return grid;
}

/// Attaches stroke `k` at the chosen nearest point: C (`c3`) and the parent's radius there, C inserted into the
/// parent's centre line (unless u is overridden: the branch moves, and its own base is inserted instead); ties
/// broken by the seeded generator. Returns the parent.
TreeBranch* AttachToNearest(const TreeParameters& s, std::size_t k, const std::vector<Candidate>& nearest, double best,
  const BranchOverride& edit, Tree& tree, StrokeReport& report, Eigen::Vector3d& c3, double& parentRadiusAtC,
  StrokeSegmentGrid* grid)
{
  std::size_t pick = 0;
  if (nearest.size() > 1)
  {
    RandomStream random(s.seed, 0x5354524F4B45ull + k);
    pick = static_cast<std::size_t>(random.Integer(0, static_cast<std::int64_t>(nearest.size()) - 1));
  }
  const Candidate chosen = nearest[pick];
  TreeBranch& host = tree.branches[chosen.branch];
  report.parentId = host.id;
  report.distance = best;
  const Eigen::Vector3d a = host.centre[chosen.segment], b = host.centre[chosen.segment + 1];
  const double ra = host.radii[chosen.segment], rb = host.radii[chosen.segment + 1];
  double mu = chosen.mu;
  if (mu < 1e-9 || mu > 1.0 - 1e-9)
  {
    mu = mu < 0.5 ? 0.0 : 1.0;
    c3 = mu == 0.0 ? a : b;
    parentRadiusAtC = mu == 0.0 ? ra : rb;
  }
  else
  {
    // C = lambda*A + (1 - lambda)*B, inserted into the parent's centre line.
    const double lambda = 1.0 - mu;
    c3 = lambda * a + (1.0 - lambda) * b;
    parentRadiusAtC = lambda * ra + (1.0 - lambda) * rb;
    if (std::isnan(edit.u)) // with u overridden the branch moves, and its own base is inserted instead
    {
      host.centre.insert(host.centre.begin() + static_cast<std::ptrdiff_t>(chosen.segment) + 1, c3);
      host.radii.insert(host.radii.begin() + static_cast<std::ptrdiff_t>(chosen.segment) + 1, parentRadiusAtC);
      if (grid)
      {
        grid->Split(chosen.branch, a.head<2>(), c3.head<2>(), b.head<2>());
      }
    }
  }
  report.lambda = 1.0 - mu;
  return &host;
}

/// The arc-length position (0 base, 1 tip) of C on the parent's centre line.
double PositionOnParent(const TreeBranch& parent, const Eigen::Vector3d& c3)
{
  double along = 0.0, total = 0.0;
  bool found = false;
  for (std::size_t j = 0; j + 1 < parent.centre.size(); ++j)
  {
    if (!found && parent.centre[j] == c3)
    {
      along = total;
      found = true;
    }
    total += (parent.centre[j + 1] - parent.centre[j]).norm();
  }
  if (!found)
  {
    along = total;
  }
  return total > 0.0 ? along / total : 0.0;
}

/// The plane angle: theta* from the length rule, then the phyllotaxis candidate, or the overridden rotation angle.
/// Sets the report's angles and `phi`, the rotation angle in degrees; "" or why the override cannot be used.
std::string ChoosePlaneAngle(const TreeParameters& s, const std::vector<Eigen::Vector2d>& q, const TreeBranch& parent,
  double ratio, const BranchOverride& edit, int id, StrokeReport& report, double& phi)
{
  const double target = ratio * parent.length;
  report.targetLength = target;
  double thetaStar = 0.0;
  bool anyDx = false;
  for (std::size_t i = 0; i + 1 < q.size(); ++i)
  {
    anyDx = anyDx || q[i + 1].x() != q[i].x();
  }
  if (anyDx && target > report.planarLength)
  {
    double low = 0.0, high = Pi / 2.0;
    for (int iteration = 0; iteration < 200 && high - low > 1e-15; ++iteration)
    {
      const double mid = 0.5 * (low + high);
      (LiftedLength(q, mid) < target ? low : high) = mid;
    }
    thetaStar = 0.5 * (low + high) / Degree;
  }
  report.recommendedTheta = thetaStar;
  const bool toMinusX = q.back().x() - q.front().x() < 0.0;
  std::vector<std::pair<double, double>> candidates; // (theta, phi) in degrees
  for (int i = 1; i <= s.phyllotaxisB; ++i)
  {
    const double angle = PhyllotaxisAngle(i, s.phyllotaxisA, s.phyllotaxisB);
    const int quadrant = std::min(3, static_cast<int>(angle / 90.0));
    const bool allowed = toMinusX ? (quadrant == 1 || quadrant == 2) : (quadrant == 0 || quadrant == 3);
    const double theta = quadrant == 0 ? angle
      : quadrant == 1                  ? 180.0 - angle
      : quadrant == 2                  ? angle - 180.0
                                       : 360.0 - angle;
    if (allowed && theta < 90.0 - 1e-12)
    {
      candidates.emplace_back(theta, angle);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  double theta = 0.0;
  phi = toMinusX ? 180.0 : 0.0;
  const std::pair<double, double>* below = nullptr;
  const std::pair<double, double>* above = nullptr;
  const std::pair<double, double>* equal = nullptr;
  for (const auto& candidate : candidates)
  {
    if (std::abs(candidate.first - thetaStar) <= 1e-9)
    {
      equal = equal ? equal : &candidate;
    }
    else if (candidate.first < thetaStar)
    {
      below = &candidate;
    }
    else if (!above)
    {
      above = &candidate;
    }
  }
  const auto error = [&](const std::pair<double, double>* c) {
    return std::abs((LiftedLength(q, c->first * Degree) - target) / target);
  };
  const std::pair<double, double>* choice = equal;
  if (!choice)
  {
    choice = !below ? above : !above ? below : (error(above) < error(below) ? above : below);
  }
  if (choice)
  {
    theta = choice->first;
    phi = choice->second;
  }
  report.theta = theta;
  if (!std::isnan(edit.rotation))
  {
    // The user's rotation angle replaces the phyllotaxis choice; the branch still projects onto its stroke.
    phi = edit.rotation - 360.0 * std::floor(edit.rotation / 360.0);
    if (std::abs(std::cos(phi * Degree)) < 1e-9)
    {
      std::ostringstream out;
      out.precision(17);
      out << "BranchOverrides row of branch " << id << ": rotation_angle = " << edit.rotation
          << " lifts a stroke branch into a vertical plane at 90 degrees to the image (tan = infinity); a stroke "
             "branch takes rotation angles whose plane angle theta is below 90 degrees (not 90 or 270 mod 360)";
      return out.str();
    }
    const int quadrant = std::min(3, static_cast<int>(phi / 90.0));
    theta = quadrant == 0 ? phi : quadrant == 1 ? 180.0 - phi : quadrant == 2 ? phi - 180.0 : 360.0 - phi;
    report.theta = theta;
  }
  report.rotation = phi;
  return {};
}

/// The stroke lifted out of the image plane by `slope` about C, then scaled about C to an overridden length.
void LiftStroke(const std::vector<Eigen::Vector2d>& q, const Eigen::Vector3d& c3, double slope,
  const BranchOverride& edit, TreeBranch& branch)
{
  branch.centre.resize(q.size());
  for (std::size_t i = 0; i < q.size(); ++i)
  {
    const double dx = q[i].x() - c3.x(), dy = q[i].y() - c3.y();
    branch.centre[i] = Eigen::Vector3d(c3.x() + dx, c3.y() + dy, c3.z() + dx * slope);
  }
  branch.centre[0] = c3;
  if (!std::isnan(edit.length))
  {
    // Scaled about C to the given arc length (its projection is the stroke scaled about C).
    double lifted = 0.0;
    for (std::size_t i = 1; i < q.size(); ++i)
    {
      lifted += (branch.centre[i] - branch.centre[i - 1]).norm();
    }
    const double stretch = edit.length / lifted;
    for (std::size_t i = 1; i < q.size(); ++i)
    {
      branch.centre[i] = c3 + stretch * (branch.centre[i] - c3);
    }
  }
}

/// An overridden u: the branch moved so its base is the parent's centre-line point at u, inserted there.
void MoveToOverriddenU(const BranchOverride& edit, TreeBranch& host, Eigen::Vector3d& c3, double& parentRadiusAtC,
  TreeBranch& branch, StrokeSegmentGrid* grid, std::size_t hostIndex)
{
  // Move the branch so its base is the parent's centre-line point at u, and insert that point there.
  std::vector<double> arc(host.centre.size(), 0.0);
  for (std::size_t j = 1; j < host.centre.size(); ++j)
  {
    arc[j] = arc[j - 1] + (host.centre[j] - host.centre[j - 1]).norm();
  }
  const double along = edit.u * arc.back();
  std::size_t j = static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), along) - arc.begin());
  j = std::clamp<std::size_t>(j, 1, host.centre.size() - 1) - 1;
  const double f = arc[j + 1] > arc[j] ? (along - arc[j]) / (arc[j + 1] - arc[j]) : 0.0;
  Eigen::Vector3d moved = host.centre[j] + f * (host.centre[j + 1] - host.centre[j]);
  parentRadiusAtC = host.radii[j] + f * (host.radii[j + 1] - host.radii[j]);
  const double tolerance = 1e-12 * (1.0 + arc.back());
  if ((moved - host.centre[j]).norm() <= tolerance)
  {
    moved = host.centre[j], parentRadiusAtC = host.radii[j];
  }
  else if ((moved - host.centre[j + 1]).norm() <= tolerance)
  {
    moved = host.centre[j + 1], parentRadiusAtC = host.radii[j + 1];
  }
  else
  {
    host.centre.insert(host.centre.begin() + static_cast<std::ptrdiff_t>(j) + 1, moved);
    host.radii.insert(host.radii.begin() + static_cast<std::ptrdiff_t>(j) + 1, parentRadiusAtC);
    if (grid)
    {
      grid->Split(hostIndex, host.centre[j].head<2>(), moved.head<2>(), host.centre[j + 2].head<2>());
    }
  }
  for (Eigen::Vector3d& x : branch.centre)
  {
    x += moved - c3;
  }
  c3 = moved;
  branch.position = edit.u;
}

/// An overridden angle: the branch turned about its base, in the plane of the parent's tangent and its first
/// direction, to the divergence.
void TurnToOverriddenAngle(
  const BranchOverride& edit, const TreeBranch& parent, const Eigen::Vector3d& c3, TreeBranch& branch)
{
  // Turned about its base, in the plane of the parent's tangent and its first direction, to the divergence.
  Eigen::Vector3d point;
  Eigen::Matrix3d parentFrame;
  double radius = 0.0;
  BranchFrameAt(parent, branch.position, point, parentFrame, radius);
  const Eigen::Vector3d tangent = parentFrame.col(1);
  const Eigen::Vector3d first = PolylineTangents(branch.centre)[0];
  Eigen::Vector3d axis = tangent.cross(first);
  axis = axis.norm() > 1e-12 ? Eigen::Vector3d(axis.normalized()) : PerpendicularTo(tangent, parentFrame.col(2));
  const double current = std::atan2(tangent.cross(first).norm(), tangent.dot(first));
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(edit.angle * Degree - current, axis).toRotationMatrix();
  for (std::size_t i = 1; i < branch.centre.size(); ++i)
  {
    branch.centre[i] = c3 + turn * (branch.centre[i] - c3);
  }
}

/// Length, radii (the type's rule or the override), frame and divergence angle of a lifted stroke branch.
void FinishStrokeBranch(const TreeParameters& s, const TreeBranch* parent, double parentRadiusAtC,
  const BranchOverride& edit, double phi, std::size_t sampleCount, TreeBranch& branch)
{
  std::vector<double> s3(sampleCount, 0.0);
  for (std::size_t i = 1; i < sampleCount; ++i)
  {
    s3[i] = s3[i - 1] + (branch.centre[i] - branch.centre[i - 1]).norm();
  }
  branch.length = s3.back();
  if (!parent)
  {
    branch.radius = s.radius;
  }
  else if (s.type == TreeType::Monopodial)
  {
    branch.radius = parent->radius * (1.0 - 0.618 * branch.position);
  }
  else
  {
    branch.radius = parentRadiusAtC;
  }
  if (!std::isnan(edit.radius))
  {
    branch.radius = edit.radius;
  }
  branch.radiusEnd = s.type == TreeType::Monopodial ? 0.0 : branch.radius / std::sqrt(double(s.childCount));
  branch.radii.resize(sampleCount);
  for (std::size_t i = 0; i < sampleCount; ++i)
  {
    const double f = branch.length > 0.0 ? s3[i] / branch.length : 0.0;
    branch.radii[i] = branch.radius + f * (branch.radiusEnd - branch.radius);
  }
  const Eigen::Vector3d y = PolylineTangents(branch.centre)[0];
  const Eigen::Vector3d z = PerpendicularTo(y, Eigen::Vector3d::UnitZ());
  branch.frame.col(1) = y;
  branch.frame.col(2) = z;
  branch.frame.col(0) = y.cross(z);
  branch.rotation = phi;
  if (parent)
  {
    Eigen::Vector3d point;
    Eigen::Matrix3d parentFrame;
    double radius = 0.0;
    BranchFrameAt(*parent, branch.position, point, parentFrame, radius);
    branch.angle = std::acos(std::clamp(y.dot(parentFrame.col(1)), -1.0, 1.0)) / Degree;
  }
}
} // namespace

std::string AddStrokes(
  const TreeParameters& s, const std::vector<std::vector<Eigen::Vector3d>>& strokes, Tree& tree, StrokeSearch search)
{
  if (std::string error = ValidateStrokes(strokes); !error.empty())
  {
    return error;
  }

  const int levels = s.strokesOnly ? 0 : s.strokeSubtreeDepth;
  const long long base = s.mode == TreeMode::TemplateAndStrokes ? SubtreeSize(s.childCount, s.depth) : 0;
  const long long block = SubtreeSize(s.childCount, levels);
  if (static_cast<double>(base) + static_cast<double>(block) * static_cast<double>(strokes.size()) > 2.0e9)
  {
    return "Strokes input: too many strokes for 32-bit BranchIds with this ChildCount and StrokeSubtreeDepth";
  }
  const double ratio = s.StrokeRatio();
  std::vector<std::size_t> strokeBranches;
  tree.strokes.assign(strokes.size(), StrokeReport());
  StrokeSegmentGrid grid = search == StrokeSearch::Grid ? MakeGrid(s, strokes, tree) : StrokeSegmentGrid({}, 0);
  StrokeSegmentGrid* indexed = search == StrokeSearch::Grid ? &grid : nullptr;

  for (std::size_t k = 0; k < strokes.size(); ++k)
  {
    StrokeReport& report = tree.strokes[k];
    const int id = static_cast<int>(base + static_cast<long long>(k) * block);
    report.branchId = id;
    if (s.deletedBranches.count(id))
    {
      report.branchId = -1;
      continue;
    }
    const auto& stroke = strokes[k];
    std::vector<Eigen::Vector2d> controls;
    for (int index : StrokeControlIndices(static_cast<int>(stroke.size()), s.strokeControlPoints))
    {
      controls.push_back(stroke[static_cast<std::size_t>(index)].head<2>());
    }
    const Eigen::Vector2d p = controls[0];

    // Eq. (2): the nearest existing branch segment in the image plane; exact ties by the seeded generator.
    double best = 0.0;
    const std::vector<Candidate> nearest =
      indexed ? NearestSegmentsIndexed(tree, grid, p, best) : NearestSegments(tree, p, best);

    // BranchOverrides of this stroke branch (see TreeStrokes.h: u, angle and rotation_angle need a parent).
    BranchOverride edit;
    if (const auto found = s.overrides.find(id); found != s.overrides.end())
    {
      edit = found->second;
    }

    TreeBranch branch;
    branch.id = id;
    branch.strokeIndex = static_cast<int>(k);
    branch.level = levels;
    branch.straight = false;
    Eigen::Vector3d c3(p.x(), p.y(), 0.0);
    const TreeBranch* parent = nullptr;
    double parentRadiusAtC = 0.0;
    if (!nearest.empty())
    {
      parent = AttachToNearest(s, k, nearest, best, edit, tree, report, c3, parentRadiusAtC, indexed);
    }
    // Arc-length position of C on the parent.
    if (parent)
    {
      branch.position = PositionOnParent(*parent, c3);
      branch.parentId = parent->id;
      branch.depth = parent->depth + 1;
    }
    controls[0] = c3.head<2>();
    const std::vector<Eigen::Vector2d> q = SampleBezier<2>(controls, s.segmentsPerBranch);
    report.planarLength = LiftedLength(q, 0.0);

    // Plane angle: theta* from the length rule, then the phyllotaxis candidate.
    double phi = 0.0;
    if (parent)
    {
      if (std::string error = ChoosePlaneAngle(s, q, *parent, ratio, edit, id, report, phi); !error.empty())
      {
        return error;
      }
    }
    const double slope = parent ? std::tan(phi * Degree) : 0.0;
    LiftStroke(q, c3, slope, edit, branch);
    if (parent && !std::isnan(edit.u))
    {
      const auto host = static_cast<std::size_t>(parent - tree.branches.data());
      MoveToOverriddenU(edit, tree.branches[host], c3, parentRadiusAtC, branch, indexed, host);
    }
    if (parent && !std::isnan(edit.angle))
    {
      TurnToOverriddenAngle(edit, *parent, c3, branch);
    }
    FinishStrokeBranch(s, parent, parentRadiusAtC, edit, phi, q.size(), branch);
    tree.branches.push_back(std::move(branch));
    strokeBranches.push_back(tree.branches.size() - 1);
    if (indexed)
    {
      AddToGrid(tree, tree.branches.size() - 1, grid);
    }
  }
  for (std::size_t index : strokeBranches)
  {
    GrowTemplateChildren(s, index, tree);
  }
  return {};
}

} // namespace plantmorph
