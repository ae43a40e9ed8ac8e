// SPDX-License-Identifier: GPL-3.0-or-later
// Interpolating cubic B-spline curves in 2-D and 3-D (docs/methods/leaf-outline.md, paper 003 sec. 2.1: leaf margins
// and midveins; also sketched strokes). The curve passes THROUGH its control points Q_0..Q_{n-1}; the B-spline's own
// control polygon is called the de Boor points P_j here, to keep the two apart.
//
// Choices:
// - Parameters: chord length, t_0 = 0, t_k - t_{k-1} proportional to |Q_k - Q_{k-1}|, t_{n-1} = 1 (or given ones).
// - End conditions: not-a-knot (de Boor, "A Practical Guide to Splines", ch. IV; MATLAB's `spline`). With clamped
//   cubic knots placed at every parameter, n points give n + 2 unknowns and need two end conditions. Instead of adding
//   two equations, not-a-knot removes the two knots t_1 and t_{n-2}:
//     knots = [0, 0, 0, 0, t_2, ..., t_{n-3}, 1, 1, 1, 1],  n de Boor points,  n equations C(t_k) = Q_k.
//   The curve is C2 at every knot t_2..t_{n-3} and C3 at t_1 and t_{n-2}. Natural ends (C'' = 0) were rejected: they
//   force zero curvature at the leaf's base and apex and cut the accuracy there to O(h^2); not-a-knot keeps O(h^4)
//   up to the ends (chordal cubic splines are fourth order, M. Floater 2006; the tests measure it) and reproduces any
//   cubic polynomial curve exactly, given its parameters. n = 4 is a single cubic piece, n = 3 the parabola through
//   the points and n = 2 the straight segment with uniform speed, both written as a cubic (4 de Boor points, no
//   interior knot).
// - Solve: the collocation matrix has at most 4 non-zeros a row (banded, totally positive); Eigen's SparseLU solves
//   it for all coordinates at once in O(n). The end de Boor points are set to Q_0 and Q_{n-1} exactly, so
//   Evaluate(0) and Evaluate(1) return the first and last points bit for bit (margins share them with the midvein).
// - Evaluation: knot span by binary search, then de Boor's algorithm on the de Boor points (value) and on the
//   precomputed derivative control polygons (first and second derivatives): O(log n) a call. t is clamped to [0, 1].
// - Arc length: a table of adaptive 5-point Gauss-Legendre pieces (relative accuracy 1e-12) inside each polynomial
//   piece, integrating |C'| in the piece's local parameter, built with the curve; arc length at t and its inverse
//   (safeguarded Newton) are then O(log n). Building the curve is O(n): about 25 ms for 10^4 points.
// - Dimension: a template on Dim (2 or 3, instantiated in the source); points are Eigen fixed-size vectors, so a 2-D
//   margin stays 2-D. C++17 aligned new makes std::vector<Eigen::Vector2d> safe without Eigen::aligned_allocator.
//
// A curve is immutable once built; every const member is thread safe. Plain C++ (Eigen), no VTK.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace plantmorph
{

template <int Dim>
class CubicBSpline
{
  static_assert(Dim == 2 || Dim == 3, "CubicBSpline: Dim must be 2 or 3");

public:
  using Point = Eigen::Matrix<double, Dim, 1>;
  using PointList = std::vector<Point>;

  /// Two consecutive parameters (and so two consecutive points, relative to the control polygon's length) must be at
  /// least this far apart.
  static constexpr double MinParameterGap = 1e-12;

  /// An empty curve (Empty() is true, Evaluate returns NaN). Build real ones with Interpolate.
  CubicBSpline() = default;

  /// The curve through `points` with chord-length parameters. Returns an empty string on success; otherwise a message
  /// naming the offending input and what is accepted, and `curve` is empty. Accepted: at least 2 points, finite
  /// coordinates, a control polygon (sum of |Q_k - Q_{k-1}|) of length in [1e-100, 1e100], and consecutive points
  /// distinct: at least MinParameterGap times that length apart. `points` may be curve.ControlPoints().
  static std::string Interpolate(const PointList& points, CubicBSpline& curve);
  /// As above with the parameters given: one a point, finite, parameters[0] = 0, parameters.back() = 1, each at least
  /// MinParameterGap above the one before. Coincident consecutive points (and a polygon of length 0) are then
  /// allowed: the curve pauses there.
  static std::string Interpolate(const PointList& points, const std::vector<double>& parameters, CubicBSpline& curve);

  bool Empty() const { return this->Points.empty(); }
  /// The points the curve passes through, and their parameters t_k.
  const PointList& ControlPoints() const { return this->Points; }
  const std::vector<double>& Parameters() const { return this->Params; }
  /// The B-spline control polygon: max(n, 4) points, the first and last equal to the first and last control points.
  const PointList& DeBoorPoints() const { return this->DeBoor; }
  /// The clamped knot vector, DeBoorPoints().size() + 4 values (see the header comment).
  const std::vector<double>& Knots() const { return this->KnotVector; }

  /// Position, first and second derivative with respect to t, t clamped to [0, 1]; NaN t gives NaN. At an interior
  /// knot the piece on its right is used (the curve is C2, so the side does not matter beyond rounding).
  Point Evaluate(double t) const;
  Point FirstDerivative(double t) const;
  Point SecondDerivative(double t) const;
  /// All three with one span search.
  void Derivatives(double t, Point& position, Point& first, Point& second) const;

  /// Total arc length, and the arc length from t = 0 to t (t clamped to [0, 1]); relative accuracy about 1e-12.
  double Length() const;
  double ArcLength(double t) const;
  /// The t whose ArcLength(t) is s (s clamped to [0, Length()]).
  double ParameterAtArcLength(double s) const;

  /// `count` parameters (at least 2: fewer is taken as 2) whose points split the curve into count - 1 pieces of equal
  /// arc length; the first is 0 and the last 1.
  std::vector<double> EqualArcLengthParameters(int count) const;
  PointList SampleEqualArcLength(int count) const;
  /// `count` points (at least 2) at equally spaced parameters.
  PointList SampleEqualParameter(int count) const;
  /// Points equally spaced in arc length, as few as keep the spacing at most `spacing` (the meshing resolution), both
  /// ends included; `parameters`, if given, receives their t. Returns an empty string on success, otherwise a message
  /// (spacing not a positive finite number, or more than MaxSamples points), with `points` empty.
  std::string SampleAtSpacing(double spacing, PointList& points, std::vector<double>* parameters = nullptr) const;
  static constexpr long MaxSamples = 10000000;

private:
  /// Builds the curve from validated points and parameters. Returns an empty string or why the solve failed.
  static std::string Build(const PointList& points, const std::vector<double>& parameters, CubicBSpline& curve);
  /// Index k with Knots()[k] <= t < Knots()[k + 1], in [3, DeBoorPoints().size() - 1]; t in [0, 1].
  int FindSpan(double t) const;
  /// C' on one knot span [start, start + width] as a quadratic Bezier curve in the local parameter u in [0, 1]
  /// (t = start + u * width): evaluating it needs no t, so integrating |C'| has no rounding noise from t, whose
  /// absolute error (~1e-16) is a relative one of ~1e-16 * n in |C'| on a curve of n points.
  struct SpanDerivative
  {
    Point bezier[3];
    double start = 0.0, width = 0.0;
  };
  SpanDerivative LocalDerivative(int span) const;
  /// Integral of |C'| dt over the local parameters [u0, u1] of one span: 5-point Gauss-Legendre.
  static double SpeedIntegral(const SpanDerivative& span, double u0, double u1);
  void BuildArcLengthTable();

  PointList Points;
  std::vector<double> Params;
  PointList DeBoor;
  PointList FirstPolygon;  ///< control points of C' (degree 2 on Knots()[1..m-1])
  PointList SecondPolygon; ///< control points of C'' (degree 1 on Knots()[2..m-2])
  std::vector<double> KnotVector;
  /// Arc-length table: S[i] is the arc length at parameter T[i]; each [T[i], T[i + 1]] is one Gauss-Legendre piece
  /// inside one knot span.
  std::vector<double> TableT;
  std::vector<double> TableS;
};

using CubicBSpline2d = CubicBSpline<2>;
using CubicBSpline3d = CubicBSpline<3>;

extern template class CubicBSpline<2>;
extern template class CubicBSpline<3>;

} // namespace plantmorph
