// SPDX-License-Identifier: GPL-3.0-or-later
// The drawn strokes the tree tests share (testing/python/tree/test_tree_from_sketch.py draws the same): a trunk and
// three branches in the z = 0 plane, trunk first.
#pragma once

#include <Eigen/Core>

#include <initializer_list>
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
} // namespace tree_test
} // namespace plantmorph
