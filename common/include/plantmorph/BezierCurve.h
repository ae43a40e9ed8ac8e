// SPDX-License-Identifier: GPL-3.0-or-later
// Bezier curves of any degree in 2-D or 3-D (paper 004 sec. 3.1: a traced stroke's smoothed centre line; the willow
// leaf twig). Evaluation by de Casteljau's algorithm, which is numerically stable for every degree and returns the
// first and last control points exactly at t = 0 and t = 1. Plain C++ (Eigen), no VTK.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace plantmorph
{

/// The point at parameter t (clamped to [0, 1]) of the Bezier curve of degree controls.size() - 1; a zero vector
/// for an empty control polygon. O(n^2) in the number of control points.
template <int Dim>
Eigen::Matrix<double, Dim, 1> EvaluateBezier(const std::vector<Eigen::Matrix<double, Dim, 1>>& controls, double t);

/// `count` + 1 points at the equally spaced parameters 0, 1/count, ..., 1 (count at least 1).
template <int Dim>
std::vector<Eigen::Matrix<double, Dim, 1>> SampleBezier(
  const std::vector<Eigen::Matrix<double, Dim, 1>>& controls, int count);

/// Paper 004 sec. 3.1 (index corrected, see docs/methods/tree-from-sketch.md): `n` of the `m` stroke points, point
/// i at index floor(i * (m - 1) / (n - 1)), i = 0..n-1, so the first and last stroke points are always kept. n is
/// clamped to [2, m]; m < 2 gives the points unchanged.
std::vector<int> StrokeControlIndices(int m, int n);

extern template Eigen::Matrix<double, 2, 1> EvaluateBezier<2>(const std::vector<Eigen::Matrix<double, 2, 1>>&, double);
extern template Eigen::Matrix<double, 3, 1> EvaluateBezier<3>(const std::vector<Eigen::Matrix<double, 3, 1>>&, double);
extern template std::vector<Eigen::Matrix<double, 2, 1>> SampleBezier<2>(
  const std::vector<Eigen::Matrix<double, 2, 1>>&, int);
extern template std::vector<Eigen::Matrix<double, 3, 1>> SampleBezier<3>(
  const std::vector<Eigen::Matrix<double, 3, 1>>&, int);

} // namespace plantmorph
