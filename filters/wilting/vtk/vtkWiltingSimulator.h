// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkWiltingSimulator
 * @brief   Wilts a leaf: a voxel mass-spring model stepped by implicit Newmark, played as an animation (paper 001;
 *          docs/methods/wilting.md).
 *
 * Related publication: [P001] Miao Teng, Guo Xinyu, Wen Weiliang, Lu Shenglian, "A physically based representation
 * of leaf wilting" (in Chinese), Transactions of the Chinese Society for Agricultural Machinery 45(5), 2014:
 * secs. 1-3, eqs. (3)-(5), Figs. 1-5, Table 1.
 * Full references: docs/references.md. What the code does, and where and why it departs from the paper:
 * docs/methods/wilting.md.
 *
 * vtkWiltingSimulator voxelises the input surface (cubes of edge VoxelSize, or Resolution cubes along the longest
 * side; a cube is kept when an exact triangle-box test says a triangle touches it), joins the 8 corners of every
 * voxel by 28 springs (12 structural, 16 shear), gives each voxel the material of its most significant `Region`
 * (petiole > veins > margin > blade; without `Region` everything is blade), lumps the masses to the nodes, fixes
 * the nodes within AnchorRadius of the petiole (Region 5 points) or else of the blade's base, and simulates the
 * wilting from rest under gravity and a droop pull and a contraction towards the midvein applied to the voxels'
 * bottom (margin curls down) or top (curls up) nodes, their magnitude following LoadProfile in time, and
 * optionally the lamina shrinking in its own plane (ShrinkageStrain: the springs' rest lengths shorten) and its
 * lower face shrinking before its upper (CurlStrain: an intrinsic bend, along the lines from the base with
 * CurlDirection Radial, rising over CurlTime and partly relaxing over CurlRelaxationTime). The time
 * stepping is implicit Newmark (beta 1/4, gamma 1/2) with Newton-Raphson, Rayleigh damping on the tangent
 * stiffness (compression clamp optional), and a sparse Cholesky or preconditioned CG solve. Every input point
 * (surface and lines, e.g. veins) is bound once to its voxel and follows it by trilinear (or tricubic)
 * interpolation. See plantmorph::WiltingSimulation (filters/wilting/core/WiltingSimulation.h) for the model's formulas and
 * the choices made where the paper is silent (docs/methods/wilting.md says why).
 *
 * Petiole (PetioleLength > 0; not in the paper): a straight petiole of that length (whole voxels) is added from the
 * blade's base along -y in the blade's plane, one or two voxels wide and thick, with PetioleMaterial; a stand holds
 * its far end (the nodes within AnchorRadius of it, at least its end face) instead of the blade's base. The blade
 * can then sag, roll, yaw and swing on it, as a detached leaf on a stand does; the petiole carries gravity but no
 * wilting load. It shows in the voxel model (port 1, Region 5), not on port 0. The cucumber fit tried it and does
 * not use it (docs/wilting-calibration.md "Petiole").
 *
 * Time: the filter advertises TIME_STEPS (one per frame, every FrameInterval from 0 to Duration) and TIME_RANGE.
 * It simulates once per change of its input or properties, with progress over the whole run and abort honoured,
 * keeps every frame, and serves a requested time from that cache (linear interpolation between the two nearest
 * frames), so scrubbing the animation never re-simulates. The input is taken at its own (only) state: the
 * filter removes the update time from its upstream request.
 *
 * Input port 1, optional (`Veins`; SetVeinsConnection): polylines on the surface, e.g. VenationFilter's port 0
 * (feed its port 1, the blade, to port 0). Their points are not voxelised; they mark the voxels they lie in with
 * their `Region` (primary and secondary veins make vein voxels; tertiary veins and veinlets, finer than a voxel,
 * keep the blade's material) and follow the voxels like the surface's points (docs/methods/wilting.md: every input
 * point, surface and veins, follows the voxels). A single input holding both polygons and lines works too: its lines
 * are carried along on port 0.
 *
 * Outputs:
 * - port 0: the input with every point moved (points keep the input's precision) and every array passed through
 *   (TCoords stays the active texture coordinates), plus the point array `Displacement`;
 * - port 1: the voxel model, a vtkUnstructuredGrid of hexahedra, point arrays `Displacement`, `Velocity`, `Fixed`,
 *   `Mass`, cell array `Region`;
 * - port 2: a vtkTable of every frame: `Time`, `TipX`, `TipY`, `TipZ` (the tip: largest LeafUV v, else the point
 *   farthest from the base) and the energies `Kinetic`, `Spring`, `Gravity` (relative to rest);
 * - port 3: the veins (input port 1) moved with the leaf, every array kept, plus `Displacement`; empty without
 *   veins.
 *
 * Several leaves (a point or cell array `LeafId` on Input, else separate connected blades, e.g. LeafOutlineSource
 * outputs appended or VenationFilter's Blade of several leaves; common/vtk/PlantMorphLeafExchange.h): each leaf
 * wilts alone, with its own voxels, base, tip and veins, so each leaf's outputs are those of the leaf run alone, bit
 * for bit. The veins then need a point array `LeafId` naming their leaf (VenationFilter's veins of several leaves
 * have it; an error otherwise). Ports 0, 1 and 3 are the leaves' results appended in LeafId order, each point and
 * cell marked with `LeafId`; port 2 has every leaf's frames, a first column `LeafId`, in LeafId order. Under MPI each
 * leaf wilts on one rank (largest leaves first, each to the least loaded rank) and its outputs stay there; the
 * table is gathered on rank 0. One leaf wilts on rank 0, gathered whole.
 *
 * Field data on port 0: `WiltingSimulator.SimulationCount` (simulations run so far: scrubbing does not raise it)
 * and `WiltingSimulator.FrameTime` (the time served).
 *
 * Presets: with Preset other than Custom the materials, loads, load profile and Rayleigh damping come from the
 * preset (plantmorph::ApplyWiltingPreset: Cucumber, Tomato, Watermelon) and the corresponding properties are
 * ignored (Duration, TimeStep and the rest are always the properties'); with Custom they are used as set. The
 * Cucumber preset was fitted to paper 001's measured tip trajectory (docs/wilting-calibration.md) at this filter's
 * defaults (Resolution 14, AnchorRadius 3, TimeStep 1/60 s, one Newton iteration) on a 20.1 x 22.1 cm leaf.
 *
 * Units (docs/methods/wilting.md "Physical units"): with Units Physical (the default, and every preset)
 * the materials and loads describe the lamina, not the voxels: Density per volume of the lamina, Stiffness its
 * Young's modulus E (dyn/cm^2 with cm, = 0.1 Pa), Damping a retardation time (s), DroopForce and ContractionForce
 * pressures (force per area of leaf), CurlStrain the strain difference across BladeThickness (curvature
 * CurlStrain / BladeThickness), ShrinkageStrain a strain; BladeThickness 0 takes the leaf's longest side / 14.
 * plantmorph::WiltingLatticeOf turns them into per-spring and per-voxel values for the voxel edge used, so the
 * plate's bending stiffness E t^3 / 12, its mass and loads per area and its curvature are the same at every
 * Resolution, and sub-steps TimeStep when the voxels are finer than the blade is thick. Units Lattice is the
 * model before: per spring (dyn/cm) and per voxel (dyn), for state files saved before Units existed with Custom values.
 *
 * Errors (a vtkErrorMacro naming the property and its accepted range, and empty outputs, never a crash): any
 * property out of range or not finite, an input without triangles, a non-finite coordinate, a model larger than
 * MaximumVoxels. A blow-up during the run (non-finite value, inverted voxel, energy growing beyond the loads'
 * work) is reported with its step; the frames before it are kept and served.
 *
 * Assembly and the CG solve run on Threads threads (0: all cores) with fixed partitions: the result is
 * bit-identical on any thread count.
 *
 * Assumptions said (a warning, once per simulation): an Input without LeafUV (the base is its lowest point, the tip
 * the point farthest from the base), without Region (every point is blade), or not manifold (edges shared by more
 * than two triangles; it is voxelised as it is). TimeStep longer than Duration is an error.
 *
 * Presets: the properties a named preset sets are used only when it is Custom. One changed from its default while a
 * named preset is on is not what the output has, so a warning names it and says to choose Custom (the same in
 * pvpython, the GUI and a loaded state file, whose outputs are unchanged).
 */
#ifndef vtkWiltingSimulator_h
#define vtkWiltingSimulator_h

#include "PlantMorphWiltingVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string>

#include <memory> // for std::unique_ptr
#include <vector> // for the leaves

#include "vtkSmartPointer.h" // for the leaves

namespace plantmorph
{
struct WiltingParameters;
class WiltingSimulation;
class LeafPlan;
class Run;
}

class PLANTMORPHWILTINGVTK_EXPORT vtkWiltingSimulator : public vtkPolyDataAlgorithm
{
public:
  static vtkWiltingSimulator* New();
  vtkTypeMacro(vtkWiltingSimulator, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Presets
  {
    PRESET_CUSTOM = 0,
    PRESET_CUCUMBER = 1,
    PRESET_TOMATO = 2,
    PRESET_WATERMELON = 3
  };
  enum LoadProfiles
  {
    PROFILE_CONSTANT = 0,
    PROFILE_RAMP = 1,
    PROFILE_SIGMOID = 2
  };
  enum Sides
  {
    SIDE_BOTTOM = 0,
    SIDE_TOP = 1
  };
  enum Targets
  {
    TARGET_MIDVEIN = 0,
    TARGET_BASE = 1
  };
  enum Solvers
  {
    SOLVER_AUTO = 0,
    SOLVER_CHOLESKY = 1,
    SOLVER_CG = 2
  };

  ///@{
  /** Preset (0 Custom, 1 Cucumber, 2 Tomato, 3 Watermelon). Default Cucumber. */
  vtkSetMacro(Preset, int);
  vtkGetMacro(Preset, int);

  /**
   * What the named Preset sets instead of the greyed-out properties (materials as density, stiffness, damping;
   * loads; load profile; Rayleigh damping), one "Property = value" per line, for the read-only PresetValues box of
   * the Properties panel; for Custom, a line saying the properties are used. Computed from Preset alone.
   */
  const char* GetPresetValues();
  ///@}

  ///@{
  /** Voxel edge in model units; 0 uses Resolution. Range [0, inf). Default 0. */
  vtkSetMacro(VoxelSize, double);
  vtkGetMacro(VoxelSize, double);
  /** Physical (0, default) or Lattice (1) units of the Custom materials and loads (see the class doc). */
  vtkSetMacro(Units, int);
  vtkGetMacro(Units, int);
  /** Physical units: the lamina's thickness in model units; 0 (default): the leaf's longest side / 14. [0, 1e6]. */
  vtkSetMacro(BladeThickness, double);
  vtkGetMacro(BladeThickness, double);
  /** Voxels along the bounding box's longest side when VoxelSize is 0. Range [1, 1000]. Default 14. */
  vtkSetMacro(Resolution, int);
  vtkGetMacro(Resolution, int);
  /** Most voxels allowed (a larger model is an error). Default 2000000. */
  vtkSetMacro(MaximumVoxels, int);
  vtkGetMacro(MaximumVoxels, int);
  ///@}

  ///@{
  /** Materials (Custom preset): density (mass per unit voxel volume), spring stiffness, spring damping per region. */
  vtkSetVector3Macro(BladeMaterial, double);
  vtkGetVector3Macro(BladeMaterial, double);
  vtkSetVector3Macro(VeinMaterial, double);
  vtkGetVector3Macro(VeinMaterial, double);
  vtkSetVector3Macro(MarginMaterial, double);
  vtkGetVector3Macro(MarginMaterial, double);
  vtkSetVector3Macro(PetioleMaterial, double);
  vtkGetVector3Macro(PetioleMaterial, double);
  ///@}

  ///@{
  /** Loads (Custom preset): gravity (model units/s^2, downwards), droop pull and contraction per voxel. */
  vtkSetMacro(Gravity, double);
  vtkGetMacro(Gravity, double);
  vtkSetMacro(DroopForce, double);
  vtkGetMacro(DroopForce, double);
  vtkSetMacro(ContractionForce, double);
  vtkGetMacro(ContractionForce, double);
  vtkSetMacro(ContractionSide, int);
  vtkGetMacro(ContractionSide, int);
  /** Left/right asymmetry of the droop and of the contraction, each in [-1, 1] (default 0, symmetric): the +x half
   * of the leaf carries (1 + a) times the load, the -x half (1 - a) times (one half wilting sooner or more). */
  vtkSetMacro(DroopAsymmetry, double);
  vtkGetMacro(DroopAsymmetry, double);
  vtkSetMacro(ContractionAsymmetry, double);
  vtkGetMacro(ContractionAsymmetry, double);
  /** Leaf shrinkage: the relative shortening in [-0.4, 0.4] of the lamina springs' rest lengths at full load
   * (default 0: none), on the contraction's time profile, and its left/right asymmetry in [-1, 1] (default 0): the
   * half that shrinks more becomes the concave side of an in-plane bend, moving the tip sideways towards it. */
  vtkSetMacro(ShrinkageStrain, double);
  vtkGetMacro(ShrinkageStrain, double);
  vtkSetMacro(ShrinkageAsymmetry, double);
  vtkGetMacro(ShrinkageAsymmetry, double);
  /** The shrinkage's own rise time (s; default 0: the contraction's, ContractionTime). */
  vtkSetMacro(ShrinkageTime, double);
  vtkGetMacro(ShrinkageTime, double);
  /** Curl: the lower face of the lamina shrinking more than the upper (CurlStrain d in [-0.4, 0.4], default 0:
   * none): lower-face springs (1 - d/2), upper-face springs (1 + d/2) times their rest length at full curl, an
   * intrinsic bend of curvature d / VoxelSize (positive: apex and margins down) that, unlike ContractionForce,
   * adds no net force and turns with the leaf; its left/right asymmetry in [-1, 1] (default 0); and its relaxation:
   * the fraction r in [0, 1] (default 0) of it that goes again, over CurlRelaxationTime (s, default 0: LoadTime),
   * the upper face catching up. The curl rises on the contraction's profile (ContractionTime) or its own
 * (CurlTime). */
  vtkSetMacro(CurlStrain, double);
  vtkGetMacro(CurlStrain, double);
  vtkSetMacro(CurlAsymmetry, double);
  vtkGetMacro(CurlAsymmetry, double);
  vtkSetMacro(CurlRelaxation, double);
  vtkGetMacro(CurlRelaxation, double);
  vtkSetMacro(CurlRelaxationTime, double);
  vtkGetMacro(CurlRelaxationTime, double);
  /** The curl's own rise time (s; default 0: the contraction's, ContractionTime). */
  vtkSetMacro(CurlTime, double);
  vtkGetMacro(CurlTime, double);
  /** The curl's strain in every in-plane direction (0, Isotropic, default) or only along the lines from the base
   * (1, Radial: the leaf curls along its primary veins, apex and lobes towards the base). */
  vtkSetMacro(CurlDirection, int);
  vtkGetMacro(CurlDirection, int);
  /** Contraction towards the midvein plane (0, the paper's) or towards the base (1: margins and apex curl). */
  vtkSetMacro(ContractionTarget, int);
  vtkGetMacro(ContractionTarget, int);
  vtkSetMacro(LoadProfile, int);
  vtkGetMacro(LoadProfile, int);
  vtkSetMacro(LoadTime, double);
  vtkGetMacro(LoadTime, double);
  /** The contraction's own ramp/sigmoid duration (s); 0 (default): LoadTime. */
  vtkSetMacro(ContractionTime, double);
  vtkGetMacro(ContractionTime, double);
  ///@}

  ///@{
  /** Nodes within this distance of the petiole (or the base) are fixed. Default 3. */
  vtkSetMacro(AnchorRadius, double);
  vtkGetMacro(AnchorRadius, double);
  /**
   * Above 0: a petiole of this length (whole voxels) from the blade's base along -y, held at its far end (the
   * nodes within AnchorRadius of it), so the blade can roll, yaw and pitch on it. 0 (default): none, the blade
   * held at its base. Range [0, 10000].
   */
  vtkSetMacro(PetioleLength, double);
  vtkGetMacro(PetioleLength, double);
  ///@}

  ///@{
  /** Simulated time, time step and frame spacing (seconds). Defaults 10, 1/60, 0.1. */
  vtkSetMacro(Duration, double);
  vtkGetMacro(Duration, double);
  vtkSetMacro(TimeStep, double);
  vtkGetMacro(TimeStep, double);
  vtkSetMacro(FrameInterval, double);
  vtkGetMacro(FrameInterval, double);
  ///@}

  ///@{
  /** Rayleigh damping (Custom preset): C = RayleighAlpha M + RayleighBeta K. */
  vtkSetMacro(RayleighAlpha, double);
  vtkGetMacro(RayleighAlpha, double);
  vtkSetMacro(RayleighBeta, double);
  vtkGetMacro(RayleighBeta, double);
  ///@}

  ///@{
  /** Newton iterations per step [1, 100] (default 1); compression clamp (default on); solver (0 Auto, 1
   * Cholesky, 2 CG); threads (0 all); tricubic embedding (default off). */
  vtkSetMacro(NewtonIterations, int);
  vtkGetMacro(NewtonIterations, int);
  vtkSetMacro(CompressionClamp, bool);
  vtkGetMacro(CompressionClamp, bool);
  vtkBooleanMacro(CompressionClamp, bool);
  vtkSetMacro(Solver, int);
  vtkGetMacro(Solver, int);
  vtkSetMacro(Threads, int);
  vtkGetMacro(Threads, int);
  vtkSetMacro(Tricubic, bool);
  vtkGetMacro(Tricubic, bool);
  vtkBooleanMacro(Tricubic, bool);
  ///@}

  /** The optional veins (input port 1). */
  void SetVeinsConnection(vtkAlgorithmOutput* output);
  void SetVeinsData(vtkPolyData* veins);

  /** Number of simulations run so far (the cache's test hook: scrubbing must not raise it). */
  vtkGetMacro(SimulationCount, int);

protected:
  vtkWiltingSimulator();
  ~vtkWiltingSimulator() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// With a named Preset, warns (once per simulation) about each property the preset sets that was changed from
  /// its default (it is not what the output has).
  void WarnAboutPresetOverrides();
  /// Reads `leaf` and `veins` (may be null) into `simulation` and sets it up; false (the error reported, prefixed by
  /// `label`) when it cannot be. What had to be assumed about the input is warned about.
  bool SetUpSimulation(plantmorph::WiltingSimulation& simulation, vtkPolyData* leaf, vtkPolyData* veins,
    const plantmorph::WiltingParameters& parameters, const std::string& label);
  /// Runs a set-up simulation, its progress shown over [progressBegin, progressEnd]; false when aborted. A blow-up
  /// is reported (prefixed by `label`); the frames before it are kept.
  bool RunSimulation(
    plantmorph::WiltingSimulation& simulation, const std::string& label, double progressBegin, double progressEnd);
  /// RequestData's body (PlantMorphLayer.h): the leaves found (one, or several each on its rank) wilt, served at
  /// `time`.
  void Execute(plantmorph::Run& run, double time);
  /// One leaf: wilts it on rank 0, whole, and serves `time`.
  void WiltLeaf(plantmorph::Run& run, double time, vtkPolyData* input, vtkPolyData* veins);
  /// Runs the simulation unless the cache holds it for these inputs and properties; false when it failed or was
  /// aborted (nothing to serve; the error is reported).
  bool Simulate(vtkPolyData* input, vtkPolyData* veins, const plantmorph::WiltingParameters& parameters,
    vtkMTimeType pieceTime, vtkMTimeType veinsTime);
  /// Several leaves (collective): each leaf `plan` gives this rank wilts alone with its own veins; outputs appended
  /// in LeafId order, the frame tables' rows gathered on rank 0.
  void WiltLeaves(
    plantmorph::Run& run, const plantmorph::LeafPlan& plan, double time, vtkPolyData* input, vtkPolyData* veins);
  /// Simulate for the leaves this rank owns, one simulation each (cached like Simulate's).
  bool SimulateLeaves(const std::vector<vtkSmartPointer<vtkPolyData>>& leaves,
    const std::vector<vtkSmartPointer<vtkPolyData>>& veins, const std::vector<vtkTypeInt64>& leafIds,
    const plantmorph::WiltingParameters& parameters, vtkMTimeType pieceTime, vtkMTimeType veinsTime);

  int Preset = PRESET_CUCUMBER;
  std::string PresetValues;
  double VoxelSize = 0.0;
  int Units = 0;
  double BladeThickness = 0.0;
  int Resolution = 14;
  int MaximumVoxels = 2000000;
  // The XML's defaults (Units Physical: density, Young's modulus in dyn/cm^2, damping time): the preset warning
  // compares the properties with a default-constructed instance, so these must equal WiltingSimulator.xml's.
  double BladeMaterial[3] = { 0.02, 25200.0, 0.0 };
  double VeinMaterial[3] = { 0.04, 50400.0, 0.0 };
  double MarginMaterial[3] = { 0.03, 20160.0, 0.0 };
  double PetioleMaterial[3] = { 0.05, 126000.0, 0.0 };
  double Gravity = 981.0;
  double DroopForce = 3.92;
  double ContractionForce = 1.96;
  double DroopAsymmetry = 0.0;
  double ContractionAsymmetry = 0.0;
  double ShrinkageStrain = 0.0;
  double ShrinkageAsymmetry = 0.0;
  double CurlStrain = 0.0;
  double CurlAsymmetry = 0.0;
  double CurlRelaxation = 0.0;
  double CurlRelaxationTime = 0.0;
  double CurlTime = 0.0;
  double ShrinkageTime = 0.0;
  int CurlDirection = 0;
  int ContractionSide = SIDE_BOTTOM;
  int ContractionTarget = TARGET_MIDVEIN;
  int LoadProfile = PROFILE_SIGMOID;
  double LoadTime = 8.0;
  double ContractionTime = 0.0;
  double AnchorRadius = 3.0;
  double PetioleLength = 0.0;
  double Duration = 10.0;
  double TimeStep = 1.0 / 60.0;
  double FrameInterval = 0.1;
  double RayleighAlpha = 2.0;
  double RayleighBeta = 0.01;
  int NewtonIterations = 1;
  bool CompressionClamp = true;
  int Solver = SOLVER_AUTO;
  int Threads = 0;
  bool Tricubic = false;
  int SimulationCount = 0;

private:
  vtkWiltingSimulator(const vtkWiltingSimulator&) = delete;
  void operator=(const vtkWiltingSimulator&) = delete;

  struct Cache;
  std::unique_ptr<Cache> Cached;
};

#endif
