// SPDX-License-Identifier: GPL-3.0-or-later
// The blade's axis of mirror symmetry through a point (LeafShape.h).
#include "LeafShape.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace plantmorph
{
namespace fit
{
namespace
{
/// Points in the plane, bucketed for nearest-neighbour distances.
class PlaneGrid
{
public:
  PlaneGrid(const std::vector<Eigen::Vector2d>& points, double cell)
    : Points(points)
  {
    this->Low = this->High = points.front();
    for (const auto& p : points)
    {
      this->Low = this->Low.cwiseMin(p);
      this->High = this->High.cwiseMax(p);
    }
    const Eigen::Vector2d span = this->High - this->Low;
    this->Cell = std::max({ cell, span.x() / 512.0, span.y() / 512.0, 1e-300 });
    this->Nx = static_cast<int>(span.x() / this->Cell) + 1;
    this->Ny = static_cast<int>(span.y() / this->Cell) + 1;
    this->Start.assign(static_cast<std::size_t>(this->Nx * this->Ny + 1), 0);
    std::vector<int> key(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      key[i] = this->Key(points[i]);
      ++this->Start[key[i] + 1];
    }
    for (std::size_t c = 1; c < this->Start.size(); ++c)
      this->Start[c] += this->Start[c - 1];
    this->Ids.resize(points.size());
    std::vector<int> at(this->Start.begin(), this->Start.end() - 1);
    for (std::size_t i = 0; i < points.size(); ++i)
      this->Ids[at[key[i]]++] = static_cast<int>(i);
  }

  /// Distance from q to the nearest point, or `cap` when none is nearer. Rings of cells outward from q's cell: every
  /// cell of ring r or beyond is at least r - 1 cells away, so the search stops once the nearest found is that close (a
  /// mirrored point on the blade stops after a ring or two instead of reading every cell within the cap; exact).
  double Distance(const Eigen::Vector2d& q, double cap) const
  {
    const int ci = static_cast<int>(std::floor((q.x() - this->Low.x()) / this->Cell));
    const int cj = static_cast<int>(std::floor((q.y() - this->Low.y()) / this->Cell));
    const int reach = static_cast<int>(std::ceil(cap / this->Cell));
    double best = cap * cap;
    auto visit = [&](int i, int j) {
      if (i < 0 || i >= this->Nx || j < 0 || j >= this->Ny)
        return;
      const int c = i * this->Ny + j;
      for (int k = this->Start[c]; k < this->Start[c + 1]; ++k)
        best = std::min(best, (this->Points[this->Ids[k]] - q).squaredNorm());
    };
    for (int r = 0; r <= reach; ++r)
    {
      const double covered = (r - 1) * this->Cell; // ring r lies r - 1 whole cells beyond q's cell
      if (r > 1 && best <= covered * covered)
        break;
      if (r == 0)
      {
        visit(ci, cj);
        continue;
      }
      for (int i = ci - r; i <= ci + r; ++i)
      {
        visit(i, cj - r);
        visit(i, cj + r);
      }
      for (int j = cj - r + 1; j <= cj + r - 1; ++j)
      {
        visit(ci - r, j);
        visit(ci + r, j);
      }
    }
    return std::sqrt(best);
  }

private:
  int Key(const Eigen::Vector2d& p) const
  {
    const int i = std::clamp(static_cast<int>((p.x() - this->Low.x()) / this->Cell), 0, this->Nx - 1);
    const int j = std::clamp(static_cast<int>((p.y() - this->Low.y()) / this->Cell), 0, this->Ny - 1);
    return i * this->Ny + j;
  }
  const std::vector<Eigen::Vector2d>& Points;
  Eigen::Vector2d Low, High;
  double Cell = 1.0;
  int Nx = 1, Ny = 1;
  std::vector<int> Start, Ids;
};
} // namespace

Eigen::Vector3d SymmetryAxis(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& through,
  const Eigen::Vector3d& normal, const Eigen::Vector3d& hint, double spacing, const ParallelFor& parallel)
{
  const Eigen::Vector3d n = normal.normalized();
  Eigen::Vector3d e1 = hint - hint.dot(n) * n;
  if (!(e1.norm() > 1e-12 * (hint.norm() + 1e-300)))
    e1 = n.unitOrthogonal();
  e1.normalize();
  const Eigen::Vector3d e2 = n.cross(e1);
  if (points.empty() || !(spacing > 0.0))
    return e1;
  std::vector<Eigen::Vector2d> plane(points.size());
  ForEachIndex(parallel, points.size(), [&](std::size_t i) {
    plane[i] = { (points[i] - through).dot(e1), (points[i] - through).dot(e2) };
  });
  const PlaneGrid grid(plane, spacing);
  // Mirror at most 4000 of the points (every k-th): the score is a mean, and 4000 samples pin it well enough.
  const std::size_t stride = std::max<std::size_t>(1, plane.size() / 4000);
  // The fraction of mirrored points that land off the blade (farther than 2 spacings from every point: the area the
  // blade and its mirror image do not share), a tenth of their mean distance to the nearest point (capped at 5
  // spacings, in units of that cap) to rank lines that share the same area, and a small preference for the hint's
  // direction (an ellipse is symmetric about both its axes).
  const double cap = 5.0 * spacing;
  auto score = [&](double angle) {
    const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
    double sum = 0.0, off = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < plane.size(); i += stride, ++count)
    {
      const double d = grid.Distance(2.0 * plane[i].dot(u) * u - plane[i], cap);
      sum += d;
      off += d > 2.0 * spacing ? 1.0 : 0.0;
    }
    const double s = std::sin(angle), n = static_cast<double>(count);
    return off / n + 0.1 * sum / (n * cap) + 0.02 * s * s;
  };
  const double pi = 3.14159265358979323846;
  const int steps = 90;
  std::vector<double> scores(steps);
  ForEachIndex(
    parallel, steps, [&](std::size_t k) { scores[k] = score(-0.5 * pi + pi * double(k) / steps); }, 1);
  double bestAngle = 0.0, bestScore = 1e300;
  for (int k = 0; k < steps; ++k)
    if (scores[k] < bestScore) // the first of equal scores, as the loop that scored them in turn took
    {
      bestScore = scores[k];
      bestAngle = -0.5 * pi + pi * k / steps;
    }
  // Golden-section search within a step either side.
  double lo = bestAngle - pi / steps, hi = bestAngle + pi / steps;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
  double fa = score(a), fb = score(b);
  for (int iteration = 0; iteration < 20; ++iteration)
  {
    if (fa < fb)
    {
      hi = b;
      b = a;
      fb = fa;
      a = hi - g * (hi - lo);
      fa = score(a);
    }
    else
    {
      lo = a;
      a = b;
      fa = fb;
      b = lo + g * (hi - lo);
      fb = score(b);
    }
  }
  const double angle = fa < fb ? a : b;
  return (std::cos(angle) * e1 + std::sin(angle) * e2).normalized();
}

} // namespace fit
} // namespace plantmorph
