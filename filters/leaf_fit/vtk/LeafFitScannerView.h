// SPDX-License-Identifier: GPL-3.0-or-later
// LeafFitFilter's HiddenMargin column: where the scanner's view past a fitted leaf's margin was blocked
// (plantmorph::HiddenMargin, ScannerView.h; docs/methods/leaf-fit.md, "HiddenMargin").
//
// The scan must say where its points were seen from: a point array named Range (the distance measured from the
// scanner, in the input's units) and one named ScanPosition (which scanner position: 0, 1, ...), as VirtualScanner
// writes them and terrestrial scans exported with their ranges carry them. Without both, HiddenMargin is NaN.
// Collective: every scanner's position is solved from every rank's points (the equations added in rank order), and
// its depth map is merged from every rank's points (the least range per cell: the same on any number of ranks).
#pragma once

#include "LeafFit.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

class vtkMultiProcessController;
class vtkPointSet;

namespace plantmorph
{
namespace fittable
{

/// Per point of the local piece, its scanner (ScanPosition; -1 when unknown), its range (Range, scaled) and its leaf
/// (a number the ranks agree on; -1 on no leaf, or when the leaves are not known before the fit).
struct ScanRanges
{
  std::vector<int> scanner;
  std::vector<double> range;
  std::vector<std::int64_t> leaf;
};

/// The input's ScanPosition and Range point arrays (empty vectors when it lacks either); ranges times `scale`.
ScanRanges ReadScanRanges(vtkPointSet* input, double scale);

/// A fitted leaf on this rank, and how many of its points each scanner gave (index: ScanPosition).
struct LeafView
{
  LeafFitResult* fit = nullptr;
  std::vector<double> pointsFrom;
  std::int64_t leaf = -1; ///< its number in ScanRanges::leaf: its own points do not block the view past it
};

/// Collective: sets each leaf's traits.hiddenMargin from the depth maps of the scanners that saw it (`points` and
/// `scan` the local piece; `up` the UpAxis). Leaves stay NaN when no rank knows its scanners. Returns, alike on every
/// rank, what could not be done (the scanner positions whose points' ranges gave no position), else "".
std::string SetHiddenMargins(vtkMultiProcessController* controller, const std::vector<Eigen::Vector3d>& points,
  const ScanRanges& scan, const Eigen::Vector3d& up, std::vector<LeafView>& leaves);

} // namespace fittable
} // namespace plantmorph
