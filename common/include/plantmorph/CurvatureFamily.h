// SPDX-License-Identifier: GPL-3.0-or-later
// Curvature and torsion functions of paper 002 (eqs. (4)-(8), (10); docs/methods/leaf-outline.md), each a function of
// arc length s on [0, S] with one peak.
//
// The peak is given as an integral-like constant mu = S * h (the paper's mu for curvature, eta for torsion), not as
// h itself: with mu held fixed, every family but the exponential one is phi(s) = (1/S) * g(s/S), so growing S gives an
// exact scaled copy of the curve (the paper's similarity theorem). The exponential family keeps b1 and u3 (its
// values at s = 0 and s = S) fixed instead, so its shape changes as S grows: the paper's phototropism (Fig. 3).
//
//   Constant      phi = mu / S
//   Triangular    eq. (4): rises linearly to h at lambda*S, falls linearly to 0 at S
//   Power         eqs. (5)/(6): h*(s/(lambda S))^n1 before the peak, h*((S - s)/((1 - lambda) S))^n2 after (the
//                 paper prints (s - S)^n2; its base is negative there, so |S - s| is used)
//   Exponential   eq. (7): b1*exp(b2 s) before lambda*S, b3*exp(-b4 s) after; phi(0) = b1, phi(lambda S) = h,
//                 phi(S) = u3 (b1 is ignored when lambda = 0, u3 when lambda = 1)
//   NotchedApex   eq. (8), the "duck tongue": a triangle of peak h on [0, S4] then a triangle of peak u4 = h/beta on
//                 [S4, (1 + alpha4) S4], peaked at lambda2 of the way; S = (1 + alpha4) S4. A negative beta makes u4
//                 negative (allowed where the positive notch does not show: docs/methods/leaf-outline.md).
#pragma once

#include <string>
#include <vector>

namespace plantmorph
{

struct CurvatureFamily
{
  enum Type : int
  {
    Constant = 0,
    Triangular = 1,
    Power = 2,
    Exponential = 3,
    NotchedApex = 4,
  };

  Type type = Triangular;
  double mu = 2.0;      ///< S * h: peak value times the curve length
  double lambda = 0.7;  ///< where the peak is, as a fraction of S (NotchedApex: of S4, for the first triangle)
  double n1 = 1.0;      ///< Power: exponent before the peak
  double n2 = 1.0;      ///< Power: exponent after the peak
  double b1 = 0.001;    ///< Exponential: value at s = 0
  double u3 = 0.001;    ///< Exponential: value at s = S
  double beta = 2.0;    ///< NotchedApex: h / u4, |beta| > 1
  double alpha4 = 0.3;  ///< NotchedApex: length of the notch piece as a fraction of S4, in (0, 1)
  double lambda2 = 0.5; ///< NotchedApex: where the notch piece peaks, as a fraction of it

  /// Empty when the parameters are valid for a curve of length S; otherwise a message that names the parameter (with
  /// `name` in front, e.g. "Curvature") and its accepted range.
  std::string Validate(double length, const std::string& name) const;

  /// The function's value at arc length s of a curve of length S (parameters must be valid).
  double Evaluate(double s, double length) const;

  /// Arc lengths in (0, S) where the function is not smooth (integrators step exactly onto them).
  std::vector<double> Breakpoints(double length) const;
};

} // namespace plantmorph
