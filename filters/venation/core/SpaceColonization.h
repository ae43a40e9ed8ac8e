// SPDX-License-Identifier: GPL-3.0-or-later
// Space colonization venation (Runions, Fuhrer, Lane, Federl, Rolland-Lagan, Prusinkiewicz 2005, "Modeling and
// visualization of leaf venation patterns", open and closed venation; docs/methods/venation.md): the VenationPattern
// SpaceColonization of GrowVenation, on any blade carrying LeafUV.
//
// The blade grows uniformly about its base from `growthStart` of its final size to 1 (a stage s; every distance
// below is physical, in final leaf lengths L, so at stage s it is distance / s in the final blade's working plane:
// veins laid down early are stretched as the leaf expands). Each step:
// - auxin sources: sourceDensity * (new blade area) darts thrown uniformly in the blade (Poisson-disk dart throwing):
//   a dart closer than the birth distance 0.5 / sqrt(sourceDensity) to a source or to a vein node is dropped;
// - every source picks its nearest vein node within `attractionDistance`; every node with sources grows one node a
//   step D = killDistance / 2 towards the mean of the unit vectors to its sources (if that point is inside the blade);
// - open venation: a source with a vein node within `killDistance` is removed, so the network stays a tree;
// - closed venation (`closedVenation`, Runions sec. 4): a source pulls every node of its relative neighbourhood
//   within the attraction distance (no other node closer both to the source and to it), except those already within
//   the kill distance, which wait; it is removed once its whole neighbourhood is within the kill distance, and the
//   veins that met there are joined to the one nearest it (the links close the loops).
// When no source lies within the attraction distance of any node, that step the distance doubles until one does,
// so a static blade (growthStart = 1) or a sparse start still grows. Growth ends when no
// source is left (or none can make a node grow) once the blade is full size.
// Every neighbour query goes through uniform grids of cells about the kill distance (with counts per cell of about
// the attraction distance, so an empty neighbourhood costs a few cells), and a source with no node near enough
// sleeps for as many steps as veins need to come within reach, so a step costs about the sources near veins plus
// the nodes they move, not the whole network.
// Widths by the pipe model: a free end has width 1, a node w = (sum of its children's w^n)^(1/n) (n =
// `murrayExponent`, 3 is Murray's law), scaled so the base is `primaryWidth` * L (closed venation: along the tree
// the veins grew as; a link takes the widths of the nodes it joins). Orders: the vein from the base
// continues through the child of largest width (order 1); every other child starts a vein one order higher (at
// most 4, VeinOrderQuaternary: the higher orders; no free-ending veinlets of order 5).
//
// Plain C++17 + Eigen, no VTK.
#pragma once

#include "VenationBlade.h"
#include "VenationGrowth.h"

#include <functional>
#include <string>

namespace plantmorph
{

/// Grows space-colonization venation on the blade `locator` was built on (parameters already validated). Empty on
/// success; otherwise a message (and `result` is empty).
std::string GrowSpaceColonization(const BladeLocator& locator, const VenationParameters& parameters,
  VenationResult& result, const std::function<bool(double)>& progress);

} // namespace plantmorph
