// SPDX-License-Identifier: GPL-3.0-or-later
#include "WiltingSimulation.h"

#include <plantmorph/RangeError.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace plantmorph
{

int WiltingMaterialOf(int region)
{
  switch (region)
  {
    case 1:
    case 2:
      return WiltingVein;
    case 4:
      return WiltingMargin;
    case 5:
      return WiltingPetiole;
    default:
      return WiltingBlade;
  }
}

std::size_t CountNonManifoldEdges(const std::vector<std::array<int, 3>>& triangles)
{
  std::map<std::pair<int, int>, int> edgeUse;
  for (const auto& t : triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int a = t[k], b = t[(k + 1) % 3];
      ++edgeUse[{ std::min(a, b), std::max(a, b) }];
    }
  }
  return static_cast<std::size_t>(
    std::count_if(edgeUse.begin(), edgeUse.end(), [](const auto& e) { return e.second > 2; }));
}

std::string WiltingInputAssumptions(const WiltingInput& input, bool surfaceHasRegion)
{
  std::ostringstream assumed;
  if (input.leafUV.empty())
  {
    assumed << "the Input has no LeafUV point array (2 components), so its base is taken as its lowest point (least "
               "y) and its tip as its point farthest from the base. ";
  }
  if (!surfaceHasRegion)
  {
    assumed << "the Input has no Region point array, so every point of it counts as blade (no margin or midvein "
               "material). ";
  }
  const std::size_t shared = CountNonManifoldEdges(input.triangles);
  if (shared > 0)
  {
    assumed << "the Input is not a manifold surface (" << shared << " edge(s) shared by more than two triangles): it "
            << "is voxelised as it is, each triangle on its own. ";
  }
  std::string text = assumed.str();
  return text.empty() ? text : text.substr(0, text.size() - 1);
}

std::string FittedBladeWarning(const WiltingInput& input, const WiltingParameters& parameters)
{
  if (!input.fitted || !(parameters.anchorFraction > 0.0) || parameters.voxelSize > 0.0 ||
    parameters.resolution >= FittedBladeResolution)
  {
    return std::string();
  }
  std::ostringstream message;
  message << "the Input is a fitted blade (LeafFitFilter) and the preset is verified on fitted cucumber scans of "
             "5-40 cm from Resolution "
          << FittedBladeResolution << " on (no voxel inverted, no rise-back): the smallest Resolution that holds is "
          << FittedBladeResolution << " (Resolution " << parameters.resolution << " asked)";
  return message.str();
}

std::string ValidateWilting(const WiltingParameters& p)
{
  std::ostringstream message;
  static const char* names[WiltingMaterialCount] = { "Blade", "Vein", "Margin", "Petiole" };
  if (!(p.voxelSize >= 0.0) || !std::isfinite(p.voxelSize))
  {
    message << OutOfRange("VoxelSize", p.voxelSize, "[0, inf)", "0: use Resolution");
  }
  else if (p.voxelSize == 0.0 && (p.resolution < 1 || p.resolution > 1000))
  {
    message << OutOfRange("Resolution", p.resolution, "[1, 1000]");
  }
  else if (!(p.gravity >= 0.0) || !std::isfinite(p.gravity))
  {
    message << OutOfRange("Gravity", p.gravity, "[0, inf)");
  }
  else if (!(std::abs(p.droopForce) <= 1e9))
  {
    message << OutOfRange("DroopForce", p.droopForce, "[-1e9, 1e9]", "negative pulls up");
  }
  else if (!(std::abs(p.contractionForce) <= 1e9))
  {
    message << OutOfRange("ContractionForce", p.contractionForce, "[-1e9, 1e9]", "negative pushes away");
  }
  else if (!(p.droopAsymmetry >= -1.0 && p.droopAsymmetry <= 1.0))
  {
    message << OutOfRange("DroopAsymmetry", p.droopAsymmetry, "[-1, 1]");
  }
  else if (!(p.contractionAsymmetry >= -1.0 && p.contractionAsymmetry <= 1.0))
  {
    message << OutOfRange("ContractionAsymmetry", p.contractionAsymmetry, "[-1, 1]");
  }
  else if (!(std::abs(p.shrinkageStrain) <= 0.4))
  {
    message << OutOfRange("ShrinkageStrain", p.shrinkageStrain, "[-0.4, 0.4]", "negative swells");
  }
  else if (!(p.shrinkageAsymmetry >= -1.0 && p.shrinkageAsymmetry <= 1.0))
  {
    message << OutOfRange("ShrinkageAsymmetry", p.shrinkageAsymmetry, "[-1, 1]");
  }
  else if (!(std::abs(p.curlStrain) <= 0.4))
  {
    message << OutOfRange("CurlStrain", p.curlStrain, "[-0.4, 0.4]", "negative curls up");
  }
  else if (!(p.curlAsymmetry >= -1.0 && p.curlAsymmetry <= 1.0))
  {
    message << OutOfRange("CurlAsymmetry", p.curlAsymmetry, "[-1, 1]");
  }
  else if (!(p.curlRelaxation >= 0.0 && p.curlRelaxation <= 1.0))
  {
    message << OutOfRange("CurlRelaxation", p.curlRelaxation, "[0, 1]");
  }
  else if (!(p.shrinkageTime >= 0.0) || !std::isfinite(p.shrinkageTime))
  {
    message << OutOfRange("ShrinkageTime", p.shrinkageTime, "[0, inf)", "0: ContractionTime");
  }
  else if (!(p.curlTime >= 0.0) || !std::isfinite(p.curlTime))
  {
    message << OutOfRange("CurlTime", p.curlTime, "[0, inf)", "0: ContractionTime");
  }
  else if (!(p.curlRelaxationTime >= 0.0) || !std::isfinite(p.curlRelaxationTime))
  {
    message << OutOfRange("CurlRelaxationTime", p.curlRelaxationTime, "[0, inf)", "0: LoadTime");
  }
  else if (!(p.loadTime > 0.0) || !std::isfinite(p.loadTime))
  {
    message << OutOfRange("LoadTime", p.loadTime, "(0, inf)");
  }
  else if (!(p.referenceVoxelSize >= 0.0) || !std::isfinite(p.referenceVoxelSize))
  {
    message << "the reference voxel size must be >= 0 and finite (got " << p.referenceVoxelSize << ")";
  }
  else if (!(p.contractionTime >= 0.0) || !std::isfinite(p.contractionTime))
  {
    message << OutOfRange("ContractionTime", p.contractionTime, "[0, inf)", "0: LoadTime");
  }
  else if (!(p.bladeThickness >= 0.0 && p.bladeThickness <= 1e6))
  {
    message << OutOfRange("BladeThickness", p.bladeThickness, "[0, 1e6]", "0: the leaf's longest side / 14");
  }
  else if (!(p.throughStiffness > 0.0 && p.throughStiffness <= 1e6))
  {
    message << OutOfRange("throughStiffness", p.throughStiffness, "(0, 1e6]", "1: every spring alike");
  }
  else if (p.substeps < 0 || p.substeps > 1000)
  {
    message << OutOfRange("Substeps", p.substeps, "[0, 1000]", "0: automatic");
  }
  else if (!(p.anchorRadius >= 0.0) || !std::isfinite(p.anchorRadius))
  {
    message << OutOfRange("AnchorRadius", p.anchorRadius, "[0, inf)");
  }
  else if (!(p.referenceLength >= 0.0) || !std::isfinite(p.referenceLength))
  {
    message << OutOfRange("referenceLength", p.referenceLength, "[0, inf)", "0: the materials as given");
  }
  else if (!(p.anchorFraction >= 0.0 && p.anchorFraction <= 10.0))
  {
    message << OutOfRange("anchorFraction", p.anchorFraction, "[0, 10]", "0: AnchorRadius");
  }
  else if (!(p.petioleLength >= 0.0 && p.petioleLength <= 1e4))
  {
    message << OutOfRange("PetioleLength", p.petioleLength, "[0, 10000]", "0: no petiole");
  }
  else if (!(p.duration > 0.0 && p.duration <= 1e4))
  {
    message << OutOfRange("Duration", p.duration, "(0, 10000]", "seconds");
  }
  else if (!(p.frameInterval > 0.0) || !std::isfinite(p.frameInterval))
  {
    message << OutOfRange("FrameInterval", p.frameInterval, "(0, inf)");
  }
  else
  {
    for (int m = 0; m < WiltingMaterialCount; ++m)
    {
      const WiltingMaterial& material = p.materials[static_cast<std::size_t>(m)];
      const std::string name = names[m];
      const bool physical = p.units == WiltingUnits::Physical;
      if (!(material.density > 0.0) || !std::isfinite(material.density))
        message << OutOfRange(name + "Density", material.density, "(0, inf)");
      else if (!(material.stiffness > 0.0) || !std::isfinite(material.stiffness))
        message << OutOfRange(name + (physical ? "YoungsModulus" : "Stiffness"), material.stiffness, "(0, inf)");
      else if (!(material.damping >= 0.0) || !std::isfinite(material.damping))
        message << OutOfRange(name + (physical ? "DampingTime" : "Damping"), material.damping, "[0, inf)");
      if (!message.str().empty())
        break;
    }
  }
  if (message.str().empty())
  {
    const std::string newmark = ValidateNewmark(p.newmark);
    if (!newmark.empty())
    {
      return newmark;
    }
    if (p.newmark.timeStep > p.duration)
    {
      // One step longer than the whole run: a one-row trajectory and a leaf that never moves.
      message << "TimeStep = " << p.newmark.timeStep << " s is longer than Duration = " << p.duration
              << " s: TimeStep must be in (0, Duration]";
    }
    else if (p.duration / p.newmark.timeStep > 1e7)
    {
      message << "Duration / TimeStep must be at most 1e7 steps";
    }
  }
  return message.str();
}

