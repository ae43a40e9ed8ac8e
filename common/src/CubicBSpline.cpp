// SPDX-License-Identifier: GPL-3.0-or-later
#include <plantmorph/CubicBSpline.h>

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace plantmorph
{
namespace
{
constexpr int Degree = 3;
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

// The control polygon's length must lie in this range: squares of lengths and derivatives then neither under- nor
// overflow (derivatives are at most ~1e12 times the length: parameters are at least 1e-12 apart).
constexpr double MinPolygonLength = 1e-100;
constexpr double MaxPolygonLength = 1e100;

// 5-point Gauss-Legendre rule on [-1, 1] (exact for degree 9).
constexpr int GaussCount = 5;
constexpr double GaussNodes[GaussCount] = { 0.0, -0.538469310105683091036314420700, 0.538469310105683091036314420700,
  -0.906179845938663992797626878299, 0.906179845938663992797626878299 };
constexpr double GaussWeights[GaussCount] = { 0.568888888888888888888888888889, 0.478628670499366468041291514836,
  0.478628670499366468041291514836, 0.236926885056189087514264040720, 0.236926885056189087514264040720 };

// Arc-length table: a Gauss-Legendre piece is accepted when halving it changes its integral by at most this times
// the integral (or by at most ArcLengthFloor times the control polygon's length times its parameter length, for
// pieces where the curve barely moves), or when halving stopped helping: the change did not shrink to half the
// change one level up. Smooth pieces shrink it ~1000x a level, pieces with a cusp (|C'| = 0) ~4x; rounding noise
// does not shrink it, and is where refinement must stop. Pieces are halved at most MaxDepth times.
constexpr double ArcLengthTolerance = 1e-12;
constexpr double ArcLengthFloor = 1e-15;
constexpr int MaxDepth = 40;
// And a span never gets more than this many pieces, whatever the criteria say (a bound on work and memory).
constexpr int MaxPiecesPerSpan = 1024;

template <int Dim>
std::string FormatPoint(const Eigen::Matrix<double, Dim, 1>& p)
{
  std::ostringstream out;
  out.precision(10);
  out << "(" << p[0];
  for (int i = 1; i < Dim; ++i)
    out << ", " << p[i];
  out << ")";
  return out.str();
}

/// The four non-zero cubic B-splines N_{span-3..span}(t) (The NURBS Book, alg. A2.2).
void BasisFunctions(int span, double t, const std::vector<double>& knots, double basis[Degree + 1])
{
  double left[Degree + 1], right[Degree + 1];
  basis[0] = 1.0;
  for (int j = 1; j <= Degree; ++j)
  {
    left[j] = t - knots[span + 1 - j];
    right[j] = knots[span + j] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r)
    {
      const double temp = basis[r] / (right[r + 1] + left[j - r]);
      basis[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    basis[j] = saved;
  }
}

/// The blossom of a degree-p B-spline with knots `knots` and control points `points` on the span k
/// (knots[k] <= x < knots[k + 1], or x at the span's right end), at x[0..p-1]: de Boor's algorithm with the parameter
/// x[r - 1] at level r. All x equal to t: the point at t. Uses points[k - p..k].
template <int Dim>
Eigen::Matrix<double, Dim, 1> Blossom(
  int p, int k, const double* x, const double* knots, const Eigen::Matrix<double, Dim, 1>* points)
{
  Eigen::Matrix<double, Dim, 1> d[Degree + 1];
  for (int j = 0; j <= p; ++j)
    d[j] = points[j + k - p];
  for (int r = 1; r <= p; ++r)
  {
    for (int j = p; j >= r; --j)
    {
      const double a = knots[j + k - p];
      const double alpha = (x[r - 1] - a) / (knots[j + 1 + k - r] - a);
      d[j] = (1.0 - alpha) * d[j - 1] + alpha * d[j];
    }
  }
  return d[p];
}

/// De Boor's algorithm: the point at t of a degree-p B-spline, on the span k.
template <int Dim>
Eigen::Matrix<double, Dim, 1> DeBoorPoint(
  int p, int k, double t, const double* knots, const Eigen::Matrix<double, Dim, 1>* points)
{
  const double x[Degree] = { t, t, t };
  return Blossom<Dim>(p, k, x, knots, points);
}

/// At least 2 points, finite coordinates, a control polygon whose length is 0 (only if `allowCoincident`) or in
/// [MinPolygonLength, MaxPolygonLength], and (unless `allowCoincident`) consecutive points at least `gap` times that
/// length apart. Fills `chords` (|Q_i+1 - Q_i|). Returns an empty string or the first problem found.
template <int Dim>
std::string ValidatePoints(const std::vector<Eigen::Matrix<double, Dim, 1>>& points, bool allowCoincident, double gap,
  std::vector<double>& chords)
{
  std::ostringstream message;
  message.precision(10);
  const std::size_t n = points.size();
  if (n < 2)
  {
    message << "control points: need at least 2, got " << n;
    return message.str();
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!points[i].allFinite())
    {
      message << "control points: point " << i << " = " << FormatPoint<Dim>(points[i])
              << " has a non-finite coordinate; coordinates must be finite numbers";
      return message.str();
    }
  }
  chords.resize(n - 1);
  double total = 0.0;
  for (std::size_t i = 1; i < n; ++i)
  {
    chords[i - 1] = (points[i] - points[i - 1]).stableNorm(); // no under- or overflow of the squares
    total += chords[i - 1];
  }
  if (!allowCoincident)
  {
    for (std::size_t i = 1; i < n; ++i)
    {
      if (chords[i - 1] == 0.0)
      {
        message << "control points: points " << i - 1 << " and " << i << " coincide at " << FormatPoint<Dim>(points[i])
                << " (zero chord length); consecutive points must be distinct";
        return message.str();
      }
    }
  }
  if (!(total >= MinPolygonLength && total <= MaxPolygonLength) && !(allowCoincident && total == 0.0))
  {
    message << "control points: the control polygon's length " << total << " is outside [" << MinPolygonLength << ", "
            << MaxPolygonLength << "]; rescale the points (e.g. to cm)";
    return message.str();
  }
  if (allowCoincident)
    return std::string();
  for (std::size_t i = 1; i < n; ++i)
  {
    if (chords[i - 1] < gap * total)
    {
      message << "control points: points " << i - 1 << " and " << i << " are only " << chords[i - 1]
              << " apart, less than " << gap << " of the control polygon's length " << total
              << "; consecutive points must be distinct";
      return message.str();
    }
  }
  return std::string();
}

/// One parameter a point, finite, from exactly 0 to exactly 1, each at least `gap` above the one before.
std::string ValidateParameters(const std::vector<double>& parameters, std::size_t n, double gap)
{
  std::ostringstream message;
  message.precision(17);
  if (parameters.size() != n)
  {
    message << "parameters: need one per control point (" << n << "), got " << parameters.size();
    return message.str();
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!std::isfinite(parameters[i]))
    {
      message << "parameters: t[" << i << "] = " << parameters[i] << " is not a finite number";
      return message.str();
    }
  }
  if (parameters.front() != 0.0)
  {
    message << "parameters: t[0] = " << parameters.front() << ", must be 0";
    return message.str();
  }
  if (parameters.back() != 1.0)
  {
    message << "parameters: t[" << n - 1 << "] = " << parameters.back() << ", must be 1";
    return message.str();
  }
  for (std::size_t i = 1; i < n; ++i)
  {
    if (!(parameters[i] - parameters[i - 1] >= gap))
    {
      message << "parameters: t[" << i << "] = " << parameters[i] << " does not exceed t[" << i - 1
              << "] = " << parameters[i - 1] << " by at least " << gap << "; parameters must increase strictly";
      return message.str();
    }
  }
  return std::string();
}
} // namespace

