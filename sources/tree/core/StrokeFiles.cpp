// SPDX-License-Identifier: GPL-3.0-or-later
#include "StrokeFiles.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/TextNumbers.h>

#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <unordered_map>

namespace plantmorph
{

namespace
{
using Strokes = std::vector<std::vector<Eigen::Vector3d>>;
using Point = Eigen::Vector2d;

bool IsSpace(char c)
{
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f';
}

char Lower(char c)
{
  return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
}

// ---------------------------------------------------------------------------------------------------------------
// CSV

/// One CSV line [begin, end) into trimmed fields, the way the reader always split them (a trailing separator adds
/// no empty field).
void SplitCsvFields(const char* begin, const char* end, std::vector<std::string>& fields)
{
  fields.clear();
  const auto isSeparator = [](char c) { return c == ',' || c == ';' || c == '\t'; };
  const auto isTrimmed = [](char c) { return c == ' ' || c == '\r' || c == '"'; };
  const char* p = begin;
  while (p < end)
  {
    const char* q = p;
    while (q < end && !isSeparator(*q))
    {
      ++q;
    }
    const char* a = p;
    const char* b = q;
    while (a < b && isTrimmed(*a))
    {
      ++a;
    }
    while (b > a && isTrimmed(*(b - 1)))
    {
      --b;
    }
    fields.emplace_back(a, b);
    p = q < end ? q + 1 : q;
  }
}

/// Parses a whole field as one number: Ok, NotANumber (also for trailing junk), TooLong or NotFinite.
NumberStatus FieldNumber(const std::string& field, double& value)
{
  const char* next = nullptr;
  const NumberStatus status = ScanNumber(field.data(), field.data() + field.size(), next, value);
  if (status == NumberStatus::Ok && next != field.data() + field.size())
  {
    return NumberStatus::NotANumber;
  }
  return status;
}

std::string LineError(std::size_t number, const std::string& what)
{
  return "StrokeFile: line " + std::to_string(number) + ": " + what;
}

// ---------------------------------------------------------------------------------------------------------------
// SVG: affine maps, numbers, lengths

/// x' = a x + c y + e, y' = b x + d y + f (SVG's matrix(a b c d e f)).
struct Affine
{
  double a = 1.0, b = 0.0, c = 0.0, d = 1.0, e = 0.0, f = 0.0;
  bool identity = true;

  Point Apply(const Point& p) const
  {
    if (this->identity)
    {
      return p;
    }
    return Point(this->a * p.x() + this->c * p.y() + this->e, this->b * p.x() + this->d * p.y() + this->f);
  }
  /// this * other: other applies first.
  Affine Then(const Affine& other) const
  {
    if (other.identity)
    {
      return *this;
    }
    if (this->identity)
    {
      return other;
    }
    Affine r;
    r.identity = false;
    r.a = this->a * other.a + this->c * other.b;
    r.b = this->b * other.a + this->d * other.b;
    r.c = this->a * other.c + this->c * other.d;
    r.d = this->b * other.c + this->d * other.d;
    r.e = this->a * other.e + this->c * other.f + this->e;
    r.f = this->b * other.e + this->d * other.f + this->f;
    return r;
  }
  /// The largest factor by which the map stretches a length (largest singular value of [a c; b d]).
  double Stretch() const
  {
    if (this->identity)
    {
      return 1.0;
    }
    const double s = this->a * this->a + this->b * this->b + this->c * this->c + this->d * this->d;
    const double det = this->a * this->d - this->b * this->c;
    return std::sqrt(0.5 * (s + std::sqrt(std::max(0.0, s * s - 4.0 * det * det))));
  }
};

Affine Matrix(double a, double b, double c, double d, double e, double f)
{
  Affine m;
  m.a = a;
  m.b = b;
  m.c = c;
  m.d = d;
  m.e = e;
  m.f = f;
  m.identity = false;
  return m;
}

/// Reads numbers separated by SVG's comma-wsp from [p, end).
class NumberList
{
public:
  NumberList(const char* begin, const char* end)
    : Begin(begin)
    , P(begin)
    , End(end)
  {
  }

