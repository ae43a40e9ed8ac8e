// SPDX-License-Identifier: GPL-3.0-or-later
// CloudComparisonFilter under MPI (pvbatch, pvserver): the measured cloud stays distributed, each rank compares its
// own points (docs/methods/comparison.md, "Under MPI").
//
// The reference (a leaf, a plant: small) is gathered onto rank 0 once and broadcast, so every rank holds it whole and
// builds the same distance structure: each point's distance is computed exactly as serially (bit for bit). What
// needs every point is reduced over the ranks, the same on every rank whatever the split:
// - counts, minimum and maximum exactly; the sums of the mean, deviation and RMS as per-rank compensated sums
//   (plantmorph::CompensatedSum) added in rank order, equal to the serial ones to about one rounding;
// - the percentiles exactly, by a distributed selection: each order statistic's key interval is split at 255
//   candidates a round, every rank counting its own (sorted once) distances at or below each, one AllReduce for all
//   ten order statistics; the interval shrinks 256-fold a round, so 8 rounds at most;
// - the histogram over the global [minimum, maximum], the bins' counts summed;
// - registration: its landmarks (every k-th point of the whole cloud, at most RegistrationLandmarks, the stride
//   the serial run takes) are gathered on every rank in global order, so every rank runs the serial registration on
//   the same landmarks and finds the same transform bit for bit;
// - the reverse direction (Symmetric): each rank's distance from every reference point to its own piece, the
//   minimum over the ranks (exact: the nearest of all is the nearest of the ranks' nearest).
//
// Every function here is collective: every rank calls it, in the same order. A null controller means serial.
#pragma once

#include "CloudStatistics.h"

#include "vtkSmartPointer.h"

#include <cstddef>
#include <cstdint>
#include <vector>

class vtkMultiProcessController;
class vtkPointSet;

namespace plantmorph
{
namespace cloudmpi
{

/// The global controller when this process is one of several MPI ranks, else null (serial: nothing is exchanged).
vtkMultiProcessController* Parallel();

/// The whole reference on every rank: gathered onto rank 0 (as PlantMorphWholeInput.h does) and broadcast.
vtkSmartPointer<vtkPointSet> Replicate(vtkMultiProcessController* controller, vtkPointSet* piece);

/// The points of all ranks, this rank's, and the global index of its first point (ranks in order).
struct PointLayout
{
  std::uint64_t total = 0;
  std::uint64_t count = 0;
  std::uint64_t first = 0;
};
PointLayout Layout(vtkMultiProcessController* controller, std::uint64_t count);

/// The registration landmarks of the whole cloud: the points of global index 0, k, 2k, ... with k the stride that
/// keeps at most `limit` of layout.total (RegisterPoints' own), gathered on every rank in global order.
std::vector<double> Landmarks(
  vtkMultiProcessController* controller, const PointLayout& layout, const double* xyz, std::size_t limit);

/// ComputeDistanceStatistics of the distances of every rank (`count` here), the same result on every rank. `tasks`
/// runs the serial case's two parts (see ComputeDistanceStatistics).
DistanceStatistics Statistics(vtkMultiProcessController* controller, const double* distances, std::size_t count,
  double maximumDistance, const ParallelFor& tasks = SerialFor);

/// ComputeDistanceHistogram of the distances of every rank; `whole` is Statistics' result (its range). The counting
/// runs on `parallelFor`.
DistanceHistogram Histogram(vtkMultiProcessController* controller, const double* distances, std::size_t count,
  std::size_t bins, double maximumDistance, const DistanceStatistics& whole,
  const ParallelFor& parallelFor = SerialFor);

/// Every element replaced by its minimum over the ranks (the same length on every rank).
void MinimumOverRanks(vtkMultiProcessController* controller, std::vector<double>& values);

} // namespace cloudmpi
} // namespace plantmorph
