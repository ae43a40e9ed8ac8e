// SPDX-License-Identifier: GPL-3.0-or-later
// Venation of paper 000 (sec. 3; docs/methods/venation.md) grown on any blade that carries LeafUV: the algorithm layer
// of VenationFilter.
//
// Everything grows in the blade's flat working plane (VenationBlade.h) inside one planar VeinGraph whose margin
// edges are the blade's boundary, so no vein leaves the blade and every ending on the margin or on another vein is
// a shared node (VeinGraph.h).
//
// - Primary veins (sec. 3.1.1): the curves u = u_i of LeafUV from the base (v = 0) to the apex (v = 1), traced by
//   locating (u_i, v) in the blade's LeafUV: the midvein u = 0 for pinnate patterns, `primaries` curves evenly over
//   |u| <= `primarySpread` for arcuate (acrodromous) ones and `parallelVeins` over |u| <= `parallelSpread` for
//   parallel ones, all starting at the base node (on a pointed leaf they also meet at the apex).
// - Secondary veins (sec. 3.1.2): branch points every `secondarySpacing` along the midvein, each moved up by a
//   random amount in [0, spacing/2], left and right sides independent. In the frame of the midvein at the branch
//   point (T towards the apex, N outwards) a secondary is y = s*cot(theta) + k*w*(s/w)^2 at lateral distance s:
//   eq. (2)'s arch with k rising from `curvatureBase` at the base to `curvatureApex` at the apex, started at the
//   divergence angle theta (from `divergenceAngle` at the base to `divergenceAngleApex` at the apex, so
//   divergence is no longer a right angle as in the printed eq. (2)). The pattern decides how it ends:
//   craspedodromous on the margin; brochidodromous forks at `forkFraction` of its way to the margin and loops to
//   the fork of the secondary above along eq. (4)'s cubic (x = x_f + dx*t^3, y = y_f + dy*t); semicraspedodromous
//   does both; eucamptodromous stops at the fork and turns up along the loop's first half, ending free;
//   reticulodromous stops free halfway; cladodromous forks and its branch turns towards the base along eq. (3),
//   y = y_f - c*sqrt(w*x) (c = `branchCurvature`), to the margin.
// - Tertiary veins by seed growth (sec. 3.1.3): seeds on the secondaries (on the primaries where a pattern has no
//   secondaries) every three areole sizes, each growing a first edge away from its vein; every free node then adds
//   two edges with junction angles drawn around 120 deg (deviation `junctionAngleDeviation`, every angle at least
//   `minJunctionAngle`) of lengths 0.6..1.4 `areoleSize`. An edge meeting a vein stops there (a junction on it);
//   growth is breadth first over all fronts. Termination: after a budget of edges (40 per areole the blade holds,
//   at most `maxSegments`) every remaining front is extended straight until it meets a vein or the margin, so the
//   network stays closed.
// - Veinlets (Fig. 8b): in every areole larger than the veinlet length squared, a free-ending chain of one to three
//   short edges (`veinletLength` areole sizes each) from the middle of one of its edges, first edge perpendicular
//   to it, stopping before it would meet anything (VeinOrder 4).
// - Palmate venation by leaf growth (sec. 3.2): the primaries' end points lie on the blade's real margin, fanned
//   over its angular extent seen from the base (PalmateFan.h; docs/methods/venation.md): one at each lobe tip of a lobed blade, the two
//   outermost at the basal lobes of a cordate one, otherwise `palmateVeins` spread evenly in angle; each primary's
//   2^`forkLevels` branch ends spread over its share of the angles. The vein of each end point is its path through
//   the leaf growing about its base: P(g) = B + g*(p(g) - B), g from 0 to 1, a straight ray wherever every such
//   path stays inside the blade (a blade star-shaped from its base); otherwise the same construction in LeafUV,
//   P(g) = F(g*p(g) + (0, g*(1 - g)*(1 - v_p)/4)) (F: LeafUV to the blade, v_p the end's v), which cannot leave the
//   blade (the ginkgo's cusp-like base, cordate blades' basal lobes) and arches into the blade rather than along a
//   base edge v = 0.
//   Dichotomous forks: a group of end points shares one parameter (their mean) until growth `forkSize` (later
//   levels evenly after it), then the two halves move linearly apart to their own means by g = 1, so one vein
//   splits into two.
//   Sub-lobe veins (`subLobeVeins`, palmate only, not in the paper): a sub-lobe tip is a vertex of the outer boundary
//   loop where the distance d to the nearest primary has a local maximum, and walking the loop either way from it
//   one meets a concave (reflex) vertex at least 0.02 L lower in d before meeting a higher d or a primary's end
//   (d < 0.01 L): a lobe's smooth flank, which falls to its primary's end at the lobe tip without a sinus, is no
//   sub-lobe. From the foot F of the tip T on its nearest primary, at distance h, the vein leaves the primary
//   h cot(theta)/2 nearer the base (theta the divergence angle) and is the quadratic Bezier curve through the control
//   point (F + T)/2: it leaves at the divergence angle and meets the margin at T along FT. These are grown before
//   the regular secondaries, which stop where they meet them.
//
// - Space colonization (Runions et al. 2005, open venation), a method of its own: SpaceColonization.h.
//
// Widths (`VeinWidth`): primaries taper from `primaryWidth` (a fraction of the leaf length) to `primaryTaper` of it
// at their end; secondaries from `secondaryWidthRatio` of it to half that; tertiaries and veinlets a constant
// `tertiaryWidthRatio` and `veinletWidthRatio` of it, quaternaries (the finer reticulum) the mean of the two (at
// most the tertiaries' ratio). A shared node takes the widest vein's width.
// Lengths (`secondarySpacing`, `areoleSize`, `veinletLength` in areole sizes, `primaryWidth`) are fractions of the
// leaf length L (the midvein's length in the working plane), so a preset fits any leaf size. All randomness comes
// from RandomStream(seed, phase): the same seed gives the same network bit for bit.
//
// Plain C++17 + Eigen, no VTK.
#pragma once