namespace
{
/// The blade's base: the point with the smallest LeafUV v (then the smallest |u|), else the smallest y.
std::size_t BasePoint(const WiltingInput& input)
{
  std::size_t base = 0;
  for (std::size_t p = 1; p < input.points.size(); ++p)
  {
    const bool lower = input.leafUV.empty() ? input.points[p][1] < input.points[base][1]
                                            : (input.leafUV[p][1] < input.leafUV[base][1] ||
                                                (input.leafUV[p][1] == input.leafUV[base][1] &&
                                                  std::abs(input.leafUV[p][0]) < std::abs(input.leafUV[base][0])));
    if (lower)
    {
      base = p;
    }
  }
  return base;
}

/// Whether corners a < b of a voxel (0-3 bottom, 4-7 top) lie on one horizontal face.
bool OnOneFace(int a, int b)
{
  return (a < 4) == (b < 4);
}

/// Nodes with lumped masses, and the 28 springs and the hexahedron of every voxel. With shrinkage or curl: the 28
/// springs of each voxel, in voxel order (else empty).
std::vector<int> AddVoxelSprings(
  const VoxelGrid& grid, const WiltingParameters& parameters, double springScale, MassSpringSystem& springs)
{
  const double h = grid.h;
  std::vector<int> voxelSprings;
  for (const Eigen::Vector3d& x : grid.nodes)
  {
    springs.AddNode(x, 0.0);
  }
  for (std::size_t v = 0; v < grid.voxels.size(); ++v)
  {
    const WiltingMaterial& material =
      parameters.materials[static_cast<std::size_t>(WiltingMaterialOf(grid.regions[v]))];
    const double stiffness = material.stiffness * springScale;
    const double damping = material.damping * springScale;
    const double mass = material.density * h * h * h;
    const std::array<int, 8>& c = grid.corners[v];
    for (int node : c)
    {
      springs.AddMass(node, mass / 8.0);
    }
    for (int a = 0; a < 8; ++a)
    {
      for (int b = a + 1; b < 8; ++b)
      {
        const double factor = OnOneFace(a, b) ? 1.0 : parameters.throughStiffness;
        const int spring = springs.AddSpring(
          c[static_cast<std::size_t>(a)], c[static_cast<std::size_t>(b)], factor * stiffness, factor * damping);
        if (parameters.shrinkageStrain != 0.0 || parameters.curlStrain != 0.0)
        {
          voxelSprings.push_back(spring);
        }
      }
    }
    springs.AddHexahedron(c);
  }
  return voxelSprings;
}

/// Where the leaf is held: anchor points (nodes within AnchorRadius of one are fixed) and nodes fixed whatever
/// AnchorRadius is.
struct AnchorPlan
{
  std::vector<Eigen::Vector3d> anchors;
  std::vector<int> heldNodes;
  std::size_t firstAnchor = 0; ///< without a petiole: its voxel's nodes are held when AnchorRadius reaches none
};

/// Anchors: the petiole's far end, or the input's petiole points, or the blade's base.
AnchorPlan PlanAnchors(
  const WiltingInput& input, const WiltingParameters& parameters, const PetiolePlacement& petiole, std::size_t base)
{
  AnchorPlan plan;
  plan.firstAnchor = base;
  if (parameters.petioleLength > 0.0)
  {
    plan.anchors.push_back(petiole.end);
    plan.heldNodes = petiole.endNodes;
  }
  else
  {
    for (std::size_t p = 0; p < input.regions.size(); ++p)
    {
      if (input.regions[p] == 5)
      {
        plan.firstAnchor = plan.anchors.empty() ? p : plan.firstAnchor;
        plan.anchors.push_back(input.points[p]);
      }
    }
    if (plan.anchors.empty())
    {
      plan.anchors.push_back(input.points[base]);
    }
  }
  return plan;
}

/// The distance of a point from the nearest anchor.
double AnchorDistance(const Eigen::Vector3d& x, const std::vector<Eigen::Vector3d>& anchors)
{
  double nearest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& anchor : anchors)
  {
    nearest = std::min(nearest, (x - anchor).norm());
  }
  return nearest;
}