template <int Dim>
std::string CubicBSpline<Dim>::Interpolate(const PointList& points, CubicBSpline& curve)
{
  // `points` may be curve.ControlPoints(): curve changes only at the end.
  std::vector<double> chords;
  std::string message = ValidatePoints<Dim>(points, false, MinParameterGap, chords);
  if (message.empty())
  {
    std::vector<double> parameters(points.size(), 0.0);
    for (std::size_t i = 1; i < points.size(); ++i)
      parameters[i] = parameters[i - 1] + chords[i - 1];
    const double total = parameters.back();
    for (double& t : parameters)
      t /= total;
    parameters.back() = 1.0;
    message = Build(points, parameters, curve);
  }
  if (!message.empty())
    curve = CubicBSpline();
  return message;
}

template <int Dim>
std::string CubicBSpline<Dim>::Interpolate(
  const PointList& points, const std::vector<double>& parameters, CubicBSpline& curve)
{
  std::vector<double> chords;
  std::string message = ValidatePoints<Dim>(points, true, MinParameterGap, chords);
  if (message.empty())
    message = ValidateParameters(parameters, points.size(), MinParameterGap);
  if (message.empty())
    message = Build(points, parameters, curve);
  if (!message.empty())
    curve = CubicBSpline();
  return message;
}

