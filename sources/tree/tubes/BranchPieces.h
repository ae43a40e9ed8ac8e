// SPDX-License-Identifier: GPL-3.0-or-later
// A tree's branches split between pieces (ParaView's UPDATE_PIECE_NUMBER / UPDATE_NUMBER_OF_PIECES: one piece per
// MPI rank), and a tube mesh cut down to one piece's tubes. Plain C++, no VTK.
//
// The plan (PlanPieces) is deterministic: every rank computes the same one from the same skeleton. The tubes are laid
// out in depth-first order (children in index order), tree by tree: a "unit" is a tree (a tube without a parent) or a
// merged tree (a tube marked as a unit root, its subtree), units in the order of their roots' indices, and a unit's
// depth-first run does not enter the units rooted below it. Each tube weighs its segments + 1 + its children, in
// units of 2 sides triangles: 2 sides triangles per segment, plus its cap or the junction hull at its end, which it
// owns and which has about 2 sides facets per ring it joins (its end ring and each child's base ring). (Segments + 1
// alone left a piece 1.7 % of the triangles off its share on a 3-piece ChildCount 8 template: TreePiecesTest.) The
// run is cut into `pieces` consecutive parts of (nearly) equal weight: cut k goes to the unit boundary nearest
// k / pieces of the total weight when one lies within a quarter of a piece's weight of it (a forest or a merged tree
// is split by tree first), else to the tube boundary nearest it (within one tube's weight). So a piece is a run of the depth-first order: whole subtrees,
// plus the branches on the path from the run's first branch up to where its subtree was cut. With more pieces than
// tubes some pieces are empty.
//
// KeepTubes cuts a mesh built for (at least) the selected tubes down to those: their triangles and the points these
// use, in tube order: first each selected tube's own (a hull corner of a tube's dropped part that only another
// piece's facet uses is left to that piece), then the points of other tubes that their triangles use (a welded junction's facet owned by a selected
// tube may use the rings of its parent, siblings or children in another piece), appended after
// pointOffsets.back() as copies. Each triangle is in the piece of the tube that owns it (BuildWeldedTubes'
// ownership), so the pieces' triangles are the serial mesh's, each once; where pieces meet, a piece's surface is
// open (its boundary edges are the neighbouring pieces' boundary edges, reversed), and the union is closed.
#pragma once

#include "BranchTubes.h"

#include <cstdint>
#include <string>
#include <vector>

namespace plantmorph
{

/// The piece of every tube (0 .. pieces - 1) as described above. `unitRoots` (optional, one per tube; may be empty):
/// tubes that start a unit of their own although they have a parent (a merged tree's root). pieces must be >= 1.
std::vector<int> PlanPieces(const std::vector<TubeInput>& tubes, const std::vector<char>& unitRoots, int pieces);

/// "" when `piece` of `pieces` is a valid request (pieces >= 1, 0 <= piece < pieces), else the message.
std::string ValidatePieceRequest(int piece, int pieces);

/// The tubes of piece `piece` in `plan`, as a mask (1: selected).
std::vector<char> TubesOfPiece(const std::vector<int>& plan, int piece);

/// `mesh` cut down to the `selected` tubes (see above): tube t keeps [pointOffsets[t], pointOffsets[t + 1]) (its own
/// points that the kept triangles use) and its triangles (empty ranges for the others); the other tubes' points
/// they use follow pointOffsets.back(). On a whole mesh with every tube selected: the mesh unchanged.
void KeepTubes(TubeMesh& mesh, const std::vector<char>& selected);

} // namespace plantmorph