/// The share of the voxel with corners `corners` within `radius` of an anchor, sampled at 6 x 6 x 6 points.
double HeldShare(
  const VoxelGrid& grid, const std::array<int, 8>& corners, const std::vector<Eigen::Vector3d>& anchors, double radius)
{
  constexpr int samples = 6;
  Eigen::Vector3d low = grid.nodes[static_cast<std::size_t>(corners[0])], high = low;
  for (int node : corners)
  {
    low = low.cwiseMin(grid.nodes[static_cast<std::size_t>(node)]);
    high = high.cwiseMax(grid.nodes[static_cast<std::size_t>(node)]);
  }
  if (AnchorDistance(0.5 * (low + high), anchors) > radius + (high - low).norm())
  {
    return 0.0;
  }
  int inside = 0;
  for (int a = 0; a < samples; ++a)
  {
    for (int b = 0; b < samples; ++b)
    {
      for (int c = 0; c < samples; ++c)
      {
        const Eigen::Vector3d at = (Eigen::Vector3d(a, b, c) + Eigen::Vector3d::Constant(0.5)) / samples;
        inside += AnchorDistance(low + at.cwiseProduct(high - low), anchors) <= radius ? 1 : 0;
      }
    }
  }
  return static_cast<double>(inside) / (samples * samples * samples);
}

/// Holds the leaf within `radius` of the anchors in proportion to each voxel's share f of the held ball: every node
/// of a voxel wholly inside (f = 1) is fixed, so the leaf is held by whole voxels and no voxel hangs on a fixed node
/// or edge of its own (a hold node by node did that where the circle crosses the grid, and turned such a voxel
/// inside out); a voxel partly inside has its 28 springs stiffened by f / (1 - f) of their own stiffness and
/// damping, so it goes from free to rigid as the ball covers it. Holding whole the voxels whose centres were in the
/// ball made the held region jump by a ring of voxels with the Resolution, and the tip path with it (0.26 leaf
/// lengths from Resolution 22's at 15, 0.16 at 20). A ball too small to hold a whole voxel holds whole the voxels
/// whose centres it holds. Returns the number of nodes fixed.
std::size_t HoldVoxelsNearAnchors(const VoxelGrid& grid, const std::vector<Eigen::Vector3d>& anchors, double radius,
  const WiltingParameters& parameters, double springScale, MassSpringSystem& springs)
{
  std::vector<double> shares;
  bool graded = false;
  for (const std::array<int, 8>& c : grid.corners)
  {
    shares.push_back(HeldShare(grid, c, anchors, radius));
    graded = graded || shares.back() >= 1.0;
  }
  std::vector<char> fixed(grid.nodes.size(), 0);
  for (std::size_t v = 0; v < grid.corners.size(); ++v)
  {
    const std::array<int, 8>& c = grid.corners[v];
    const double share = shares[v];
    if (!graded)
    {
      // A ball that holds no whole voxel cannot grade the hold: the voxels whose centres it holds are held whole.
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (int node : c)
      {
        centre += grid.nodes[static_cast<std::size_t>(node)];
      }
      const char held = AnchorDistance(centre / 8.0, anchors) <= radius ? 1 : 0;
      for (int node : c)
      {
        fixed[static_cast<std::size_t>(node)] |= held;
      }
    }
    else if (share >= 1.0)
    {
      for (int node : c)
      {
        fixed[static_cast<std::size_t>(node)] = 1;
      }
    }
    else if (share > 0.0)
    {
      const WiltingMaterial& material =
        parameters.materials[static_cast<std::size_t>(WiltingMaterialOf(grid.regions[v]))];
      const double extra = share / (1.0 - share) * springScale;
      for (int a = 0; a < 8; ++a)
      {
        for (int b = a + 1; b < 8; ++b)
        {
          const double factor = (OnOneFace(a, b) ? 1.0 : parameters.throughStiffness) * extra;
          springs.AddSpring(c[static_cast<std::size_t>(a)], c[static_cast<std::size_t>(b)], factor * material.stiffness,
            factor * material.damping);
        }
      }
    }
  }
  std::size_t fixedCount = 0;
  for (std::size_t n = 0; n < fixed.size(); ++n)
  {
    if (fixed[n] != 0)
    {
      springs.SetFixed(static_cast<int>(n), true);
      ++fixedCount;
    }
  }
  return fixedCount;
}

