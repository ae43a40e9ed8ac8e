// SPDX-License-Identifier: GPL-3.0-or-later
#include <plantmorph/BezierCurve.h>

#include <algorithm>

namespace plantmorph
{

template <int Dim>
Eigen::Matrix<double, Dim, 1> EvaluateBezier(const std::vector<Eigen::Matrix<double, Dim, 1>>& controls, double t)
{
  using Point = Eigen::Matrix<double, Dim, 1>;
  if (controls.empty())
  {
    return Point::Zero();
  }
  if (t <= 0.0)
  {
    return controls.front();
  }
  if (t >= 1.0)
  {
    return controls.back();
  }
  std::vector<Point> work(controls);
  for (std::size_t level = work.size() - 1; level > 0; --level)
  {
    for (std::size_t k = 0; k < level; ++k)
    {
      work[k] = (1.0 - t) * work[k] + t * work[k + 1];
    }
  }
  return work[0];
}

template <int Dim>
std::vector<Eigen::Matrix<double, Dim, 1>> SampleBezier(
  const std::vector<Eigen::Matrix<double, Dim, 1>>& controls, int count)
{
  count = std::max(count, 1);
  std::vector<Eigen::Matrix<double, Dim, 1>> points(static_cast<std::size_t>(count) + 1);
  for (int k = 0; k <= count; ++k)
  {
    points[static_cast<std::size_t>(k)] = EvaluateBezier<Dim>(controls, static_cast<double>(k) / count);
  }
  return points;
}

std::vector<int> StrokeControlIndices(int m, int n)
{
  std::vector<int> indices;
  if (m < 2)
  {
    for (int i = 0; i < m; ++i)
    {
      indices.push_back(i);
    }
    return indices;
  }
  n = std::clamp(n, 2, m);
  for (int i = 0; i < n; ++i)
  {
    // 64-bit product: m and n up to 2^31 without overflow.
    indices.push_back(static_cast<int>(static_cast<long long>(i) * (m - 1) / (n - 1)));
  }
  return indices;
}

template Eigen::Matrix<double, 2, 1> EvaluateBezier<2>(const std::vector<Eigen::Matrix<double, 2, 1>>&, double);
template Eigen::Matrix<double, 3, 1> EvaluateBezier<3>(const std::vector<Eigen::Matrix<double, 3, 1>>&, double);
template std::vector<Eigen::Matrix<double, 2, 1>> SampleBezier<2>(const std::vector<Eigen::Matrix<double, 2, 1>>&, int);
template std::vector<Eigen::Matrix<double, 3, 1>> SampleBezier<3>(const std::vector<Eigen::Matrix<double, 3, 1>>&, int);

} // namespace plantmorph
