// SPDX-License-Identifier: GPL-3.0-or-later
#include "SpaceCurveLeaf.h"

#include "PalmateLeaf.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RangeError.h>
#include <plantmorph/DataContract.h>

#include <Eigen/Geometry>

#include <cmath>
#include <sstream>

namespace plantmorph
{
namespace
{
std::string Check(bool ok, const char* property, double value, const char* range)
{
  return CheckRange(ok, property, value, range);
}

} // namespace

std::string ValidateSpaceCurveParameters(const SpaceCurveParameters& p, const SpaceCurveMeshParameters& m)
{
  std::string e;
  if (!(e = Check(std::isfinite(p.length) && p.length > 0 && p.length <= 1e6, "CurveLength", p.length, "(0, 1e6]"))
         .empty() ||
    !(e = p.curvature.Validate(p.length, "Curvature")).empty() ||
    !(e = p.torsion.Validate(p.length, "Torsion")).empty() ||
    !(e = Check(std::isfinite(p.opening) && std::abs(p.opening) < 1, "Opening", p.opening, "(-1, 1)")).empty() ||
    !(e = Check(std::isfinite(p.midveinStretchZ) && std::abs(p.midveinStretchZ) <= 10, "MidveinStretchZ",
        p.midveinStretchZ, "[-10, 10]"))
       .empty() ||
    !(e = Check(std::isfinite(p.midveinStretchXY) && std::abs(p.midveinStretchXY) <= 10, "MidveinStretchXY",
        p.midveinStretchXY, "[-10, 10]"))
       .empty() ||
    !(e = Check(std::isfinite(p.initialAngle) && std::abs(p.initialAngle) <= 360, "InitialAngle", p.initialAngle,
        "[-360, 360] degrees"))
       .empty() ||
    !(e = ValidateResolution(m.resolution)).empty() ||
    !(e = Check(m.columns >= 1 && m.columns <= MaxStripColumns, "StripColumns", m.columns, "[1, 200]")).empty() ||
    !(e = Check(p.lobes == 1 || p.lobes == 3 || p.lobes == 5, "Lobes", p.lobes, "{1, 3, 5}")).empty())
    return e;
  if (p.lobes == 1)
    return {};
  if (!(e = Check(std::isfinite(p.lobeStart) && p.lobeStart > 0 && p.lobeStart < 1, "LobeStart", p.lobeStart, "(0, 1)"))
         .empty() ||
    !(e = Check(std::isfinite(p.lobeAngle) && p.lobeAngle > 0 && p.lobeAngle <= 90, "LobeAngle", p.lobeAngle,
        "(0, 90] degrees"))
       .empty() ||
    !(e = Check(
        std::isfinite(p.lobeScale) && p.lobeScale > 0 && p.lobeScale <= 1.5, "LobeScale", p.lobeScale, "(0, 1.5]"))
       .empty() ||
    !(e = Check(p.subLobes >= 0 && p.subLobes <= 8, "SubLobes", p.subLobes, "[0, 8]")).empty() ||
    !(e = Check(std::isfinite(p.subLobeDepth) && p.subLobeDepth > 0 && p.subLobeDepth <= 0.9, "SubLobeDepth",
        p.subLobeDepth, "(0, 0.9]"))
       .empty() ||
    !(e = Check(std::isfinite(p.sinusDepth) && p.sinusDepth >= 0 && p.sinusDepth <= 0.95, "SinusDepth", p.sinusDepth,
        "[0, 0.95]"))
       .empty())
    return e;
  if (p.torsion.mu != 0.0 || p.opening != 0.0)
    return "Lobes: palmate leaves are flat (paper 002 sec. 4); set TorsionEta and Opening to 0";
  return {};
}

namespace
{
/// The unit normal g of the symmetry plane: g.c = 0, g_z = opening, |g| = 1, and g.t0 > 0 (eq. (9)).
bool SymmetryNormal(const Eigen::Vector3d& c, double opening, const Eigen::Vector3d& t0, Eigen::Vector3d& g)
{
  // In the (g_x, g_y) plane: the line c_x g_x + c_y g_y = -c_z * opening meets the circle of radius
  // sqrt(1 - opening^2).
  const Eigen::Vector2d n(c.x(), c.y());
  const double m2 = n.squaredNorm();
  if (!(m2 > 1e-24))
    return false;
  const double d = -c.z() * opening;
  const double r2 = 1.0 - opening * opening;
  const double h2 = r2 - d * d / m2;
  if (h2 < 0.0)
    return false;
  const Eigen::Vector2d foot = (d / m2) * n;
  const Eigen::Vector2d along = Eigen::Vector2d(-n.y(), n.x()) / std::sqrt(m2);
  const Eigen::Vector2d a = foot + std::sqrt(h2) * along, b = foot - std::sqrt(h2) * along;
  const Eigen::Vector3d ga(a.x(), a.y(), opening), gb(b.x(), b.y(), opening);
  const double ta = ga.dot(t0), tb = gb.dot(t0);
  g = ta >= tb ? ga : gb;
  if (g.dot(t0) < 0.0)
    g = -g; // opening = 0: the two solutions are g and -g; orient towards the initial tangent
  return g.dot(t0) > 0.0;
}
} // namespace

std::string IntegrateHalfMargin(const SpaceCurveParameters& p, int pieces, std::vector<FrenetFrame>& frames)
{
  const double angle = p.initialAngle * Pi / 180.0;
  FrenetFrame start;
  start.tangent = Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0);
  start.normal = Eigen::Vector3d(-std::sin(angle), std::cos(angle), 0.0);
  start.binormal = Eigen::Vector3d::UnitZ();
  std::vector<double> breakpoints = p.curvature.Breakpoints(p.length);
  const std::vector<double> torsionBreaks = p.torsion.Breakpoints(p.length);
  breakpoints.insert(breakpoints.end(), torsionBreaks.begin(), torsionBreaks.end());
  FrenetParameters settings;
  settings.method = p.method;
  settings.tolerance = p.tolerance;
  settings.stepsPerOutput = p.rk4StepsPerSample;
  const bool twisted = p.torsion.mu != 0.0;
  return IntegrateFrenet([&](double s) { return p.curvature.Evaluate(s, p.length); },
    twisted ? CurveFunction([&](double s) { return p.torsion.Evaluate(s, p.length); }) : CurveFunction(), start,
    UniformArcLengths(p.length, pieces), breakpoints, settings, frames);
}

