// SPDX-License-Identifier: GPL-3.0-or-later
// FitLeaf's intrinsic coordinates (cross-sections and midvein) and outline.
#include "LeafFitInternal.h"

#include <plantmorph/statistics/Median.h>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <sstream>

namespace plantmorph
{
namespace fit
{
namespace
{
/// Signed arc length of z = c0 + c1 x + c2 x^2 from x = a to x = b (8-point Gauss-Legendre: the integrand is smooth).
double ArcLength(double c1, double c2, double a, double b)
{
  static const double node[4] = { 0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363 };
  static const double weight[4] = { 0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763 };
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double sum = 0.0;
  for (int k = 0; k < 4; ++k)
    for (int sign = -1; sign <= 1; sign += 2)
    {
      const double x = mid + sign * half * node[k];
      const double slope = c1 + 2.0 * c2 * x;
      sum += weight[k] * std::sqrt(1.0 + slope * slope);
    }
  return half * sum;
}

struct SliceFit
{
  double Y = 0.0, angle = 0.0, c0 = 0.0, c1 = 0.0, c2 = 0.0, centre = 0.0, count = 0.0, width = 0.0;
};

double Quantile(std::vector<double> v, double q)
{
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

/// A quadratic cross-section of one slice's (X, Z) points, in the slice's principal frame, Huber-reweighted.
SliceFit FitSlice(const std::vector<Eigen::Vector2d>& xz, double Y)
{
  SliceFit slice;
  slice.Y = Y;
  slice.count = static_cast<double>(xz.size());
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : xz)
    mean += p;
  mean /= slice.count;
  Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
  for (const auto& p : xz)
    C += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(C);
  Eigen::Vector2d major = eig.eigenvectors().col(1);
  if (major.x() < 0.0)
    major = -major;
  slice.angle = std::atan2(major.y(), major.x());
  const double c = std::cos(slice.angle), s = std::sin(slice.angle);
  std::vector<double> x(xz.size()), z(xz.size()), w(xz.size(), 1.0);
  for (std::size_t i = 0; i < xz.size(); ++i)
  {
    x[i] = c * xz[i].x() + s * xz[i].y();
    z[i] = -s * xz[i].x() + c * xz[i].y();
  }
  Eigen::Vector3d coef = Eigen::Vector3d::Zero();
  for (int iteration = 0; iteration < 3; ++iteration)
  {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      const Eigen::Vector3d b(1.0, x[i], x[i] * x[i]);
      A += w[i] * b * b.transpose();
      r += w[i] * z[i] * b;
    }
    coef = A.ldlt().solve(r);
    std::vector<double> residual(x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
      residual[i] = std::abs(z[i] - coef[0] - coef[1] * x[i] - coef[2] * x[i] * x[i]);
    const double sigma = RobustScale(residual) + 1e-300;
    for (std::size_t i = 0; i < x.size(); ++i)
      w[i] = residual[i] <= 2.0 * sigma ? 1.0 : 2.0 * sigma / residual[i];
  }
  slice.c0 = coef[0];
  slice.c1 = coef[1];
  slice.c2 = coef[2];
  const double lo = Quantile(x, 0.01), hi = Quantile(x, 0.99);
  slice.centre = 0.5 * (lo + hi);
  slice.width = hi - lo;
  return slice;
}
} // namespace

std::string CrossSections::Build(const std::vector<Eigen::Vector3d>& local, double spacing)
{
  this->Y0 = 1e300;
  this->Y1 = -1e300;
  for (const auto& q : local)
  {
    this->Y0 = std::min(this->Y0, q.y());
    this->Y1 = std::max(this->Y1, q.y());
  }
  const int K = std::clamp(static_cast<int>(local.size() / 80), 6, 40);
  std::vector<std::vector<Eigen::Vector2d>> xz(K);
  std::vector<double> sumY(K, 0.0);
  for (const auto& q : local)
  {
    const int k = std::clamp(static_cast<int>((q.y() - this->Y0) / (this->Y1 - this->Y0) * K), 0, K - 1);
    xz[k].emplace_back(q.x(), q.z());
    sumY[k] += q.y();
  }
  std::vector<SliceFit> slices;
  for (int k = 0; k < K; ++k)
    if (xz[k].size() >= 10)
      slices.push_back(FitSlice(xz[k], sumY[k] / xz[k].size()));
  if (slices.size() < 3)
    return "no leaf shape: fewer than 3 cross-sections along the leaf hold enough points";
  double widest = 0.0;
  for (const auto& s : slices)
    widest = std::max(widest, s.width);
  // Smooth every parameter along the leaf; curvature terms weighted by how well a slice's width determines them.
  std::vector<double> Y, w0, w2, a, c0, c1, c2, centre;
  for (const auto& s : slices)
  {
    const double relative = widest > 0.0 ? s.width / widest : 0.0;
    Y.push_back(s.Y);
    w0.push_back(s.count);
    w2.push_back(s.count * relative * relative);
    a.push_back(s.angle);
    c0.push_back(s.c0);
    c1.push_back(s.c1);
    c2.push_back(s.c2);
    centre.push_back(s.centre);
  }
  const int intervals = std::clamp(static_cast<int>(slices.size()) / 3, 1, 8);
  const double lambda = 0.05;
  const std::vector<double> none;
  bool ok = this->Angle.Fit(this->Y0, this->Y1, intervals, Y, a, w2, none, lambda);
  ok = ok && this->C0.Fit(this->Y0, this->Y1, intervals, Y, c0, w0, none, lambda);
  ok = ok && this->C1.Fit(this->Y0, this->Y1, intervals, Y, c1, w2, none, lambda);
  ok = ok && this->C2.Fit(this->Y0, this->Y1, intervals, Y, c2, w2, none, lambda);
  ok = ok && this->FitCentre(intervals, Y, centre, w0, lambda, spacing);
  if (!ok)
    return "no leaf shape: the cross-sections could not be fitted";
  // The midvein's arc length along Y.
  const int samples = 1024;
  this->TableY.resize(samples + 1);
  this->TableS.resize(samples + 1);
  Eigen::Vector3d previous = this->MidveinAt(this->Y0);
  for (int i = 0; i <= samples; ++i)
  {
    this->TableY[i] = this->Y0 + (this->Y1 - this->Y0) * i / samples;
    const Eigen::Vector3d m = this->MidveinAt(this->TableY[i]);
    this->TableS[i] = i == 0 ? 0.0 : this->TableS[i - 1] + (m - previous).norm();
    previous = m;
  }
  return {};
}

bool CrossSections::FitCentre(int intervals, const std::vector<double>& Y, const std::vector<double>& centre,
  const std::vector<double>& w, double lambda, double spacing)
{
  // A slice through the tip of one lateral lobe and not its mirror image (a palmately lobed blade's lobes end at
  // slightly different heights on the two sides, or between slices) spans the terminal lobe and that lobe's tip,
  // so its centre lies far to that side (1.3 of a watermelon blade's 4.3 units of length, the slices beside it
  // 0.02): a least-squares spline follows it and moves the midvein off the terminal lobe. The centres are fitted
  // robustly (Huber, as a cross-section's points are): a slice farther than three robust deviations (and at least
  // a point spacing) from the reference loses weight in proportion. The first reference is the median of the
  // slice's own centre and its two neighbours' on either side (it follows a midvein curving in the blade, not one
  // slice nor two adjacent ones), then the spline itself.
  const std::size_t n = Y.size();
  std::vector<double> residual(n), weight(w);
  for (std::size_t k = 0; k < n; ++k)
  {
    const std::size_t from = k < 2 ? 0 : k - 2, to = std::min(n, k + 3);
    residual[k] = std::abs(centre[k] - Median(std::vector<double>(centre.begin() + from, centre.begin() + to)));
  }
  for (int iteration = 0; iteration < 4; ++iteration)
  {
    const double limit = std::max(3.0 * MadToDeviation * Median(residual), spacing);
    for (std::size_t k = 0; k < n; ++k)
      weight[k] = residual[k] <= limit ? w[k] : w[k] * limit / residual[k];
    if (!this->Centre.Fit(this->Y0, this->Y1, intervals, Y, centre, weight, {}, lambda))
      return false;
    for (std::size_t k = 0; k < n; ++k)
      residual[k] = std::abs(centre[k] - this->Centre(Y[k]));
  }
  return true;
}

void CrossSections::Section(double Y, double& angle, double& c0, double& c1, double& c2, double& centre) const
{
  const double y = std::clamp(Y, this->Y0, this->Y1);
  angle = this->Angle(y);
  c0 = this->C0(y);
  c1 = this->C1(y);
  c2 = this->C2(y);
  centre = this->Centre(y);
}

Eigen::Vector3d CrossSections::MidveinAt(double Y) const
{
  double angle, c0, c1, c2, centre;
  this->Section(Y, angle, c0, c1, c2, centre);
  const double x = centre, z = c0 + c1 * x + c2 * x * x;
  const double c = std::cos(angle), s = std::sin(angle);
  return { c * x - s * z, Y, s * x + c * z };
}

Eigen::Vector2d CrossSections::Intrinsic(const Eigen::Vector3d& q) const
{
  double angle, c0, c1, c2, centre;
  this->Section(q.y(), angle, c0, c1, c2, centre);
  const double x = std::cos(angle) * q.x() + std::sin(angle) * q.z();
  const double t = ArcLength(c1, c2, centre, x);
  // s: the midvein's arc length at this Y (linear in the table; beyond its ends, along Y).
  const double u = (q.y() - this->Y0) / (this->Y1 - this->Y0) * (this->TableY.size() - 1);
  const int i = std::clamp(static_cast<int>(std::floor(u)), 0, static_cast<int>(this->TableY.size()) - 2);
  const double f = u - i;
  const double s = (1.0 - f) * this->TableS[i] + f * this->TableS[i + 1];
  return { t, s };
}

double Outline::Phi(double s) const
{
  const double xi = std::clamp((s - this->s0) / (this->s1 - this->s0), 0.0, 1.0);
  return std::sqrt(xi * (1.0 - xi));
}

double Outline::Right(double s) const
{
  return this->Phi(s) * std::max(this->right(s), 1e-3 * (this->s1 - this->s0));
}

double Outline::Left(double s) const
{
  return -this->Phi(s) * std::max(this->left(s), 1e-3 * (this->s1 - this->s0));
}

namespace
{
/// Where the tip lies beyond the K extreme values v (ascending distances inwards from the tip, v[0] the nearest
/// sample, at most `reach` beyond it). Samples uniform by area near a tip whose area grows as d^q are a Poisson
/// process in u = d^q, so u_i (the i-th nearest, i = 1..K) has expectation i u_1's: the tip solves
/// sum_i (v_i - tip)^q = K (K + 1) / 2 (v_0 - tip)^q (bisection). q = 1.5, the parabolic (rounded) tip, between
/// blunt (1) and acute (2) tips, unless the width profile above the tip says it is a cusp (TipExponent): K is 10-40,
/// too few samples to tell q from the nearest samples alone. 1.5 was chosen on synthetic leaves of
/// all three models (500 to 12000 points): a least-squares fit of q with v_i = tip + c i^(1/q) put an acute apex up
/// to four spacings beyond the last sample (1.4 % of the length on the leaf bent at both ends), and the maximum
/// likelihood tip with a free q came out up to 4 % short on 500-1000 points; this is within 1 % from 1000 points.
double TipBeyond(const std::vector<double>& v, double reach, double q)
{
  const double K = static_cast<double>(v.size());
  auto excess = [&](double tip) {
    double sum = 0.0;
    for (double x : v)
      sum += std::pow(x - tip, q);
    return sum - K * (K + 1.0) / 2.0 * std::pow(v.front() - tip, q);
  };
  double lo = v.front() - reach, hi = v.front();
  if (excess(lo) > 0.0)
    return lo; // the samples thin out slower than any tip within reach: the farthest allowed
  for (int iteration = 0; iteration < 100; ++iteration)
  {
    const double mid = 0.5 * (lo + hi);
    (excess(mid) > 0.0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

/// The exponent q of the blade's area near its lowest tip (the area within d of the tip grows as d^q), from the
/// half-widths of the samples (t, s) `spacing` apart over the 48 spacings above the lowest: the outermost sample on
/// either side of each slice 4 spacings thick (at least 8 samples; moved out by its expected gap, as the margins'
/// stations are), fitted by a (s - tip)^p for p from 0.5 to 2.5 (least squares). A base whose width grows linearly
/// (a wedge) or slower (a rounded base) keeps q = 1.5; one whose width grows faster (the margins curving in to the
/// midvein: a cusp, narrower near its tip than a scanner's step between points) takes q = 1.5 p, 3 for a cusp whose
/// width grows as d^2, the Poisson tip of such a shape. The 10-40 nearest samples alone cannot tell q.
double TipExponent(const std::vector<Eigen::Vector2d>& ts, double spacing)
{
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& p : ts)
    lowest = std::min(lowest, p.y());
  struct Bin
  {
    double lo = 0.0, hi = 0.0, sLo = 0.0, sHi = 0.0;
    int count = 0;
  };
  const double thick = 4.0 * spacing;
  std::vector<Bin> bin(12);
  for (const auto& p : ts)
  {
    const std::size_t k = static_cast<std::size_t>((p.y() - lowest) / thick);
    if (k >= bin.size())
      continue;
    Bin& b = bin[k];
    if (b.count++ == 0 || p.x() > b.hi)
    {
      b.hi = p.x();
      b.sHi = p.y();
    }
    if (b.count == 1 || p.x() < b.lo)
    {
      b.lo = p.x();
      b.sLo = p.y();
    }
  }
  std::vector<Eigen::Vector2d> half; // (s, half-width)
  for (const Bin& b : bin)
  {
    if (b.count < 8)
      continue;
    const double gap = (b.hi - b.lo) / b.count;
    if (b.hi > 0.0)
      half.push_back({ b.sHi, b.hi + gap });
    if (b.lo < 0.0)
      half.push_back({ b.sLo, gap - b.lo });
  }
  if (half.size() < 6)
    return 1.5;
  double best = 1.0, bestError = std::numeric_limits<double>::infinity();
  for (int step = 0; step <= 40; ++step)
  {
    // h^(1/p) = alpha (s - tip), fitted by least squares; the error in h.
    const double p = 0.5 + 0.05 * step;
    double n = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (const auto& h : half)
    {
      const double y = std::pow(h.y(), 1.0 / p);
      n += 1.0;
      sx += h.x();
      sy += y;
      sxx += h.x() * h.x();
      sxy += h.x() * y;
    }
    const double alpha = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    if (!(alpha > 0.0))
      continue;
    const double tip = (sx - sy / alpha) / n;
    double error = 0.0;
    for (const auto& h : half)
      error += std::pow(h.y() - std::pow(alpha * std::max(h.x() - tip, 0.0), p), 2);
    if (error < bestError)
    {
      bestError = error;
      best = p;
    }
  }
  return std::clamp(1.5 * best, 1.5, 3.0);
}
} // namespace

std::string FitOutline(
  const std::vector<Eigen::Vector2d>& ts, const LeafFitParameters& options, double spacing, Outline& outline)
{
  std::vector<double> s(ts.size());
  for (std::size_t i = 0; i < ts.size(); ++i)
    s[i] = ts[i].y();
  const std::size_t K = std::clamp<std::size_t>(ts.size() / 100, 10, 40);
  if (s.size() < 2 * K)
    std::sort(s.begin(), s.end());
  else
  {
    // Only the K lowest and K highest, in order.
    std::partial_sort(s.begin(), s.begin() + K, s.end());
    std::partial_sort(s.rbegin(), s.rbegin() + K, s.rend() - K, std::greater<double>());
  }
  std::vector<double> low(s.begin(), s.begin() + K), high(s.rbegin(), s.rbegin() + K);
  for (double& v : high)
    v = -v;
  outline.s0 = TipBeyond(low, 4.0 * spacing, TipExponent(ts, spacing));
  outline.roundS0 = TipBeyond(low, 4.0 * spacing, 1.5);
  outline.s1 = -TipBeyond(high, 4.0 * spacing, 1.5);
  if (!(outline.s1 - outline.s0 > 4.0 * spacing))
    return "no leaf shape: the leaf is not longer than a few point spacings";
  // The outermost sample of each slice two point spacings thick, moved out by its expected gap to the margin: the
  // distance from the margin to the first of points of density rho in a strip of width w is 1 / (rho w), which is
  // (hi - lo) / count for the slice's own density; on a regular grid (a scanner's lines) that is half the spacing,
  // its mean. Thinner slices alias with a scanner's lines: a line on a slice's border splits between two slices
  // whose outermost points are then random subsets well inside the margin (area 7-23 % low seen from above).
  const int bins = std::clamp(static_cast<int>(std::lround((s.back() - s.front()) / (2.0 * spacing))), 12, 400);
  struct Bin
  {
    double lo = 1e300, hi = -1e300, sLo = 0.0, sHi = 0.0;
    int count = 0;
  };
  std::vector<Bin> bin(bins);
  for (const auto& p : ts)
  {
    const int k = std::clamp(static_cast<int>((p.y() - s.front()) / (s.back() - s.front()) * bins), 0, bins - 1);
    Bin& b = bin[k];
    ++b.count;
    if (p.x() > b.hi)
    {
      b.hi = p.x();
      b.sHi = p.y();
    }
    if (p.x() < b.lo)
    {
      b.lo = p.x();
      b.sLo = p.y();
    }
  }
  std::vector<double> sR, tR, phiR, sL, tL, phiL, w;
  for (const Bin& b : bin)
  {
    if (b.count < 5)
      continue;
    const double gap = (b.hi - b.lo) / b.count;
    sR.push_back(b.sHi);
    tR.push_back(b.hi + gap);
    phiR.push_back(outline.Phi(b.sHi));
    sL.push_back(b.sLo);
    tL.push_back(-(b.lo - gap));
    phiL.push_back(outline.Phi(b.sLo));
    w.push_back(1.0);
  }
  if (sR.size() < 6)
    return "no leaf shape: too few slices across the leaf hold points";
  const int intervals = std::max(1, options.outlineControlPoints - 3);
  const double lambda = 0.02 * options.outlineSmoothing;
  if (!outline.right.Fit(outline.s0, outline.s1, intervals, sR, tR, w, phiR, lambda) ||
    !outline.left.Fit(outline.s0, outline.s1, intervals, sL, tL, w, phiL, lambda))
    return "no leaf shape: the margins could not be fitted";
  outline.base = outline.s0;
  outline.apex = outline.s1;
  return {};
}

} // namespace fit
} // namespace plantmorph
