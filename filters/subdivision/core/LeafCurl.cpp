// SPDX-License-Identifier: GPL-3.0-or-later
#include "LeafCurl.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RangeError.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace plantmorph
{
namespace
{
/// sin(x) / x, 1 at 0.
double Sinc(double x)
{
  return x == 0.0 ? 1.0 : std::sin(x) / x;
}

/// (1 - cos(x)) / x, 0 at 0 (written with sin^2 so small x keeps its digits).
double Versinc(double x)
{
  if (x == 0.0)
    return 0.0;
  const double s = std::sin(0.5 * x);
  return 2.0 * s * s / x;
}

void RangeError(std::ostringstream& message, const char* name, double value, const char* range)
{
  message << OutOfRange(name, value, range);
}

/// The bend of one coordinate pair (a along the bending direction, b the height) by a circle of curvature kappa
/// tangent to the a axis: arc length `s` from the bend's axis, height `h` above the reference surface. Adds the
/// displacement to (a, b). The normal (na, nb, nc; nc along the bend's axis) is multiplied by the cofactor matrix
/// of the Jacobian J = Rot(phi) * diag(1 - h*kappa, 1, 1), i.e. Rot(phi) * diag(1, 1 - h*kappa, 1 - h*kappa): the
/// inverse transpose up to the factor det J, so it stays defined (and keeps the faces' orientation) where a point
/// lies beyond the centre of curvature and the bend turns the surface inside out (1 - h*kappa <= 0).
void Bend(double s, double kappa, double h, double& a, double& b, double* na, double* nb, double* nc)
{
  const double phi = kappa * s;
  const double sinPhi = std::sin(phi);
  const double cosPhi = std::cos(phi);
  a += s * (Sinc(phi) - 1.0) - h * sinPhi;
  b += s * Versinc(phi) + h * (cosPhi - 1.0);
  if (na)
  {
    const double stretch = 1.0 - h * kappa; // the Jacobian's scale along the bent direction at height h
    const double ta = *na;
    const double tb = stretch * *nb;
    *na = cosPhi * ta - sinPhi * tb;
    *nb = sinPhi * ta + cosPhi * tb;
    *nc *= stretch;
  }
}
} // namespace

std::string ValidateLeafCurl(const LeafCurlParameters& parameters)
{
  std::ostringstream message;
  if (!(std::abs(parameters.longitudinalAngle) <= MaxCurlAngle))
    RangeError(message, "LongitudinalAngle", parameters.longitudinalAngle, "[-360, 360] degrees");
  else if (!(std::abs(parameters.transverseAngle) <= MaxCurlAngle))
    RangeError(message, "TransverseAngle", parameters.transverseAngle, "[-360, 360] degrees");
  else if (!(parameters.transverseCenter >= 0.0 && parameters.transverseCenter <= 1.0))
    RangeError(message, "TransverseCenter", parameters.transverseCenter, "[0, 1] (v of the mid-line)");
  return message.str();
}

void LeafCurl::Interpolate(const std::vector<MidveinSample>& samples, double key, double& a, double& b)
{
  auto upper = std::upper_bound(
    samples.begin(), samples.end(), key, [](double k, const MidveinSample& sample) { return k < sample.key; });
  if (upper == samples.begin())
  {
    a = samples.front().a;
    b = samples.front().b;
    return;
  }
  if (upper == samples.end())
  {
    a = samples.back().a;
    b = samples.back().b;
    return;
  }
  const MidveinSample& p = *(upper - 1);
  const MidveinSample& q = *upper;
  const double t = (key - p.key) / (q.key - p.key); // q.key > key >= p.key, so no division by zero
  a = p.a + t * (q.a - p.a);
  b = p.b + t * (q.b - p.b);
}

std::string LeafCurl::Setup(
  const LeafCurlParameters& parameters, std::size_t count, const double* xyz, const double* leafUV)
{
  *this = LeafCurl();
  std::string error = ValidateLeafCurl(parameters);
  if (!error.empty())
    return error;
  if (count == 0 || !xyz || !leafUV)
    return "the input has no points to curl";
  std::vector<MidveinSample> byY, byV;
  for (std::size_t i = 0; i < count; ++i)
  {
    const double* p = xyz + 3 * i;
    const double* uv = leafUV + 2 * i;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      std::ostringstream message;
      message << "input point " << i << " has a non-finite coordinate (" << p[0] << ", " << p[1] << ", " << p[2] << ")";
      return message.str();
    }
    if (!std::isfinite(uv[0]) || !std::isfinite(uv[1]))
    {
      std::ostringstream message;
      message << "input point " << i << " has a non-finite LeafUV (" << uv[0] << ", " << uv[1] << ")";
      return message.str();
    }
    if (std::abs(uv[0]) <= MidveinTolerance)
    {
      byY.push_back({ p[1], p[0], p[2] });
      byV.push_back({ uv[1], p[1], p[2] });
    }
  }
  if (byY.empty())
  {
    return "the input has no midvein point (LeafUV u = 0): LeafCurlFilter rolls the blade about its midvein and "
           "needs the LeafUV array a LeafOutlineSource blade carries";
  }
  const auto byKey = [](const MidveinSample& p, const MidveinSample& q) {
    return p.key < q.key || (p.key == q.key && (p.a < q.a || (p.a == q.a && p.b < q.b)));
  };
  std::sort(byY.begin(), byY.end(), byKey);
  std::sort(byV.begin(), byV.end(), byKey);

  this->Lateral.resize(count);
  this->MidveinZ.resize(count);
  for (std::size_t i = 0; i < count; ++i)
  {
    const double* p = xyz + 3 * i;
    double midX = 0.0, midZ = 0.0;
    Interpolate(byY, p[1], midX, midZ);
    const bool onMidvein = std::abs(leafUV[2 * i]) <= MidveinTolerance;
    const double d = onMidvein ? 0.0 : p[0] - midX;
    this->Lateral[i] = d;
    this->MidveinZ[i] = onMidvein ? p[2] : midZ;
    if (d < 0.0)
      this->WidthLeft = std::max(this->WidthLeft, -d);
    else
      this->WidthRight = std::max(this->WidthRight, d);
  }
  Interpolate(byV, parameters.transverseCenter, this->CenterY, this->CenterZ);
  for (std::size_t i = 0; i < count; ++i)
  {
    const double e = xyz[3 * i + 1] - this->CenterY;
    if (e < 0.0)
      this->LengthBase = std::max(this->LengthBase, -e);
    else
      this->LengthApex = std::max(this->LengthApex, e);
  }
  this->LongitudinalRadians = parameters.longitudinalAngle * Pi / 180.0;
  this->TransverseRadians = parameters.transverseAngle * Pi / 180.0;
  this->Longitudinal = parameters.longitudinalAngle != 0.0;
  this->Transverse = parameters.transverseAngle != 0.0;
  return {};
}