  void SkipSpace()
  {
    while (this->P < this->End && IsSpace(*this->P))
    {
      ++this->P;
    }
  }
  /// Skips white space and at most one comma.
  void SkipCommaSpace()
  {
    this->SkipSpace();
    if (this->P < this->End && *this->P == ',')
    {
      ++this->P;
      this->SkipSpace();
    }
  }
  bool AtEnd()
  {
    this->SkipSpace();
    return this->P >= this->End;
  }
  bool AtNumber() const
  {
    if (this->P >= this->End)
    {
      return false;
    }
    const char c = *this->P;
    return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
  }
  /// The next number (after comma-wsp unless `first`); on failure Error says why.
  bool Number(double& value, bool first = false)
  {
    if (first)
    {
      this->SkipSpace();
    }
    else
    {
      this->SkipCommaSpace();
    }
    const char* next = nullptr;
    const NumberStatus status = ScanNumber(this->P, this->End, next, value);
    if (status != NumberStatus::Ok)
    {
      this->Error = DescribeNumberStatus(status) + " at character " + std::to_string(this->P - this->Begin + 1) +
        " ('" + Excerpt(this->P, this->End, 20) + "')";
      return false;
    }
    this->P = next;
    return true;
  }
  /// An arc flag: one character, 0 or 1.
  bool Flag(double& value)
  {
    this->SkipCommaSpace();
    if (this->P < this->End && (*this->P == '0' || *this->P == '1'))
    {
      value = *this->P == '1' ? 1.0 : 0.0;
      ++this->P;
      return true;
    }
    this->Error = "an arc flag (0 or 1) expected at character " + std::to_string(this->P - this->Begin + 1);
    return false;
  }

