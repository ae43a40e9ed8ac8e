// SPDX-License-Identifier: GPL-3.0-or-later
// Model A end to end: sample the deformed rectangle's outline and midvein, mesh the blade, fill LeafUV (interior
// points by inverting the model's map), Region and TCoords.
#pragma once

#include "DeformedRectangleModel.h"
#include "LeafGeometry.h"

#include <string>

namespace plantmorph
{

/// Returns an empty string on success; otherwise a message naming the property at fault, and `leaf` is empty.
std::string BuildDeformedRectangleLeaf(
  const DeformedRectangleParameters& parameters, const LeafMeshParameters& settings, LeafGeometry& leaf);

} // namespace plantmorph
