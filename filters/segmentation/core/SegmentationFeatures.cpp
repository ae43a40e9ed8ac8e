// SPDX-License-Identifier: GPL-3.0-or-later
// Steps 1 and 2 of the segmentation (PlantSegmentation.h): covariance features at two scales, the link graph and
// the region growing of smooth sheets.
#include "SegmentationSteps.h"

#include "PointGrid.h"
#include "SegmentationGrid.h"

#include <plantmorph/MathConstants.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
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

namespace
{
/// The radius graph: each point's neighbours closer than `link`, in ascending index, from a grid of cells of side
/// `link`.
void LinkPoints(const std::vector<Eigen::Vector3d>& points, double link, const ParallelFor& parallel, LinkGraph& graph)
{
  const std::size_t n = points.size();
  const CellGrid grid(points, link, parallel);
  const std::vector<int>& order = grid.Ordered();
  std::vector<Eigen::Vector3d> sorted(n); // the points in cell order: a block's points are nine contiguous runs
  ForEachIndex(parallel, n, [&](std::size_t k) { sorted[k] = points[static_cast<std::size_t>(order[k])]; });
  const double link2 = link * link;
  // The points are visited in cell order (a cell's points share one block).
  const auto visit = [&](std::size_t k, CellGrid::Block& block, auto&& take) {
    grid.BlockAround(sorted[k], block);
    for (int run = 0; run < block.runs; ++run)
      for (std::size_t j = block.begin[run]; j < block.end[run]; ++j)
        if (j != k && (sorted[j] - sorted[k]).squaredNorm() <= link2)
          take(order[j]);
  };
  // One pass: each fixed block of the cell order lists its points' neighbours on its own, then the lists are copied
  // into place (sorted) once the offsets are known; the blocks do not depend on the thread count.
  constexpr std::size_t Block = 4096;
  const std::size_t blocks = (n + Block - 1) / Block;
  std::vector<std::vector<int>> found(blocks);
  std::vector<std::size_t> count(n, 0);
  parallel(blocks, [&](std::size_t first, std::size_t last) {
    CellGrid::Block block;
    for (std::size_t b = first; b < last; ++b)
      for (std::size_t k = b * Block; k < std::min(n, (b + 1) * Block); ++k)
      {
        const std::size_t before = found[b].size();
        visit(k, block, [&](int j) { found[b].push_back(j); });
        count[static_cast<std::size_t>(order[k])] = found[b].size() - before;
      }
  });
  graph.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    graph.offsets[i + 1] = graph.offsets[i] + count[i];
  graph.neighbours.resize(graph.offsets[n]);
  parallel(blocks, [&](std::size_t first, std::size_t last) {
    for (std::size_t b = first; b < last; ++b)
    {
      const int* from = found[b].data();
      for (std::size_t k = b * Block; k < std::min(n, (b + 1) * Block); ++k)
      {
        const auto i = static_cast<std::size_t>(order[k]);
        const auto to = graph.neighbours.begin() + static_cast<std::ptrdiff_t>(graph.offsets[i]);
        std::copy(from, from + count[i], to);
        std::sort(to, to + static_cast<std::ptrdiff_t>(count[i]));
        from += count[i];
      }
      std::vector<int>().swap(found[b]);
    }
  });
}
} // namespace