  const char* Begin;
  const char* P;
  const char* End;
  std::string Error;
};

/// A length: a number with an optional unit, converted to user units (px). known is false for %, em, ex.
bool ParseLength(const char* text, double& value, bool& known)
{
  const char* end = text + std::strlen(text);
  NumberList list(text, end);
  known = false;
  if (!list.Number(value, true))
  {
    return false;
  }
  std::string unit(list.P, end);
  while (!unit.empty() && IsSpace(unit.back()))
  {
    unit.pop_back();
  }
  std::transform(unit.begin(), unit.end(), unit.begin(), Lower);
  static const std::pair<const char*, double> units[] = { { "", 1.0 }, { "px", 1.0 }, { "mm", 96.0 / 25.4 },
    { "cm", 96.0 / 2.54 }, { "in", 96.0 }, { "pt", 96.0 / 72.0 }, { "pc", 16.0 } };
  for (const auto& [name, factor] : units)
  {
    if (unit == name)
    {
      value *= factor;
      known = true;
      return true;
    }
  }
  return unit == "%" || unit == "em" || unit == "ex";
}

/// A transform list ("translate(10) rotate(30 5 5) ..."); false on a malformed one.
bool ParseTransform(const char* text, Affine& result)
{
  const char* end = text + std::strlen(text);
  NumberList list(text, end);
  result = Affine();
  while (!list.AtEnd())
  {
    const char* nameBegin = list.P;
    while (list.P < end && ((*list.P >= 'a' && *list.P <= 'z') || (*list.P >= 'A' && *list.P <= 'Z')))
    {
      ++list.P;
    }
    const std::string name(nameBegin, list.P);
    list.SkipSpace();
    if (list.P >= end || *list.P != '(')
    {
      return false;
    }
    ++list.P;
    double v[6] = { 0, 0, 0, 0, 0, 0 };
    int count = 0;
    list.SkipSpace();
    while (count < 6 && list.P < end && *list.P != ')')
    {
      if (!list.Number(v[count], count == 0))
      {
        return false;
      }
      ++count;
      list.SkipSpace();
    }
    if (list.P >= end || *list.P != ')')
    {
      return false;
    }
    ++list.P;
    Affine m;
    const double radians = v[0] * Pi / 180.0;
    if (name == "matrix" && count == 6)
      m = Matrix(v[0], v[1], v[2], v[3], v[4], v[5]);
    else if (name == "translate" && (count == 1 || count == 2))
      m = Matrix(1, 0, 0, 1, v[0], v[1]);
    else if (name == "scale" && (count == 1 || count == 2))
      m = Matrix(v[0], 0, 0, count == 2 ? v[1] : v[0], 0, 0);
    else if (name == "rotate" && (count == 1 || count == 3))
      m = Matrix(1, 0, 0, 1, v[1], v[2])
            .Then(Matrix(std::cos(radians), std::sin(radians), -std::sin(radians), std::cos(radians), 0, 0))
            .Then(Matrix(1, 0, 0, 1, -v[1], -v[2]));
    else if (name == "skewX" && count == 1)
      m = Matrix(1, 0, std::tan(radians), 1, 0, 0);
    else if (name == "skewY" && count == 1)
      m = Matrix(1, std::tan(radians), 0, 1, 0, 0);
    else
      return false;
    result = result.Then(m);
    list.SkipCommaSpace();
  }
  return true;
}

/// The outermost <svg>'s viewBox mapped onto its width and height (px) with preserveAspectRatio.
bool ViewportTransform(const pugi::xml_node& svg, Affine& result, std::string& error)
{
  result = Affine();
  const char* viewBox = svg.attribute("viewBox").value();
  if (!*viewBox)
  {
    return true;
  }
  const char* end = viewBox + std::strlen(viewBox);
  NumberList list(viewBox, end);
  double box[4];
  for (int i = 0; i < 4; ++i)
  {
    if (!list.Number(box[i], i == 0))
    {
      error = "StrokeFile: the <svg> viewBox '" + Excerpt(viewBox, end) + "' is not four numbers: " + list.Error;
      return false;
    }
  }
  if (!(box[2] > 0.0 && box[3] > 0.0) || !list.AtEnd())
  {
    error = "StrokeFile: the <svg> viewBox '" + Excerpt(viewBox, end) +
      "' must be four numbers (min-x, min-y, width, height) with width and height > 0";
    return false;
  }
  double size[2] = { box[2], box[3] };
  const char* names[2] = { "width", "height" };
  for (int i = 0; i < 2; ++i)
  {
    const char* text = svg.attribute(names[i]).value();
    double value = 0.0;
    bool known = false;
    if (*text && !ParseLength(text, value, known))
    {
      error = std::string("StrokeFile: the <svg> ") + names[i] + " '" + Excerpt(text, text + std::strlen(text)) +
        "' is not a length (a number with px, mm, cm, in, pt, pc or no unit)";
      return false;
    }
    if (known && value > 0.0)
    {
      size[i] = value;
    }
  }
  double sx = size[0] / box[2];
  double sy = size[1] / box[3];
  std::string aspect = svg.attribute("preserveAspectRatio").value();
  double tx = 0.0, ty = 0.0; // fraction of the free space: 0 min, 0.5 mid, 1 max
  if (aspect.find("none") == std::string::npos)
  {
    const bool slice = aspect.find("slice") != std::string::npos;
    const double s = slice ? std::max(sx, sy) : std::min(sx, sy);
    sx = s;
    sy = s;
    tx = aspect.find("xMin") != std::string::npos ? 0.0 : aspect.find("xMax") != std::string::npos ? 1.0 : 0.5;
    ty = aspect.find("YMin") != std::string::npos ? 0.0 : aspect.find("YMax") != std::string::npos ? 1.0 : 0.5;
  }
  const double ox = tx * (size[0] - box[2] * sx);
  const double oy = ty * (size[1] - box[3] * sy);
  result = Matrix(sx, 0, 0, sy, ox - box[0] * sx, oy - box[1] * sy);
  return true;
}

/// A nested <svg>'s viewport: its x, y (lengths; percentages count 0) and its own viewBox mapping, as SVG draws it.
bool NestedViewport(const pugi::xml_node& svg, Affine& result, std::string& error)
{
  double offset[2] = { 0.0, 0.0 };
  const char* names[2] = { "x", "y" };
  for (int i = 0; i < 2; ++i)
  {
    const char* text = svg.attribute(names[i]).value();
    bool known = false;
    if (*text && !ParseLength(text, offset[i], known))
    {
      error = std::string("StrokeFile: a nested <svg> has ") + names[i] + " '" +
        Excerpt(text, text + std::strlen(text)) +
        "' that is not a length (a number with px, mm, cm, in, pt, pc or no unit)";
      return false;
    }
    offset[i] = known ? offset[i] : 0.0;
  }
  Affine viewBox;
  if (!ViewportTransform(svg, viewBox, error))
  {
    return false;
  }
  result = Matrix(1, 0, 0, 1, offset[0], offset[1]).Then(viewBox);
  return true;
}

// ---------------------------------------------------------------------------------------------------------------
// SVG: path data to user-space polylines

std::string TooManyPoints()
{
  return "its strokes hold more points than are read from a file of this size (" + std::to_string(kStrokePointsFloor) +
    " + " + std::to_string(kStrokePointsPerByte) + " per byte, at most " + std::to_string(kMaxStrokeFilePoints) + ")";
}

/// Number of equal parameter steps so that (step^2 / 8) * maxSecond <= tolerance, for a parameter span of 1.
int CurveSteps(double maxSecond, double tolerance)
{
  const double n = std::ceil(std::sqrt(maxSecond / (8.0 * tolerance)));
  if (!(n < kMaxCurveSegments)) // also NaN and infinity
  {
    return kMaxCurveSegments;
  }
  return std::max(1, static_cast<int>(n));
}

class PathFlattener
{
public:
  PathFlattener(double tolerance, std::size_t& budget)
    : Tolerance(tolerance)
    , Budget(budget)
  {
  }

  std::string Run(const char* begin, const char* end, std::vector<std::vector<Point>>& out);

private:
  bool Add(const Point& p)
  {
    if (this->Budget == 0)
    {
      return false;
    }
    --this->Budget;
    this->Stroke.push_back(p);
    return true;
  }
  bool Cubic(const Point& p0, const Point& p1, const Point& p2, const Point& p3);
  bool Quadratic(const Point& p0, const Point& p1, const Point& p2);
  bool Arc(const Point& p0, double rx, double ry, double angle, bool large, bool sweep, const Point& p1);
  std::string Command(char command, NumberList& list);

