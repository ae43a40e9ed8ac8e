// SPDX-License-Identifier: GPL-3.0-or-later
// WiltingSimulator's algorithm (paper 001; docs/methods/wilting.md): the voxel mass-spring leaf, its loads, the
// implicit Newmark run and its frames. Plain C++17 + Eigen, no VTK; vtkWiltingSimulator is a thin layer over it.
//
// Model (choices where the paper is silent are marked *; docs/methods/wilting.md says why):
// - Voxels: WiltingVoxelizer (exact triangle-box tests), VoxelSize or Resolution cubes along the longest side.
// - Springs: the 28 node pairs of each voxel (12 edges, 12 face diagonals, 4 body diagonals) with the voxel's
//   region stiffness k and dashpot c; * a pair shared by neighbouring voxels is one spring whose k and c are the
//   sums of the voxels' (a face shared by two voxels is as stiff as the two voxels' halves of material behind it).
// - Materials per region class (blade 0 and * tertiary veins 3, finer than a voxel; veins 1-2; margin 4; petiole 5):
//   Density (mass per unit voxel volume; * the voxel's mass is Density h^3, lumped 1/8 to each corner), Stiffness
//   (k of each spring, force per unit length) and Damping (c of each spring's dashpot).
// - Anchors: * the input points with Region 5 (petiole), or else the blade's base (the point with the smallest
//   LeafUV v, or the smallest y without LeafUV); * the leaf is held by whole voxels: every node of each voxel whose
//   centre is within AnchorRadius of one is fixed (at least the nodes of the base point's voxel), so no voxel hangs
//   on a fixed node or edge of its own.
// - Petiole (* not in the paper; PetioleLength 0, the default, adds none): a detached leaf on a stand hangs from
//   its petiole, which bends and twists. PetioleLength > 0 adds a straight petiole of round(PetioleLength / h) >= 1
//   voxels from the base along -y in the blade's plane, one or two voxels wide and thick (the cells around the
//   base, AddPetiole), with the Petiole material; the blade's cells on its path become petiole. The stand holds its
//   far end: the voxels within AnchorRadius of the end's centre, and at least the end face's nodes, are the anchors instead
//   of those above, so the blade itself is free and can roll, yaw and pitch on the petiole. The petiole carries
//   gravity but none of the wilting loads, shrinkage or curl (the blade wilts, the petiole holds it), and the
//   output's surface has none: it shows in the voxel model (Region 5). The blade's voxels are those without a
//   petiole (the grid grows by whole cells).
// - Loads at time t (gravity and droop scaled by LoadFactor(t), the contraction by its own): gravity m g (0, 0, -1)
//   per node (* it comes in with the droop: the turgid leaf carries its weight at t = 0, its shape the input's, and
//   wilting withdraws that support; applied at once it dropped a large soft leaf below its end, which swung back
//   11-17 % of its length; Constant, the paper's profile: at once); droop: a pull
//   DroopForce (0, 0, -1) per voxel (* not the petiole's, Region 5: the blade wilts); contraction: ContractionForce per voxel towards the midvein plane x = x_base
//   (* the plane through the base along +Y; voxels whose centre is within h/2 of it get none), or with
//   ContractionTarget Base towards the base point in the XY plane (voxels within h/2 of it get none), each voxel's
//   loads split over its four bottom (ContractionSide Bottom: the margin curls down, cucumber) or top (Top: curls up,
//   tomato) nodes. * Loads are dead loads (fixed directions).
// - Asymmetry (* not in the paper; default 0, then the loads are exactly the symmetric ones above): DroopAsymmetry
//   a_d and ContractionAsymmetry a_c in [-1, 1] scale a voxel's droop by 1 + a_d s and its contraction by
//   1 + a_c s, s = +1 for voxels whose centre lies more than h/2 on the +x side of the midvein plane x = x_base,
//   -1 on the -x side, 0 on it: one half of a real leaf loses turgor sooner or more than the other (a = 1: only
//   the +x half is loaded, with twice the load; -1: only the -x half). For a leaf symmetric about the midvein the
//   total load is unchanged, and a and -a give mirror-image motions.
// - Shrinkage (* not in the paper; default 0, then nothing changes): the lamina losing area as it dehydrates (leaf
//   shrinkage). ShrinkageStrain e in [-0.4, 0.4] at full load: each spring's rest length L becomes (1 - e_v c(t)) L
//   for the part k_v of its stiffness that voxel v contributes (a shared spring: L (1 - sum k_v e_v c / sum k_v)),
//   e_v = e (1 + a_s s) with ShrinkageAsymmetry a_s in [-1, 1] and s the voxel's side as above (petiole voxels: 0),
//   c(t) the contraction's load factor (ContractionTime), or its own over ShrinkageTime. The rest lengths are the integrator's, so the shrinking
//   is implicit (stable at any strain) and adds no load: a flat leaf, both faces shrinking alike, shortens and
//   narrows in its plane towards its anchor without curling (ContractionForce, on one face, curls); the half that
//   shrinks more becomes the concave side of a bend in the leaf's plane, so the tip moves sideways towards it.
//   The energies keep the unshrunk rest lengths; the blow-up guard counts the shrinking as work (a rest length
//   L (1 - x) is a spring of rest length L with a pull k x L between its ends).
// - Curl (* not in the paper; default 0, then nothing changes): the two faces of the lamina shrinking unequally.
//   CurlStrain d in [-0.4, 0.4] at full curl: in every blade, vein and margin voxel the springs between two bottom
//   nodes get the rest length (1 - d/2) L, those between two top nodes (1 + d/2) L, the others keep theirs (a shared
//   spring: stiffness-weighted, as the shrinkage; on top of it, x = e_v c(t) + d_v g(t) per voxel), with
//   d_v = d (1 + a_c s), CurlAsymmetry a_c in [-1, 1]. The mean length of the two faces is unchanged: no in-plane
//   shrinking, only an intrinsic bend of curvature d / h (h the voxel edge, the plate's thickness), positive: the
//   lower face concave, the apex and margins curling down. It is internal, so unlike ContractionForce (dead loads
//   in fixed directions) it adds no net force and turns with the leaf. Time: g(t) = c(t) - r c_r(t), c the
//   profile over CurlTime (0: the contraction's, ContractionTime), c_r the same profile over CurlRelaxationTime (0: LoadTime) and
//   CurlRelaxation r in [0, 1]: the lower (abaxial) face, with the stomata, drying first and the upper face
//   catching up a fraction r later, so the curl rises and then relaxes by r. Rest lengths as the shrinkage's.
//   CurlDirection Radial: the strain only along the lines from the base (a face spring of direction n gets
//   (n . r)^2 of it, r the unit vector from the base to the voxel's centre in the XY plane): the leaf curls along
//   its primary veins, apex and lobes towards the base, which a wide plate can do (an isotropic curl asks a plate
//   for curvature in two directions at once, which it cannot take without stretching).
// - LoadProfile: Constant 1 (the paper), Ramp min(1, t/LoadTime), Sigmoid: the logistic 1/(1 + exp(-12 (t/T -
//   1/2))) rescaled to go from 0 at t = 0 to 1 at t = T = LoadTime (slow start, then faster: the measured wilting).
//   The contraction follows the same profile over its own ContractionTime (0: LoadTime): * the paper sees the
//   margins change first, and the cucumber fit wants the curl earlier than the droop.
// - Integration: NewmarkIntegrator (Rayleigh damping, Newton, compression clamp, Cholesky or CG).
// - Blow-up guard: a non-finite value, an inverted voxel (a corner Jacobian <= 0, relative to rest), or mechanical
//   energy (kinetic + spring + gravity, from rest) above twice the work the droop and contraction loads and the
//   support of the weight not yet withdrawn have done plus the work gravity can do stops the run with a message naming the step; the frames so far are kept.
// - Frames: the state every FrameInterval (rounded to whole steps) from 0 to Duration.
#pragma once