void ComputeFeatures(const std::vector<Eigen::Vector3d>& points, double spacing, const SegmentationParameters& p,
  const ParallelFor& parallel, PointFeatures& f, LinkGraph& graph)
{
  const std::size_t n = points.size();
  // The features' radius: FeatureScale spacings, or wider when the range noise is large next to it (a plane's
  // normal from points of noise sigma within r is off by about 2 sigma / r: NoiseScale sigma keeps it near 10 deg).
  constexpr double NoiseScale = 12.0;
  f.noise = NoiseLevel(points, 2.0 * p.featureScale * spacing, parallel);
  const double r = std::max(p.featureScale * spacing, NoiseScale * f.noise);
  f.radius = r;
  // The covariances are sums of cell moments (count, mean, scatter), so that a ball costs about the same whatever
  // the density and the noise. Each is computed once per cell, at its points' mean, and shared by its points: cells
  // of side r / 8 for the balls of radius r (at the default scale a cell holds a point or two: the ball is nearly
  // exact, the normals and creases sharp; r / 4 merged two touching leaves of the pipeline test's herb), cells of
  // side r / 2 for the balls of 2r (only the spread across the main axis is read at that scale).
  const BallMoments near(points, r / 8.0, r, parallel), wide(points, r / 2.0, 2.0 * r, parallel);
  const std::size_t m = near.Cells().CellCount();
  std::vector<Eigen::Vector3d> normal(m, Eigen::Vector3d::UnitX());
  std::vector<Eigen::Vector3d> direction(m, Eigen::Vector3d::Zero());
  std::vector<float> spread(m, 0.0f), variation(m, 1.0f), wideSpread(wide.Cells().CellCount(), 0.0f);
  parallel(m, [&](std::size_t begin, std::size_t end) {
    CellGrid::Block block;
    for (std::size_t k = begin; k < end; ++k)
    {
      const auto c = static_cast<std::size_t>(near.QueryOrder()[k]);
      double count = 0.0;
      const Eigen::Matrix3d covariance = near.Covariance(near.Means()[c], count, block);
      if (count < 3.0)
        continue; // too few points to have a shape: linear, on no surface
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(covariance); // closed form: a tenth of the iterative solver's cost
      const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);
      normal[c] = solver.eigenvectors().col(0);
      direction[c] = solver.eigenvectors().col(2);
      spread[c] = Spread(l, r);
      const double sum = l.sum();
      variation[c] = sum > 0.0 ? static_cast<float>(l[0] / sum) : 1.0f;
    }
  });
  parallel(wideSpread.size(), [&](std::size_t begin, std::size_t end) {
    CellGrid::Block block;
    for (std::size_t k = begin; k < end; ++k)
    {
      const auto c = static_cast<std::size_t>(wide.QueryOrder()[k]);
      double count = 0.0;
      const Eigen::Matrix3d covariance = wide.Covariance(wide.Means()[c], count, block);
      if (count >= 3.0)
      {
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
        solver.computeDirect(covariance, Eigen::EigenvaluesOnly);
        wideSpread[c] = Spread(solver.eigenvalues().cwiseMax(0.0), 2.0 * r);
      }
    }
  });
  f.normal.resize(n);
  f.spread.resize(n);
  f.variation.resize(n);
  f.direction.resize(n);
  f.nearSpread.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto c = static_cast<std::size_t>(near.Cells().CellOfPoint(i));
    f.normal[i] = normal[c];
    f.spread[i] = std::max(spread[c], wideSpread[static_cast<std::size_t>(wide.Cells().CellOfPoint(i))]);
    f.variation[i] = variation[c];
    f.direction[i] = direction[c];
    f.nearSpread[i] = spread[c];
  }
  LinkPoints(points, p.linkScale * spacing, parallel, graph);
}

int GrowRegions(const PointFeatures& f, const LinkGraph& graph, const SegmentationParameters& p,
  const ParallelFor& parallel, std::vector<int>& region)
{
  const std::size_t n = f.normal.size();
  const double cosine = std::cos(p.normalAngle * Pi / 180.0);
  // The points by ascending variation, ties by index (a stable sort): a radix sort of the variation's bits, made
  // to order as the values do, above the index.
  std::vector<std::uint64_t> keys(n);
  ForEachIndex(parallel, n, [&](std::size_t i) {
    const float v = f.variation[i] + 0.0f; // -0 is +0
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    bits = (bits & 0x80000000u) ? ~bits : bits | 0x80000000u;
    keys[i] = static_cast<std::uint64_t>(bits) << 32 | i;
  });
  SortKeysInParallel(parallel, keys, 32, 64);
  std::vector<int> order(n);
  ForEachIndex(parallel, n, [&](std::size_t k) { order[k] = static_cast<int>(keys[k] & 0xffffffffu); });
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
