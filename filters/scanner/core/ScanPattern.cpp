// SPDX-License-Identifier: GPL-3.0-or-later
#include "ScanPattern.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RangeError.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace plantmorph
{

namespace
{
constexpr double Degree = Pi / 180.0;

Vec3 Sub(const Vec3& a, const Vec3& b)
{
  return { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
}
Vec3 Add(const Vec3& a, const Vec3& b)
{
  return { a[0] + b[0], a[1] + b[1], a[2] + b[2] };
}
Vec3 Scale(const Vec3& a, double s)
{
  return { s * a[0], s * a[1], s * a[2] };
}
double Dot(const Vec3& a, const Vec3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 Cross(const Vec3& a, const Vec3& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}
double Norm(const Vec3& a)
{
  return std::sqrt(Dot(a, a));
}
Vec3 Normalized(const Vec3& a)
{
  return Scale(a, 1.0 / Norm(a));
}
bool Finite(const Vec3& a)
{
  return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]);
}

/// An orthonormal frame looking along `forward` with `up` as near upwards as it can be (another axis when the two
/// are parallel).
ScannerPose Frame(const Vec3& origin, const Vec3& forward, const Vec3& up)
{
  ScannerPose pose;
  pose.origin = origin;
  pose.forward = Normalized(forward);
  Vec3 right = Cross(pose.forward, Normalized(up));
  if (Norm(right) < 1e-9)
  {
    const Vec3 other = std::abs(pose.forward[0]) < 0.9 ? Vec3{ 1.0, 0.0, 0.0 } : Vec3{ 0.0, 1.0, 0.0 };
    right = Cross(pose.forward, other);
  }
  pose.right = Normalized(right);
  pose.up = Cross(pose.right, pose.forward);
  return pose;
}

/// Rodrigues: `v` turned by `angle` about the unit `axis`.
Vec3 Rotate(const Vec3& v, const Vec3& axis, double angle)
{
  const double c = std::cos(angle), s = std::sin(angle);
  return Add(Add(Scale(v, c), Scale(Cross(axis, v), s)), Scale(axis, Dot(axis, v) * (1.0 - c)));
}

/// Beams over a field of `field` degrees `step` apart, centred; a full turn does not repeat its first beam.
std::uint64_t GridCount(double field, double step, bool fullTurnPossible)
{
  if (fullTurnPossible && field >= 360.0 - 1e-9)
    return static_cast<std::uint64_t>(std::max(1.0, std::floor(360.0 / step + 1e-9)));
  return static_cast<std::uint64_t>(std::floor(field / step + 1e-9)) + 1;
}

std::string Range(const char* name, double value, const char* range)
{
  return OutOfRange(name, value, range);
}
} // namespace

std::string BeamPattern::Setup(const ScannerParameters& p)
{
  this->Poses.clear();
  this->Path.clear();
  this->Azimuth0.clear();
  this->Elevation0.clear();
  this->AzimuthCos.clear();
  this->AzimuthSin.clear();
  this->ElevationCos.clear();
  this->ElevationSin.clear();
  this->PerPose = 0;
  this->Type = p.type;
  if (p.type != ScannerType::Terrestrial && p.type != ScannerType::Line && p.type != ScannerType::DepthCamera)
    return Range("ScannerType", static_cast<double>(static_cast<int>(p.type)), "0 Terrestrial, 1 Line, 2 Depth camera");
  if (p.positions.empty())
    return "Positions: give at least one scanner position (x, y, z)";
  for (std::size_t i = 0; i < p.positions.size(); ++i)
  {
    if (!Finite(p.positions[i]))
    {
      std::ostringstream s;
      s << "Positions: position " << i << " (" << p.positions[i][0] << ", " << p.positions[i][1] << ", "
        << p.positions[i][2] << ") is not finite";
      return s.str();
    }
  }
  if (!Finite(p.lookAt))
    return "LookAt: the point looked at must be finite";
  if (!Finite(p.up) || Norm(p.up) == 0.0)
    return "Up: the up direction must be finite and not zero";
  if (!(p.rangeNoise >= 0.0 && p.rangeNoise <= 1e6))
    return Range("RangeNoise", p.rangeNoise, "[0, 1e6]");
  if (!(p.angularJitter >= 0.0 && p.angularJitter <= 10.0))
    return Range("AngularJitter", p.angularJitter, "[0, 10] degrees");
  if (!(p.dropoutProbability >= 0.0 && p.dropoutProbability <= 1.0))
    return Range("DropoutProbability", p.dropoutProbability, "[0, 1]");
  if (!(p.maximumRange > 0.0 && p.maximumRange <= 1e30))
    return Range("MaximumRange", p.maximumRange, "(0, 1e30]");
  if (p.maximumBeams < 1 || p.maximumBeams > AbsoluteMaximumBeams)
    return Range("MaximumBeams", static_cast<double>(p.maximumBeams), "[1, 4e9]");
  std::string error;
  switch (p.type)
  {
    case ScannerType::Terrestrial:
      error = this->SetupTerrestrial(p);
      break;
    case ScannerType::DepthCamera:
      error = this->SetupDepthCamera(p);
      break;
    case ScannerType::Line:
      error = this->SetupLine(p);
      break;
  }
  if (!error.empty())
  {
    this->Poses.clear();
    this->PerPose = 0;
  }
  return error;
}

namespace
{
/// The beam budget, checked on the count alone (as a double: a product that would overflow is refused too).
std::string Budget(double beams, const ScannerParameters& p)
{
  if (beams > static_cast<double>(p.maximumBeams))
  {
    std::ostringstream s;
    s << std::fixed << std::setprecision(0) << "MaximumBeams: this set-up casts " << beams
      << " beams, more than MaximumBeams = " << p.maximumBeams
      << " (raise it up to 4e9, or coarsen AngularStep, Resolution, LineSpacing or TurntableSteps)";
    return s.str();
  }
  return {};
}

/// The point at arc length `s` along the polyline through `path` (its first point for s <= 0 or a single point).
Vec3 PointAlong(const std::vector<Vec3>& path, double s)
{
  for (std::size_t i = 1; i < path.size(); ++i)
  {
    const Vec3 d = Sub(path[i], path[i - 1]);
    const double l = Norm(d);
    if (s <= l || i + 1 == path.size())
      return l > 0.0 ? Add(path[i - 1], Scale(d, std::min(1.0, std::max(0.0, s / l)))) : path[i - 1];
    s -= l;
  }
  return path.front();
}

/// The viewing direction from `position` to LookAt, or an error naming the position.
std::string Towards(const ScannerParameters& p, std::size_t i, Vec3& forward)
{
  forward = Sub(p.lookAt, p.positions[i]);
  if (Norm(forward) == 0.0)
  {
    std::ostringstream s;
    s << "LookAt: it coincides with position " << i << "; the scanner needs a direction to look in";
    return s.str();
  }
  return {};
}
} // namespace

std::string BeamPattern::SetupTerrestrial(const ScannerParameters& p)
{
  if (!(p.horizontalFieldOfView > 0.0 && p.horizontalFieldOfView <= 360.0))
    return Range("HorizontalFieldOfView", p.horizontalFieldOfView, "(0, 360] degrees");
  if (!(p.verticalFieldOfView > 0.0 && p.verticalFieldOfView <= 180.0))
    return Range("VerticalFieldOfView", p.verticalFieldOfView, "(0, 180] degrees");
  if (!(p.angularStep >= 1e-4 && p.angularStep <= 90.0))
    return Range("AngularStep", p.angularStep, "[1e-4, 90] degrees");
  this->Columns = GridCount(p.horizontalFieldOfView, p.angularStep, true);
  this->Rows = GridCount(p.verticalFieldOfView, p.angularStep, false);
  const std::string over = Budget(
    static_cast<double>(this->Columns) * static_cast<double>(this->Rows) * static_cast<double>(p.positions.size()), p);
  if (!over.empty())
    return over;
  this->Step = p.angularStep * Degree;
  this->WorldZ = Normalized(p.up);
  const ScannerPose world = Frame(Vec3{ 0.0, 0.0, 0.0 }, this->WorldZ, Vec3{ 0.0, 1.0, 0.0 });
  this->WorldX = world.right;
  this->WorldY = Cross(this->WorldZ, this->WorldX);
  for (std::size_t i = 0; i < p.positions.size(); ++i)
  {
    Vec3 forward;
    const std::string error = Towards(p, i, forward);
    if (!error.empty())
      return error;
    forward = Normalized(forward);
    this->Poses.push_back(Frame(p.positions[i], forward, p.up));
    this->Azimuth0.push_back(std::atan2(Dot(forward, this->WorldY), Dot(forward, this->WorldX)));
    this->Elevation0.push_back(std::asin(std::max(-1.0, std::min(1.0, Dot(forward, this->WorldZ)))));
    for (std::uint64_t c = 0; c < this->Columns; ++c)
    {
      const double azimuth =
        this->Azimuth0.back() + (static_cast<double>(c) - 0.5 * static_cast<double>(this->Columns - 1)) * this->Step;
      this->AzimuthCos.push_back(std::cos(azimuth));
      this->AzimuthSin.push_back(std::sin(azimuth));
    }
    for (std::uint64_t r = 0; r < this->Rows; ++r)
    {
      const double elevation =
        this->Elevation0.back() + (static_cast<double>(r) - 0.5 * static_cast<double>(this->Rows - 1)) * this->Step;
      this->ElevationCos.push_back(std::cos(elevation));
      this->ElevationSin.push_back(std::sin(elevation));
    }
  }
  this->PerPose = this->Columns * this->Rows;
  return {};
}

std::string BeamPattern::SetupDepthCamera(const ScannerParameters& p)
{
  if (!(p.horizontalFieldOfView > 0.0 && p.horizontalFieldOfView < 180.0))
    return Range("HorizontalFieldOfView", p.horizontalFieldOfView, "(0, 180) degrees for a depth camera");
  if (!(p.verticalFieldOfView > 0.0 && p.verticalFieldOfView < 180.0))
    return Range("VerticalFieldOfView", p.verticalFieldOfView, "(0, 180) degrees for a depth camera");
  for (int k = 0; k < 2; ++k)
  {
    if (p.resolution[k] < 1 || p.resolution[k] > 100000)
      return Range(k == 0 ? "Resolution (width)" : "Resolution (height)", p.resolution[k], "[1, 100000] pixels");
  }
  this->Columns = static_cast<std::uint64_t>(p.resolution[0]);
  this->Rows = static_cast<std::uint64_t>(p.resolution[1]);
  const std::string over = Budget(
    static_cast<double>(this->Columns) * static_cast<double>(this->Rows) * static_cast<double>(p.positions.size()), p);
  if (!over.empty())
    return over;
  this->TanX = std::tan(0.5 * p.horizontalFieldOfView * Degree);
  this->TanY = std::tan(0.5 * p.verticalFieldOfView * Degree);
  for (std::size_t i = 0; i < p.positions.size(); ++i)
  {
    Vec3 forward;
    const std::string error = Towards(p, i, forward);
    if (!error.empty())
      return error;
    this->Poses.push_back(Frame(p.positions[i], forward, p.up));
  }
  this->PerPose = this->Columns * this->Rows;
  return {};
}

std::string BeamPattern::SetupLine(const ScannerParameters& p)
{
  if (!(p.verticalFieldOfView > 0.0 && p.verticalFieldOfView <= 180.0))
    return Range("VerticalFieldOfView", p.verticalFieldOfView, "(0, 180] degrees (the fan's opening)");
  if (!(p.angularStep >= 1e-4 && p.angularStep <= 90.0))
    return Range("AngularStep", p.angularStep, "[1e-4, 90] degrees");
  if (p.lineMotion != LineMotion::Path && p.lineMotion != LineMotion::Turntable)
    return Range("LineMotion", static_cast<double>(static_cast<int>(p.lineMotion)), "0 Path, 1 Turntable");
  this->Rows = GridCount(p.verticalFieldOfView, p.angularStep, false);
  this->Columns = 1;
  this->Step = p.angularStep * Degree;
  if (p.lineMotion == LineMotion::Turntable)
  {
    if (p.turntableSteps < 1 || p.turntableSteps > 1000000)
      return Range("TurntableSteps", p.turntableSteps, "[1, 1e6]");
    if (!Finite(p.turntableAxis) || Norm(p.turntableAxis) == 0.0)
      return "TurntableAxis: the turntable's axis must be finite and not zero";
    const std::string over =
      Budget(static_cast<double>(this->Rows) * p.turntableSteps * static_cast<double>(p.positions.size()), p);
    if (!over.empty())
      return over;
    const Vec3 axis = Normalized(p.turntableAxis);
    for (std::size_t i = 0; i < p.positions.size(); ++i)
    {
      Vec3 forward;
      const std::string error = Towards(p, i, forward);
      if (!error.empty())
        return error;
      const ScannerPose start = Frame(p.positions[i], forward, p.up);
      for (int s = 0; s < p.turntableSteps; ++s)
      {
        // The object turns by +angle: in its frame the scanner turns by -angle about the axis through LookAt.
        const double angle = -2.0 * Pi * s / p.turntableSteps;
        ScannerPose pose;
        pose.origin = Add(p.lookAt, Rotate(Sub(start.origin, p.lookAt), axis, angle));
        pose.forward = Rotate(start.forward, axis, angle);
        pose.right = Rotate(start.right, axis, angle);
        pose.up = Rotate(start.up, axis, angle);
        this->Poses.push_back(pose);
      }
    }
  }
  else
  {
    if (!(p.lineSpacing > 0.0 && std::isfinite(p.lineSpacing)))
      return Range("LineSpacing", p.lineSpacing, "(0, inf) model units");
    double length = 0.0;
    for (std::size_t i = 1; i < p.positions.size(); ++i)
      length += Norm(Sub(p.positions[i], p.positions[i - 1]));
    // Every fan looks in the direction from the middle of the path to LookAt: the middle fan looks at LookAt and
    // the strip the fans sweep is centred on it.
    const Vec3 middle = PointAlong(p.positions, 0.5 * length);
    const Vec3 forward = Sub(p.lookAt, middle);
    if (Norm(forward) == 0.0)
      return "LookAt: it coincides with the middle of the path; the line scanner needs a direction to look in";
    const double fans = std::floor(length / p.lineSpacing + 1e-9) + 1.0;
    const std::string over = Budget(fans * static_cast<double>(this->Rows), p);
    if (!over.empty())
      return over;
    const ScannerPose start = Frame(p.positions[0], forward, p.up);
    this->Path = p.positions;
    std::size_t segment = 0;
    double segmentStart = 0.0;
    for (std::uint64_t k = 0; k < static_cast<std::uint64_t>(fans); ++k)
    {
      const double s = std::min(length, static_cast<double>(k) * p.lineSpacing);
      while (segment + 2 < p.positions.size() &&
        segmentStart + Norm(Sub(p.positions[segment + 1], p.positions[segment])) < s)
      {
        segmentStart += Norm(Sub(p.positions[segment + 1], p.positions[segment]));
        ++segment;
      }
      ScannerPose pose = start;
      if (p.positions.size() > 1)
      {
        const Vec3 d = Sub(p.positions[segment + 1], p.positions[segment]);
        const double l = Norm(d);
        const double f = l > 0.0 ? std::min(1.0, std::max(0.0, (s - segmentStart) / l)) : 0.0;
        pose.origin = Add(p.positions[segment], Scale(d, f));
      }
      this->Poses.push_back(pose);
    }
  }
  this->PerPose = this->Rows;
  return {};
}

void BeamPattern::Beam(std::uint64_t index, double origin[3], double direction[3], std::int64_t& pose) const
{
  this->Beams(index, 1, origin, direction, &pose);
}

void BeamPattern::Beams(
  std::uint64_t first, std::size_t count, double* origins, double* directions, std::int64_t* poses) const
{
  if (count == 0)
    return;
  std::uint64_t pose = first / this->PerPose;
  const std::uint64_t local = first % this->PerPose;
  std::uint64_t row = local / this->Columns, column = local % this->Columns;
  for (std::size_t i = 0; i < count; ++i)
  {
    const ScannerPose& frame = this->Poses[pose];
    poses[i] = static_cast<std::int64_t>(pose);
    for (int k = 0; k < 3; ++k)
      origins[3 * i + k] = frame.origin[k];
    this->Direction(pose, row, column, directions + 3 * i);
    if (++column == this->Columns) // the next beam: row-major within a pose
    {
      column = 0;
      if (++row == this->Rows)
      {
        row = 0;
        ++pose;
      }
    }
  }
}

void BeamPattern::Direction(std::uint64_t poseIndex, std::uint64_t row, std::uint64_t column, double direction[3]) const
{
  const ScannerPose& frame = this->Poses[poseIndex];
  Vec3 d;
  switch (this->Type)
  {
    case ScannerType::Terrestrial:
    {
      const std::size_t a = static_cast<std::size_t>(poseIndex * this->Columns + column);
      const std::size_t e = static_cast<std::size_t>(poseIndex * this->Rows + row);
      const double c = this->ElevationCos[e];
      d = Add(Add(Scale(this->WorldX, c * this->AzimuthCos[a]), Scale(this->WorldY, c * this->AzimuthSin[a])),
        Scale(this->WorldZ, this->ElevationSin[e]));
      break;
    }
    case ScannerType::DepthCamera:
    {
      const double x =
        (2.0 * (static_cast<double>(column) + 0.5) / static_cast<double>(this->Columns) - 1.0) * this->TanX;
      const double y = (1.0 - 2.0 * (static_cast<double>(row) + 0.5) / static_cast<double>(this->Rows)) * this->TanY;
      d = Normalized(Add(frame.forward, Add(Scale(frame.right, x), Scale(frame.up, y))));
      break;
    }
    case ScannerType::Line:
    {
      const double angle = (static_cast<double>(row) - 0.5 * static_cast<double>(this->Rows - 1)) * this->Step;
      d = Add(Scale(frame.forward, std::cos(angle)), Scale(frame.up, std::sin(angle)));
      break;
    }
  }
  for (int k = 0; k < 3; ++k)
    direction[k] = d[k];
}

void BeamPattern::SetupLines(
  double length, std::size_t maxPoses, std::vector<double>& segments, std::vector<std::int64_t>& pose) const
{
  segments.clear();
  pose.clear();
  auto add = [&](const Vec3& a, const Vec3& b, std::int64_t id) {
    segments.insert(segments.end(), { a[0], a[1], a[2], b[0], b[1], b[2] });
    pose.push_back(id);
  };
  for (std::size_t i = 1; i < this->Path.size(); ++i)
    add(this->Path[i - 1], this->Path[i], -1);
  const std::size_t poses = this->Poses.size();
  if (poses == 0 || this->PerPose == 0 || maxPoses == 0)
    return;
  const std::size_t shown = std::min(poses, maxPoses);
  const std::uint64_t last = this->PerPose - 1;
  // A fan (one column) has two ends, a grid four corners.
  std::vector<std::uint64_t> corners{ 0, last };
  if (this->Columns > 1)
    corners = { 0, this->Columns - 1, last - (this->Columns - 1), last };
  for (std::size_t j = 0; j < shown; ++j)
  {
    const std::size_t i = shown == 1 ? 0 : j * (poses - 1) / (shown - 1);
    const ScannerPose& frame = this->Poses[i];
    add(frame.origin, Add(frame.origin, Scale(frame.forward, length)), static_cast<std::int64_t>(i));
    for (std::uint64_t corner : corners)
    {
      double o[3], d[3];
      std::int64_t id;
      this->Beam(static_cast<std::uint64_t>(i) * this->PerPose + corner, o, d, id);
      add(frame.origin, Add(frame.origin, Scale(Vec3{ d[0], d[1], d[2] }, length)), static_cast<std::int64_t>(i));
    }
  }
}

} // namespace plantmorph
