// SPDX-License-Identifier: GPL-3.0-or-later
// The scanner models of docs/methods/virtual-scanner.md as beam generators: a pattern knows how many beams it casts and, for any beam
// index, the beam's origin, unit direction and pose (the ScanPosition it reports), without storing the beams, so
// any thread can make any beam and the scan's output does not depend on how the beams are shared out.
//
// Terrestrial: per position, a spherical azimuth/elevation grid (AngularStep apart, HorizontalFieldOfView by
//   VerticalFieldOfView, centred on the direction to LookAt; azimuth about Up, elevation from the plane normal to
//   Up). Beam order: position, elevation row (lowest first), azimuth (increasing).
// Depth camera: per position, a pinhole looking at LookAt with Up upwards, Resolution[0] x Resolution[1] pixels over
//   the two fields of view, one beam through each pixel centre. Beam order: position, row (top first), column.
// Line, path: a fan of beams (AngularStep apart over VerticalFieldOfView, in the plane of the viewing direction and
//   Up) moved along the polyline through Positions, one fan every LineSpacing of arc length; every fan looks in the
//   direction from the middle of the path (half its arc length) to LookAt, so the middle fan looks at LookAt and the
//   swept strip is centred on it (a fan looking at the fixed point from every origin would, spanning Up, sweep the
//   one line through LookAt along Up). Pose: the fan's index along the path.
// Line, turntable: the object turns about the axis TurntableAxis through LookAt, TurntableSteps times a full turn;
//   as the points are reported in the object's frame, the scanner (a fan at each position looking at LookAt) turns
//   the other way. Pose: position * TurntableSteps + step.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace plantmorph
{

enum class ScannerType
{
  Terrestrial = 0,
  Line = 1,
  DepthCamera = 2
};

enum class LineMotion
{
  Path = 0,
  Turntable = 1
};

using Vec3 = std::array<double, 3>;

/// Every property of the scan (the VTK layer's properties, one to one). Angles in degrees, lengths in model units.
struct ScannerParameters
{
  ScannerType type = ScannerType::Terrestrial;
  std::vector<Vec3> positions{ Vec3{ 0.0, -5.0, 1.0 } };
  Vec3 lookAt{ 0.0, 0.0, 0.0 };
  Vec3 up{ 0.0, 0.0, 1.0 };
  double horizontalFieldOfView = 60.0;
  double verticalFieldOfView = 40.0;
  double angularStep = 0.2;
  int resolution[2] = { 640, 480 };
  LineMotion lineMotion = LineMotion::Path;
  double lineSpacing = 0.01;
  int turntableSteps = 360;
  Vec3 turntableAxis{ 0.0, 0.0, 1.0 };
  double rangeNoise = 0.0;    ///< standard deviation of the range, model units
  double angularJitter = 0.0; ///< standard deviation of each beam's direction (two axes), degrees
  double dropoutProbability = 0.0;
  double maximumRange = 1000.0;
  bool intensityFalloff = true; ///< Intensity = cos(incidence) / range^2; cos(incidence) alone when false
  std::uint64_t seed = 0;
  std::uint64_t maximumBeams = 50000000;
};

/// One scanner pose: where the beams start and the frame they are aimed in.
struct ScannerPose
{
  Vec3 origin;
  Vec3 forward, right, up; // orthonormal
};

class BeamPattern
{
public:
  /// Checks every parameter (the error names the property and its accepted range) and counts the beams; an
  /// empty string on success. Nothing is allocated per beam, so a count over the budget is cheap to refuse.
  std::string Setup(const ScannerParameters& parameters);

  std::uint64_t BeamCount() const { return this->Poses.size() * this->PerPose; }
  std::uint64_t PoseCount() const { return this->Poses.size(); }
  std::uint64_t BeamsPerPose() const { return this->PerPose; }
  const ScannerPose& Pose(std::size_t i) const { return this->Poses[i]; }

  /// Beam `index` (< BeamCount()): its origin, unit direction and pose index.
  void Beam(std::uint64_t index, double origin[3], double direction[3], std::int64_t& pose) const;
  /// Beams first .. first + count - 1 (< BeamCount()), exactly as Beam gives them, x y z each in `origins` and
  /// `directions`, their poses in `poses`: the pose, row and column are divided out once, not per beam.
  void Beams(std::uint64_t first, std::size_t count, double* origins, double* directions, std::int64_t* poses) const;

  /// The scanner set-up to draw: for each pose (at most `maxPoses`, spread evenly) the beams at the corners of its
  /// field (the two ends of a line scanner's fan) and its central beam, each `length` long, as segments (x0 y0 z0 x1 y1 z1) with their pose, and for a
  /// line scanner on a path the path itself (pose -1).
  void SetupLines(
    double length, std::size_t maxPoses, std::vector<double>& segments, std::vector<std::int64_t>& pose) const;

private:
  /// The direction of the beam at (row, column) of pose `pose`.
  void Direction(std::uint64_t pose, std::uint64_t row, std::uint64_t column, double direction[3]) const;
  ScannerType Type = ScannerType::Terrestrial;
  std::vector<ScannerPose> Poses;
  std::vector<Vec3> Path;
  std::uint64_t PerPose = 0;
  // Terrestrial: azimuth and elevation grid, radians; world frame (x, y horizontal, z = Up).
  std::uint64_t Columns = 0, Rows = 0;
  double Step = 0.0;
  Vec3 WorldX{}, WorldY{}, WorldZ{};
  std::vector<double> Azimuth0, Elevation0; // per pose
  // Terrestrial: per pose, cos and sin of each column's azimuth and each row's elevation (the same expressions as
  // per beam, evaluated once), so a beam costs no trigonometry.
  std::vector<double> AzimuthCos, AzimuthSin, ElevationCos, ElevationSin;
  // Depth camera: half-extents of the image plane at distance 1.
  double TanX = 0.0, TanY = 0.0;
  std::string SetupTerrestrial(const ScannerParameters& p);
  std::string SetupDepthCamera(const ScannerParameters& p);
  std::string SetupLine(const ScannerParameters& p);
};

/// The largest beam count Setup accepts whatever MaximumBeams says (a hard guard against a mistyped step).
constexpr std::uint64_t AbsoluteMaximumBeams = 4000000000ull;

} // namespace plantmorph
