// SPDX-License-Identifier: GPL-3.0-or-later
// QSM cylinder tables (quantitative structure models of trees) read and written without VTK (docs/formats/qsm.md):
// TreeQSM's text output (one cylinder per line, blank-separated, 14 or 17 columns: radius, length, start x y z, axis
// direction x y z, parent, extension, branch, branch order, position in branch, [mad, SurfCov,] added, [UnmodRadius];
// an optional header line naming them, start_point and axis_direction standing for three columns each) and the
// SimpleForest / rTwig CSV (a header naming ID, parentID, startX..startZ, endX..endZ or axisX..axisZ with length,
// radius, and any further columns: branchID, branchOrder, growthLength, ...).
//
// Names are matched after NormalName (case, '_', blanks and a unit in parentheses ignored: start_x = startX = "Start
// X"). Values are decimal numbers; NA, NaN and empty fields are missing (NaN), TRUE / FALSE are 1 / 0. Lines starting
// with '#' are comments; one after the cylinders ends the table (TreeQSM writes its branch and tree data below).
// One pass, linear; a line of at most kMaxQsmLineLength characters and kMaxQsmColumns columns; errors are "line N:
// what" and leave the table empty.
#pragma once

#include <array>
#include <cstddef>
#include <initializer_list>
#include <istream>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

namespace plantmorph
{

constexpr std::size_t kMaxQsmLineLength = std::size_t(1) << 16;
constexpr std::size_t kMaxQsmColumns = 1000;

struct QsmTable
{
  std::vector<std::string> names; ///< one per column
  std::size_t columns = 0;
  std::vector<double> values; ///< row-major, one row per cylinder
  bool treeQsm = false;       ///< TreeQSM's positional layout (no header, or its own header)
  // Resolved per cylinder:
  std::vector<std::array<double, 3>> start, end;
  std::vector<double> radius;
  std::vector<double> id, parent; ///< TreeQSM: the row number (1-based) and its parent column (0: none)

  std::size_t Rows() const { return this->columns ? this->values.size() / this->columns : 0; }
  /// The column whose NormalName is one of `names`, or -1.
  int Column(std::initializer_list<const char*> names) const;
};

/// Reads the whole stream; "" or "line N: what" / what is missing (the table then empty).
std::string ReadQsmTable(std::istream& in, QsmTable& table);

/// One cylinder to write.
struct QsmCylinder
{
  double id = 0, parent = 0;
  std::array<double, 3> start{}, end{};
  double radius = 0;
  double branch = 0, branchOrder = 0;
};

/// The columns WriteQsmTable writes first, in order (SimpleForest's names; rTwig reads them).
const std::vector<std::string>& QsmStandardColumns();

/// Writes a CSV: QsmStandardColumns() (axis = the unit direction, length = |end - start|), then the `extra` columns
/// (`extraValues` row-major, one row per cylinder), numbers in their shortest exact form. "" or the reason.
std::string WriteQsmTable(std::ostream& out, const std::vector<QsmCylinder>& cylinders,
  const std::vector<std::string>& extra = {}, const std::vector<double>& extraValues = {});

/// One polyline of a tree skeleton (TreeFromSketchSource's Skeleton: BranchId, ParentId, Radius per point).
struct QsmPolyline
{
  double branchId = 0;
  double parentId = -1; ///< a branchId of another polyline, or anything else for none
  double order = std::numeric_limits<double>::quiet_NaN(); ///< branch order; NaN: the depth below its root
  std::vector<std::array<double, 3>> points;
  std::vector<double> radii; ///< one per point
};

/// The polylines' segments as cylinders, in order (`lineOf`: each cylinder's polyline): ids 1, 2, ...; a segment's
/// parent the segment before it, a polyline's first segment's the parent polyline's segment ending at its point
/// nearest to the first point (its first segment for its first point; 0 for none); radius the mean of the two
/// points'; branch the polyline's branchId.
std::vector<QsmCylinder> CylindersOfPolylines(const std::vector<QsmPolyline>& lines, std::vector<std::size_t>& lineOf);

/// A closed tube for one cylinder: `sides` points around each end, the side quads and the two end polygons
/// (`polygons`: point counts then indices, as VTK's legacy cell layout, the indices from `first`).
void CylinderTube(const std::array<double, 3>& start, const std::array<double, 3>& end, double radius, int sides,
  long long first, std::vector<std::array<double, 3>>& points, std::vector<long long>& polygons);

} // namespace plantmorph