#include "MassSpringSystem.h"
#include "NewmarkIntegrator.h"
#include "WiltingEmbedding.h"
#include "WiltingVoxelizer.h"

#include <Eigen/Core>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace plantmorph
{

enum class WiltingLoadProfile : int
{
  Constant = 0,
  Ramp = 1,
  Sigmoid = 2
};

enum class WiltingContractionSide : int
{
  Bottom = 0,
  Top = 1
};

/// Where the contraction pulls: towards the midvein plane (the paper's lateral contraction: the margins curl), or
/// towards the base (* the lamina shrinking on one side in every in-plane direction: the margins and the apex curl,
/// which shortens the leaf; the cucumber fit needs it, benchmarks/README.md "wilting calibration").
enum class WiltingContractionTarget : int
{
  Midvein = 0,
  Base = 1
};

/// How the curl's strain is oriented in the lamina's plane: the same in every direction, or only along the lines
/// from the base (* the lamina contracting along its primary veins: the apex and lobes curl towards the base
/// while the margins stay level, a bend a wide plate can take without stretching; an isotropic curl of a plate
/// wider than it is curved cannot, and mostly curls the margins).
enum class WiltingCurlDirection : int
{
  Isotropic = 0,
  Radial = 1
};

/// How WiltingParameters' materials, loads and curl are read (docs/methods/wilting.md "Physical units").
/// Physical: a lamina of thickness bladeThickness, whatever the voxels: Young's modulus, density per volume, a
/// dashpot as a retardation time, droop and contraction as pressures (force per area of leaf), curl as the strain
/// difference across the thickness; WiltingLatticeOf turns them into the springs and per-voxel loads of a voxel
/// edge h so that the plate's bending stiffness, mass and loads per area and its intrinsic curvature do not depend
/// on h. Lattice: per spring and per voxel, as given (the model before physical units; referenceVoxelSize applies).
enum class WiltingUnits : int
{
  Physical = 0,
  Lattice = 1
};

/// Region classes with their own material.
enum WiltingMaterialClass : int
{
  WiltingBlade = 0,
  WiltingVein = 1,
  WiltingMargin = 2,
  WiltingPetiole = 3
};
inline constexpr int WiltingMaterialCount = 4;
/// The material class of a Region value.
int WiltingMaterialOf(int region);

struct WiltingMaterial
{
  /// Lattice: mass per unit voxel volume; Physical: mass per unit volume of the lamina (g/cm^3 with cm).
  double density = 0.05;
  /// Lattice: spring constant (dyn/cm); Physical: Young's modulus E (dyn/cm^2 = 0.1 Pa with cm).
  double stiffness = 2000.0;
  /// Lattice: spring dashpot (g/s); Physical: retardation time (s), each spring's dashpot that times its stiffness.
  double damping = 0.0;
};

struct WiltingParameters
{
  double voxelSize = 0.0; ///< > 0: cube edge; 0: from resolution
  /// Physical (presets and the filter's default) or Lattice (the unit tests' and the VegaFEM cross-check's).
  WiltingUnits units = WiltingUnits::Lattice;
  /// Physical units: the lamina's thickness t (model units); 0: the leaf's longest side / 14 (* the Cucumber fit's
  /// voxel edge: an effective thickness that scales with the leaf, so geometrically similar leaves wilt alike).
  double bladeThickness = 0.0;
  /// Physical units: integrator sub-steps per TimeStep; 0: automatic, ceil((t / h)^2) (the lattice's highest
  /// frequency grows as 1 / h^2 at a fixed bending stiffness; 1 when h >= t).
  int substeps = 0;
  /// Set by WiltingLatticeOf (1 otherwise): the stiffness of the springs that cross the layer (the 4 vertical
  /// edges, 8 vertical face diagonals and 4 body diagonals of each cube, which do not stretch in bending) relative
  /// to the face springs'. Physical units with voxels coarser than the blade is thick (h > t): (h / t)^2, so they
  /// keep the stiffness E t / 18 of h = t while the face springs soften to E t^3 / (18 h^2) for the bending
  /// stiffness: a coarse voxel does not shear or invert under loads its bending carries.
  double throughStiffness = 1.0;
  int resolution = 20; ///< cubes along the longest side when voxelSize is 0
  std::array<WiltingMaterial, WiltingMaterialCount> materials{};
  double gravity = 981.0; ///< downward (-Z) acceleration, model units / s^2
  double droopForce = 0.0;
  double contractionForce = 0.0;
  /// In [-1, 1]: the droop on the +x half of the leaf is (1 + a) times, on the -x half (1 - a) times DroopForce.
  double droopAsymmetry = 0.0;
  /// In [-1, 1]: the same for the contraction (one half of the lamina shrinking more than the other).
  double contractionAsymmetry = 0.0;
  /// In [-0.4, 0.4]: the relative shortening of the rest length of every lamina spring at full load (leaf
  /// shrinkage), on the contraction's profile; negative swells.
  double shrinkageStrain = 0.0;
  /// In [-1, 1]: the shrinkage on the +x half is (1 + a), on the -x half (1 - a) times ShrinkageStrain.
  double shrinkageAsymmetry = 0.0;
  /// The shrinkage's own ramp / sigmoid duration (s); 0: the contraction's (contractionTime, or loadTime).
  double shrinkageTime = 0.0;
  /// In [-0.4, 0.4]: the lower face's springs (1 - d/2), the upper face's (1 + d/2) times their rest length at full
  /// curl: an intrinsic bend of curvature d / h, positive curling the apex and margins down.
  double curlStrain = 0.0;
  /// In [-1, 1]: the curl on the +x half is (1 + a), on the -x half (1 - a) times CurlStrain.
  double curlAsymmetry = 0.0;
  /// In [0, 1]: the fraction of the curl that relaxes again (the upper face catching up), over curlRelaxationTime.
  double curlRelaxation = 0.0;
  /// The curl's own ramp / sigmoid duration (s); 0: the contraction's (contractionTime, or loadTime).
  double curlTime = 0.0;
  /// The relaxation's ramp / sigmoid duration (s), from t = 0; 0: loadTime.
  double curlRelaxationTime = 0.0;
  /// Isotropic, or Radial: a spring of direction n gets (n . r)^2 of the face strain, r the unit vector from the
  /// base in the XY plane.
  WiltingCurlDirection curlDirection = WiltingCurlDirection::Isotropic;
  /// > 0: the materials' stiffness and damping and the droop and contraction loads were given for voxels of this
  /// edge (a preset's fit); Setup scales them to the actual edge h, stiffness by h/h0 (a spring lattice's modulus
  /// is k/h) and loads by (h/h0)^3 (loads per volume, like gravity), so a fit carries over to other resolutions
  /// approximately. 0: used as given.
  double referenceVoxelSize = 0.0;
  WiltingContractionSide contractionSide = WiltingContractionSide::Bottom;
  WiltingContractionTarget contractionTarget = WiltingContractionTarget::Midvein;
  WiltingLoadProfile loadProfile = WiltingLoadProfile::Sigmoid;
  double loadTime = 5.0; ///< ramp / sigmoid duration (s)
  /// The contraction's own ramp / sigmoid duration (s); 0: loadTime. * The paper sees the margins change first.
  double contractionTime = 0.0;
  double anchorRadius = 1.0; ///< model units (used when anchorFraction is 0)
  /// > 0: the anchor radius is this fraction of the leaf's longest side (the bounding box's, as BladeThickness), in
  /// place of anchorRadius: how far a preset's fitted leaf was held, carried over to leaves of any size (a radius in
  /// model units holds a small leaf over much of its length and a large one by a stub). 0: anchorRadius.
  double anchorFraction = 0.0;
  /// Physical units, > 0: the materials' Young's moduli and the droop and contraction pressures are those of a leaf
  /// whose longest side is this long (a preset's fitted leaf); Setup scales them by the leaf's longest side over it
  /// (elastic similarity: a leaf k times as long has k times the modulus and pressures, so with the default
  /// thickness, which also grows k times, its own weight bends it by the same fraction of its length and the
  /// droop and contraction move it by the same fraction; otherwise gravity's share grows as the length). 0: as given.
  double referenceLength = 0.0;
  /// > 0: a petiole of this length (model units, whole voxels) from the blade's base along -y, held at its far end
  /// (AddPetiole); 0: none, the blade held at its base.
  double petioleLength = 0.0;
  double duration = 10.0; ///< simulated seconds
  double frameInterval = 0.1;
  bool tricubic = false;
  NewmarkParameters newmark; ///< time step, damping, Newton, solver, threads
  std::size_t maxVoxels = 2000000;
};

/// Empty when usable; otherwise a message naming the property and its range.
std::string ValidateWilting(const WiltingParameters& parameters);

/// Physical units for a voxel edge h and blade thickness t, as the lattice's per-spring and per-voxel values
/// (units Lattice, referenceVoxelSize 0, the time step divided by the sub-steps); Lattice parameters are returned
/// as they are. The one-voxel layer is a plate of thickness h whose cubes' 28 springs of constant k give it the
/// bending stiffness D = 3/2 k h^2 per width (cylindrical bending: the four edges and four horizontal face
/// diagonals of each cube along the bend; the other springs do not stretch), so k = E t^3 / (18 h^2) gives
/// D = E t^3 / 12 at every h (its in-plane stiffness, 3 k per width, grows as h shrinks: the limit is the
/// inextensible plate). A voxel is h^2 of the lamina: mass rho t h^2 (density rho t / h), droop p h^2; the
/// contraction q h^2 pulls its face (ContractionSide) at t / 2 from the mid-plane: (1 + t/h)/2 of it on that face's
/// four nodes and (1 - t/h)/2 on the other's (faceShare; all on the face when h = t, the model before); curl d
/// (a strain difference across t, curvature d / t) strains the lattice's faces by -+ d h / (2 t); dashpots tau k.
WiltingParameters WiltingLatticeOf(const WiltingParameters& parameters, double h, double thickness,
  double* faceShare = nullptr, int* substeps = nullptr);

/// Physical units with a referenceLength: the parameters with the moduli and pressures scaled to a leaf whose
/// longest side is `longest` (elastic similarity) and referenceLength 0; otherwise the parameters as they are.
WiltingParameters SimilarTo(const WiltingParameters& parameters, double longest);

/// Physical units: empty when a voxel edge h holds the lamina of `thickness` (h at most the thickness), else the
/// refusal naming the smallest Resolution that holds (the largest VoxelSize when one was given); `longest` is the
/// leaf's longest side.
std::string CoarseVoxelError(const WiltingParameters& parameters, double h, double thickness, double longest);

/// The blade thickness Physical units use for a leaf whose bounding box's longest side is `longest`.
double WiltingBladeThickness(const WiltingParameters& parameters, double longest);

/// The load factor in [0, 1] at time t.
double WiltingLoadFactor(WiltingLoadProfile profile, double t, double loadTime);

struct WiltingInput
{
  std::vector<Eigen::Vector3d> points;       ///< every input point (surface and lines)
  std::vector<std::array<int, 3>> triangles; ///< the surface, voxelised
  std::vector<int> regions;                  ///< one per point, or empty
  std::vector<Eigen::Vector2d> leafUV;       ///< one per point, or empty
  /// The surface is a LeafFitFilter blade (its field data has PlantMorph.FitModel.*): its base (LeafUV v = 0) is the
  /// bottom of its fitted outline, which fills a cordate leaf's sinus.
  bool fitted = false;
};

/// The point pairs that are edges of more than two of `triangles` (a non-manifold surface has some).
std::size_t CountNonManifoldEdges(const std::vector<std::array<int, 3>>& triangles);

/// What the simulation has to assume about `input`, as sentences for a warning, or "": no LeafUV (the base is the
/// lowest point, the tip the point farthest from it), no Region on the surface (`surfaceHasRegion` false: every
/// surface point is blade), edges shared by more than two triangles (voxelised as it is).
std::string WiltingInputAssumptions(const WiltingInput& input, bool surfaceHasRegion);

/// The smallest Resolution that holds for a preset (held in leaf lengths) on a fitted blade: on the sweep of
/// benchmarks/README.md "Fitted scans" (LeafOutlineSource's cucumber blade of 5-40 cm scanned and fitted, held by
/// whole voxels) every Resolution from 14 ran its 10 s without inverting a voxel and without rising back, as on the
/// source's blade. It is the coarsest the default BladeThickness (longest side / 14) accepts, so only a preset with a
/// thicker BladeThickness can run a fitted blade below it, where nothing was verified.
inline constexpr int FittedBladeResolution = 14;

/// A preset (anchorFraction > 0) run on a fitted blade (input.fitted) at a Resolution below FittedBladeResolution
/// (VoxelSize 0): the warning naming that Resolution and why; otherwise "".
std::string FittedBladeWarning(const WiltingInput& input, const WiltingParameters& parameters);

struct WiltingFrame
{
  double time = 0.0;
  std::vector<double> q; ///< node displacements
  std::vector<double> v; ///< node velocities
  double kinetic = 0.0, spring = 0.0, gravity = 0.0;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero(); ///< the tip point's position
};

class WiltingSimulation
{
public:
  /// Voxelises, builds the mass-spring system, binds the points. Empty on success, else a message.
  std::string Setup(const WiltingInput& input, const WiltingParameters& parameters);
  /// Simulates from rest to Duration. `progress(fraction)` may return false to abort (then Aborted() is true and
  /// the frames so far are kept). Returns an empty string, or the blow-up guard's message.
  std::string Run(const std::function<bool(double)>& progress = nullptr);
  bool Aborted() const { return this->WasAborted; }
  /// Integrator steps per TimeStep (Physical units; 1 for Lattice) and the blade thickness used (0: Lattice).
  int Substeps() const { return this->SubstepCount; }
  double BladeThickness() const { return this->Thickness; }
  /// The anchor radius used (model units: anchorRadius, or anchorFraction of the leaf's longest side).
  double AnchorRadius() const { return this->Radius; }

  const std::vector<WiltingFrame>& Frames() const { return this->FrameList; }
  /// The frame times the run will produce (known after Setup).
  std::vector<double> FrameTimes() const;
  const VoxelGrid& Grid() const { return this->Voxels; }
  const MassSpringSystem& System() const { return this->Springs; }
  const WiltingEmbedding& Embedding() const { return this->Embed; }
  const NewmarkIntegrator& Integrator() const { return this->Newmark; }
  int TipPoint() const { return this->Tip; }
  const std::vector<Eigen::Vector3d>& InputPoints() const { return this->Points; }
  /// The petiole AddPetiole placed (voxels 0 without one).
  const PetiolePlacement& Petiole() const { return this->PetioleCells; }
  /// The positions of the input points at frame `f`.
  std::vector<Eigen::Vector3d> PointPositions(std::size_t f) const;
  /// The external force (3 per node) at time t.
  void ExternalForce(double t, std::vector<double>& force) const;
  /// The springs' rest lengths at time t (one per spring; the system's own without shrinkage).
  std::vector<double> RestLengths(double t) const;

private:
  WiltingParameters Params;
  VoxelGrid Voxels;
  MassSpringSystem Springs;
  WiltingEmbedding Embed;
  NewmarkIntegrator Newmark;
  PetiolePlacement PetioleCells;
  std::vector<Eigen::Vector3d> Points;
  std::vector<double> GravityForce;    // per node
  std::vector<double> LoadForce;       // per node, droop at full load
  std::vector<double> ContractionLoad; // per node, contraction at full load
  std::vector<double> SpringShrinkage; // per spring, its strain at full load; empty without shrinkage
  std::vector<double> SpringCurl;      // per spring, its curl strain at full curl; empty without curl
  double ContractionFactor(double t) const;
  double ShrinkageFactor(double t) const;
  double CurlFactor(double t) const;
  /// Whether the rest lengths change in time (shrinkage or curl).
  bool RestLengthsChange() const { return !this->SpringShrinkage.empty() || !this->SpringCurl.empty(); }
  /// Every spring's relative shortening at time t.
  void SpringStrains(double t, std::vector<double>& strains) const;
  /// The rest lengths L (1 - strain).
  void RestLengthsFromStrains(const std::vector<double>& strains, std::vector<double>& lengths) const;
  int Tip = 0;
  int SubstepCount = 1;
  double Thickness = 0.0;
  double Radius = 0.0;
  int StepsPerFrame = 1;
  int FrameCount = 1;
  std::vector<WiltingFrame> FrameList;
  bool WasAborted = false;
};

} // namespace plantmorph
