// SPDX-License-Identifier: GPL-3.0-or-later
// Steps 1 and 2 of the segmentation (PlantSegmentation.h): covariance features at two scales, the link graph and
// the region growing of smooth sheets.
#include "SegmentationSteps.h"

#include "PointGrid.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>

namespace plantmorph
{
namespace segmentation
{
namespace
{
/// At most this many neighbours (every k-th of the list) enter a covariance: a wide neighbourhood (large noise
/// widens it, see ComputeFeatures) costs no more than a narrow one, and its covariance barely changes.
constexpr std::size_t CovarianceSample = 256;

/// Eigenvalues (ascending) and vectors of the covariance of points[ids] (with at least 3 points; else zeros).
void Covariance(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, Eigen::Vector3d& values,
  Eigen::Matrix3d& vectors)
{
  values.setZero();
  vectors.setIdentity();
  if (ids.size() < 3)
    return;
  const std::size_t stride = (ids.size() + CovarianceSample - 1) / CovarianceSample;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double count = 0.0;
  for (std::size_t k = 0; k < ids.size(); k += stride, count += 1.0)
    mean += points[static_cast<std::size_t>(ids[k])];
  mean /= count;
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < ids.size(); k += stride)
  {
    const Eigen::Vector3d d = points[static_cast<std::size_t>(ids[k])] - mean;
    c += d * d.transpose();
  }
  c /= count;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(c);
  values = solver.eigenvalues().cwiseMax(0.0);
  vectors = solver.eigenvectors();
}

/// The neighbourhood's width across its main axis over the radius: sqrt(l2) / radius (0.5 on a disk, 0.26 on a
/// half disk (a leaf's margin), about rho / (sqrt(2) radius) on a twig of radius rho).
float Spread(const Eigen::Vector3d& l, double radius)
{
  return static_cast<float>(std::sqrt(l[1]) / radius);
}
} // namespace

double NoiseLevel(const std::vector<Eigen::Vector3d>& points, double r, const ParallelFor& parallel)
{
  const std::size_t step = std::max<std::size_t>(1, points.size() / 5000);
  const std::size_t count = (points.size() + step - 1) / step;
  const PointGrid grid(points, r);
  std::vector<double> residual(count, 0.0);
  parallel(count, [&](std::size_t begin, std::size_t end) {
    std::vector<int> near;
    for (std::size_t k = begin; k < end; ++k)
    {
      grid.Within(points[k * step], r, near);
      Eigen::Vector3d l;
      Eigen::Matrix3d v;
      Covariance(points, near, l, v);
      residual[k] = std::sqrt(l[0]);
    }
  });
  std::nth_element(residual.begin(), residual.begin() + static_cast<std::ptrdiff_t>(count / 4), residual.end());
  return residual[count / 4];
}

void ComputeFeatures(const std::vector<Eigen::Vector3d>& points, double spacing, const SegmentationParameters& p,
  const ParallelFor& parallel, PointFeatures& f, LinkGraph& graph)
{
  const std::size_t n = points.size();
  // The features' radius: FeatureScale spacings, or wider when the range noise is large next to it (a plane's
  // normal from points of noise sigma within r is off by about 2 sigma / r: NoiseScale sigma keeps it near 10 deg).
  constexpr double NoiseScale = 12.0;
  const double r =
    std::max(p.featureScale * spacing, NoiseScale * NoiseLevel(points, 2.0 * p.featureScale * spacing, parallel));
  const double link = p.linkScale * spacing;
  f.radius = r;
  const PointGrid grid(points, r);
  f.normal.assign(n, Eigen::Vector3d::UnitZ());
  f.spread.assign(n, 0.0f);
  f.variation.assign(n, 1.0f);
  std::vector<std::vector<int>> near(n);
  parallel(n, [&](std::size_t begin, std::size_t end) {
    std::vector<int> wide, small;
    for (std::size_t i = begin; i < end; ++i)
    {
      grid.Within(points[i], 2.0 * r, wide);
      small.clear();
      for (int j : wide)
      {
        const double d2 = (points[static_cast<std::size_t>(j)] - points[i]).squaredNorm();
        if (d2 <= r * r)
          small.push_back(j);
        if (d2 <= link * link && static_cast<std::size_t>(j) != i)
          near[i].push_back(j);
      }
      std::sort(near[i].begin(), near[i].end());
      Eigen::Vector3d l1, l2;
      Eigen::Matrix3d v1, v2;
      Covariance(points, small, l1, v1);
      Covariance(points, wide, l2, v2);
      f.normal[i] = v1.col(0);
      f.spread[i] = std::max(Spread(l1, r), Spread(l2, 2.0 * r));
      const double sum = l1.sum();
      f.variation[i] = sum > 0.0 ? static_cast<float>(l1[0] / sum) : 1.0f;
    }
  });
  graph.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    graph.offsets[i + 1] = graph.offsets[i] + near[i].size();
  graph.neighbours.resize(graph.offsets[n]);
  for (std::size_t i = 0; i < n; ++i)
  {
    std::copy(near[i].begin(), near[i].end(), graph.neighbours.begin() + static_cast<std::ptrdiff_t>(graph.offsets[i]));
    std::vector<int>().swap(near[i]);
  }
}

int GrowRegions(
  const PointFeatures& f, const LinkGraph& graph, const SegmentationParameters& p, std::vector<int>& region)
{
  const std::size_t n = f.normal.size();
  const double cosine = std::cos(p.normalAngle * 3.14159265358979323846 / 180.0);
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
    [&](int a, int b) { return f.variation[static_cast<std::size_t>(a)] < f.variation[static_cast<std::size_t>(b)]; });
  // Points on a crease (two leaves crossing, a leaf's fold, a branch's junction) join a region but do not grow it:
  // their surface variation is above the plant's median (flat leaf interiors, noise) by CreaseVariation.
  std::vector<float> sorted(f.variation);
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(n / 2), sorted.end());
  const float crease = sorted[n / 2] + static_cast<float>(p.creaseVariation);
  region.assign(n, -1);
  int count = 0;
  std::deque<int> queue;
  for (int seed : order)
  {
    if (region[static_cast<std::size_t>(seed)] >= 0 || IsLinear(f, static_cast<std::size_t>(seed)))
      continue;
    region[static_cast<std::size_t>(seed)] = count;
    queue.push_back(seed);
    while (!queue.empty())
    {
      const auto q = static_cast<std::size_t>(queue.front());
      queue.pop_front();
      if (f.variation[q] > crease && static_cast<int>(q) != seed)
        continue;
      for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
      {
        const auto j = static_cast<std::size_t>(graph.neighbours[e]);
        if (region[j] < 0 && !IsLinear(f, j) && std::abs(f.normal[q].dot(f.normal[j])) >= cosine)
        {
          region[j] = count;
          queue.push_back(static_cast<int>(j));
        }
      }
    }
    ++count;
  }
  return count;
}

} // namespace segmentation
} // namespace plantmorph
