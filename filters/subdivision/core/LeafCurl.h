// SPDX-License-Identifier: GPL-3.0-or-later
// LeafCurlFilter's algorithm (docs/methods/subdivision-and-curl.md; paper 003 sec. 3, Fig. 7): longitudinal curl, the
// two halves rolling about the midvein, and transverse curl, the apex and base parts bending about the blade's
// mid-line, both as isometric bending. Plain C++17, no VTK: it works on flat arrays and is unit-tested directly.
//
// The flat blade. The input's x and y are taken as the flat blade (data contract: XY plane, base at the origin,
// midvein along +Y); the midvein is the set of points whose LeafUV u is 0 (|u| <= MidveinTolerance). From them, by
// linear interpolation in y, come the midvein's x_mid(y) and height z_mid(y), and, by interpolation in v, the
// height y_c of the mid-line, the line across the blade at v = TransverseCenter.
//
// Longitudinal curl. A point's signed lateral distance is measured, d = x - x_mid(y) (negative on the left half),
// not derived from LeafUV u: that keeps the bending exactly isometric. Each half gets ONE radius,
// R = W / angle, W the half's half-width (the largest |d| on that side, the widest point of its margin); the point
// goes to arc length d along the circle of radius R tangent to the blade at the midvein:
//     x' = x_mid + d * sin(phi) / phi,   z' = z_mid + d * (1 - cos(phi)) / phi,   phi = angle * d / W,
// so the margin's tangent at the widest row turns through exactly `angle` (positive rolls the halves up, +Z) and
// narrower rows turn through less, lying on the same cylinder. Because R does not change along the blade the map
// is a cylinder wrap: every length on a flat blade with a straight midvein is preserved exactly (edges, being
// chords, shorten by about (l/R)^2/24). A bent midvein (x_mid varying with y) is followed point by point, which
// strains lengths by about |dx_mid/dy| * (1 - cos(phi)). At 180 degrees the widest row of each half is a half circle,
// its margin at straight-line distance 2W/pi from the midvein. Midvein points (d = 0) never move.
//
// Transverse curl: the same construction along the blade, about the mid-line y = y_c: e = y - y_c, one radius for
// the apex part (length L = the largest e) and one for the base part (the largest -e), psi = angle * e / L; a
// positive angle bends both ends up (+Z). Applied after the longitudinal curl (as documented) to the curled points.
//
// Non-flat input (a space-curve leaf with torsion, or a leaf already curled). Each curl is a bend of space (Barr's
// global bending): the point's height above the reference (h = z - z_mid(y) for the longitudinal curl, h = z - z_c
// for the transverse one, z_c the midvein's height at the mid-line) is carried along the bent surface's normal,
// P = C(d) + h * N(d). On a flat blade h = 0 and this is the arc above; relief and an earlier curl ride along. Each
// curl alone is isometric on a flat blade; both together bend the blade in two directions, which no isometry can
// (users ask for the combination anyway): then the transverse bend stretches or compresses the rolled halves
// by the factor (1 - h * angle / L).
//
// Combined curls can fold: where a rolled half rises above the mid-line by more than the transverse radius
// L / TransverseAngle (large angles on both), the transverse bend passes the centre of curvature and turns that part
// inside out. Nothing stops it (the user asked for it); the normals stay consistent with the faces there.
//
// Normals (optional): transformed with the cofactor matrix of each bend's Jacobian (the inverse transpose up to the
// determinant), i.e. rotated by phi (psi) and, off the reference surface, rescaled across the bending direction,
// then normalised. Exact for a flat blade; consistent with the faces' orientation even where a combined curl folds.
//
// Angle 0 skips its curl: both angles 0 give bit-identical points and normals.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace plantmorph
{

struct LeafCurlParameters
{
  double longitudinalAngle = 90.0; ///< degrees the margin's tangent turns through, [-360, 360]; + rolls up (+Z)
  double transverseAngle = 0.0;    ///< degrees the apex's (and the base's) tangent turns through, [-360, 360]
  double transverseCenter = 0.5;   ///< v of the mid-line the transverse curl bends about, [0, 1]
};

inline constexpr double MaxCurlAngle = 360.0;
/// |LeafUV u| up to this marks a midvein point.
inline constexpr double MidveinTolerance = 1e-9;

/// Empty when every parameter is finite and in its range; otherwise a message naming the property and the range.
std::string ValidateLeafCurl(const LeafCurlParameters& parameters);

/// The curl of one blade: Setup() measures the blade (midvein, half-widths, mid-line), then Map() moves any point
/// (thread-safe, so callers may run it in parallel over the points).
class LeafCurl
{
public:
  /// `xyz`: 3 * count coordinates; `leafUV`: 2 * count (u, v). Returns an empty string on success; otherwise a
  /// message (bad parameters, no points, a non-finite coordinate or LeafUV, no midvein point) and the object is
  /// not usable.
  std::string Setup(const LeafCurlParameters& parameters, std::size_t count, const double* xyz, const double* leafUV);

  /// True when both angles are 0: Map() would return every point and normal unchanged.
  bool IsIdentity() const { return !this->Longitudinal && !this->Transverse; }

  /// Point `index` of the blade given to Setup, at `in` (its coordinates there), moved to `out`. When `normal` is
  /// not null, the normal at the point is transformed in place (and normalised; a zero normal stays zero).
  void Map(std::size_t index, const double in[3], double out[3], double normal[3] = nullptr) const;

  ///@{
  /// What Setup measured (for tests and field data).
  double LeftHalfWidth() const { return this->WidthLeft; }
  double RightHalfWidth() const { return this->WidthRight; }
  double BaseLength() const { return this->LengthBase; }
  double ApexLength() const { return this->LengthApex; }
  double MidLineY() const { return this->CenterY; }
  double LateralDistance(std::size_t index) const { return this->Lateral[index]; }
  ///@}

private:
  struct MidveinSample
  {
    double key; // y, or v
    double a;   // x, or y
    double b;   // z
  };
  static void Interpolate(const std::vector<MidveinSample>& samples, double key, double& a, double& b);

  bool Longitudinal = false;
  bool Transverse = false;
  double LongitudinalRadians = 0.0;
  double TransverseRadians = 0.0;
  double WidthLeft = 0.0;
  double WidthRight = 0.0;
  double LengthBase = 0.0;
  double LengthApex = 0.0;
  double CenterY = 0.0;
  double CenterZ = 0.0;
  std::vector<double> Lateral;  // d per point
  std::vector<double> MidveinZ; // z_mid(y) per point
};

/// Convenience for tests and serial callers: curls `xyz` (3 * count) in place, and `normals` (3 * count) when not
/// null. Returns Setup's error (and leaves the arrays untouched) or an empty string.
std::string CurlLeaf(const LeafCurlParameters& parameters, std::size_t count, double* xyz, const double* leafUV,
  double* normals = nullptr);

} // namespace plantmorph