template <int Dim>
std::string CubicBSpline<Dim>::Build(
  const PointList& points, const std::vector<double>& parameters, CubicBSpline& curve)
{
  CubicBSpline c;
  c.Points = points;
  c.Params = parameters;
  const int n = static_cast<int>(points.size());
  if (n <= 3)
  {
    // One cubic piece: the straight segment (n = 2) or the parabola through the three points (n = 3), degree-raised.
    c.KnotVector = { 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0 };
    const Point& q0 = points.front();
    const Point& q1 = points.back();
    Point middle = 0.5 * (q0 + q1); // quadratic Bezier middle point of the segment: uniform speed
    if (n == 3)
    {
      const double t = parameters[1];
      middle = (points[1] - (1.0 - t) * (1.0 - t) * q0 - t * t * q1) / (2.0 * t * (1.0 - t));
    }
    c.DeBoor = { q0, (q0 + 2.0 * middle) / 3.0, (2.0 * middle + q1) / 3.0, q1 };
  }
  else
  {
    // Not-a-knot: the parameters t_1 and t_{n-2} are not knots.
    c.KnotVector.reserve(n + 4);
    c.KnotVector.assign(Degree + 1, 0.0);
    c.KnotVector.insert(c.KnotVector.end(), parameters.begin() + 2, parameters.end() - 2);
    c.KnotVector.insert(c.KnotVector.end(), Degree + 1, 1.0);

    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<std::size_t>(n) * (Degree + 1));
    Eigen::Matrix<double, Eigen::Dynamic, Dim> rhs(n, Dim);
    for (int k = 0; k < n; ++k)
    {
      const int span = c.FindSpan(parameters[k]);
      double basis[Degree + 1];
      BasisFunctions(span, parameters[k], c.KnotVector, basis);
      for (int j = 0; j <= Degree; ++j)
      {
        if (basis[j] != 0.0)
          entries.emplace_back(k, span - Degree + j, basis[j]);
      }
      rhs.row(k) = points[k].transpose();
    }
    Eigen::SparseMatrix<double> matrix(n, n);
    matrix.setFromTriplets(entries.begin(), entries.end());
    matrix.makeCompressed();
    Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
    solver.compute(matrix);
    Eigen::Matrix<double, Eigen::Dynamic, Dim> solution;
    if (solver.info() == Eigen::Success)
      solution = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !solution.allFinite())
    {
      return "control points: the interpolation system could not be solved (" + solver.lastErrorMessage() +
        "); check the points and parameters";
    }
    c.DeBoor.resize(n);
    for (int j = 0; j < n; ++j)
      c.DeBoor[j] = solution.row(j).transpose();
    // Determined exactly by the clamped ends: no rounding at the curve's ends.
    c.DeBoor.front() = points.front();
    c.DeBoor.back() = points.back();
  }

  const int count = static_cast<int>(c.DeBoor.size());
  const std::vector<double>& u = c.KnotVector;
  c.FirstPolygon.resize(count - 1);
  for (int i = 0; i + 1 < count; ++i)
    c.FirstPolygon[i] = 3.0 * (c.DeBoor[i + 1] - c.DeBoor[i]) / (u[i + 4] - u[i + 1]);
  c.SecondPolygon.resize(count - 2);
  for (int i = 0; i + 2 < count; ++i)
    c.SecondPolygon[i] = 2.0 * (c.FirstPolygon[i + 1] - c.FirstPolygon[i]) / (u[i + 4] - u[i + 2]);

  const auto finite = [](const PointList& list) {
    return std::all_of(list.begin(), list.end(), [](const Point& p) { return p.allFinite(); });
  };
  if (!finite(c.FirstPolygon) || !finite(c.SecondPolygon))
  {
    return "control points: the curve's derivatives overflow (coordinates too large for the points' spacing); scale "
           "the points down";
  }

  c.BuildArcLengthTable();
  curve = std::move(c);
  return std::string();
}