  double Tolerance;
  std::size_t& Budget;
  std::vector<Point> Stroke;
  std::vector<std::vector<Point>>* Out = nullptr;
  Point Current = Point::Zero();
  Point Start = Point::Zero();
  Point Control = Point::Zero(); // last cubic or quadratic control point, for S and T
  char Previous = 0;             // upper-case previous command
};

bool PathFlattener::Cubic(const Point& p0, const Point& p1, const Point& p2, const Point& p3)
{
  const double second = 6.0 * std::max((p0 - 2.0 * p1 + p2).norm(), (p1 - 2.0 * p2 + p3).norm());
  const int n = CurveSteps(second, this->Tolerance);
  for (int k = 1; k < n; ++k)
  {
    const double t = static_cast<double>(k) / n;
    const double s = 1.0 - t;
    if (!this->Add(s * s * s * p0 + 3.0 * s * s * t * p1 + 3.0 * s * t * t * p2 + t * t * t * p3))
      return false;
  }
  return this->Add(p3);
}

bool PathFlattener::Quadratic(const Point& p0, const Point& p1, const Point& p2)
{
  const int n = CurveSteps(2.0 * (p0 - 2.0 * p1 + p2).norm(), this->Tolerance);
  for (int k = 1; k < n; ++k)
  {
    const double t = static_cast<double>(k) / n;
    const double s = 1.0 - t;
    if (!this->Add(s * s * p0 + 2.0 * s * t * p1 + t * t * p2))
      return false;
  }
  return this->Add(p2);
}

/// SVG 1.1 appendix F.6: endpoint to centre parameterisation, radii scaled up when too small.
bool PathFlattener::Arc(const Point& p0, double rx, double ry, double angle, bool large, bool sweep, const Point& p1)
{
  rx = std::abs(rx);
  ry = std::abs(ry);
  if (p0 == p1)
  {
    return true; // omitted
  }
  if (rx == 0.0 || ry == 0.0 || !std::isfinite(rx * rx * ry * ry))
  {
    return this->Add(p1); // a straight line (radii so large that their products overflow: straight to a double's
                          // precision, as drawn)
  }
  const double phi = angle * Pi / 180.0;
  const double cp = std::cos(phi), sp = std::sin(phi);
  const Point h = 0.5 * (p0 - p1);
  const Point q(cp * h.x() + sp * h.y(), -sp * h.x() + cp * h.y());
  const double lambda = (q.x() * q.x()) / (rx * rx) + (q.y() * q.y()) / (ry * ry);
  if (lambda > 1.0)
  {
    rx *= std::sqrt(lambda);
    ry *= std::sqrt(lambda);
  }
  const double num = rx * rx * ry * ry - rx * rx * q.y() * q.y() - ry * ry * q.x() * q.x();
  const double den = rx * rx * q.y() * q.y() + ry * ry * q.x() * q.x();
  double root = den > 0.0 ? std::sqrt(std::max(0.0, num / den)) : 0.0;
  if (large == sweep)
  {
    root = -root;
  }
  const Point cq(root * rx * q.y() / ry, -root * ry * q.x() / rx);
  const Point centre(
    cp * cq.x() - sp * cq.y() + 0.5 * (p0.x() + p1.x()), sp * cq.x() + cp * cq.y() + 0.5 * (p0.y() + p1.y()));
  const double theta1 = std::atan2((q.y() - cq.y()) / ry, (q.x() - cq.x()) / rx);
  double delta = std::atan2((-q.y() - cq.y()) / ry, (-q.x() - cq.x()) / rx) - theta1;
  if (sweep && delta < 0.0)
    delta += 2.0 * Pi;
  else if (!sweep && delta > 0.0)
    delta -= 2.0 * Pi;
  if (!std::isfinite(delta) || !std::isfinite(centre.x()) || !std::isfinite(centre.y()))
  {
    return this->Add(p1);
  }
  // |p''(theta)| <= max(rx, ry), over a parameter span |delta|.
  const int n = CurveSteps(std::max(rx, ry) * delta * delta, this->Tolerance);
  for (int k = 1; k < n; ++k)
  {
    const double t = theta1 + delta * k / n;
    const double x = rx * std::cos(t), y = ry * std::sin(t);
    if (!this->Add(Point(centre.x() + cp * x - sp * y, centre.y() + sp * x + cp * y)))
      return false;
  }
  return this->Add(p1);
}

/// One command's numbers (the letter already read) and its points; an empty string or what is wrong.
std::string PathFlattener::Command(char command, NumberList& list)
{
  const char upper = static_cast<char>(command >= 'a' ? command - 'a' + 'A' : command);
  const bool relative = command >= 'a';
  int count = 2; // M L T
  if (upper == 'A')
    count = 7;
  else if (upper == 'C')
    count = 6;
  else if (upper == 'S' || upper == 'Q')
    count = 4;
  else if (upper == 'H' || upper == 'V')
    count = 1;
  double v[7];
  for (int i = 0; i < count; ++i)
  {
    const bool ok = upper == 'A' && (i == 3 || i == 4) ? list.Flag(v[i]) : list.Number(v[i], i == 0);
    if (!ok)
    {
      return std::string("its '") + command + "' command needs " + std::to_string(count) + " numbers: " + list.Error;
    }
  }
  const Point base = relative ? this->Current : Point::Zero();
  const auto at = [&](int i) -> Point { return Point(v[i], v[i + 1]) + base; };
  Point end = this->Current;
  bool ok = true;
  char kind = upper;
  switch (upper)
  {
    case 'M':
      end = at(0);
      if (!this->Stroke.empty())
      {
        this->Out->push_back(std::move(this->Stroke));
        this->Stroke.clear();
      }
      this->Start = end;
      ok = this->Add(end);
      break;
    case 'L':
      end = at(0);
      ok = this->Add(end);
      break;
    case 'H':
      end.x() = relative ? this->Current.x() + v[0] : v[0];
      ok = this->Add(end);
      break;
    case 'V':
      end.y() = relative ? this->Current.y() + v[0] : v[0];
      ok = this->Add(end);
      break;
    case 'C':
    case 'S':
    {
      const Point c1 = upper == 'C'                        ? at(0)
        : (this->Previous == 'C' || this->Previous == 'S') ? Point(2.0 * this->Current - this->Control)
                                                           : this->Current;
      const Point c2 = upper == 'C' ? at(2) : at(0);
      end = upper == 'C' ? at(4) : at(2);
      ok = this->Cubic(this->Current, c1, c2, end);
      this->Control = c2;
      break;
    }
    case 'Q':
    case 'T':
    {
      const Point c = upper == 'Q'                         ? at(0)
        : (this->Previous == 'Q' || this->Previous == 'T') ? Point(2.0 * this->Current - this->Control)
                                                           : this->Current;
      end = upper == 'Q' ? at(2) : at(0);
      ok = this->Quadratic(this->Current, c, end);
      this->Control = c;
      break;
    }
    case 'A':
      end = at(5);
      ok = this->Arc(this->Current, v[0], v[1], v[2], v[3] != 0.0, v[4] != 0.0, end);
      break;
    default:
      kind = 0;
      break;
  }
  if (!ok)
  {
    return TooManyPoints();
  }
  this->Current = end;
  this->Previous = kind;
  return {};
}

std::string PathFlattener::Run(const char* begin, const char* end, std::vector<std::vector<Point>>& out)
{
  this->Out = &out;
  NumberList list(begin, end);
  char command = 0;
  while (!list.AtEnd())
  {
    const char c = *list.P;
    if (!list.AtNumber())
    {
      if (std::string("MmLlHhVvCcSsQqTtAaZz").find(c) == std::string::npos || c == 0)
      {
        return "its path data has '" + Excerpt(list.P, list.P + 1) + "' at character " +
          std::to_string(list.P - begin + 1) + " where a command letter (M L H V C S Q T A Z) or a number belongs";
      }
      if (command == 0 && c != 'M' && c != 'm')
      {
        return "its path data must start with M or m";
      }
      command = c;
      ++list.P;
    }
    else if (command == 0)
    {
      return "its path data must start with M or m";
    }
    else if (command == 'Z' || command == 'z')
    {
      return "its path data has a number after Z at character " + std::to_string(list.P - begin + 1);
    }
    if (command == 'Z' || command == 'z')
    {
      if (!this->Stroke.empty() && !this->Add(this->Start))
      {
        return TooManyPoints();
      }
      this->Current = this->Start;
      this->Previous = 'Z';
      continue;
    }
    const std::string error = this->Command(command, list);
    if (!error.empty())
    {
      return error;
    }
    if (command == 'M' || command == 'm')
    {
      command = command == 'M' ? 'L' : 'l'; // numbers after a moveto are linetos
    }
    list.SkipCommaSpace();
  }
  if (!this->Stroke.empty())
  {
    out.push_back(std::move(this->Stroke));
    this->Stroke.clear();
  }
  return {};
}

// ---------------------------------------------------------------------------------------------------------------
// SVG: elements

std::string LocalName(const pugi::xml_node& node)
{
  std::string name = node.name();
  const auto colon = name.find(':');
  if (colon != std::string::npos && name.compare(0, colon, "svg") == 0)
  {
    name = name.substr(colon + 1);
  }
  std::transform(name.begin(), name.end(), name.begin(), Lower);
  return name;
}

/// "<path id="x"> (line 12)" for error messages.
std::string Describe(const pugi::xml_node& node, const std::string& text)
{
  std::string what = "<" + Excerpt(node.name(), node.name() + std::strlen(node.name()));
  const char* id = node.attribute("id").value();
  if (*id)
  {
    what += " id=\"" + Excerpt(id, id + std::strlen(id)) + "\"";
  }
  what += ">";
  const std::ptrdiff_t offset = node.offset_debug();
  if (offset >= 0 && static_cast<std::size_t>(offset) <= text.size())
  {
    what += " (line " + std::to_string(1 + std::count(text.begin(), text.begin() + offset, '\n')) + ")";
  }
  return what;
}

/// The polylines of one drawing element, in its user space.
std::string ElementPolylines(const pugi::xml_node& node, const std::string& name, double tolerance, std::size_t& budget,
  std::vector<std::vector<Point>>& out)
{
  if (name == "path")
  {
    const char* d = node.attribute("d").value();
    PathFlattener flattener(tolerance, budget);
    return flattener.Run(d, d + std::strlen(d), out);
  }
  std::vector<Point> points;
  if (name == "line")
  {
    double v[4];
    const char* names[4] = { "x1", "y1", "x2", "y2" };
    for (int i = 0; i < 4; ++i)
    {
      const char* text = node.attribute(names[i]).value();
      bool known = true;
      v[i] = 0.0;
      if (*text && (!ParseLength(text, v[i], known) || !known))
      {
        return std::string("its ") + names[i] + " '" + Excerpt(text, text + std::strlen(text)) +
          "' is not a length (a number with px, mm, cm, in, pt, pc or no unit)";
      }
    }
    points = { Point(v[0], v[1]), Point(v[2], v[3]) };
  }
  else
  {
    const char* text = node.attribute("points").value();
    NumberList list(text, text + std::strlen(text));
    while (!list.AtEnd())
    {
      double x = 0.0, y = 0.0;
      if (!list.Number(x, points.empty()) || !list.Number(y))
      {
        return "its points must be pairs of numbers x,y: " + list.Error;
      }
      if (budget == 0)
      {
        return TooManyPoints();
      }
      --budget;
      points.emplace_back(x, y);
    }
    if (name == "polygon" && !points.empty())
    {
      points.push_back(points.front());
    }
  }
  if (!points.empty())
  {
    out.push_back(std::move(points));
  }
  return {};
}

bool IsHidden(const std::string& name)
{
  static const char* hidden[] = { "defs", "symbol", "clippath", "mask", "marker", "pattern", "metadata", "title",
    "desc", "style", "script", "foreignobject" };
  return std::any_of(std::begin(hidden), std::end(hidden), [&](const char* h) { return name == h; });
}

/// Appends the element's strokes (its polylines through `ctm`, y flipped).
std::string AddElement(const pugi::xml_node& node, const std::string& name, const Affine& ctm, std::size_t& budget,
  const std::string& text, Strokes& strokes, std::vector<std::string>* origins)
{
  const double stretch = ctm.Stretch();
  const double tolerance = stretch > 0.0 && std::isfinite(stretch) ? kSvgCurveTolerance / stretch : HUGE_VAL;
  std::vector<std::vector<Point>> polylines;
  const std::string error = ElementPolylines(node, name, tolerance, budget, polylines);
  if (!error.empty())
  {
    return "StrokeFile: the SVG element " + Describe(node, text) + ": " + error;
  }
  for (const auto& polyline : polylines)
  {
    std::vector<Eigen::Vector3d> stroke;
    stroke.reserve(polyline.size());
    for (const Point& p : polyline)
    {
      const Point q = ctm.Apply(p);
      if (!std::isfinite(q.x()) || !std::isfinite(q.y()))
      {
        return "StrokeFile: the SVG element " + Describe(node, text) +
          ": a point overflows a double once its transforms apply";
      }
      stroke.emplace_back(q.x(), -q.y(), 0.0);
    }
    strokes.push_back(std::move(stroke));
    if (origins)
    {
      origins->push_back("the SVG element " + Describe(node, text) +
        (polylines.size() > 1 ? ", subpath " + std::to_string(&polyline - polylines.data() + 1) : ""));
    }
  }
  return {};
}

/// Walks the tree in document order without recursion, composing transforms.
std::string WalkSvg(const pugi::xml_node& root, const Affine& viewport, const std::string& text, Strokes& strokes,
  std::vector<std::string>* origins)
{
  std::size_t budget = StrokePointBudget(text.size());
  std::vector<Affine> ctms; // ctms[k]: the transform of the element at depth k + 1
  pugi::xml_node node = root;
  int depth = 1;
  while (node)
  {
    bool descend = false;
    if (node.type() == pugi::node_element)
    {
      const std::string name = LocalName(node);
      if (!IsHidden(name))
      {
        const Affine& parent = depth == 1 ? viewport : ctms[static_cast<std::size_t>(depth - 2)];
        Affine local;
        const char* transform = node.attribute("transform").value();
        if (*transform && !ParseTransform(transform, local))
        {
          return "StrokeFile: the SVG element " + Describe(node, text) + " has a transform '" +
            Excerpt(transform, transform + std::strlen(transform)) +
            "' that is not a list of matrix, translate, scale, rotate, skewX, skewY";
        }
        if (name == "svg" && depth > 1)
        {
          Affine nested; // a nested viewport: its x, y and viewBox (SVG 1.1 sec. 7.9)
          std::string error;
          if (!NestedViewport(node, nested, error))
          {
            return error + " (" + Describe(node, text) + ")";
          }
          local = local.Then(nested);
        }
        const Affine ctm = parent.Then(local);
        if (name == "path" || name == "polyline" || name == "polygon" || name == "line")
        {
          const std::string error = AddElement(node, name, ctm, budget, text, strokes, origins);
          if (!error.empty())
          {
            return error;
          }
        }
        else if (node.first_child())
        {
          if (depth >= kMaxSvgDepth)
          {
            return "StrokeFile: the SVG element " + Describe(node, text) + " is nested deeper than " +
              std::to_string(kMaxSvgDepth) + " levels (the most read)";
          }
          ctms.resize(static_cast<std::size_t>(depth));
          ctms.back() = ctm;
          descend = true;
        }
      }
    }
    if (descend)
    {
      node = node.first_child();
      ++depth;
      continue;
    }
    while (node && node != root && !node.next_sibling())
    {
      node = node.parent();
      --depth;
    }
    if (!node || node == root)
    {
      break;
    }
    node = node.next_sibling();
  }
  return {};
}
} // namespace

std::size_t StrokePointBudget(std::size_t bytes)
{
  return bytes >= kMaxStrokeFilePoints / kStrokePointsPerByte
    ? kMaxStrokeFilePoints
    : std::min(kMaxStrokeFilePoints, kStrokePointsFloor + kStrokePointsPerByte * bytes);
}

std::string ParseStrokeCsv(
  const std::string& text, std::vector<std::vector<Eigen::Vector3d>>& strokes, std::vector<std::string>* origins)
{
  strokes.clear();
  if (origins)
  {
    origins->clear();
  }
  std::unordered_map<std::string, std::size_t> order;
  std::vector<std::string> fields;
  std::size_t number = 0;
  std::size_t points = 0;
  const char* p = text.data();
  const char* end = p + text.size();
  while (p < end)
  {
    const char* lineEnd = std::find(p, end, '\n');
    const char* line = p;
    p = lineEnd < end ? lineEnd + 1 : end;
    ++number;
    const auto fail = [&](const std::string& what) {
      strokes.clear();
      if (origins)
      {
        origins->clear();
      }
      return LineError(number, what);
    };
    if (static_cast<std::size_t>(lineEnd - line) > kMaxStrokeLineLength)
    {
      return fail("longer than " + std::to_string(kMaxStrokeLineLength) +
        " characters (a stroke file has one point, stroke_id, x, y, per line)");
    }
    if (std::find(line, lineEnd, '\0') != lineEnd)
    {
      return fail("holds a NUL byte: not a text file of rows stroke_id, x, y");
    }
    const char* first = std::find_if(line, lineEnd, [](char c) { return c != ' '; });
    const bool blank =
      std::all_of(line, lineEnd, [](char c) { return c == ' ' || c == '\r' || c == ',' || c == ';' || c == '\t'; });
    if (blank || *first == '#')
    {
      continue;
    }
    SplitCsvFields(line, lineEnd, fields);
    if (fields.size() < 3)
    {
      return fail("has fewer than 3 fields (stroke_id, x, y)");
    }
    double xy[2] = { 0.0, 0.0 };
    bool numeric = true;
    for (int k = 0; k < 2; ++k)
    {
      const NumberStatus status = FieldNumber(fields[static_cast<std::size_t>(k) + 1], xy[k]);
      if (status == NumberStatus::TooLong || status == NumberStatus::NotFinite)
      {
        return fail(std::string(k == 0 ? "x" : "y") + " is " + DescribeNumberStatus(status));
      }
      numeric = numeric && status == NumberStatus::Ok;
    }
    if (!numeric)
    {
      if (order.empty())
      {
        continue; // a header line
      }
      return fail("x and y must be numbers ('" + Excerpt(line, lineEnd) + "')");
    }
    auto [it, inserted] = order.emplace(fields[0], strokes.size());
    if (inserted)
    {
      strokes.emplace_back();
      if (origins)
      {
        origins->push_back("stroke_id '" + Excerpt(fields[0].data(), fields[0].data() + fields[0].size()) +
          "' from line " + std::to_string(number));
      }
    }
    if (++points > kMaxStrokeFilePoints)
    {
      return fail("a stroke file holds at most " + std::to_string(kMaxStrokeFilePoints) + " points");
    }
    strokes[it->second].emplace_back(xy[0], xy[1], 0.0);
  }
  return {};
}

std::string ParseStrokeSvg(
  const std::string& text, std::vector<std::vector<Eigen::Vector3d>>& strokes, std::vector<std::string>* origins)
{
  strokes.clear();
  if (origins)
  {
    origins->clear();
  }
  const auto nul = text.find('\0');
  if (nul != std::string::npos)
  {
    return "StrokeFile: the SVG file holds a NUL byte at offset " + std::to_string(nul) + ": not an XML text file";
  }
  pugi::xml_document document;
  const pugi::xml_parse_result result =
    document.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!result)
  {
    const auto offset = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, result.offset));
    const auto at = text.begin() + static_cast<std::ptrdiff_t>(std::min(offset, text.size()));
    const auto line = 1 + std::count(text.begin(), at, '\n');
    return "StrokeFile: the SVG file is not well-formed XML (" + std::string(result.description()) + " at line " +
      std::to_string(line) + ", byte " + std::to_string(offset) + "): a truncated or damaged file?";
  }
  const pugi::xml_node root = document.document_element();
  if (LocalName(root) != "svg")
  {
    return "StrokeFile: the file's root element is <" + Excerpt(root.name(), root.name() + std::strlen(root.name())) +
      ">, not <svg>";
  }
  Affine viewport;
  std::string error;
  if (!ViewportTransform(root, viewport, error))
  {
    return error;
  }
  error = WalkSvg(root, viewport, text, strokes, origins);
  if (!error.empty())
  {
    strokes.clear();
    if (origins)
    {
      origins->clear();
    }
    return error;
  }
  if (strokes.empty())
  {
    return "StrokeFile: no <path d=...>, <polyline points=...>, <polygon points=...> or <line> element with points "
           "in the SVG file";
  }
  return {};
}

