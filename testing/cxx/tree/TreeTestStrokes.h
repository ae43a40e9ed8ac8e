// SPDX-License-Identifier: GPL-3.0-or-later
// The drawn strokes the tree tests share (testing/python/tree/test_tree_from_sketch.py draws the same): a trunk and
// three branches in the z = 0 plane, trunk first.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstddef>

#include <cstdint>
#include <initializer_list>
#include <random>
#include <utility>
#include <vector>

namespace plantmorph
{
namespace tree_test
{
/// A stroke through (x, y, 0) points.
inline std::vector<Eigen::Vector3d> Line(std::initializer_list<std::pair<double, double>> points)
{
  std::vector<Eigen::Vector3d> line;
  for (const auto& [x, y] : points)
    line.emplace_back(x, y, 0.0);
  return line;
}

/// The four sample strokes; the first three are the tree of the junction reach measurements.
inline std::vector<std::vector<Eigen::Vector3d>> SampleStrokes()
{
  return { Line({ { 0, 0 }, { 0.2, 3 }, { -0.1, 6 }, { 0.1, 9 }, { 0, 12 } }),
    Line({ { 0.3, 6 }, { 1.5, 7.5 }, { 3, 8.2 }, { 4, 10 } }),
    Line({ { -0.2, 4 }, { -1, 5 }, { -2.5, 5.5 }, { -3.5, 7 }, { -4, 8 } }),
    Line({ { 2.0, 7.8 }, { 2.2, 9 }, { 2.1, 10.5 } }) };
}

/// n random strokes of `points` points (n >= 1): a vertical trunk of height 100, then each stroke starts on a random
/// earlier stroke, exactly at one of its points when `onPoints` (exact ties: the point is shared by two segments and
/// by the strokes that start there) or near one (uniform noise of 0.5), and heads in a random direction for 1 to 20.
inline std::vector<std::vector<Eigen::Vector3d>> RandomStrokes(
  std::size_t n, int points, std::uint64_t seed, bool onPoints)
{
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::vector<Eigen::Vector3d>> strokes;
  strokes.push_back(Line({ { 0, 0 }, { 0, 100 } }));
  for (std::size_t k = 1; k < n; ++k)
  {
    const auto& from = strokes[std::size_t(unit(random) * double(k)) % k];
    Eigen::Vector3d start = from[std::size_t(unit(random) * double(from.size())) % from.size()];
    if (!onPoints)
    {
      start += Eigen::Vector3d(unit(random) - 0.5, unit(random) - 0.5, 0.0);
    }
    const double angle = unit(random) * 6.283185307179586, length = 1.0 + 19.0 * unit(random);
    std::vector<Eigen::Vector3d> stroke;
    for (int i = 0; i < points; ++i)
    {
      const double t = length * i / (points - 1), bend = 0.3 * std::sin(3.0 * i);
      stroke.push_back(start + t * Eigen::Vector3d(std::cos(angle + bend * 0.1), std::sin(angle + bend * 0.1), 0.0));
    }
    strokes.push_back(stroke);
  }
  return strokes;
}
} // namespace tree_test
} // namespace plantmorph
