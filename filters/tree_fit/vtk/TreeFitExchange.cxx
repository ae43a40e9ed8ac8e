// SPDX-License-Identifier: GPL-3.0-or-later
#include "TreeFitExchange.h"

#include <stdexcept>

namespace plantmorph
{
namespace treefitvtk
{
namespace
{
/// Appends and reads numbers in one order (PackFit, UnpackFit).
struct Reader
{
  const std::vector<double>& data;
  std::size_t at = 0;
  double Next()
  {
    if (at >= data.size())
      throw std::runtime_error("a packed tree fit ended early");
    return data[at++];
  }
  int Int() { return static_cast<int>(this->Next()); }
  Eigen::Vector3d Vector()
  {
    const double x = this->Next(), y = this->Next();
    return { x, y, this->Next() };
  }
};
} // namespace

std::vector<double> PackFit(const TreeFitResult& fit)
{
  std::vector<double> out{ static_cast<double>(fit.error.size()) };
  for (char c : fit.error)
    out.push_back(static_cast<unsigned char>(c));
  out.push_back(static_cast<double>(fit.cylinders.size()));
  for (const TreeCylinder& c : fit.cylinders)
  {
    out.insert(out.end(), c.start.data(), c.start.data() + 3);
    out.insert(out.end(), c.end.data(), c.end.data() + 3);
    out.insert(out.end(),
      { c.radius, c.length, c.fittedRadius, static_cast<double>(c.parent), static_cast<double>(c.branch),
        static_cast<double>(c.order), static_cast<double>(c.segment), static_cast<double>(c.points), c.fitRMS,
        c.support, c.coverage, c.measured ? 1.0 : 0.0, c.growthLength });
  }
  out.push_back(static_cast<double>(fit.branches.size()));
  for (const TreeBranchRow& b : fit.branches)
  {
    out.insert(out.end(),
      { static_cast<double>(b.id), static_cast<double>(b.parent), static_cast<double>(b.order), b.length, b.volume,
        b.baseDiameter, b.angle, b.azimuth, b.inclination, b.height, static_cast<double>(b.cylinders.size()) });
    out.insert(out.end(), b.cylinders.begin(), b.cylinders.end());
  }
  const std::vector<double> traits = TreeTraitValues(fit.traits);
  out.insert(out.end(), traits.begin(), traits.end());
  return out;
}

TreeFitResult UnpackFit(const std::vector<double>& packed)
{
  TreeFitResult fit;
  Reader in{ packed };
  for (int k = 0, n = in.Int(); k < n; ++k)
    fit.error.push_back(static_cast<char>(in.Int()));
  fit.cylinders.resize(static_cast<std::size_t>(in.Int()));
  for (TreeCylinder& c : fit.cylinders)
  {
    c.start = in.Vector();
    c.end = in.Vector();
    c.radius = in.Next(), c.length = in.Next(), c.fittedRadius = in.Next();
    c.parent = in.Int(), c.branch = in.Int(), c.order = in.Int(), c.segment = in.Int(), c.points = in.Int();
    c.fitRMS = in.Next(), c.support = in.Next(), c.coverage = in.Next();
    c.measured = in.Next() != 0.0;
    c.growthLength = in.Next();
  }
  fit.branches.resize(static_cast<std::size_t>(in.Int()));
  for (TreeBranchRow& b : fit.branches)
  {
    b.id = in.Int(), b.parent = in.Int(), b.order = in.Int();
    b.length = in.Next(), b.volume = in.Next(), b.baseDiameter = in.Next(), b.angle = in.Next();
    b.azimuth = in.Next(), b.inclination = in.Next(), b.height = in.Next();
    b.cylinders.resize(static_cast<std::size_t>(in.Int()));
    for (int& k : b.cylinders)
      k = in.Int();
  }
  TreeTraits& t = fit.traits;
  for (double* value : { &t.height, &t.dbh, &t.trunkVolume, &t.branchVolume, &t.totalVolume, &t.trunkLength,
         &t.totalBranchLength, &t.branchCount, &t.order1, &t.order2, &t.order3, &t.order4Plus, &t.crownProjectedArea,
         &t.crownBaseHeight, &t.points, &t.woodPoints, &t.cylinders, &t.fitRMS, &t.spacing, &t.noise,
         &t.measuredVolumeFraction, &t.woodHeight })
    *value = in.Next();
  return fit;
}

} // namespace treefitvtk
} // namespace plantmorph
