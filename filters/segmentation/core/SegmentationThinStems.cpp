// SPDX-License-Identifier: GPL-3.0-or-later
// Thin stems stay wood (PlantSegmentation.h, step 3's last rule): a stem only a few point spacings across, where
// leaves hang off it, is followed along its own axis from the wood it continues.
#include "SegmentationSteps.h"

#include "PointGrid.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <deque>

namespace plantmorph
{
namespace segmentation
{
namespace
{
/// A thin stem is at most this many spacings in radius (4 spacings across: 2-4 points), plus ThinStemNoise times
/// the range noise (the noise widens the scanned line).
constexpr double ThinStemSpacings = 2.0, ThinStemNoise = 3.0;
/// The wood within the features' radius r of a point of a thin stem spans at least this fraction of the ball's
/// diameter 2r along its axis (a line through the ball's centre spans all of it; a line ending at the centre, a stem
/// followed to where the leaves begin, half): a run far longer than wide (at the default scale 8 spacings or more,
/// at least twice the widest stem's width).
constexpr double ThinStemSpan = 0.4;
/// Beside a stem's continuation the leaf points (beyond the stem's radius, within r) lie on one side of it, a blade
/// hanging off the stem or touching it along its edge; when at least this fraction of them lie on the other side
/// too, the line runs inside a sheet (a blade continuing the stem in line, its midrib on the stem's axis): the
/// stem ended where that blade begins.
constexpr double InsideSheetFraction = 0.25;
/// A stem stands off the plane of a blade beside it: its points near the line followed (the wood within r) by more
/// than StemRunOffNoise times the range noise (root mean square), the point taken by more than StemPointOffNoise
/// times it. A blade's own margin, a band of wood at its edge where the features saw no sheet, lies in the blade's
/// plane within the noise; a stem of radius rho beside a blade touching it lies up to 2 rho off its plane.
constexpr double StemRunOffNoise = 2.0, StemPointOffNoise = 1.0;

/// The line of the wood points within r of a point (`line` false when they are no thin run): their mean, their
/// main axis, their root mean square distance from it.
struct StemLine
{
  bool line = false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::Zero();
  double across = 0.0;   ///< root mean square distance of the wood from the axis
  std::vector<int> wood; ///< the wood points within r
};

StemLine ThinLineAround(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& near,
  const std::vector<int>& organ, double radius, double maximumRadius, double spacing)
{
  StemLine s;
  std::vector<int>& wood = s.wood;
  for (int j : near)
    if (organ[static_cast<std::size_t>(j)] == OrganWood)
      wood.push_back(j);
  // a run spanning ThinStemSpan of the ball holds at least one point a spacing along it
  if (static_cast<double>(wood.size()) * spacing < ThinStemSpan * 2.0 * radius)
    return s;
  const Eigen::Matrix3d scatter = Scatter(points, wood, s.mean) / static_cast<double>(wood.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);
  s.axis = solver.eigenvectors().col(2);
  // a uniform run of length L has the variance L^2 / 12 along it; the points of a stem of radius rho lie about
  // rho from its axis (its visible side: within rho)
  s.across = std::sqrt(l[0] + l[1]);
  s.line = std::sqrt(12.0 * l[2]) >= ThinStemSpan * 2.0 * radius && s.across <= 0.5 * maximumRadius;
  return s;
}

/// Whether point `at`, on the line followed (`line`: its axis, the wood within r), lies off the sheet beside it:
/// the points `near` (within r of `at`) beyond `maximumRadius` from the line and within r / 2 of `at` along it are a
/// blade hanging off the stem or touching it along its edge, on one side of the line; their plane passes through
/// their mean, normal to the main direction of their features' normals (steadier than the plane of a narrow band
/// of noisy points). The stem stands off it (StemRunOffNoise, StemPointOffNoise). False when those points lie on
/// both sides of the line (InsideSheetFraction: the line runs inside a sheet, a blade continuing the stem in line,
/// its midrib on the stem's axis); true when there are under 4 or their normals agree no more than a leaf region's
/// must (SheetCoherence: no sheet, another twig or several surfaces).
bool OffTheSheetBeside(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const std::vector<int>& near,
  const StemLine& line, const Eigen::Vector3d& at, double maximumRadius, double sheetCoherence)
{
  std::vector<int> beside;
  std::vector<Eigen::Vector3d> across;
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (int j : near)
  {
    const Eigen::Vector3d d = points[static_cast<std::size_t>(j)] - at;
    const double along = d.dot(line.axis);
    const Eigen::Vector3d e = d - along * line.axis;
    if (std::abs(along) > 0.5 * f.radius || e.norm() <= maximumRadius)
      continue;
    beside.push_back(j);
    across.push_back(e.normalized());
    m += across.back() * across.back().transpose();
  }
  if (across.size() < 4)
    return true;
  const Eigen::Vector3d side = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m).eigenvectors().col(2);
  const auto positive =
    std::count_if(across.begin(), across.end(), [&](const Eigen::Vector3d& e) { return e.dot(side) > 0.0; });
  const auto fewer = std::min<std::size_t>(static_cast<std::size_t>(positive), across.size() - positive);
  if (static_cast<double>(fewer) >= InsideSheetFraction * static_cast<double>(across.size()))
    return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d normals = Eigen::Matrix3d::Zero();
  for (int j : beside)
  {
    mean += points[static_cast<std::size_t>(j)];
    normals += f.normal[static_cast<std::size_t>(j)] * f.normal[static_cast<std::size_t>(j)].transpose();
  }
  mean /= static_cast<double>(beside.size());
  const Eigen::Vector3d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(normals).eigenvectors().col(2);
  double coherence = 0.0;
  for (int j : beside)
    coherence += std::abs(f.normal[static_cast<std::size_t>(j)].dot(normal));
  if (coherence < sheetCoherence * static_cast<double>(beside.size()))
    return true; // no sheet: a line of points, or several surfaces
  const double noise = f.noise;
  double runOff = 0.0;
  for (int j : line.wood)
    runOff += std::pow((points[static_cast<std::size_t>(j)] - mean).dot(normal), 2);
  return std::abs((at - mean).dot(normal)) > StemPointOffNoise * noise &&
    std::sqrt(runOff / static_cast<double>(line.wood.size())) > StemRunOffNoise * noise;
}
} // namespace

std::size_t ThinStemsStayWood(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f,
  const LinkGraph& graph, double spacing, double sheetCoherence, std::vector<int>& organ, std::vector<int>& region,
  std::vector<double>& confidence)
{
  const std::size_t n = points.size();
  const double r = f.radius;
  const double maximumRadius = ThinStemSpacings * spacing + ThinStemNoise * f.noise;
  const PointGrid grid(points, r);
  std::vector<int> near;
  // the wood points linked to a leaf point, in index order: where a stem may run on among leaves
  std::deque<int> queue;
  std::vector<char> queued(n, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (organ[i] != OrganWood)
      continue;
    for (std::size_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e)
      if (organ[static_cast<std::size_t>(graph.neighbours[e])] == OrganLeaf)
      {
        queued[i] = 1;
        queue.push_back(static_cast<int>(i));
        break;
      }
  }
  std::size_t made = 0;
  while (!queue.empty())
  {
    const auto q = static_cast<std::size_t>(queue.front());
    queue.pop_front();
    grid.Within(points[q], r, near);
    const StemLine s = ThinLineAround(points, near, organ, r, maximumRadius, spacing);
    if (!s.line)
      continue;
    for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
    {
      const auto j = static_cast<std::size_t>(graph.neighbours[e]);
      if (organ[j] != OrganLeaf || queued[j])
        continue;
      const Eigen::Vector3d d = points[j] - s.mean;
      if ((d - d.dot(s.axis) * s.axis).norm() > 2.0 * s.across)
        continue;
      grid.Within(points[j], r, near);
      if (!OffTheSheetBeside(points, f, near, s, points[j], maximumRadius, sheetCoherence))
        continue;
      organ[j] = OrganWood;
      region[j] = -1;
      confidence[j] = 0.5;
      queued[j] = 1;
      queue.push_back(static_cast<int>(j));
      ++made;
    }
  }
  return made;
}

} // namespace segmentation
} // namespace plantmorph
