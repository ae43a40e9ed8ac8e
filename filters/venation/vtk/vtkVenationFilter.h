// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkVenationFilter
 * @brief   Grows leaf veins on a blade (paper 000 sec. 3; docs/methods/venation.md).
 *
 * Related publication: [P000] Lu Ling, Wang Lei, "Visual modelling of plant leaf venation" (in Chinese; venue not
 * known): sec. 3, eqs. (2)-(7), Figs. 3-12.
 * Full references: docs/references.md. What the code does, and where and why it departs from the paper:
 * docs/methods/venation.md.
 *
 * Input: a triangulated blade carrying the point array `LeafUV` (every LeafOutlineSource blade does; any triangle
 * surface with the canonical leaf's (u, v) will do). Output port 0, **Veins**: the vein network as polylines lying
 * on the blade, with cell arrays `VeinOrder` (1 primary, 2 secondary, 3 tertiary: a reticulum vein joining
 * primaries or secondaries at both ends, 4 quaternary: the finer reticulum that only subdivides areoles, 5
 * free-ending veinlet; plantmorph::ReticulumOrders) and
 * `Region` (1 primary, 2 secondary, 3 tertiary and veinlets), point arrays `VeinWidth` (model units, the active
 * scalars; for tubes as wide as the veins give ParaView's Tube filter VeinWidth / 2 (a Calculator) with "Vary
 * Radius: By Absolute Scalar", which takes the scalar as the radius), `Region` (the lowest order through the
 * point), and the blade's `LeafUV` and `TCoords` interpolated; a junction is one point shared by the veins that
 * meet there. Output port 1, **Blade**: the input passed through, its points raised along the normals over the
 * veins when EmbossDepth is not 0 (paper Fig. 10b's relief; it needs a blade fine enough to show a vein's width).
 *
 * Output port 2, **Statistics** (vtkTable, one row per leaf; the filter grows one leaf, so one row), the measures
 * plant scientists report (LEAF GUI, phenoVein; filters/venation/measures/VeinNetworkMeasures.h), measured on the network
 * in the plane it grew in (the blade's own plane for a flat blade, so in the blade's units; ScaledLeafUV for a
 * curved one, approximate): `VLA` (vein length per blade area, in the blade's units^-1: mm/mm^2 = 1/mm for a blade
 * in mm), `TotalLength`, `BladeArea`, `AreoleCount` (bounded faces enclosed by veins alone), `AreoleAreaMean`,
 * `AreoleAreaMedian`, `AreoleAreaCV` (population standard deviation over the mean), `Loopiness` (minimum spanning
 * forest length over total length: 1 for a tree), `BranchPoints` (nodes where three or more segments meet),
 * `BranchPointsPerArea`, `FreeEnds` (ends not on the blade's outer margin), `FreeEndsPerArea`, and per VeinOrder
 * `LengthPrimary`, `LengthSecondary`, `LengthTertiary`, `LengthQuaternary`, `LengthVeinlet` and the same
 * `MeanWidth...` (length-weighted; 0 for an order
 * with no vein). Output port 3, **Areole histogram** (vtkTable): `AreoleHistogramBins` equal bins from the smallest
 * to the largest areole area, one row each: `BinLower`, `BinUpper`, `Count` (the counts sum to AreoleCount; no rows
 * when there is no areole).
 *
 * Field data on port 0, the same numbers (one set): `PlantMorph.VeinLength` (4 components: primary, secondary,
 * tertiary, veinlet total lengths), `PlantMorph.VeinDensity` (= VLA), `PlantMorph.BladeArea`,
 * `PlantMorph.AreoleCount`, `PlantMorph.AreoleAreaMean`, `PlantMorph.AreoleAreaStd` (= CV times the mean),
 * `PlantMorph.BranchPoints`, `PlantMorph.FreeEnds`, `PlantMorph.VeinSegments` (the growth's segment count), and the
 * parameters used (`PlantMorph.VenationPattern`, `PlantMorph.VenationPreset`, `PlantMorph.Seed`).
 *
 * The growth rules are plantmorph::GrowVenation's (filters/venation/core/VenationGrowth.h): primaries along u = const of
 * LeafUV, secondaries by eqs. (2)-(4) ending as the pattern says, reticulate tertiaries by seed growth with
 * junction angles around 120 degrees, free-ending veinlets, palmate veins by leaf growth with dichotomous forks.
 * Lengths are fractions of the leaf length (the midvein's), so a preset fits any leaf size.
 *
 * Where the veins grow: when the blade is flat (every point within 1e-6 of its size of its least-squares plane,
 * as LeafOutlineSource's flat blades are), in that plane, so angles and lengths are the blade's own (exactly its
 * x, y when it lies in a plane z = constant). A curved blade (Model B with torsion, a blade curled or wilted
 * already) is grown in LeafUV scaled by the blade's mean stretch along u and along v (a least-squares fit over its
 * edges); angles are then approximate, and venation is best grown before curling. Either way every vein point is
 * mapped onto the blade through the triangle holding it (barycentric interpolation of the input's points), so the
 * veins lie on the surface whatever deformed it.
 *
 * `Preset` 0 (Custom) uses the properties below; 1 paper mulberry (Fig. 10, brochidodromous, secondaries at 45-70
 * degrees, reticulate tertiaries), 2 ginkgo (Fig. 11, palmate, two veins forking five times), 3 poplar (Fig. 12, semicraspedodromous,
 * reticulate with veinlets), and the wilting species 4 cucumber (palmate, five primaries to the lobe tips, reticulate),
 * 5 tomato (a leaflet of the compound leaf: pinnate semicraspedodromous with veinlets), 6 watermelon (palmate into
 * each lobe tip, veinlets) set them all except Seed, EmbossDepth, MaxSegments and AreoleHistogramBins. Same input, parameters and Seed:
 * the same output, bit for bit.
 *
 * Errors (vtkErrorMacro naming the property or array and its accepted range, and empty outputs, never a crash):
 * out-of-range or non-finite properties, no LeafUV (two components), non-triangle cells, a non-manifold edge, a
 * network that would need more than MaxSegments segments. An empty input gives empty outputs without an error
 * (pieces other than 0 of a PlantMorph source are empty under MPI, so the veins appear once).
 *
 * The values the veins grew with (a named preset's own, or the properties for Custom) are written to the veins'
 * field data as `PlantMorph.Venation.<property>` (e.g. PlantMorph.Venation.DivergenceAngle), so what a preset chose
 * can be read in ParaView's Information panel.
 *
 * Several leaves (a point or cell array `LeafId`, else separate connected blades, e.g. LeafOutlineSource outputs
 * appended; common/vtk/PlantMorphLeafExchange.h): the veins grow on each leaf alone, with the same parameters and
 * the same Seed, so every leaf's veins, blade and tables are those of the leaf run alone, bit for bit. Veins and
 * Blade are the leaves' results appended in LeafId order, each point and cell marked with the point and cell array
 * `LeafId` (the blades' numbers 0, 1, ... in the order of their first points when the input has no LeafId);
 * Statistics has one row per leaf and the Areole histogram each leaf's bins, both with a first column `LeafId`, in
 * LeafId order. The veins' field data then holds the parameters, the Seed and `PlantMorph.LeafCount` (each leaf's
 * measures are its Statistics row). Under MPI each leaf grows on one rank (largest leaves first, each to the least
 * loaded rank), its veins and blade stay there, and the tables are gathered on rank 0; one leaf grows on rank 0.
 *
 * Presets: the properties a named preset sets are used only when it is Custom. One changed from its default while a
 * named preset is on is not what the output has, so a warning names it and says to choose Custom (the same in
 * pvpython, the GUI and a loaded state file, whose outputs are unchanged).
 */
#ifndef vtkVenationFilter_h
#define vtkVenationFilter_h

#include "PlantMorphVenationVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for MakeParameters and PresetValues

class vtkTable;

namespace plantmorph
{
struct VenationParameters;
class LeafPlan;
class Run;
}

class PLANTMORPHVENATIONVTK_EXPORT vtkVenationFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkVenationFilter* New();
  vtkTypeMacro(vtkVenationFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  // Setters do not clamp: an out-of-range value is reported when the filter runs (and the outputs are empty), so a
  // typo in a script is seen rather than silently replaced by the end of the range.

  ///@{
  /** 0 Custom (the properties below), 1 paper mulberry, 2 ginkgo, 3 poplar, 4 cucumber, 5 tomato, 6 watermelon.
   * Default 1. */
  vtkSetMacro(Preset, int);
  vtkGetMacro(Preset, int);
  ///@}

  ///@{
  /**
   * The venation type of paper 000 Fig. 3: 0 craspedodromous, 1 semicraspedodromous, 2 brochidodromous, 3
   * eucamptodromous, 4 reticulodromous, 5 cladodromous, 6 arcuate (acrodromous), 7 parallel, 8 palmate
   * (actinodromous, by leaf growth). Default 2.
   */
  vtkSetMacro(Pattern, int);
  vtkGetMacro(Pattern, int);
  ///@}

  ///@{
  /** Seed of every random choice (branch point jitter, tertiary lengths and angles, veinlets). Default 0. */
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /** Arcuate: number of primaries [1, 51] (default 3) and |u| of the outermost [0, 0.49] (default 0.3). */
  vtkSetMacro(PrimaryCount, int);
  vtkGetMacro(PrimaryCount, int);
  vtkSetMacro(PrimarySpread, double);
  vtkGetMacro(PrimarySpread, double);
  ///@}

  ///@{
  /** Parallel: number of primaries [1, 101] (default 9) and |u| of the outermost [0, 0.49] (default 0.45). */
  vtkSetMacro(ParallelVeins, int);
  vtkGetMacro(ParallelVeins, int);
  vtkSetMacro(ParallelSpread, double);
  vtkGetMacro(ParallelSpread, double);
  ///@}

  ///@{
  /**
   * Secondary veins (eqs. (2)-(4)): spacing of branch points along the midvein in leaf lengths [0.005, 1] (default
   * 0.1); divergence angle from the midvein at the base and at the apex, degrees [5, 90] (default 55, 55); k of
   * eq. (2) at the base and the apex [0, 50] (default 1, 5); where forks happen, as a fraction of the way to the
   * margin [0.05, 0.98] (default 0.8); c of eq. (3) for cladodromous branches [0, 10] (default 1).
   */
  vtkSetMacro(SecondarySpacing, double);
  vtkGetMacro(SecondarySpacing, double);
  vtkSetMacro(DivergenceAngle, double);
  vtkGetMacro(DivergenceAngle, double);
  vtkSetMacro(DivergenceAngleApex, double);
  vtkGetMacro(DivergenceAngleApex, double);
  vtkSetMacro(SecondaryCurvatureBase, double);
  vtkGetMacro(SecondaryCurvatureBase, double);
  vtkSetMacro(SecondaryCurvatureApex, double);
  vtkGetMacro(SecondaryCurvatureApex, double);
  vtkSetMacro(ForkFraction, double);
  vtkGetMacro(ForkFraction, double);
  vtkSetMacro(BranchCurvature, double);
  vtkGetMacro(BranchCurvature, double);
  ///@}

  ///@{
  /**
   * Tertiary (reticulate) veins by seed growth: on or off (default on); edge length, the areole size, in leaf
   * lengths [0.001, 0.5] (default 0.05); smallest junction angle, degrees [0, 110] (default 60); standard
   * deviation of junction angles around 120 degrees [0, 60] (default 10).
   */
  vtkSetMacro(Tertiary, bool);
  vtkGetMacro(Tertiary, bool);
  vtkBooleanMacro(Tertiary, bool);
  vtkSetMacro(AreoleSize, double);
  vtkGetMacro(AreoleSize, double);
  /// Hierarchical reticulum [0, 0.8] (default 0): tertiary edges (1 + g) AreoleSize beside the primaries, falling
  /// to (1 - g) AreoleSize at the point farthest from them.
  vtkSetMacro(AreoleGradient, double);
  vtkGetMacro(AreoleGradient, double);
  vtkSetMacro(MinJunctionAngle, double);
  vtkGetMacro(MinJunctionAngle, double);
  vtkSetMacro(JunctionAngleDeviation, double);
  vtkGetMacro(JunctionAngleDeviation, double);
  ///@}

  ///@{
  /** Free-ending veinlets in the areoles (default off; needs Tertiary), their piece length in areole sizes [0.05, 2]. */
  vtkSetMacro(Veinlets, bool);
  vtkGetMacro(Veinlets, bool);
  vtkBooleanMacro(Veinlets, bool);
  vtkSetMacro(VeinletLength, double);
  vtkGetMacro(VeinletLength, double);
  ///@}

  ///@{
  /**
   * Palmate venation by leaf growth: veins from the base [1, 64] (default 4), dichotomous fork levels [0, 5]
   * (default 1), growth fraction of the first fork [0.01, 0.99] (default 0.3).
   */
  vtkSetMacro(PalmateVeins, int);
  vtkGetMacro(PalmateVeins, int);
  /// Where palmate vein ends lie: 1 (default) fanned over the blade's margin, one per lobe; 0 paper 000's
  /// construction, evenly along the canonical leaf's far edge (the Cucumber wilting preset was fitted on it).
  vtkSetMacro(PalmateEnds, int);
  vtkGetMacro(PalmateEnds, int);
  vtkSetMacro(ForkLevels, int);
  vtkGetMacro(ForkLevels, int);
  /// Palmate: secondaries off each primary, 0 none (default), 1 craspedodromous (to the margin), 2 brochidodromous
  /// (looping); spaced, angled and forked by the secondary-vein properties.
  vtkSetMacro(PalmateSecondaries, int);
  vtkGetMacro(PalmateSecondaries, int);
  /// Palmate: 1 sends one secondary from the nearest primary to every sub-lobe tip found on the margin (a sub-lobe:
  /// a bulge between two sinuses at least 0.02 leaf lengths deep, seen from the primaries); 0 (default) none.
  vtkSetMacro(SubLobeVeins, int);
  vtkGetMacro(SubLobeVeins, int);
  /// Pinnate: 1 adds straight secondaries into the parts of the blade farther than SecondarySpacing from every
  /// primary and secondary (a broad blade's flanks below the lowest secondaries), at most 8; 0 (default) none.
  vtkSetMacro(FlankSecondaries, int);
  vtkGetMacro(FlankSecondaries, int);
  vtkSetMacro(ForkSize, double);
  vtkGetMacro(ForkSize, double);
  ///@}

  ///@{
  /**
   * Space colonization (Runions et al. 2005): kill distance [0.0002, 0.2] leaf lengths (default 0.01), attraction
   * distance [KillDistance, 2] (default 0.1), auxin-source darts per leaf length squared [1, 1e8] (default 3000),
   * Murray exponent of the pipe model [1, 4] (default 3), blade size when veins start [0.02, 1] (default 0.1).
   */
  vtkSetMacro(KillDistance, double);
  vtkGetMacro(KillDistance, double);
  vtkSetMacro(AttractionDistance, double);
  vtkGetMacro(AttractionDistance, double);
  vtkSetMacro(SourceDensity, double);
  vtkGetMacro(SourceDensity, double);
  vtkSetMacro(MurrayExponent, double);
  vtkGetMacro(MurrayExponent, double);
  vtkSetMacro(GrowthStart, double);
  vtkGetMacro(GrowthStart, double);
  /** Space colonization: closed venation (veins meet at sources, making loops) instead of open (a tree). */
  vtkSetMacro(ClosedVenation, bool);
  vtkGetMacro(ClosedVenation, bool);
  vtkBooleanMacro(ClosedVenation, bool);
  ///@}

  ///@{
  /**
   * Space colonization: marginal growth (Runions et al. 2005), auxin sources added only within one
   * AttractionDistance of the growing margin, so the finest veins form last near the margin; off (default): added
   * uniformly over the whole blade as it grows.
   */
  vtkSetMacro(MarginalGrowth, bool);
  vtkGetMacro(MarginalGrowth, bool);
  vtkBooleanMacro(MarginalGrowth, bool);
  ///@}

  ///@{
  /**
   * Widths: primary width at the base in leaf lengths [0, 0.2] (default 0.015), its end width as a fraction
   * [0, 1] (default 0.3); secondary, tertiary and veinlet widths as fractions of the primary's [0, 1] (default
   * 0.5, 0.2, 0.12).
   */
  vtkSetMacro(PrimaryWidth, double);
  vtkGetMacro(PrimaryWidth, double);
  vtkSetMacro(PrimaryTaper, double);
  vtkGetMacro(PrimaryTaper, double);
  vtkSetMacro(SecondaryWidthRatio, double);
  vtkGetMacro(SecondaryWidthRatio, double);
  vtkSetMacro(TertiaryWidthRatio, double);
  vtkGetMacro(TertiaryWidthRatio, double);
  vtkSetMacro(VeinletWidthRatio, double);
  vtkGetMacro(VeinletWidthRatio, double);
  ///@}

  ///@{
  /**
   * Relief on the Blade port: the height, in model units, a vein of the primary's width raises the blade along
   * its normals (a smooth bump as wide as the vein, finer veins proportionally lower). [-1e3, 1e3], default 0 (the
   * blade passes through unchanged).
   */
  vtkSetMacro(EmbossDepth, double);
  vtkGetMacro(EmbossDepth, double);
  ///@}

  ///@{
  /** The most vein segments a network may need [100, 1e8] (default 2e6); more is refused with a message. */
  vtkSetMacro(MaxSegments, int);
  vtkGetMacro(MaxSegments, int);
  ///@}

  ///@{
  /** Bins of the Areole histogram port [1, 1e4], default 20: equal bins from the smallest to the largest area. */
  vtkSetMacro(AreoleHistogramBins, int);
  vtkGetMacro(AreoleHistogramBins, int);
  ///@}

  /**
   * What the named Preset sets, one "Property = value" per line (Pattern by name), for the read-only PresetValues
   * box of the Properties panel, which shows it beside the greyed-out properties the preset overrides; for Custom,
   * a line saying the properties are used. Computed from Preset alone (no update needed); the veins' field data
   * holds the same values as PlantMorph.Venation.<property>.
   */
  const char* GetPresetValues();

protected:
  vtkVenationFilter();
  ~vtkVenationFilter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  /// Ports 0 (Veins) and 1 (Blade): vtkPolyData; 2 (Statistics) and 3 (Areole histogram): vtkTable.
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// With a named Preset, warns about each property only Custom uses that was changed from its default (it is not
  /// what the output has).
  void WarnAboutPresetOverrides();
  /// The parameters to grow with (the named preset's, or the properties for Custom); a message naming the first
  /// out-of-range property of the wrapper's own, else empty (the algorithm validates the rest).
  std::string MakeParameters(plantmorph::VenationParameters& parameters);
  /// The wrapper's own settings (Preset, EmbossDepth, MaxSegments, AreoleHistogramBins): "" or a message naming the
  /// first out of range.
  std::string ValidateSettings();
  /// The growth properties into `parameters` (Custom).
  void ReadCustomParameters(plantmorph::VenationParameters& parameters);
  /// Several leaves: grows the veins of each leaf `plan` gives this rank, alone, and appends them; the tables'
  /// rows gathered on rank 0 in LeafId order (collective).
  void GrowLeaves(plantmorph::Run& run, const plantmorph::LeafPlan& plan);
  /// RequestData's body (PlantMorphLayer.h): the leaves found (one, or several each on its rank) grow their veins.
  void Execute(plantmorph::Run& run);

  std::string PresetValues;
  int Preset = 1;
  int Pattern = 2;
  int Seed = 0;
  int PrimaryCount = 3;
  double PrimarySpread = 0.3;
  int ParallelVeins = 9;
  double ParallelSpread = 0.45;
  double SecondarySpacing = 0.1;
  double DivergenceAngle = 55.0;
  double DivergenceAngleApex = 55.0;
  double SecondaryCurvatureBase = 1.0;
  double SecondaryCurvatureApex = 5.0;
  double ForkFraction = 0.8;
  double BranchCurvature = 1.0;
  bool Tertiary = true;
  double AreoleSize = 0.05;
  double AreoleGradient = 0.0;
  double MinJunctionAngle = 60.0;
  double JunctionAngleDeviation = 10.0;
  bool Veinlets = false;
  double VeinletLength = 0.4;
  int PalmateVeins = 4;
  int PalmateEnds = 1;
  int ForkLevels = 0;
  int PalmateSecondaries = 0;
  int SubLobeVeins = 0;
  int FlankSecondaries = 0;
  double ForkSize = 0.3;
  double KillDistance = 0.01;
  double AttractionDistance = 0.1;
  double SourceDensity = 3000.0;
  double MurrayExponent = 3.0;
  double GrowthStart = 0.1;
  bool ClosedVenation = false;
  bool MarginalGrowth = false;
  double PrimaryWidth = 0.015;
  double PrimaryTaper = 0.3;
  double SecondaryWidthRatio = 0.5;
  double TertiaryWidthRatio = 0.2;
  double VeinletWidthRatio = 0.12;
  double EmbossDepth = 0.0;
  int MaxSegments = 2000000;
  int AreoleHistogramBins = 20;

private:
  vtkVenationFilter(const vtkVenationFilter&) = delete;
  void operator=(const vtkVenationFilter&) = delete;
};

#endif