/// Tip: the largest LeafUV v (closest to the midvein), else the point farthest from the base.
std::size_t TipPointOf(const WiltingInput& input, std::size_t base)
{
  std::size_t tip = 0;
  for (std::size_t p = 1; p < input.points.size(); ++p)
  {
    const bool higher = input.leafUV.empty()
      ? (input.points[p] - input.points[base]).squaredNorm() > (input.points[tip] - input.points[base]).squaredNorm()
      : (input.leafUV[p][1] > input.leafUV[tip][1] ||
          (input.leafUV[p][1] == input.leafUV[tip][1] &&
            std::abs(input.leafUV[p][0]) < std::abs(input.leafUV[tip][0])));
    if (higher)
    {
      tip = p;
    }
  }
  return tip;
}

/// The loads at full load: gravity, droop and contraction per node (3 each); with shrinkage or curl, the sum over
/// every spring's voxels of k_v e_v (divided by the spring's k at the end).
struct FullLoads
{
  std::vector<double>& gravity;
  std::vector<double>& droop;
  std::vector<double>& contraction;
  std::vector<double>& shrinkage;
  std::vector<double>& curl;
};

/// The blade's own midvein: its Region 1 points with a LeafUV (the Veins input's points have none: NaN); every
/// Region 1 point when the input has no LeafUV.
std::vector<std::size_t> MidveinPoints(const WiltingInput& input)
{
  std::vector<std::size_t> midvein;
  for (std::size_t p = 0; p < input.regions.size(); ++p)
  {
    if (input.regions[p] == 1 && (input.leafUV.empty() || input.leafUV[p].allFinite()))
    {
      midvein.push_back(p);
    }
  }
  return midvein;
}

/// The grid axis across the leaf: x when the leaf's axis (base to tip) runs more along y than x, else y.
int AcrossAxis(const WiltingInput& input, std::size_t base)
{
  const Eigen::Vector3d axis = input.points[TipPointOf(input, base)] - input.points[base];
  return std::abs(axis.y()) >= std::abs(axis.x()) ? 0 : 1;
}

/// A voxel's side of the midvein plane (-1, 0 or 1), and the XY directions from the base to it and of its
/// contraction.
struct VoxelDirections
{
  double side = 0.0;
  Eigen::Vector2d fromBase = Eigen::Vector2d::Zero();
  Eigen::Vector2d towards = Eigen::Vector2d::Zero();
};

VoxelDirections DirectionsOf(
  const VoxelGrid& grid, std::size_t v, double midX, double baseY, WiltingContractionTarget target)
{
  const double h = grid.h;
  VoxelDirections out;
  const double centreX = grid.origin[0] + h * (grid.voxels[v][0] + 0.5);
  const double centreY = grid.origin[1] + h * (grid.voxels[v][1] + 0.5);
  // The voxel's side of the midvein plane, for the asymmetric loads (1 + a * side is exactly 1 when a = 0).
  const double sideOffset = centreX - midX;
  out.side = std::abs(sideOffset) <= 0.5 * h ? 0.0 : (sideOffset > 0.0 ? 1.0 : -1.0);
  // The unit vector from the base to the voxel's centre in the XY plane (none within h/2 of the base).
  const Eigen::Vector2d offset(centreX - midX, centreY - baseY);
  out.fromBase = offset.norm() <= 0.5 * h ? Eigen::Vector2d::Zero() : Eigen::Vector2d(offset / offset.norm());
  if (target == WiltingContractionTarget::Base)
  {
    out.towards = -out.fromBase;
  }
  else
  {
    const double offsetX = centreX - midX;
    out.towards[0] = std::abs(offsetX) <= 0.5 * h ? 0.0 : (offsetX > 0.0 ? -1.0 : 1.0);
  }
  return out;
}

/// Adds voxel v's curl strain to its 28 springs (+d_v/2 between two bottom corners, -d_v/2 between two top corners).
void AddVoxelCurl(const VoxelGrid& grid, std::size_t v, const WiltingParameters& parameters, double stiffness,
  const VoxelDirections& directions, const std::vector<int>& voxelSprings, std::vector<double>& curl)
{
  const std::array<int, 8>& c = grid.corners[v];
  const double strain = (1.0 + parameters.curlAsymmetry * directions.side) * parameters.curlStrain;
  // Radial: the strain along the line from the base, (n . r)^2 of it along a spring of direction n, r =
  // fromBase (none for the voxels within h/2 of the base in the XY plane).
  const bool radial = parameters.curlDirection == WiltingCurlDirection::Radial;
  const Eigen::Vector2d& r = directions.fromBase;
  std::size_t pair = 0;
  for (int a = 0; a < 8; ++a) // the pairs in the order AddVoxelSprings added them; corners 0-3 bottom, 4-7 top
  {
    for (int b = a + 1; b < 8; ++b, ++pair)
    {
      double face = (a < 4 && b < 4) ? 0.5 : ((a >= 4 && b >= 4) ? -0.5 : 0.0);
      if (radial && face != 0.0)
      {
        const Eigen::Vector3d n = (grid.nodes[static_cast<std::size_t>(c[static_cast<std::size_t>(b)])] -
          grid.nodes[static_cast<std::size_t>(c[static_cast<std::size_t>(a)])])
                                    .normalized();
        const double along = n[0] * r[0] + n[1] * r[1];
        face *= along * along;
      }
      curl[static_cast<std::size_t>(voxelSprings[28 * v + pair])] += stiffness * face * strain;
    }
  }
}