#include "VeinGraph.h"
#include "VenationBlade.h"

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace plantmorph
{

enum class VenationPattern : int
{
  Craspedodromous = 0,
  Semicraspedodromous = 1,
  Brochidodromous = 2,
  Eucamptodromous = 3,
  Reticulodromous = 4,
  Cladodromous = 5,
  Arcuate = 6,
  Parallel = 7,
  Palmate = 8,
  SpaceColonization = 9, ///< Runions et al. 2005, open venation (SpaceColonization.h)
};
inline constexpr int VenationPatternCount = 10;

/// Palmate: the secondaries each primary sends towards the margin (docs/methods/venation.md "Palmate secondaries").
enum class PalmateSecondaries : int
{
  None = 0,            ///< bare primaries (paper 000's Fig. 9)
  Craspedodromous = 1, ///< each secondary runs on to the margin
  Brochidodromous = 2, ///< each forks at `forkFraction` of its way and loops to the next one out along its primary
};
inline constexpr int PalmateSecondariesCount = 3;

struct VenationParameters
{
  VenationPattern pattern = VenationPattern::Brochidodromous;
  std::uint64_t seed = 0;
  int primaries = 3;                 ///< arcuate: number of primary veins (odd counts include the midvein)
  double primarySpread = 0.3;        ///< arcuate: |u| of the outermost primaries, [0, 0.49]
  int parallelVeins = 9;             ///< parallel: number of primary veins
  double parallelSpread = 0.45;      ///< parallel: |u| of the outermost primaries, [0, 0.49]
  double secondarySpacing = 0.1;     ///< distance between branch points along the midvein, in leaf lengths
  double divergenceAngle = 55.0;     ///< degrees between midvein and secondary at the base, (5, 90]
  double divergenceAngleApex = 55.0; ///< the same at the apex (linear in between)
  double curvatureBase = 1.0;        ///< k of eq. (2) at the base
  double curvatureApex = 5.0;        ///< k of eq. (2) at the apex
  double forkFraction = 0.8;         ///< where secondaries fork, as a fraction of their way to the margin, (0, 1)
  double branchCurvature = 1.0;      ///< c of eq. (3) (cladodromous branches)
  bool tertiary = true;
  double areoleSize = 0.05; ///< tertiary edge length, in leaf lengths
  /// Hierarchical reticulum: tertiary edges are (1 + g) areoleSize long beside the primaries, falling linearly with
  /// the distance from them to (1 - g) areoleSize at the point of the blade farthest from any; 0: even, [0, 0.8]
  double areoleGradient = 0.0;
  double minJunctionAngle = 60.0;
  double junctionAngleDeviation = 10.0; ///< standard deviation of the junction angles around 120 deg
  bool veinlets = false;
  double veinletLength = 0.4; ///< in areole sizes
  int palmateVeins = 4;       ///< palmate: primaries on a blade without lobes (a lobed one gets one per lobe)
  /// palmate: where the vein ends lie. true: fanned over the blade's margin (PalmateFan.h); false: paper 000's
  /// construction, evenly along the canonical leaf's far edge v = 1, grown in LeafUV (the ends bunch towards the
  /// apex on an entire blade; kept because the Cucumber wilting preset was fitted on it).
  bool palmateFan = true;
  /// palmate: secondaries off every primary, every `secondarySpacing` along it on both sides, at the divergence
  /// angle (none where the primary's neighbour or the margin is nearer than half a spacing along that line)
  PalmateSecondaries palmateSecondaries = PalmateSecondaries::None;
  /// pinnate: secondaries into bare flanks (docs/methods/venation.md "Flank secondaries"): while some blade point
  /// lies farther than `secondarySpacing` from every primary and secondary, a straight secondary from the nearest
  /// such vein through that point on to the margin (at most 8)
  bool flankSecondaries = false;
  /// palmate: one secondary from the nearest primary to every sub-lobe tip of the margin (a local maximum of the
  /// distance from the primaries with a sinus at least 0.02 L deep on both sides; docs/methods/venation.md)
  bool subLobeVeins = false;
  /// palmate: dichotomous forks along each primary of an entire blade (the ginkgo's fan); 0: undivided primaries
  int forkLevels = 0;
  double forkSize = 0.3;       ///< growth fraction of the first dichotomous fork, (0, 1)
  double primaryWidth = 0.015; ///< in leaf lengths
  double primaryTaper = 0.3;   ///< width at the end of a primary, as a fraction of its width at the base
  double secondaryWidthRatio = 0.5;
  double tertiaryWidthRatio = 0.2;
  double veinletWidthRatio = 0.12;
  // Space colonization (SpaceColonization.h); distances in leaf lengths of the full-grown blade.
  double killDistance = 0.01;      ///< a source dies when a vein node comes this close; the vein step is half of it
  double attractionDistance = 0.1; ///< a source draws its nearest vein node within this distance
  double sourceDensity = 3000.0;   ///< auxin-source darts per unit blade area (leaf length squared)
  double murrayExponent = 3.0;     ///< pipe model: w^n of a vein is the sum of w^n of its branches
  double growthStart = 0.1;        ///< blade size (fraction of the final) when veins start; 1 = a static blade
  bool closedVenation = false; ///< closed: a source draws its whole relative neighbourhood and dies when all reach it
  /// marginal growth (Runions 2005): sources are added only within one attraction distance of the growing margin
  /// (false: uniformly over the whole blade as it grows)
  bool marginalGrowth = false;
  std::size_t maxSegments = 2000000; ///< refuse (with a message) networks that would need more edges
  /// Benchmarks only: the vein graph's grid cells as a multiple of their default size (about one areole); a huge
  /// value puts every edge in one cell, so every crossing test looks at every edge (brute force).
  double gridCellScale = 1.0;
};

/// Presets of paper 000's figures, and of the wilting species (paper 001; docs/methods/venation.md "Presets").
enum class VenationPreset : int
{
  Custom = 0,
  PaperMulberry = 1, ///< Broussonetia, Fig. 10: pinnate brochidodromous, secondaries at 45-70 deg, reticulate
  Ginkgo = 2,        ///< Fig. 11: palmate, dichotomous
  Poplar = 3,        ///< Fig. 12: semicraspedodromous, reticulate tertiaries with free-ending veinlets
  Cucumber = 4,      ///< palmate: five primaries to the lobe and basal-lobe tips, reticulate
  Tomato = 5,        ///< one leaflet of the compound leaf: pinnate semicraspedodromous, reticulate with veinlets
  Watermelon = 6,    ///< palmate, one primary to each lobe tip, fine reticulum with veinlets
};
inline constexpr int VenationPresetCount = 7;
VenationParameters MakeVenationPreset(VenationPreset preset);
std::string VenationPresetName(VenationPreset preset);
std::string VenationPatternName(VenationPattern pattern);
/// The parameters a venation grows with that a named preset sets, by VenationFilter's property names, in the
/// order of its panel (booleans and enumerations as numbers).
std::vector<std::pair<const char*, double>> VenationParameterValues(const VenationParameters& parameters);
/// What a named preset sets, for the read-only PresetValues box of VenationFilter's panel: a title line, then one
/// "Property = value" line per VenationParameterValues entry (Pattern by name).
std::string DescribeVenationPreset(VenationPreset preset);

/// Empty when every parameter is in range; otherwise the message naming the property and its accepted range.
std::string ValidateVenationParameters(const VenationParameters& parameters);

struct VenationStatistics
{
  double length[VeinOrderCount] = {}; ///< total vein length per VeinOrder (index 0 unused: the margin)
  double density = 0.0;               ///< total vein length per blade area
  double bladeArea = 0.0;
  std::size_t areoles = 0; ///< faces enclosed by veins only
  double areoleAreaMean = 0.0;
  double areoleAreaStd = 0.0;
  std::size_t branchPoints = 0; ///< nodes where three or more vein edges meet
  std::size_t freeEnds = 0;     ///< vein ends that meet nothing
  std::size_t segments = 0;     ///< vein edges (margin excluded)
};

struct VenationResult
{
  std::vector<Eigen::Vector2d> nodes;  ///< working-plane points of the vein nodes used by veins
  std::vector<BladeLocation> location; ///< each node's triangle and weights on the blade
  std::vector<double> width;           ///< VeinWidth of each node
  std::vector<int> order;              ///< lowest VeinOrder of the veins through each node
  struct Polyline
  {
    std::vector<int> nodes;
    int order = VeinOrderPrimary;
  };
  std::vector<Polyline> veins;
  VenationStatistics statistics;
  std::vector<double> junctionAngles; ///< growth junctions: the three angles of each, degrees (for tests)
  double leafLength = 0.0;
};

/// Grows the venation. Empty on success; otherwise a message (and `result` is empty). `progress` gets fractions in
/// [0, 1] and returns false to abort.
std::string GrowVenation(const VenationBlade& blade, const VenationParameters& parameters, VenationResult& result,
  const std::function<bool(double)>& progress = {});

/// Emboss heights for relief: for every blade point, depth * (w / w_max) * (1 - (d / w)^2)^2 of the nearest vein
/// within its width w (d the distance to it, w_max the widest vein), the highest over all veins; 0 elsewhere.
std::vector<double> VeinReliefHeights(const VenationBlade& blade, const VenationResult& veins, double depth);

} // namespace plantmorph
