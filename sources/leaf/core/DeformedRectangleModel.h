// SPDX-License-Identifier: GPL-3.0-or-later
// Model A of LeafOutlineSource: the deformed rectangle of paper 000, sec. 1, eq. (1).
//
// A leaf is the image of the rectangle u in [-0.5, 0.5], v in [0, 1] under
//
//   x = a_x*u + sum_k X_k(u, v) + Bending*b_y*v^2
//   y = b_y*v + sum_k Y_k(u, v)
//
// with every term  Amplitude * Scale * m(u, v) * sin(Frequency*pi*w + Phase),  Scale one of a_x (Width) or b_y
// (Length), m one of 1, u, v, u*v and w one of u, v. Eq. (1) needs the scale as a separate choice (its x term is
// scaled by b_y), so a term has seven numbers, not six (docs/methods/leaf-outline.md):
//
//   [Target (0 = x, 1 = y), Scale (0 = Width a_x, 1 = Length b_y), Amplitude,
//    Multiplier (0 = 1, 1 = u, 2 = v, 3 = u*v), Frequency, Variable (0 = u, 1 = v), Phase (radians)]
//
// Asymmetry alpha in (-1, 1) widens the right half and narrows the left one smoothly:
//   x <- x_mid(v) + (1 + alpha*sin(pi*u)) * (x - x_mid(v)),   x_mid(v) = x(0, v),
// which keeps the midvein u = 0 where it was. The map is finally translated so that the midvein's base (u, v) =
// (0, 0) is at the origin, as every PlantMorph leaf is.
//
// Plain C++ (Eigen), no VTK: unit-tested directly.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace plantmorph
{

struct SinusoidTerm
{
  enum Target : int
  {
    X = 0,
    Y = 1
  };
  enum Scale : int
  {
    Width = 0,
    Length = 1
  };
  enum Multiplier : int
  {
    One = 0,
    U = 1,
    V = 2,
    UV = 3
  };
  enum Variable : int
  {
    VariableU = 0,
    VariableV = 1
  };

  Target target = X;
  Scale scale = Width;
  double amplitude = 0.0;
  Multiplier multiplier = One;
  double frequency = 0.0;
  Variable variable = VariableU;
  double phase = 0.0;
};

/// Numbers per term in the flat representation used by the `Terms` property.
inline constexpr int TermColumns = 7;

struct DeformedRectangleParameters
{
  double width = 1.1;  ///< a_x, the initial rectangle's width (model units, cm in the presets)
  double length = 1.0; ///< b_y, the initial rectangle's height
  double bending = 0.0;
  double asymmetry = 0.0;
  std::vector<SinusoidTerm> terms;
};

/// Parses a flat list of 7-number rows into terms. Returns an empty string on success, else a message naming the
/// offending row and column and the accepted values.
std::string ParseTerms(const std::vector<double>& flat, std::vector<SinusoidTerm>& terms);
std::vector<double> FlattenTerms(const std::vector<SinusoidTerm>& terms);

/// Checks every parameter (finite, in range). Empty string: valid. Otherwise a message that names the property and
/// its accepted range.
std::string Validate(const DeformedRectangleParameters& parameters);

/// The blade's length from base to apex: |x(0, 1) - x(0, 0)|, the chord of the midvein u = 0. Parameters must
/// have passed Validate().
double BladeLength(const DeformedRectangleParameters& parameters);

/// Scales a_x and b_y by one factor so the blade is `length` long from base to apex (BladeLength). Every term is
/// proportional to a_x or b_y, so the leaf stays similar: the same shape at another size. Parameters must have passed
/// Validate(). Empty string, or a message when the apex falls onto the base (nothing to scale).
std::string ScaleToBladeLength(DeformedRectangleParameters& parameters, double length);

class DeformedRectangleModel
{
public:
  /// The parameters must have passed Validate().
  explicit DeformedRectangleModel(DeformedRectangleParameters parameters);

  const DeformedRectangleParameters& Parameters() const { return this->Params; }

  /// The leaf point of (u, v), base translated to the origin.
  Eigen::Vector2d Evaluate(double u, double v) const;
  /// d(x, y)/d(u, v): column 0 is d/du, column 1 is d/dv.
  Eigen::Matrix2d Jacobian(double u, double v) const;
  /// Newton's method for the (u, v) with Evaluate(u, v) = point, started at guess and kept inside the rectangle.
  /// Returns false (leaving the best iterate in uv) when it does not converge to 1e-10 of the leaf's size.
  bool Invert(const Eigen::Vector2d& point, const Eigen::Vector2d& guess, Eigen::Vector2d& uv) const;

  /// A length that measures the leaf (max of a_x, b_y): tolerances are relative to it.
  double Size() const;

private:
  Eigen::Vector2d EvaluateUntranslated(double u, double v) const;
  /// Value and derivatives of the sum of all terms of one target, before asymmetry.
  void SumTerms(SinusoidTerm::Target target, double u, double v, double& value, double& du, double& dv) const;

  DeformedRectangleParameters Params;
  Eigen::Vector2d Base;
};

} // namespace plantmorph
