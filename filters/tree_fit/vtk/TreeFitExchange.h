// SPDX-License-Identifier: GPL-3.0-or-later
// TreeFitFilter under MPI (pvbatch, pvserver): each tree is fitted whole on one owner rank, as LeafFitFilter's leaves,
// through the fitters' common exchange (plantmorph::OwnerExchange, common/vtk/PlantMorphOwnerExchange.h): every rank
// sends its points of each tree to the tree's owner, which fits the tree and sends each point's results back to the
// rank that holds the point, where the Scan output stays. The fitted trees (cylinders, branches, traits: small next to
// the points) travel as numbers (PackFit) and are gathered on rank 0 in TreeId order, which writes Cylinders,
// Skeleton, Trees and Branches exactly as a serial run.
#pragma once

#include "TreeFit.h"

#include <vector>

namespace plantmorph
{
namespace treefitvtk
{

/// A tree's fit without its per-point vectors, as numbers (to travel between ranks), and back.
std::vector<double> PackFit(const TreeFitResult& fit);
TreeFitResult UnpackFit(const std::vector<double>& packed);

} // namespace treefitvtk
} // namespace plantmorph
