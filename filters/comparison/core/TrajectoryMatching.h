// SPDX-License-Identifier: GPL-3.0-or-later
// TrajectoryComparisonFilter's algorithm (docs/methods/comparison.md; paper 001 sec. 3, Table 1): match
// each measured sample of a trajectory (a leaf tip's positions over time) to a simulated sample and report the
// distances. Plain C++17, no VTK.
//
// Two matchings:
// - Closest sample (what paper 001 did): each measured sample independently to the simulated sample nearest to it
//   (ties to the lower index). Two measurements may share a simulated sample, and the order in time may be lost.
// - Time-monotone: each measurement to one simulated sample with STRICTLY increasing simulated indices (distinct
//   measurement times get distinct, ordered simulated times), minimising the sum of the Euclidean distances, by
//   dynamic programming in O(n m) time and memory (n measured, m simulated samples; ties to the earliest indices).
//   It needs m >= n. Samples are taken in the order given (sort by time upstream if need be); times are carried
//   into the output but do not enter the cost.
//
// Summary: mean and maximum of each matching's distances, and the angle between the overall motion directions,
// measured last minus first sample against matched-simulated last minus first (the paper's comparison: for the
// closest-sample matching on paper 001's Table 1 this is the 6.1 degrees its unit vectors give; the paper prints
// 19.1, which its own vectors do not support). The angle is NaN when either direction is the zero vector.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace plantmorph
{

struct TrajectoryMatch
{
  std::vector<std::size_t> simulatedIndex; ///< per measured sample
  std::vector<double> distance;            ///< |simulated - measured|
  std::vector<double> delta;               ///< simulated - measured, x,y,z per measured sample
  double meanDistance = 0.0;
  double maxDistance = 0.0;
  double directionAngle = 0.0; ///< degrees between (m_last - m_first) and (s_j(last) - s_j(first))
};

struct TrajectoryComparison
{
  TrajectoryMatch closest;
  TrajectoryMatch monotone;
  bool hasMonotone = false; ///< false when there are fewer simulated than measured samples, or too many pairs
  std::string error;        ///< empty on success
};

/// measured: n x,y,z triples; simulated: m triples. Needs n >= 2, m >= 2 and finite coordinates. The monotone
/// matching is computed when m >= n and n * m <= maximumMonotonePairs (it takes 16 bytes per pair), else
/// hasMonotone is false.
TrajectoryComparison CompareTrajectories(const double* measured, std::size_t n, const double* simulated, std::size_t m,
  std::size_t maximumMonotonePairs = 20000000);

/// Angle in degrees between two 3-D vectors (NaN if either is zero), computed with atan2 (accurate near 0 and 180).
double AngleBetween(const double a[3], const double b[3]);

} // namespace plantmorph