void LeafCurl::Map(std::size_t index, const double in[3], double out[3], double normal[3]) const
{
  out[0] = in[0];
  out[1] = in[1];
  out[2] = in[2];
  if (this->IsIdentity())
    return;
  if (this->Longitudinal)
  {
    const double d = this->Lateral[index];
    const double width = d < 0.0 ? this->WidthLeft : this->WidthRight;
    if (d != 0.0 && width > 0.0)
    {
      const double h = in[2] - this->MidveinZ[index];
      Bend(d, this->LongitudinalRadians / width, h, out[0], out[2], normal, normal ? normal + 2 : nullptr,
        normal ? normal + 1 : nullptr);
    }
  }
  if (this->Transverse)
  {
    const double e = in[1] - this->CenterY;
    const double length = e < 0.0 ? this->LengthBase : this->LengthApex;
    if (e != 0.0 && length > 0.0)
    {
      const double h = out[2] - this->CenterZ;
      Bend(e, this->TransverseRadians / length, h, out[1], out[2], normal ? normal + 1 : nullptr,
        normal ? normal + 2 : nullptr, normal);
    }
  }
  if (normal)
  {
    const double norm = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    if (norm > 0.0)
    {
      normal[0] /= norm;
      normal[1] /= norm;
      normal[2] /= norm;
    }
  }
}

std::string CurlLeaf(
  const LeafCurlParameters& parameters, std::size_t count, double* xyz, const double* leafUV, double* normals)
{
  LeafCurl curl;
  std::string error = curl.Setup(parameters, count, xyz, leafUV);
  if (!error.empty())
    return error;
  if (curl.IsIdentity())
    return {};
  for (std::size_t i = 0; i < count; ++i)
  {
    const double in[3] = { xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2] };
    curl.Map(i, in, xyz + 3 * i, normals ? normals + 3 * i : nullptr);
  }
  return {};
}

} // namespace plantmorph