/// Every voxel's droop and contraction on its bottom (or top) corners, and its shrinkage and curl strains on its
/// springs (none for the petiole's voxels).
void AccumulateVoxelLoads(const VoxelGrid& grid, const Eigen::Vector3d& basePoint, const WiltingParameters& parameters,
  double springScale, double loadScale, double faceShare, const std::vector<int>& voxelSprings, FullLoads& loads)
{
  const double midX = basePoint[0];
  const double baseY = basePoint[1];
  const bool top = parameters.contractionSide == WiltingContractionSide::Top;
  for (std::size_t v = 0; v < grid.voxels.size(); ++v)
  {
    const std::array<int, 8>& c = grid.corners[v];
    const VoxelDirections directions = DirectionsOf(grid, v, midX, baseY, parameters.contractionTarget);
    const double side = directions.side;
    const Eigen::Vector2d& towards = directions.towards;
    const double droop = (1.0 + parameters.droopAsymmetry * side) * parameters.droopForce;
    const double contraction = (1.0 + parameters.contractionAsymmetry * side) * parameters.contractionForce;
    const int material = WiltingMaterialOf(grid.regions[v]);
    // The droop on the contraction side's four nodes; the contraction faceShare there and the rest on the other
    // face's (faceShare 1 in Lattice units: all on the side's face).
    for (int corner = 0; corner < 8 && material != WiltingPetiole; ++corner)
    {
      const bool onSide = top == (corner >= 4);
      const double share = onSide ? faceShare : 1.0 - faceShare;
      const std::size_t node = static_cast<std::size_t>(c[static_cast<std::size_t>(corner)]);
      if (share != 0.0)
      {
        loads.contraction[3 * node + 0] += 0.25 * share * loadScale * contraction * towards[0];
        loads.contraction[3 * node + 1] += 0.25 * share * loadScale * contraction * towards[1];
      }
      if (onSide)
      {
        loads.droop[3 * node + 2] -= 0.25 * loadScale * droop;
      }
    }
    const double stiffness = parameters.materials[static_cast<std::size_t>(material)].stiffness * springScale;
    if (parameters.shrinkageStrain != 0.0 && material != WiltingPetiole)
    {
      const double strain = (1.0 + parameters.shrinkageAsymmetry * side) * parameters.shrinkageStrain;
      std::size_t pair = 0;
      for (int a = 0; a < 8; ++a) // the pairs in the order AddVoxelSprings added them
      {
        for (int b = a + 1; b < 8; ++b, ++pair)
        {
          const double factor = OnOneFace(a, b) ? 1.0 : parameters.throughStiffness;
          loads.shrinkage[static_cast<std::size_t>(voxelSprings[28 * v + pair])] += factor * stiffness * strain;
        }
      }
    }
    if (parameters.curlStrain != 0.0 && material != WiltingPetiole)
    {
      AddVoxelCurl(grid, v, parameters, stiffness, directions, voxelSprings, loads.curl);
    }
  }
}

/// The loads at full load (FullLoads) for the finalised system: gravity from the lumped masses, the voxels' loads,
/// none on fixed nodes; the strains divided by each spring's stiffness from its voxels (`voxelStiffness`, without
/// the hold's: a partly held voxel is stiffer, its rest shape is the lamina's).
void ComputeFullLoads(const VoxelGrid& grid, const Eigen::Vector3d& basePoint, const WiltingParameters& parameters,
  double springScale, double loadScale, double faceShare, const std::vector<int>& voxelSprings,
  const std::vector<double>& voxelStiffness, const MassSpringSystem& springs, FullLoads& loads)
{
  const std::size_t n = grid.nodes.size();
  loads.gravity.assign(3 * n, 0.0);
  loads.droop.assign(3 * n, 0.0);
  loads.contraction.assign(3 * n, 0.0);
  // With shrinkage: per spring, the sum over its voxels of k_v e_v (divided by the spring's k below).
  loads.shrinkage.assign(parameters.shrinkageStrain == 0.0 ? 0 : springs.SpringCount(), 0.0);
  // With curl: the same for the curl strain (+d_v/2 between two bottom corners, -d_v/2 between two top corners).
  loads.curl.assign(parameters.curlStrain == 0.0 ? 0 : springs.SpringCount(), 0.0);
  const std::vector<double>& masses = springs.Masses();
  for (std::size_t i = 0; i < n; ++i)
  {
    loads.gravity[3 * i + 2] = -masses[i] * parameters.gravity;
  }
  AccumulateVoxelLoads(grid, basePoint, parameters, springScale, loadScale, faceShare, voxelSprings, loads);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (springs.IsFixed(i))
    {
      for (int c = 0; c < 3; ++c)
      {
        loads.gravity[3 * i + static_cast<std::size_t>(c)] = 0.0;
        loads.droop[3 * i + static_cast<std::size_t>(c)] = 0.0;
        loads.contraction[3 * i + static_cast<std::size_t>(c)] = 0.0;
      }
    }
  }
  for (std::vector<double>* strains : { &loads.shrinkage, &loads.curl })
  {
    for (std::size_t e = 0; e < strains->size(); ++e)
    {
      (*strains)[e] /= voxelStiffness[e];
    }
  }
}
} // namespace

WiltingParameters SimilarTo(const WiltingParameters& parameters, double longest)
{
  WiltingParameters similar = parameters;
  if (parameters.units != WiltingUnits::Physical || !(parameters.referenceLength > 0.0))
  {
    return similar;
  }
  const double scale = longest / parameters.referenceLength;
  for (WiltingMaterial& material : similar.materials)
  {
    material.stiffness *= scale;
  }
  similar.droopForce *= scale;
  similar.contractionForce *= scale;
  similar.referenceLength = 0.0;
  return similar;
}

std::string CoarseVoxelError(const WiltingParameters& parameters, double h, double thickness, double longest)
{
  if (h <= thickness * (1.0 + 1e-9))
  {
    return std::string();
  }
  // One voxel layer thicker than the lamina it stands for: the curl's strains (d h / t across the layer) and the
  // through-thickness springs ((h / t)^2 stiffer) leave the range where the lattice is the plate, and the runs
  // invert voxels or swing back (benchmarks/README.md "wilting convergence").
  std::ostringstream message;
  message << "the voxels (edge " << h << ") are coarser than the blade is thick (BladeThickness " << thickness
          << (parameters.bladeThickness > 0.0 ? "" : ", the leaf's longest side / 14")
          << "): Physical units need a voxel edge of at most the thickness, ";
  if (parameters.voxelSize > 0.0)
  {
    message << "VoxelSize at most " << thickness;
  }
  else
  {
    message << "the smallest Resolution that holds is "
            << static_cast<int>(std::ceil(longest / thickness * (1.0 - 1e-9)));
  }
  message << " (or a larger BladeThickness)";
  return message.str();
}

double WiltingBladeThickness(const WiltingParameters& parameters, double longest)
{
  return parameters.bladeThickness > 0.0 ? parameters.bladeThickness : longest / 14.0;
}