template <int Dim>
int CubicBSpline<Dim>::FindSpan(double t) const
{
  // Spans Degree..last, last = number of de Boor points - 1 = knots - Degree - 2; binary search on the inner knots.
  const int last = static_cast<int>(this->KnotVector.size()) - Degree - 2;
  const auto begin = this->KnotVector.begin();
  return static_cast<int>(std::upper_bound(begin + Degree + 1, begin + last + 1, t) - begin) - 1;
}

template <int Dim>
typename CubicBSpline<Dim>::Point CubicBSpline<Dim>::Evaluate(double t) const
{
  if (this->Empty() || std::isnan(t))
    return Point::Constant(NaN);
  t = std::clamp(t, 0.0, 1.0);
  const int k = this->FindSpan(t);
  return DeBoorPoint<Dim>(Degree, k, t, this->KnotVector.data(), this->DeBoor.data());
}

template <int Dim>
typename CubicBSpline<Dim>::Point CubicBSpline<Dim>::FirstDerivative(double t) const
{
  if (this->Empty() || std::isnan(t))
    return Point::Constant(NaN);
  t = std::clamp(t, 0.0, 1.0);
  const int k = this->FindSpan(t);
  return DeBoorPoint<Dim>(Degree - 1, k - 1, t, this->KnotVector.data() + 1, this->FirstPolygon.data());
}

template <int Dim>
typename CubicBSpline<Dim>::Point CubicBSpline<Dim>::SecondDerivative(double t) const
{
  if (this->Empty() || std::isnan(t))
    return Point::Constant(NaN);
  t = std::clamp(t, 0.0, 1.0);
  const int k = this->FindSpan(t);
  return DeBoorPoint<Dim>(Degree - 2, k - 2, t, this->KnotVector.data() + 2, this->SecondPolygon.data());
}

template <int Dim>
void CubicBSpline<Dim>::Derivatives(double t, Point& position, Point& first, Point& second) const
{
  if (this->Empty() || std::isnan(t))
  {
    position = first = second = Point::Constant(NaN);
    return;
  }
  t = std::clamp(t, 0.0, 1.0);
  const int k = this->FindSpan(t);
  const double* knots = this->KnotVector.data();
  position = DeBoorPoint<Dim>(Degree, k, t, knots, this->DeBoor.data());
  first = DeBoorPoint<Dim>(Degree - 1, k - 1, t, knots + 1, this->FirstPolygon.data());
  second = DeBoorPoint<Dim>(Degree - 2, k - 2, t, knots + 2, this->SecondPolygon.data());
}

template <int Dim>
typename CubicBSpline<Dim>::SpanDerivative CubicBSpline<Dim>::LocalDerivative(int span) const
{
  // The Bezier points of the quadratic C' on [a, b] are its blossom at (a, a), (a, b) and (b, b).
  SpanDerivative local;
  const double a = this->KnotVector[span], b = this->KnotVector[span + 1];
  const double x[3][2] = { { a, a }, { a, b }, { b, b } };
  for (int i = 0; i < 3; ++i)
    local.bezier[i] = Blossom<Dim>(Degree - 1, span - 1, x[i], this->KnotVector.data() + 1, this->FirstPolygon.data());
  local.start = a;
  local.width = b - a;
  return local;
}