std::string BuildSpaceCurveLeaf(const SpaceCurveParameters& p, const SpaceCurveMeshParameters& m, LeafGeometry& leaf)
{
  if (p.lobes != 1)
    return BuildPalmateLeaf(p, m, leaf);
  leaf = LeafGeometry();
  std::string error = ValidateSpaceCurveParameters(p, m);
  if (!error.empty())
    return error;
  const int n = m.resolution;
  std::vector<FrenetFrame> frames;
  error = IntegrateHalfMargin(p, n, frames);
  if (!error.empty())
    return "Curvature/Torsion: " + error;

  const Eigen::Vector3d base = frames.front().position;
  const Eigen::Vector3d chord = frames.back().position - base;
  const double chordLength = chord.norm();
  if (!(chordLength > 1e-9 * p.length))
    return "Curvature: the half-margin closes on itself (its end is its start); lower CurvatureMu";
  const Eigen::Vector3d c = chord / chordLength;
  Eigen::Vector3d g;
  if (!SymmetryNormal(c, p.opening, frames.front().tangent, g))
    return "Opening: no symmetry plane through the chord makes that angle with +Z; move Opening towards 0";

  // Both half-margins and the midvein, sample by sample.
  // Midvein sample i sits at i/n of the way along the chord (so it never folds back, even where a hooked margin
  // does) and takes the shape of the margin's projection onto the symmetry plane: that projection's offset from the
  // chord, stretched.
  std::vector<Eigen::Vector3d> own(n + 1), mirrored(n + 1), midvein(n + 1);
  for (int i = 0; i <= n; ++i)
  {
    const Eigen::Vector3d r = frames[i].position;
    own[i] = r;
    mirrored[i] = r - 2.0 * (r - base).dot(g) * g;
    const Eigen::Vector3d projected = r - (r - base).dot(g) * g;
    const Eigen::Vector3d offset = projected - (base + (projected - base).dot(c) * c);
    midvein[i] = base + (static_cast<double>(i) / n) * chord +
      p.midveinStretchXY * Eigen::Vector3d(offset.x(), offset.y(), 0.0) +
      p.midveinStretchZ * Eigen::Vector3d(0.0, 0.0, offset.z());
  }
  midvein.front() = base;
  midvein.back() = frames.back().position;
  mirrored.back() = frames.back().position;

  // Chord along +Y, base at the origin; the half-margin lying on -X is the left one.
  const Eigen::Matrix3d rotation = Eigen::Quaterniond::FromTwoVectors(c, Eigen::Vector3d::UnitY()).toRotationMatrix();
  double side = 0.0;
  for (int i = 0; i <= n; ++i)
  {
    own[i] = rotation * (own[i] - base);
    mirrored[i] = rotation * (mirrored[i] - base);
    midvein[i] = rotation * (midvein[i] - base);
    side += own[i].x() - midvein[i].x();
  }
  const std::vector<Eigen::Vector3d>& left = side < 0.0 ? own : mirrored;
  const std::vector<Eigen::Vector3d>& right = side < 0.0 ? mirrored : own;

  std::vector<double> v(n + 1, 0.0);
  for (int i = 1; i <= n; ++i)
    v[i] = v[i - 1] + (midvein[i] - midvein[i - 1]).norm();
  for (int i = 1; i <= n; ++i)
    v[i] /= v[n];
  v[n] = 1.0;

  // Vertices: the outline first (base, then left/midvein/right of every inner row, then the apex), so the Outline
  // port can take the blade's first points; the strip's inner points after them.
  std::vector<Eigen::Vector3d> points;
  BladeMesh& blade = leaf.blade;
  auto add = [&](const Eigen::Vector3d& x, double u, double vv, int region) {
    points.push_back(x);
    blade.uv.emplace_back(u, vv);
    blade.region.push_back(region);
    return static_cast<int>(points.size() - 1);
  };
  const int columns = m.columns;
  const int baseId = add(Eigen::Vector3d::Zero(), 0.0, 0.0, RegionMidvein);
  std::vector<std::vector<int>> rows(n + 1);
  rows[0].assign(2 * columns + 1, baseId);
  for (int i = 1; i < n; ++i)
  {
    rows[i].assign(2 * columns + 1, -1);
    rows[i][0] = add(left[i], -0.5, v[i], RegionMargin);
    rows[i][columns] = add(midvein[i], 0.0, v[i], RegionMidvein);
    rows[i][2 * columns] = add(right[i], 0.5, v[i], RegionMargin);
  }
  const int apexId = add(midvein[n], 0.0, 1.0, RegionMidvein);
  rows[n].assign(2 * columns + 1, apexId);
  for (int i = 1; i < n; ++i)
  {
    for (int j = 1; j < 2 * columns; ++j)
    {
      if (j == columns)
        continue;
      const bool leftHalf = j < columns;
      const double f = leftHalf ? static_cast<double>(j) / columns : static_cast<double>(j - columns) / columns;
      const Eigen::Vector3d x = leftHalf ? Eigen::Vector3d((1 - f) * left[i] + f * midvein[i])
                                         : Eigen::Vector3d((1 - f) * midvein[i] + f * right[i]);
      rows[i][j] = add(x, -0.5 + 0.5 * static_cast<double>(j) / columns, v[i], RegionBlade);
    }
  }

  // Triangles: fans at the base and apex, two per quad between inner rows; counter-clockwise seen from +Z when flat.
  for (int i = 0; i < n; ++i)
  {
    for (int j = 0; j < 2 * columns; ++j)
    {
      const int a = rows[i][j], b = rows[i][j + 1], c2 = rows[i + 1][j + 1], d = rows[i + 1][j];
      if (i == 0)
        blade.triangles.push_back({ a, c2, d });
      else if (i + 1 == n)
        blade.triangles.push_back({ a, b, c2 });
      else
      {
        blade.triangles.push_back({ a, b, c2 });
        blade.triangles.push_back({ a, c2, d });
      }
    }
  }

  leaf.leftMargin.push_back(baseId);
  leaf.rightMargin.push_back(baseId);
  leaf.midvein.push_back(baseId);
  for (int i = 1; i < n; ++i)
  {
    leaf.leftMargin.push_back(rows[i][0]);
    leaf.midvein.push_back(rows[i][columns]);
    leaf.rightMargin.push_back(rows[i][2 * columns]);
  }
  leaf.leftMargin.push_back(apexId);
  leaf.rightMargin.push_back(apexId);
  leaf.midvein.push_back(apexId);

  // A flat leaf whose margin hooks back across its own strip would fold: refuse it rather than output overlaps.
  const bool flat = p.torsion.mu == 0.0 && p.opening == 0.0;
  for (const auto& t : blade.triangles)
  {
    if (!flat)
      break;
    const Eigen::Vector3d e1 = points[t[1]] - points[t[0]], e2 = points[t[2]] - points[t[0]];
    if (!(e1.x() * e2.y() - e1.y() * e2.x() > 0.0))
    {
      leaf = LeafGeometry();
      return "Curvature: the margin hooks back across the blade, so the strips would overlap; lower CurvatureMu or "
             "move CurvatureLambda away from 1";
    }
  }
  for (const Eigen::Vector3d& x : points)
  {
    if (!x.allFinite())
    {
      leaf = LeafGeometry();
      return "Curvature/Torsion: the leaf has non-finite points";
    }
    blade.points.emplace_back(x.x(), x.y());
    leaf.z.push_back(x.z());
  }
  leaf.normals = VertexNormals(points, blade.triangles);
  leaf.tcoords = BoundingBoxTextureCoordinates(blade.points);
  return {};
}

} // namespace plantmorph