WiltingParameters WiltingLatticeOf(
  const WiltingParameters& parameters, double h, double thickness, double* faceShare, int* substeps)
{
  WiltingParameters lattice = parameters;
  if (faceShare)
  {
    *faceShare = 1.0;
  }
  if (substeps)
  {
    *substeps = 1;
  }
  if (parameters.units == WiltingUnits::Lattice)
  {
    return lattice;
  }
  const double t = thickness;
  lattice.units = WiltingUnits::Lattice;
  lattice.referenceVoxelSize = 0.0;
  for (WiltingMaterial& material : lattice.materials)
  {
    const double youngs = material.stiffness;
    material.stiffness = youngs * t * t * t / (18.0 * h * h); // D = 3/2 k h^2 = E t^3 / 12
    material.damping = material.damping * material.stiffness; // a retardation time
    material.density = material.density * t / h;              // rho t per area, h^2 of it per voxel
  }
  lattice.droopForce = parameters.droopForce * h * h;
  lattice.contractionForce = parameters.contractionForce * h * h;
  lattice.curlStrain = parameters.curlStrain * h / t; // curvature d / t on a plate of thickness h
  if (faceShare)
  {
    *faceShare = 0.5 * (1.0 + t / h); // moment arm t / 2: (F_side - F_other) h / 2 = q h^2 t / 2
  }
  lattice.throughStiffness = std::max(1.0, (h / t) * (h / t));
  const int steps =
    parameters.substeps > 0 ? parameters.substeps : std::max(1, static_cast<int>(std::ceil((t / h) * (t / h) - 1e-9)));
  lattice.newmark.timeStep = parameters.newmark.timeStep / steps;
  if (substeps)
  {
    *substeps = steps;
  }
  return lattice;
}

double WiltingLoadFactor(WiltingLoadProfile profile, double t, double loadTime)
{
  if (profile == WiltingLoadProfile::Constant)
  {
    return 1.0;
  }
  const double s = std::clamp(t / loadTime, 0.0, 1.0);
  if (profile == WiltingLoadProfile::Ramp)
  {
    return s;
  }
  const auto logistic = [](double x) { return 1.0 / (1.0 + std::exp(-12.0 * (x - 0.5))); };
  return (logistic(s) - logistic(0.0)) / (logistic(1.0) - logistic(0.0));
}

std::string WiltingSimulation::Setup(const WiltingInput& input, const WiltingParameters& parameters)
{
  this->Voxels = VoxelGrid();
  this->Springs = MassSpringSystem();
  this->Embed = WiltingEmbedding();
  this->FrameList.clear();
  this->WasAborted = false;
  this->FrameCount = 0;
  const std::string invalid = ValidateWilting(parameters);
  if (!invalid.empty())
  {
    return invalid;
  }
  this->Params = parameters;
  this->Points = input.points;
  if (!input.leafUV.empty() && input.leafUV.size() != input.points.size())
  {
    return "the LeafUV array does not have one value per point";
  }
  VoxelizeParameters options;
  options.voxelSize = parameters.voxelSize;
  options.resolution = parameters.resolution;
  options.maxVoxels = parameters.maxVoxels;
  // * From a Resolution, node planes through the base across and along the leaf: the midvein runs between two
  // voxel columns and the held ball is centred on a node at every Resolution. Centred on the bounding box, a
  // symmetric blade's midvein ran along a node plane at even Resolutions and through the middle of a voxel column at
  // odd ones, two lattices that fold differently along the midvein (the odd Resolutions' tip paths converged apart
  // from the even ones'), and the held voxels' shares of the ball changed with where the base fell in its cell. A
  // VoxelSize grid stays centred.
  const std::size_t base = input.points.empty() ? 0 : BasePoint(input);
  if (!input.points.empty() && !(parameters.voxelSize > 0.0))
  {
    const int across = AcrossAxis(input, base);
    options.align[static_cast<std::size_t>(across)] = true;
    options.align[static_cast<std::size_t>(1 - across)] = true;
    options.alignAt = input.points[base];
  }
  std::string error = Voxelize(input.points, input.triangles, input.regions, options, this->Voxels);
  if (!error.empty())
  {
    return error;
  }
  WidenMidvein(input.points, MidveinPoints(input), AcrossAxis(input, base), this->Voxels);
  this->PetioleCells = PetiolePlacement();
  if (parameters.petioleLength > 0.0)
  {
    error =
      AddPetiole(this->Voxels, input.points[base], parameters.petioleLength, parameters.maxVoxels, this->PetioleCells);
    if (!error.empty())
    {
      return error;
    }
  }
  const VoxelGrid& grid = this->Voxels;
  const double h = grid.h;
  // Physical units: the lattice's springs and per-voxel loads for this h (Lattice units: as they are).
  Eigen::Vector3d low = input.points.front(), high = input.points.front();
  for (const Eigen::Vector3d& x : input.points)
  {
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
  }
  const bool physical = parameters.units == WiltingUnits::Physical;
  this->Thickness = physical ? WiltingBladeThickness(parameters, (high - low).maxCoeff()) : 0.0;
  if (physical)
  {
    error = CoarseVoxelError(parameters, h, this->Thickness, (high - low).maxCoeff());
    if (!error.empty())
    {
      return error;
    }
  }
  double faceShare = 1.0;
  this->Params = WiltingLatticeOf(
    SimilarTo(parameters, (high - low).maxCoeff()), h, this->Thickness, &faceShare, &this->SubstepCount);
  if (physical && !(std::abs(this->Params.curlStrain) <= 1.0))
  {
    std::ostringstream message;
    message << OutOfRange("CurlStrain", parameters.curlStrain, "[-0.4, 0.4]",
      "and |CurlStrain| h / BladeThickness at most 1 for the voxel edge h = " + std::to_string(h));
    return message.str();
  }
  const double ratio = this->Params.referenceVoxelSize > 0.0 ? h / this->Params.referenceVoxelSize : 1.0;
  const double springScale = ratio;
  const double loadScale = ratio * ratio * ratio;
  const std::vector<int> voxelSprings = AddVoxelSprings(grid, this->Params, springScale, this->Springs);
  std::vector<double> voxelStiffness;
  for (const MassSpringSpring& spring : this->Springs.Springs())
  {
    voxelStiffness.push_back(spring.stiffness);
  }

  // Anchors: the petiole's far end, or the input's petiole points, or the blade's base.
  AnchorPlan anchors = PlanAnchors(input, parameters, this->PetioleCells, base);
  this->Radius =
    parameters.anchorFraction > 0.0 ? parameters.anchorFraction * (high - low).maxCoeff() : parameters.anchorRadius;
  const std::size_t fixedCount =
    HoldVoxelsNearAnchors(grid, anchors.anchors, this->Radius, this->Params, springScale, this->Springs);
  error = this->Embed.Bind(grid, input.points, parameters.tricubic);
  if (!error.empty())
  {
    return error;
  }
  if (anchors.heldNodes.empty() && fixedCount == 0)
  {
    const auto& held = grid.corners[static_cast<std::size_t>(this->Embed.Voxels()[anchors.firstAnchor])];
    anchors.heldNodes.assign(held.begin(), held.end());
  }
  for (int node : anchors.heldNodes)
  {
    this->Springs.SetFixed(node, true);
  }
  error = this->Springs.Finalize();
  if (!error.empty())
  {
    return error;
  }
  this->Tip = static_cast<int>(TipPointOf(input, base));

  // Forces at full load.
  FullLoads loads{ this->GravityForce, this->LoadForce, this->ContractionLoad, this->SpringShrinkage,
    this->SpringCurl };
  ComputeFullLoads(grid, input.points[base], this->Params, springScale, loadScale, faceShare, voxelSprings,
    voxelStiffness, this->Springs, loads);
  error = this->Newmark.Setup(this->Springs, this->Params.newmark);
  if (!error.empty())
  {
    return error;
  }
  // Frames as the user's TimeStep gives them (each of its steps SubstepCount integrator steps).
  this->StepsPerFrame = this->SubstepCount *
    std::max(1, static_cast<int>(std::lround(parameters.frameInterval / parameters.newmark.timeStep)));
  const double frameTime = this->StepsPerFrame * this->Params.newmark.timeStep;
  this->FrameCount = 1 + static_cast<int>(std::floor(parameters.duration / frameTime + 1e-9));
  return std::string();
}