template <int Dim>
double CubicBSpline<Dim>::SpeedIntegral(const SpanDerivative& span, double u0, double u1)
{
  const double half = 0.5 * (u1 - u0), middle = 0.5 * (u0 + u1);
  double sum = 0.0;
  for (int i = 0; i < GaussCount; ++i)
  {
    const double u = middle + half * GaussNodes[i], v = 1.0 - u;
    sum += GaussWeights[i] * (v * v * span.bezier[0] + 2.0 * u * v * span.bezier[1] + u * u * span.bezier[2]).norm();
  }
  return span.width * half * sum;
}

template <int Dim>
void CubicBSpline<Dim>::BuildArcLengthTable()
{
  double polygon = 0.0;
  for (std::size_t i = 1; i < this->Points.size(); ++i)
    polygon += (this->Points[i] - this->Points[i - 1]).norm();

  this->TableT.assign(1, 0.0);
  this->TableS.assign(1, 0.0);
  const std::vector<double>& knots = this->KnotVector;
  const int last = static_cast<int>(this->DeBoor.size()) - 1;
  for (int k = Degree; k <= last; ++k)
  {
    if (!(knots[k] < knots[k + 1]))
      continue;
    const SpanDerivative span = this->LocalDerivative(k);
    const double floor = ArcLengthFloor * polygon * span.width; // per unit of u
    int pieces = 0;
    // Adaptive Gauss-Legendre on [u0, u1] whose one-piece integral is `whole`; `previous` is the change halving
    // made one level up. Accepted pieces go into the table in order. Written so that NaN stops the refinement.
    auto refine = [&](auto& self, double u0, double u1, double whole, double previous, int depth) -> void {
      const double middle = 0.5 * (u0 + u1);
      const double left = SpeedIntegral(span, u0, middle);
      const double right = SpeedIntegral(span, middle, u1);
      const double change = std::abs(left + right - whole);
      const bool refineMore = depth < MaxDepth && pieces < MaxPiecesPerSpan &&
        change > ArcLengthTolerance * (left + right) && change > floor * (u1 - u0) && change <= 0.5 * previous;
      if (!refineMore)
      {
        pieces += 2;
        const double s = this->TableS.back();
        this->TableT.push_back(span.start + middle * span.width);
        this->TableS.push_back(s + left);
        this->TableT.push_back(u1 == 1.0 ? knots[k + 1] : span.start + u1 * span.width);
        this->TableS.push_back(s + left + right);
        return;
      }
      self(self, u0, middle, left, change, depth + 1);
      self(self, middle, u1, right, change, depth + 1);
    };
    refine(refine, 0.0, 1.0, SpeedIntegral(span, 0.0, 1.0), std::numeric_limits<double>::infinity(), 0);
  }
}

template <int Dim>
double CubicBSpline<Dim>::Length() const
{
  return this->Empty() ? 0.0 : this->TableS.back();
}

template <int Dim>
double CubicBSpline<Dim>::ArcLength(double t) const
{
  if (this->Empty() || std::isnan(t))
    return NaN;
  t = std::clamp(t, 0.0, 1.0);
  if (t == 1.0)
    return this->TableS.back();
  const std::ptrdiff_t i = std::upper_bound(this->TableT.begin(), this->TableT.end(), t) - this->TableT.begin() - 1;
  const SpanDerivative span = this->LocalDerivative(this->FindSpan(this->TableT[i]));
  return this->TableS[i] +
    SpeedIntegral(span, (this->TableT[i] - span.start) / span.width, (t - span.start) / span.width);
}

