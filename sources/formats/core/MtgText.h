// SPDX-License-Identifier: GPL-3.0-or-later
// MTG files (multiscale tree graphs, the FORM-A text of AMAPmod, OpenAlea's openalea.mtg, XploRer and
// MultiScaleTreeGraph.jl) read and written without VTK, so that they are unit-tested and fuzzed alone
// (docs/formats/mtg.md describes the grammar as read and as written).
//
// A file has the sections CODE: (FORM-A), CLASSES: (SYMBOL SCALE DECOMPOSITION INDEXATION DEFINITION), DESCRIPTION:
// (LEFT RIGHT RELTYPE MAX), FEATURES: (NAME TYPE) and MTG:, whose first line names the columns: the entity code
// columns, then one column per feature. Each following line holds one entity code, in the column its tab
// indentation gives, and the feature values of the code's last entity in the feature columns. A code is a chain of
// labels (symbol + index) joined by '/' (the next entity is a component of the previous, one scale finer), '<' (it
// follows the previous), '+' (it branches on the previous) and '<<' (E1<<E4 is E1<E2<E3<E4). A code starting with
// '^' starts from the last entity of the latest line in the same column; any other from the last entity of the latest
// line one column to the left (column 0: as '^', the root '$' for the first line). A '<' or '+' to a coarser scale
// relates the coarser entities, and the first component of the new entity at the finer scale gets the same relation
// (as openalea.mtg does: "^<U2/E6" makes U2 follow U1 and E6 follow the E5 the line started from); a line that went
// coarser so stands on the finer entity it started from, which a later '<' or '+' to that scale in its column
// follows. A '/' to a scale not finer than its start makes a component of the complex one scale coarser ("/P2": a
// new plant); a '/' that skips scales makes unnamed complexes between.
//
// Reading is one pass, linear in the file; a line of at most kMaxMtgLineLength characters is held, every entity
// costs one record plus one value per feature, and a '<<' range creates at most kMaxMtgRange entities. Errors are
// "line N: what" for the caller to prefix with the file's name, and leave the graph empty.
#pragma once

#include <array>
#include <cstddef>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

namespace plantmorph
{

constexpr std::size_t kMaxMtgLineLength = std::size_t(1) << 16;
/// Most entities one '<<' range creates.
constexpr long long kMaxMtgRange = 100000;
/// Most entities of a file (a bound on memory whatever the ranges).
constexpr std::size_t kMaxMtgEntities = std::size_t(1) << 26;
/// Most scales (CLASSES' SCALE values 0..kMaxMtgScale).
constexpr int kMaxMtgScale = 64;

struct MtgClass
{
  std::string symbol;
  int scale = 0;
  std::string decomposition, indexation, definition;
};

enum class MtgFeatureKind
{
  Integer, ///< INT
  Real,    ///< REAL
  Text,    ///< STRING, ALPHA, dates (DD/MM/YY, ...) and any other type: kept as written
};

struct MtgFeature
{
  std::string name;
  std::string type; ///< as the file spells it
  MtgFeatureKind kind = MtgFeatureKind::Real;
};

struct MtgEntity
{
  std::string symbol;
  long long index = -1; ///< the label's number (-1: none written)
  int scale = 0;
  long long complex = -1;       ///< the entity it is a component of ('/'), -1 for the root
  long long parent = -1;        ///< the entity it follows or branches on at its own scale, -1 if none
  char edge = 0;                ///< '<' or '+' (0 without parent)
  std::size_t line = 0;         ///< the file's line that made it (0: the root)
  long long pendingParent = -1; ///< while its first component is not made: the finer entity that component relates to
  char pendingEdge = 0;

  std::string Label() const { return this->index < 0 ? this->symbol : this->symbol + std::to_string(this->index); }
};

struct MtgGraph
{
  std::string code; ///< the CODE: value (FORM-A)
  std::vector<MtgClass> classes;
  std::vector<std::array<std::string, 4>> description;
  std::vector<MtgFeature> features; ///< the FEATURES section's, in order
  /// Entity 0 is the root ('$', scale 0); the others in file order (a parent or complex always before).
  std::vector<MtgEntity> entities;
  /// One column per feature, one value per entity: numbers (NaN where missing) for INT and REAL, else text ("").
  std::vector<std::vector<double>> numbers;
  std::vector<std::vector<std::string>> texts;

  int FeatureIndex(const std::string& name) const;
  int FinestScale() const;
};

/// Reads the whole stream; "" or "line N: what" (the graph then empty).
std::string ReadMtg(std::istream& in, MtgGraph& graph);

/// The polylines a graph becomes: one per axis of the finest scale with coordinates (or the finest scale at all).
struct MtgAxis
{
  std::vector<long long> entities; ///< in order along the axis
  long long bearer = -1;           ///< the entity it branches on (or follows, for a second successor), -1 for none
  long long parentAxis = -1;
  int order = 0; ///< 0 for an axis without bearer, its parent axis's + 1 for a branch
};

struct MtgGeometry
{
  int scale = 0;
  bool explicitCoordinates = false; ///< XX, YY, ZZ given at this scale
  std::vector<MtgAxis> axes;
  /// Per entity (indexed as graph.entities): its point; only the entities of `scale` are set.
  std::vector<std::array<double, 3>> positions;
  std::size_t placedWithoutCoordinates = 0; ///< entities of `scale` without XX YY ZZ, placed on their axis
  std::string warning;                      ///< "" or what the caller should say (default layout, missing points)
};

/// The axes and points. With XX, YY, ZZ features (each entity's point, as openalea.mtg's PlantFrame reads them), the
/// finest scale where any entity has all three; an entity of that scale lacking them is placed on its axis between
/// the measured entities around it, linearly by rank (from the bearer's point before the first measured one, at the
/// last measured point after it): a digitised "E1<<E35" run measured at E35 only is spread along the axis.
/// Without them the default layout in the XY plane (y up, the image plane of TreeFromSketchSource's strokes): axes
/// without bearer grow from the origin along +y, a branch from its bearer's point at 45 degrees to its bearer's axis,
/// alternately to the left and right; each entity one step further, the step its Length (or length) feature when
/// positive, else 1.
MtgGeometry BuildMtgGeometry(const MtgGraph& graph);

/// A tree to write: one branch per axis (TreeFromSketchSource's skeleton: BranchId, ParentId, points, radii).
struct MtgTreeBranch
{
  long long id = 0;
  long long parentId = -1;
  std::vector<std::array<double, 3>> points;
  std::vector<double> radii; ///< one per point, or empty (no diameter written)
};

/// Writes FORM-A with the scales plant (P, 1), axis (A, 2) and segment (S, 3): one S per point (its XX, YY, ZZ and
/// diam = 2 radius), '<' along an axis, '+' from the parent's point nearest to the branch's first point. A branch
/// whose parent is not among the branches starts a plant. "" or why it cannot be written (a negative id, a cycle).
std::string WriteMtg(std::ostream& out, const std::vector<MtgTreeBranch>& branches);

} // namespace plantmorph