std::string ReadStrokeFile(
  const std::string& path, std::vector<std::vector<Eigen::Vector3d>>& strokes, std::vector<std::string>* origins)
{
  strokes.clear();
  std::string extension = path.size() >= 4 ? path.substr(path.size() - 4) : std::string();
  std::transform(extension.begin(), extension.end(), extension.begin(), Lower);
  if (extension != ".svg" && extension != ".csv" && extension != ".txt")
  {
    return "StrokeFile: '" + path + "' is neither .csv (stroke_id, x, y) nor .svg";
  }
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file)
  {
    return "StrokeFile: cannot open '" + path + "'";
  }
  const std::streamoff size = file.tellg();
  if (size < 0 || static_cast<std::size_t>(size) > kMaxStrokeFileBytes)
  {
    return "StrokeFile: '" + path + "' is larger than " + std::to_string(kMaxStrokeFileBytes >> 20) +
      " MiB (the largest stroke file read)";
  }
  std::string content(static_cast<std::size_t>(size), '\0');
  file.seekg(0);
  if (size > 0 && !file.read(&content[0], size))
  {
    return "StrokeFile: cannot read '" + path + "'";
  }
  return extension == ".svg" ? ParseStrokeSvg(content, strokes, origins) : ParseStrokeCsv(content, strokes, origins);
}

std::string StrokeFileError(const std::string& error, const std::string& path, const std::vector<std::string>& origins)
{
  const std::string input = "Strokes input";
  if (error.compare(0, input.size(), input) != 0)
  {
    return error;
  }
  std::string rest = error.substr(input.size());
  const std::string stroke = ", stroke ";
  if (rest.compare(0, stroke.size(), stroke) == 0)
  {
    std::size_t digits = stroke.size();
    while (digits < rest.size() && rest[digits] >= '0' && rest[digits] <= '9')
    {
      ++digits;
    }
    const std::string number = rest.substr(stroke.size(), digits - stroke.size());
    const std::size_t k = number.empty() || number.size() > 18 ? origins.size() : std::stoull(number);
    if (k < origins.size())
    {
      rest = ", stroke " + number + " (" + origins[k] + ")" + rest.substr(digits);
    }
  }
  return "StrokeFile '" + path + "'" + rest;
}

} // namespace plantmorph