template <int Dim>
double CubicBSpline<Dim>::ParameterAtArcLength(double s) const
{
  if (this->Empty() || std::isnan(s))
    return NaN;
  const double length = this->Length();
  if (s <= 0.0)
    return 0.0;
  if (s >= length)
    return 1.0;
  const std::ptrdiff_t last = static_cast<std::ptrdiff_t>(this->TableS.size()) - 2;
  const std::ptrdiff_t i = std::clamp<std::ptrdiff_t>(
    std::upper_bound(this->TableS.begin(), this->TableS.end(), s) - this->TableS.begin() - 1, 0, last);
  const double sa = this->TableS[i], sb = this->TableS[i + 1];
  if (!(sb > sa))
    return this->TableT[i];
  // Safeguarded Newton on the arc length from the piece's start, in the span's local parameter u, where |C'| width
  // is its derivative and the piece brackets the root.
  const SpanDerivative span = this->LocalDerivative(this->FindSpan(this->TableT[i]));
  const double ua = (this->TableT[i] - span.start) / span.width;
  double low = ua, high = (this->TableT[i + 1] - span.start) / span.width;
  double u = low + (high - low) * (s - sa) / (sb - sa);
  for (int iteration = 0; iteration < 100; ++iteration)
  {
    const double f = sa + SpeedIntegral(span, ua, u) - s;
    if (std::abs(f) <= 1e-15 * length)
      break;
    (f > 0.0 ? high : low) = u;
    const double v = 1.0 - u;
    const double speed =
      span.width * (v * v * span.bezier[0] + 2.0 * u * v * span.bezier[1] + u * u * span.bezier[2]).norm();
    double next = speed > 0.0 ? u - f / speed : 0.5 * (low + high);
    if (!(next > low && next < high))
      next = 0.5 * (low + high);
    if (next == u || high - low <= 4.0 * std::numeric_limits<double>::epsilon())
      break;
    u = next;
  }
  return std::clamp(span.start + u * span.width, this->TableT[i], this->TableT[i + 1]);
}

template <int Dim>
std::vector<double> CubicBSpline<Dim>::EqualArcLengthParameters(int count) const
{
  if (this->Empty())
    return {};
  count = std::max(count, 2);
  std::vector<double> parameters(count);
  const double length = this->Length();
  parameters.front() = 0.0;
  for (int i = 1; i + 1 < count; ++i)
    parameters[i] = this->ParameterAtArcLength(length * i / (count - 1));
  parameters.back() = 1.0;
  return parameters;
}

template <int Dim>
typename CubicBSpline<Dim>::PointList CubicBSpline<Dim>::SampleEqualArcLength(int count) const
{
  PointList points;
  for (double t : this->EqualArcLengthParameters(count))
    points.push_back(this->Evaluate(t));
  return points;
}

template <int Dim>
typename CubicBSpline<Dim>::PointList CubicBSpline<Dim>::SampleEqualParameter(int count) const
{
  PointList points;
  if (this->Empty())
    return points;
  count = std::max(count, 2);
  points.reserve(count);
  for (int i = 0; i < count; ++i)
    points.push_back(this->Evaluate(i + 1 == count ? 1.0 : static_cast<double>(i) / (count - 1)));
  return points;
}

template <int Dim>
std::string CubicBSpline<Dim>::SampleAtSpacing(double spacing, PointList& points, std::vector<double>* parameters) const
{
  points.clear();
  if (parameters)
    parameters->clear();
  if (this->Empty())
    return "curve: empty (build it with Interpolate first)";
  std::ostringstream message;
  if (!(spacing > 0.0) || !std::isfinite(spacing))
  {
    message << "spacing: " << spacing << " is not a positive finite number";
    return message.str();
  }
  const double pieces = std::max(1.0, std::ceil(this->Length() / spacing));
  if (!(pieces + 1.0 <= static_cast<double>(MaxSamples)))
  {
    message << "spacing: " << spacing << " would need " << pieces + 1.0 << " points on a curve of length "
            << this->Length() << ", more than " << MaxSamples;
    return message.str();
  }
  const std::vector<double> t = this->EqualArcLengthParameters(static_cast<int>(pieces) + 1);
  points.reserve(t.size());
  for (double ti : t)
    points.push_back(this->Evaluate(ti));
  if (parameters)
    *parameters = t;
  return std::string();
}

template class CubicBSpline<2>;
template class CubicBSpline<3>;

} // namespace plantmorph
