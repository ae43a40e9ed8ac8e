// SPDX-License-Identifier: GPL-3.0-or-later
#include "QsmTable.h"

#include "FormatText.h"

#include <plantmorph/TextNumbers.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace plantmorph
{

int QsmTable::Column(std::initializer_list<const char*> wanted) const
{
  for (const char* name : wanted)
  {
    for (std::size_t c = 0; c < this->names.size(); ++c)
    {
      if (NormalName(this->names[c]) == name)
      {
        return static_cast<int>(c);
      }
    }
  }
  return -1;
}

namespace
{
const std::vector<std::string>& TreeQsmNames(std::size_t columns)
{
  static const std::vector<std::string> seventeen = { "radius", "length", "start_x", "start_y", "start_z", "axis_x",
    "axis_y", "axis_z", "parent", "extension", "branch", "branch_order", "position_in_branch", "mad", "SurfCov",
    "added", "UnmodRadius" };
  static const std::vector<std::string> fourteen = { "radius", "length", "start_x", "start_y", "start_z", "axis_x",
    "axis_y", "axis_z", "parent", "extension", "branch", "branch_order", "position_in_branch", "added" };
  return columns == 14 ? fourteen : seventeen;
}

/// The fields of a line: split at ',' when it has one, else at ';' when it has one, else (a header line with a tab,
/// whose names may hold blanks: "radius (m)") at tabs, else at runs of blanks.
std::vector<std::string> Fields(const std::string& line, bool header)
{
  const char separator = line.find(',') != std::string::npos ? ','
    : line.find(';') != std::string::npos                    ? ';'
    : header && line.find('\t') != std::string::npos         ? '\t'
                                                             : ' ';
  std::vector<std::string> fields;
  if (separator != ' ')
  {
    for (const std::string& f : SplitAt(line, separator))
    {
      fields.push_back(Trim(f));
    }
    return fields;
  }
  std::size_t pos = 0;
  while (pos < line.size())
  {
    while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t'))
    {
      ++pos;
    }
    const std::size_t begin = pos;
    while (pos < line.size() && line[pos] != ' ' && line[pos] != '\t')
    {
      ++pos;
    }
    if (pos > begin)
    {
      fields.push_back(line.substr(begin, pos - begin));
    }
  }
  return fields;
}

std::string Unquoted(const std::string& text)
{
  if (text.size() >= 2 && (text.front() == '"' || text.front() == '\'') && text.back() == text.front())
  {
    return text.substr(1, text.size() - 2);
  }
  return text;
}

/// A field's value: a number, a missing value (NaN) or TRUE / FALSE; false for anything else.
bool FieldValue(const std::string& raw, double& value)
{
  const std::string field = Unquoted(raw);
  if (ParseWholeNumber(field, value))
  {
    return true;
  }
  const std::string n = NormalName(field);
  if (n.empty() || n == "na" || n == "nan")
  {
    value = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (n == "true" || n == "false")
  {
    value = n == "true" ? 1.0 : 0.0;
    return true;
  }
  return false;
}

/// The header's names, TreeQSM's start_point and axis_direction expanded to three columns each.
std::vector<std::string> HeaderNames(const std::vector<std::string>& fields, bool& treeQsm)
{
  std::vector<std::string> names;
  treeQsm = false;
  for (const std::string& f : fields)
  {
    const std::string name = Unquoted(f);
    const std::string n = NormalName(name);
    if (n == "startpoint" || n == "axisdirection")
    {
      treeQsm = true;
      const std::string stem = n == "startpoint" ? "start_" : "axis_";
      names.insert(names.end(), { stem + "x", stem + "y", stem + "z" });
    }
    else
    {
      names.push_back(name);
    }
  }
  return names;
}

/// Start, end, radius, ids of every row, from the named columns; "" or what is missing.
std::string Resolve(QsmTable& t)
{
  const int radius = t.Column({ "radius", "radiuscyl" });
  const int sx = t.Column({ "startx" }), sy = t.Column({ "starty" }), sz = t.Column({ "startz" });
  const int ex = t.Column({ "endx" }), ey = t.Column({ "endy" }), ez = t.Column({ "endz" });
  const int ax = t.Column({ "axisx" }), ay = t.Column({ "axisy" }), az = t.Column({ "axisz" });
  const int length = t.Column({ "length" });
  const int id = t.treeQsm ? -1 : t.Column({ "id", "cylinderid", "cylid" });
  const int parent = t.Column({ "parentid", "parent", "parentcylinderid" });
  const bool ends = ex >= 0 && ey >= 0 && ez >= 0, axis = ax >= 0 && ay >= 0 && az >= 0 && length >= 0;
  if (radius < 0 || sx < 0 || sy < 0 || sz < 0 || !(ends || axis))
  {
    return "the table names no " +
      std::string(radius < 0           ? "radius"
          : sx < 0 || sy < 0 || sz < 0 ? "startX, startY, startZ"
                                       : "endX, endY, endZ (nor axisX, axisY, axisZ with length)") +
      " column: a QSM cylinder table needs a radius, the start and the end (or axis and length) of each cylinder";
  }
  const std::size_t rows = t.Rows(), n = t.columns;
  for (std::size_t r = 0; r < rows; ++r)
  {
    const double* row = &t.values[r * n];
    const std::array<double, 3> s = { row[sx], row[sy], row[sz] };
    std::array<double, 3> e{};
    if (ends)
    {
      e = { row[ex], row[ey], row[ez] };
    }
    else
    {
      const double norm = std::sqrt(row[ax] * row[ax] + row[ay] * row[ay] + row[az] * row[az]);
      const double scale = norm > 0 ? row[length] / norm : 0.0;
      e = { s[0] + scale * row[ax], s[1] + scale * row[ay], s[2] + scale * row[az] };
    }
    for (int k = 0; k < 3; ++k)
    {
      if (!std::isfinite(s[static_cast<std::size_t>(k)]) || !std::isfinite(e[static_cast<std::size_t>(k)]) ||
        !std::isfinite(row[radius]))
      {
        return "cylinder " + std::to_string(r + 1) + " (table row " + std::to_string(r + 1) +
          ") has a missing start, end or radius";
      }
    }
    t.start.push_back(s);
    t.end.push_back(e);
    t.radius.push_back(row[radius]);
    t.id.push_back(id >= 0 ? row[id] : static_cast<double>(r + 1));
    t.parent.push_back(parent >= 0 ? row[parent] : 0.0);
  }
  return {};
}

/// The reader's state between lines.
struct QsmParser
{
  explicit QsmParser(QsmTable& table)
    : Table(table)
  {
  }

  QsmTable& Table;
  std::size_t Number = 0;
  bool HeaderDone = false;
  bool Ended = false; ///< a comment after the cylinders: the rest is not read
  std::vector<double> Row;

  std::string Fail(const std::string& what) const { return "line " + std::to_string(this->Number) + ": " + what; }

  /// One line; "" or the error.
  std::string Line(const std::string& line)
  {
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#')
    {
      this->Ended = this->Ended || (!trimmed.empty() && this->Table.Rows() > 0);
      return {};
    }
    std::vector<std::string> fields = Fields(trimmed, false);
    if (fields.size() > kMaxQsmColumns)
    {
      return this->Fail("more than " + std::to_string(kMaxQsmColumns) + " columns");
    }
    this->Row.assign(fields.size(), 0.0);
    std::size_t bad = fields.size();
    for (std::size_t c = 0; c < fields.size() && bad == fields.size(); ++c)
    {
      bad = FieldValue(fields[c], this->Row[c]) ? bad : c;
    }
    if (!this->HeaderDone)
    {
      this->HeaderDone = true;
      if (bad < fields.size())
      {
        fields = Fields(trimmed, true);
        this->Table.names = HeaderNames(fields, this->Table.treeQsm);
        this->Table.columns = this->Table.names.size();
        return this->Table.columns > kMaxQsmColumns
          ? this->Fail("more than " + std::to_string(kMaxQsmColumns) + " columns")
          : std::string();
      }
    }
    if (bad < fields.size())
    {
      return this->Fail("column " + std::to_string(bad + 1) + " is not a number: '" +
        Excerpt(fields[bad].data(), fields[bad].data() + fields[bad].size(), 40) + "'");
    }
    if (this->Table.columns == 0)
    {
      this->Table.columns = fields.size();
      if (fields.size() != 14 && fields.size() != 17)
      {
        return this->Fail("no header and " + std::to_string(fields.size()) +
          " columns: TreeQSM's cylinder table has 14 or 17 (a CSV needs a header naming its columns)");
      }
      this->Table.treeQsm = true;
      const std::vector<std::string>& standard = TreeQsmNames(fields.size());
      for (std::size_t c = 0; c < fields.size(); ++c)
      {
        this->Table.names.push_back(standard[c]);
      }
    }
    if (fields.size() != this->Table.columns)
    {
      return this->Fail(std::to_string(fields.size()) + " columns where the " +
        (this->Table.Rows() ? "first row" : "header") + " has " + std::to_string(this->Table.columns));
    }
    this->Table.values.insert(this->Table.values.end(), this->Row.begin(), this->Row.end());
    return {};
  }
};
} // namespace

std::string ReadQsmTable(std::istream& in, QsmTable& table)
{
  table = QsmTable();
  LineReader lines(in, kMaxQsmLineLength);
  QsmParser parser(table);
  std::string line;
  while (!parser.Ended && lines.Next(line))
  {
    if (lines.Number() == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0)
    {
      line.erase(0, 3);
    }
    parser.Number = lines.Number();
    const std::string error = parser.Line(line);
    if (!error.empty())
    {
      table = QsmTable();
      return error;
    }
  }
  std::string error = !lines.Error().empty() ? lines.Error() : table.Rows() == 0 ? "no cylinder row" : Resolve(table);
  if (!error.empty())
  {
    table = QsmTable();
  }
  return error;
}

const std::vector<std::string>& QsmStandardColumns()
{
  static const std::vector<std::string> names = { "ID", "parentID", "startX", "startY", "startZ", "endX", "endY",
    "endZ", "axisX", "axisY", "axisZ", "radius", "length", "branchID", "branchOrder" };
  return names;
}

std::string WriteQsmTable(std::ostream& out, const std::vector<QsmCylinder>& cylinders,
  const std::vector<std::string>& extra, const std::vector<double>& extraValues)
{
  if (extraValues.size() != cylinders.size() * extra.size())
  {
    return "the extra columns' values do not fill one row per cylinder";
  }
  std::string header;
  for (const std::string& name : QsmStandardColumns())
  {
    header += (header.empty() ? "" : ",") + name;
  }
  for (const std::string& name : extra)
  {
    header += "," + name;
  }
  out << header << '\n';
  for (std::size_t i = 0; i < cylinders.size(); ++i)
  {
    const QsmCylinder& c = cylinders[i];
    const double d[3] = { c.end[0] - c.start[0], c.end[1] - c.start[1], c.end[2] - c.start[2] };
    const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double inverse = length > 0 ? 1.0 / length : 0.0;
    const double row[15] = { c.id, c.parent, c.start[0], c.start[1], c.start[2], c.end[0], c.end[1], c.end[2],
      d[0] * inverse, d[1] * inverse, d[2] * inverse, c.radius, length, c.branch, c.branchOrder };
    for (int k = 0; k < 15; ++k)
    {
      out << (k ? "," : "") << (std::isfinite(row[k]) ? ExactNumber(row[k]) : "NA");
    }
    for (std::size_t k = 0; k < extra.size(); ++k)
    {
      const double v = extraValues[i * extra.size() + k];
      out << ',' << (std::isfinite(v) ? ExactNumber(v) : "NA");
    }
    out << '\n';
  }
  return out ? std::string() : std::string("the file could not be written");
}

namespace
{
/// The depth of polyline `i` below its root (parents by branchId; a cycle stops the walk).
double DepthOf(std::size_t i, const std::vector<QsmPolyline>& lines, const std::vector<long long>& parentLine)
{
  double depth = 0;
  for (long long p = parentLine[i]; p >= 0 && depth <= static_cast<double>(lines.size()); p = parentLine[p])
  {
    ++depth;
  }
  return depth;
}
} // namespace

std::vector<QsmCylinder> CylindersOfPolylines(const std::vector<QsmPolyline>& lines, std::vector<std::size_t>& lineOf)
{
  std::map<double, std::size_t> byId;
  for (std::size_t i = 0; i < lines.size(); ++i)
  {
    byId.emplace(lines[i].branchId, i);
  }
  std::vector<long long> parentLine(lines.size(), -1);
  std::vector<double> firstCylinder(lines.size(), 0);
  double next = 1;
  for (std::size_t i = 0; i < lines.size(); ++i)
  {
    const auto p = byId.find(lines[i].parentId);
    parentLine[i] = p == byId.end() || p->second == i ? -1 : static_cast<long long>(p->second);
    firstCylinder[i] = next;
    next += lines[i].points.size() > 1 ? static_cast<double>(lines[i].points.size() - 1) : 0.0;
  }
  std::vector<QsmCylinder> cylinders;
  lineOf.clear();
  for (std::size_t i = 0; i < lines.size(); ++i)
  {
    const QsmPolyline& line = lines[i];
    double parent = 0;
    if (parentLine[i] >= 0 && !line.points.empty())
    {
      const QsmPolyline& p = lines[static_cast<std::size_t>(parentLine[i])];
      std::size_t nearest = 0;
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < p.points.size(); ++k)
      {
        const double dx = p.points[k][0] - line.points[0][0], dy = p.points[k][1] - line.points[0][1],
                     dz = p.points[k][2] - line.points[0][2];
        const double d = dx * dx + dy * dy + dz * dz;
        nearest = d < best ? k : nearest;
        best = std::min(best, d);
      }
      parent = p.points.size() > 1
        ? firstCylinder[static_cast<std::size_t>(parentLine[i])] + static_cast<double>(nearest > 0 ? nearest - 1 : 0)
        : 0.0;
    }
    const double order = std::isfinite(line.order) ? line.order : DepthOf(i, lines, parentLine);
    for (std::size_t k = 0; k + 1 < line.points.size(); ++k)
    {
      QsmCylinder c;
      c.id = firstCylinder[i] + static_cast<double>(k);
      c.parent = k == 0 ? parent : c.id - 1;
      c.start = line.points[k];
      c.end = line.points[k + 1];
      c.radius = k + 1 < line.radii.size() ? 0.5 * (line.radii[k] + line.radii[k + 1])
                                           : std::numeric_limits<double>::quiet_NaN();
      c.branch = line.branchId;
      c.branchOrder = order;
      cylinders.push_back(c);
      lineOf.push_back(i);
    }
  }
  return cylinders;
}

void CylinderTube(const std::array<double, 3>& start, const std::array<double, 3>& end, double radius, int sides,
  long long first, std::vector<std::array<double, 3>>& points, std::vector<long long>& polygons)
{
  std::array<double, 3> d = { end[0] - start[0], end[1] - start[1], end[2] - start[2] };
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  d = length > 0 ? std::array<double, 3>{ d[0] / length, d[1] / length, d[2] / length }
                 : std::array<double, 3>{ 0.0, 0.0, 1.0 };
  // u: a unit vector normal to d (from the axis d is least along), v = d x u.
  const int least = std::abs(d[0]) <= std::abs(d[1]) && std::abs(d[0]) <= std::abs(d[2]) ? 0
    : std::abs(d[1]) <= std::abs(d[2])                                                   ? 1
                                                                                         : 2;
  std::array<double, 3> e{};
  e[static_cast<std::size_t>(least)] = 1.0;
  std::array<double, 3> u = { e[1] * d[2] - e[2] * d[1], e[2] * d[0] - e[0] * d[2], e[0] * d[1] - e[1] * d[0] };
  const double un = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  u = { u[0] / un, u[1] / un, u[2] / un };
  const std::array<double, 3> v = { d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0] };
  const double pi = std::acos(-1.0);
  for (const auto* centre : { &start, &end })
  {
    for (int k = 0; k < sides; ++k)
    {
      const double a = 2.0 * pi * k / sides, c = std::cos(a) * radius, s = std::sin(a) * radius;
      points.push_back(
        { (*centre)[0] + c * u[0] + s * v[0], (*centre)[1] + c * u[1] + s * v[1], (*centre)[2] + c * u[2] + s * v[2] });
    }
  }
  for (int k = 0; k < sides; ++k)
  {
    const long long a = first + k, b = first + (k + 1) % sides;
    polygons.insert(polygons.end(), { 4, a, b, b + sides, a + sides });
  }
  polygons.push_back(sides); // the start cap, facing back
  for (int k = sides - 1; k >= 0; --k)
  {
    polygons.push_back(first + k);
  }
  polygons.push_back(sides); // the end cap
  for (int k = 0; k < sides; ++k)
  {
    polygons.push_back(first + sides + k);
  }
}

} // namespace plantmorph