std::vector<double> WiltingSimulation::FrameTimes() const
{
  std::vector<double> times;
  for (int f = 0; f < this->FrameCount; ++f)
  {
    times.push_back(f * this->StepsPerFrame * this->Params.newmark.timeStep);
  }
  return times;
}

void WiltingSimulation::ExternalForce(double t, std::vector<double>& force) const
{
  // * Gravity comes in with the droop: the turgid leaf at t = 0 carries its own weight (its shape is the input's),
  // and what the wilting withdraws is that support, so the net weight grows from zero on the droop's profile
  // (Constant, the paper's: at once). Applied at once to a leaf at rest, it dropped the blade like a released
  // spring, and a large, soft leaf (Tomato, 40 cm) overshot and swung back 11-17 % of its length.
  const double factor = WiltingLoadFactor(this->Params.loadProfile, t, this->Params.loadTime);
  const double contraction = this->ContractionFactor(t);
  force.resize(this->GravityForce.size());
  for (std::size_t k = 0; k < force.size(); ++k)
  {
    force[k] = factor * (this->GravityForce[k] + this->LoadForce[k]) + contraction * this->ContractionLoad[k];
  }
}

namespace
{
/// A duration property: its own value, or (0) the one it defaults to.
double OwnOr(double time, double fallback)
{
  return time > 0.0 ? time : fallback;
}
}

double WiltingSimulation::ContractionFactor(double t) const
{
  return WiltingLoadFactor(this->Params.loadProfile, t, OwnOr(this->Params.contractionTime, this->Params.loadTime));
}

double WiltingSimulation::ShrinkageFactor(double t) const
{
  const double contractionTime = OwnOr(this->Params.contractionTime, this->Params.loadTime);
  return WiltingLoadFactor(this->Params.loadProfile, t, OwnOr(this->Params.shrinkageTime, contractionTime));
}

double WiltingSimulation::CurlFactor(double t) const
{
  const double contractionTime = OwnOr(this->Params.contractionTime, this->Params.loadTime);
  const double relaxation = this->Params.curlRelaxation == 0.0 ? 0.0
                                                               : this->Params.curlRelaxation *
      WiltingLoadFactor(this->Params.loadProfile, t, OwnOr(this->Params.curlRelaxationTime, this->Params.loadTime));
  return WiltingLoadFactor(this->Params.loadProfile, t, OwnOr(this->Params.curlTime, contractionTime)) - relaxation;
}

void WiltingSimulation::SpringStrains(double t, std::vector<double>& strains) const
{
  // The profiles once per time, not per spring.
  const double shrinkage = this->SpringShrinkage.empty() ? 0.0 : this->ShrinkageFactor(t);
  const double curl = this->SpringCurl.empty() ? 0.0 : this->CurlFactor(t);
  strains.resize(this->Springs.SpringCount());
  for (std::size_t e = 0; e < strains.size(); ++e)
  {
    double strain = this->SpringShrinkage.empty() ? 0.0 : shrinkage * this->SpringShrinkage[e];
    if (!this->SpringCurl.empty())
    {
      strain += curl * this->SpringCurl[e];
    }
    strains[e] = strain;
  }
}

void WiltingSimulation::RestLengthsFromStrains(const std::vector<double>& strains, std::vector<double>& lengths) const
{
  const std::vector<MassSpringSpring>& springs = this->Springs.Springs();
  lengths.resize(springs.size());
  for (std::size_t e = 0; e < springs.size(); ++e)
  {
    lengths[e] = springs[e].restLength * (1.0 - strains[e]);
  }
}

std::vector<double> WiltingSimulation::RestLengths(double t) const
{
  std::vector<double> strains, lengths;
  this->SpringStrains(t, strains);
  this->RestLengthsFromStrains(strains, lengths);
  return lengths;
}

std::vector<Eigen::Vector3d> WiltingSimulation::PointPositions(std::size_t f) const
{
  std::vector<double> d(3 * this->Points.size());
  this->Embed.Interpolate(this->FrameList[f].q.data(), d.data());
  std::vector<Eigen::Vector3d> x(this->Points.size());
  for (std::size_t p = 0; p < x.size(); ++p)
  {
    x[p] = this->Points[p] + Eigen::Vector3d(d[3 * p], d[3 * p + 1], d[3 * p + 2]);
  }
  return x;
}

std::string WiltingSimulation::Run(const std::function<bool(double)>& progress)
{
  this->FrameList.clear();
  this->WasAborted = false;
  this->Newmark.Reset();
  // With shrinkage or curl: the springs' strains at the step's start and end, and the rest lengths they give.
  std::vector<double> strainBefore, strainAfter, restLengths;
  if (this->RestLengthsChange())
  {
    this->SpringStrains(0.0, strainBefore);
    this->RestLengthsFromStrains(strainBefore, restLengths);
    this->Newmark.SetRestLengths(restLengths);
  }
  {
    // From rest (R = 0, v = 0) with the consistent acceleration M^-1 f(0): second order from the first step.
    std::vector<double> f0;
    this->ExternalForce(0.0, f0);
    std::vector<double> a0(f0.size(), 0.0);
    for (std::size_t i = 0; i < this->Springs.NodeCount(); ++i)
    {
      for (std::size_t c = 0; c < 3 && !this->Springs.IsFixed(i); ++c)
      {
        a0[3 * i + c] = f0[3 * i + c] / this->Springs.Masses()[i];
      }
    }
    this->Newmark.SetState(std::vector<double>(f0.size(), 0.0), std::vector<double>(f0.size(), 0.0), a0, 0.0);
  }
  const Eigen::Vector3d g(0.0, 0.0, -this->Params.gravity);
  const double gravity0 = this->Springs.GravityEnergy(this->Newmark.Displacement().data(), g);
  const std::vector<double> zero(this->GravityForce.size(), 0.0);
  // The tip's displacement weights, to record the trajectory without interpolating every point.
  const auto record = [&](double time) {
    WiltingFrame frame;
    frame.time = time;
    frame.q = this->Newmark.Displacement();
    frame.v = this->Newmark.Velocity();
    frame.kinetic = this->Springs.KineticEnergy(frame.v.data());
    frame.spring = this->Springs.SpringEnergy(frame.q.data());
    frame.gravity = this->Springs.GravityEnergy(frame.q.data(), g) - gravity0;
    std::vector<double> d(3 * this->Points.size());
    this->Embed.Interpolate(frame.q.data(), d.data());
    const std::size_t t = static_cast<std::size_t>(this->Tip);
    frame.tip = this->Points[t] + Eigen::Vector3d(d[3 * t], d[3 * t + 1], d[3 * t + 2]);
    this->FrameList.push_back(std::move(frame));
  };
  record(0.0);
  // Work bound for the energy guard: what the loads and gravity could have supplied.
  double work = 0.0;
  double gravityBound = 0.0;
  for (std::size_t i = 0; i < this->Springs.NodeCount(); ++i)
  {
    gravityBound += this->Springs.Masses()[i] * this->Params.gravity;
  }
  std::vector<double> force;
  std::vector<double> previousForce;
  this->ExternalForce(0.0, previousForce);
  const int totalSteps = (this->FrameCount - 1) * this->StepsPerFrame;
  const double dt = this->Params.newmark.timeStep;
  for (int step = 1; step <= totalSteps; ++step)
  {
    const double time = step * dt;
    this->ExternalForce(time, force);
    const std::vector<double> before = this->Newmark.Displacement();
    if (this->RestLengthsChange())
    {
      // The rest shape at the step's end, like the loads.
      this->SpringStrains(time, strainAfter);
      this->RestLengthsFromStrains(strainAfter, restLengths);
      this->Newmark.SetRestLengths(restLengths);
    }
    const std::string error = this->Newmark.Step(force);
    std::ostringstream message;
    if (!error.empty())
    {
      message << "the simulation blew up at step " << step << " (t = " << time << " s): " << error
              << "; reduce TimeStep or raise the stiffness or damping";
      return message.str();
    }
    const std::vector<double>& q = this->Newmark.Displacement();
    double maxDisplacement = 0.0;
    for (std::size_t k = 0; k < q.size(); ++k)
    {
      const double dq = q[k] - before[k];
      // Work of the droop and contraction loads and of the weight's support not yet withdrawn (trapezoid): full
      // gravity is in the energy.
      work += 0.5 * ((force[k] - this->GravityForce[k]) + (previousForce[k] - this->GravityForce[k])) * dq;
      maxDisplacement = std::max(maxDisplacement, std::abs(q[k]));
    }
    previousForce = force;
    if (this->RestLengthsChange())
    {
      // A rest length L (1 - x) is the spring of rest length L (the energies') with a pull k x L between its ends:
      // its work, at the step's mean x, on the step's change of length.
      const std::vector<MassSpringSpring>& springs = this->Springs.Springs();
      for (std::size_t e = 0; e < springs.size(); ++e)
      {
        const double mean = 0.5 * (strainBefore[e] + strainAfter[e]);
        work += springs[e].stiffness * mean * springs[e].restLength *
          (this->Springs.SpringLength(springs[e], before.data()) - this->Springs.SpringLength(springs[e], q.data()));
      }
      strainBefore.swap(strainAfter);
    }
    const double jacobian = this->Springs.MinimumRelativeJacobian(q.data());
    if (!(jacobian > 0.0))
    {
      message << "the simulation blew up at step " << step << " (t = " << time
              << " s): a voxel turned inside out (corner Jacobian " << jacobian
              << "); reduce TimeStep or the loads, or raise the stiffness";
      return message.str();
    }
    if (step % this->StepsPerFrame == 0)
    {
      record(time);
      const WiltingFrame& frame = this->FrameList.back();
      const double energy = frame.kinetic + frame.spring + frame.gravity;
      const double scale = std::max(1e-12, gravityBound * (maxDisplacement + this->Voxels.h));
      if (energy > 2.0 * std::max(0.0, work) + scale)
      {
        message << "the simulation blew up at step " << step << " (t = " << time << " s): its energy (" << energy
                << ") grew beyond the work of the loads (" << work << "); reduce TimeStep, or raise the damping";
        return message.str();
      }
    }
    if (progress && (step % 16 == 0 || step == totalSteps) &&
      !progress(static_cast<double>(step) / static_cast<double>(totalSteps)))
    {
      this->WasAborted = true;
      return std::string();
    }
  }
  return std::string();
}

} // namespace plantmorph
