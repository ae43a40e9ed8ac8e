// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkTreeFromSketchSource
 * @brief   Trees from paper 004: golden-ratio / phyllotaxis template trees, strokes lifted to 3-D, and leaves.
 *
 * Related publication: [P004] Liu Yisong, Xu Xianghu, Zeng Lanling, Zhan Yongzhao, "An interactive 3-D tree
 * modelling system from sketches on a single image" (in Chinese; venue not known): secs. 2-3, eqs. (1)-(3), Table 1,
 * Figs. 10-11.
 * Full references: docs/references.md. What the code does, and where and why it departs from the paper:
 * docs/methods/tree-from-sketch.md.
 *
 * Output port 0, **Branches**: every branch as one closed, watertight tube (triangles; `Sides` vertices a ring,
 * rings shared by consecutive segments in the mitre plane, rotation-minimising frames, base capped, monopodial tips
 * closed in a point, sympodial ends capped), cell arrays `BranchId`, `ParentId`, `Depth` (0 the trunk), point
 * arrays `TCoords` (active; v along the branch 0..1, u around it mirrored 0..1..0 so there is no seam) and `Normals`
 * (active). Port 1, **Skeleton**: one polyline per branch, base to tip, point array `Radius` (double) for
 * ParaView's Tube filter, cell arrays `BranchId`, `ParentId`, `Depth`. Port 2, **Leaves**: one textured quad per
 * leaf (its length a side, TCoords 0..1) or, when the Leaf input is connected, one copy of the leaf geometry per
 * leaf (its TCoords carried, scaled so its length along +Y is the leaf's length), cell array `BranchId` of the twig.
 * A leaf's length is LeafScale, tapered towards the twig's tip by LeafTipScale and spread by LeafScaleSpread
 * (sources/tree/core/TreeLeaves.h).
 * The truth a scan of the tree carries to its points (VirtualScanner): `LeafId` on the cells and points of the
 * leaves (each leaf its own, unique over the tree and the same for the same properties and Seed: the leaf's index
 * in the tree's order; -1 on the branches) and `Organ` on the cells and points of both (0 wood, 1 leaf blade, 2
 * petiole: the Leaf input's cells of Region petiole, when it has a cell array Region).
 * All outputs carry the parameters as field data (`PlantMorph.Model` = "TreeFromSketch", `PlantMorph.TreePreset`...).
 *
 * Optional input port 0, **Strokes**: polydata whose lines (each line or polyline cell one stroke, in the order
 * drawn) lie in the image's XY plane; z is ignored. When it is not connected and `StrokeFile` is set, the strokes
 * come from that .csv (stroke_id, x, y) or .svg file (each path subpath, polyline, polygon and line a stroke, curves
 * flattened to 0.1 px, transforms, viewBox and units applied; sources/tree/core/StrokeFiles.h). Optional input port 1, **Leaf**: a leaf
 * mesh (e.g. LeafOutlineSource's Blade: XY plane, base at the origin, midrib along +Y) to instance at every leaf.
 * Optional input port 2, **MergeTree**: a second tree to merge (paper 004 sec. 3.2, Fig. 11 "merged tree"): a
 * skeleton, i.e. polylines with cell arrays `BranchId`, `ParentId` and point array `Radius`, such as another
 * vtkTreeFromSketchSource's Skeleton output. It grows from branch `MergeParentBranch` at `MergeU` like a template
 * child at (`MergeAngle`, `MergeRotation`), its +Y turned into that child's direction, or (MergeParentBranch -1)
 * stands as a second trunk at `MergeOffset`, tilted by MergeAngle and turned about +Y by MergeRotation; scaled by
 * `MergeScale`. Its branches keep their shape and get BranchId = base + their id in the second tree, base (field
 * data `PlantMorph.MergeIdBase`) the first id this tree's own properties never use, so DeletedBranches and
 * BranchOverrides address them and state files keep naming them. Input that is not one tree (no lines, no
 * BranchId / ParentId / Radius, duplicate ids, no or several roots, dangling parents, cycles, NaN) is refused with a
 * message starting "Merge input is not a tree". See plantmorph::MergeTree (TreeMerge.h) for every rule.
 *
 * `Joints` 0 **Welded** (default): the branches of a tree form ONE closed, consistently oriented, manifold surface
 * (plantmorph::BuildWeldedTubes, BranchJunctions.h): at each node the child and the parent are cut back and joined
 * by the convex hull of the cut rings (no cap inside the parent, no ledge, no internal face; the hull is convex, so
 * at narrow angles it fills a little more than the exact union). A lateral child wider than 0.9 of its parent's
 * radius at the node (every child of the monopodial template) has its first segment narrowed to that at its base
 * (pipe model; skeleton `Radius` unchanged). Children whose intervals overlap share one junction. Hull facets carry
 * the child's BranchId / ParentId / Depth. A child whose junction cannot be built (see BranchJunctions.h
 * "Fallback") stays its own closed tube overlapping its parent. Branches that cross each other away from a node
 * (the template's subtrees do) are not united. Field data `PlantMorph.Junctions` counts junctions, welded
 * children, merged junctions, junctions at a parent's end (forks), narrowed children and fallbacks; Table 1's
 * presets at full depth: see docs/tracing-a-tree-photo.md "Joints". `Joints` 1 **Seated tubes** (the previous
 * behaviour, kept for comparison and for users who post-process separate tubes): each child's tube starts with its
 * base ring on the parent tube's faceted surface (plantmorph::BuildTubes, "Joints"); the parent is not cut, so the
 * child's base cap and a thin lens under it lie inside the parent and a child wider than its parent shows a ledge.
 * Field data `PlantMorph.JointRingVertices` counts the child ring vertices seated, missed, clamped and buried (zeros
 * when welded).
 *
 * `Mode`: 0 Template (the template tree of the properties, or of `Preset` 1-3, Table 1), 1 Strokes (the first
 * stroke is the trunk, the others attach to their nearest branch and are lifted to 3-D by the phyllotaxis rule; each
 * grows a template subtree of `StrokeSubtreeDepth` levels unless `StrokesOnly`), 2 Template and strokes (strokes are
 * merged into the template tree). See plantmorph::BuildTree, plantmorph::AddStrokes (TreeStrokes.h),
 * plantmorph::PlaceLeaves and plantmorph::BuildTubes for every formula and for the choices made where the paper is
 * silent. Editing: `DeletedBranches` (ids; the branch and its subtree go) and `BranchOverrides` (rows of id,
 * length, radius, u, angle, rotation_angle; NaN or -1000 keeps). Branch ids are preorder numbers of the unedited template,
 * so they stay valid under edits of other branches and in saved state files. Overrides apply to stroke branches too
 * (rotation_angle replaces the chosen phyllotaxis lifting angle, length scales the branch about its base, u moves
 * it along its parent, angle turns it about its base; see TreeStrokes.h) and to merged branches (length, radius;
 * u, angle and rotation_angle on the merged root only, other rows refused; see TreeMerge.h).
 *
 * Pieces (UPDATE_PIECE_NUMBER of UPDATE_NUMBER_OF_PIECES; under `mpirun -np N pvbatch` or a cluster pvserver one
 * piece per rank): every piece builds the same skeleton (small, deterministic), the branches are split between the
 * pieces by subtree (sources/tree/tubes/BranchPieces.h: depth-first runs balanced by segment count, a forest or a merged tree
 * split by tree first), and each piece makes only its branches' tubes and the junction facets they own, exactly as
 * the whole tree has them: the pieces' triangles together are the serial Branches output's, none twice or missing,
 * with the same cell arrays (point ids and cell order differ). A junction whose branches lie in two pieces is computed
 * in both, each writing its own facets (BranchJunctions.h). A piece's surface is a valid mesh, open where it meets
 * another piece (the union is closed); the points of another piece's branch that its facets use are copied into it.
 * Leaves go with their branch. The Skeleton output (one polyline per branch, small) is whole on piece 0 and empty on
 * the others, so it appears once and can feed another source's MergeTree input. Field data: on every piece; in a
 * piece, `PlantMorph.Junctions` and `PlantMorph.JointRingVertices` count its own branches' (summed over the pieces:
 * the serial counts) and `PlantMorph.Piece` holds (piece, pieces). The inputs (strokes, leaf, merge skeleton) are
 * small: under MPI they are gathered on rank 0 and broadcast, so every piece sees them whole. Bad parameters, bad
 * strokes (none, one point, NaN, zero length) or a tree above `MaxSegments` give an error naming the property or
 * input and its accepted range, and empty outputs. Randomness (ties in the nearest-parent search) comes only from
 * `Seed`: the same parameters, strokes and seed give bit-identical outputs.
 *
 * Presets: the properties a named preset sets are used only when it is Custom. One changed from its default while a
 * named preset is on is not what the output has, so a warning names it and says to choose Custom (the same in
 * pvpython, the GUI and a loaded state file, whose outputs are unchanged).
 */
#ifndef vtkTreeFromSketchSource_h
#define vtkTreeFromSketchSource_h

#include "PlantMorphTreeVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for StrokeFile
#include <vector> // for deletions and overrides

namespace plantmorph
{
class FieldRecord;
class Run;
struct JointReport;
struct JunctionReport;
struct Tree;
struct TreeParameters;
}
class vtkFieldData;

class PLANTMORPHTREEVTK_EXPORT vtkTreeFromSketchSource : public vtkPolyDataAlgorithm
{
public:
  static vtkTreeFromSketchSource* New();
  vtkTypeMacro(vtkTreeFromSketchSource, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// 0 Template, 1 Strokes, 2 Template and strokes. Default 0.
  vtkSetMacro(Mode, int);
  vtkGetMacro(Mode, int);
  /// 0 Custom (the properties below), 1-3 Table 1's left (monopodial 3/8), middle (sympodial 1/3) and right
  /// (monopodial 5/8) templates, which set TreeType, Depth, Ratio, Length, Radius, PhyllotaxisA/B, ChildCount.
  /// Default 1.
  vtkSetMacro(Preset, int);
  vtkGetMacro(Preset, int);
  /// 0 monopodial, 1 sympodial. Default 0.
  vtkSetMacro(TreeType, int);
  vtkGetMacro(TreeType, int);
  /// Trunk length, (0, 1e6]. Default 12.
  vtkSetMacro(Length, double);
  vtkGetMacro(Length, double);
  /// Trunk base radius, (0, 1e5]. Default 0.4.
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  /// Levels of children below the trunk, [0, 20]. Default 4.
  vtkSetMacro(Depth, int);
  vtkGetMacro(Depth, int);
  /// Phyllotaxis fraction a/b: a turns per b branches or leaves, each in [1, 1000]. Default 3/8.
  vtkSetMacro(PhyllotaxisA, int);
  vtkGetMacro(PhyllotaxisA, int);
  vtkSetMacro(PhyllotaxisB, int);
  vtkGetMacro(PhyllotaxisB, int);
  /// Children per branch, [1, 1000]. Default 8.
  vtkSetMacro(ChildCount, int);
  vtkGetMacro(ChildCount, int);
  /// Children sit on the last Ratio of their parent, [0, 1]; 0 puts them all at the tip (sympodial). Default 0.7.
  vtkSetMacro(Ratio, double);
  vtkGetMacro(Ratio, double);
  /// Sympodial child length / parent length, (0, 10]. Default 0.8.
  vtkSetMacro(LengthScale, double);
  vtkGetMacro(LengthScale, double);
  /// Divergence angles in degrees, [0, 180]: monopodial 34.4 (90 * 0.382), sympodial 55.6 (90 * 0.618).
  vtkSetMacro(MonopodialAngle, double);
  vtkGetMacro(MonopodialAngle, double);
  vtkSetMacro(SympodialAngle, double);
  vtkGetMacro(SympodialAngle, double);
  /// DIVID: segments per branch (and stroke branch), [1, 10000]. Default 4.
  vtkSetMacro(SegmentsPerBranch, int);
  vtkGetMacro(SegmentsPerBranch, int);
  /// epsilon_leaf: depth-0 twigs are this much longer, (0, 10]. Default 1.2.
  vtkSetMacro(TwigScale, double);
  vtkGetMacro(TwigScale, double);
  /// Vertices per tube ring, [3, 256]. Default 6 (the paper's hexagonal prisms).
  vtkSetMacro(Sides, int);
  vtkGetMacro(Sides, int);
  /// How children join their parents: 0 Welded (convex-hull junctions, one closed surface per tree; default), 1
  /// Seated tubes (each branch its own closed tube, base ring on the parent's surface: the surfaces overlap).
  vtkSetMacro(Joints, int);
  vtkGetMacro(Joints, int);
  /// Memory budget: at most this many skeleton segments (and leaves), [1, 1e9]. Default 2e7.
  vtkSetMacro(MaxSegments, vtkIdType);
  vtkGetMacro(MaxSegments, vtkIdType);

  /// Control points taken from each stroke (the Bezier degree + 1), [2, 64]. Default 4.
  vtkSetMacro(StrokeControlPoints, int);
  vtkGetMacro(StrokeControlPoints, int);
  /// epsilon of the length rule (stroke branch length target / parent length); <= 0: 0.6 monopodial, 0.8
  /// sympodial. Default 0.
  vtkSetMacro(StrokeLengthRatio, double);
  vtkGetMacro(StrokeLengthRatio, double);
  /// 1: no template subtrees on stroke branches. Default 0.
  vtkSetMacro(StrokesOnly, int);
  vtkGetMacro(StrokesOnly, int);
  /// Levels of template subtree on each stroke branch, [0, 20]. Default 2.
  vtkSetMacro(StrokeSubtreeDepth, int);
  vtkGetMacro(StrokeSubtreeDepth, int);
  /// A .csv (stroke_id, x, y) or .svg file of strokes, used when the Strokes input is not connected. Default "".
  void SetStrokeFile(const char* path);
  const char* GetStrokeFile() const { return this->StrokeFile.c_str(); }

  /// 1: make leaves (port 2). Default 1.
  vtkSetMacro(Leaves, int);
  vtkGetMacro(Leaves, int);
  /// 0 monopodial (spread), 1 sympodial (whorl at the tip), 2 willow (pendulous twigs). Default 0.
  vtkSetMacro(LeafType, int);
  vtkGetMacro(LeafType, int);
  /// Leaves per twig, [0, 1000]. Default 6.
  vtkSetMacro(LeafCount, int);
  vtkGetMacro(LeafCount, int);
  /// Leaves spread over the last LeafRatio of each twig, [0, 1]. Default 0.6.
  vtkSetMacro(LeafRatio, double);
  vtkGetMacro(LeafRatio, double);
  /// Leaf length (quad side), (0, 1e5]. Default 1.
  vtkSetMacro(LeafScale, double);
  vtkGetMacro(LeafScale, double);
  /// Angle between a leaf's midrib and its twig, degrees, [0, 180]. Default 45.
  vtkSetMacro(LeafAngle, double);
  vtkGetMacro(LeafAngle, double);
  /// A leaf's length at the twig's tip as a fraction of LeafScale, linear along the leafy stretch from LeafScale at
  /// its start (young leaves near the tip are smaller), (0, 10]. Default 1 (every leaf LeafScale).
  vtkSetMacro(LeafTipScale, double);
  vtkGetMacro(LeafTipScale, double);
  /// Standard deviation of the natural log of a leaf's length (log-normal sizes drawn from Seed), [0, 1]. Default 0.
  vtkSetMacro(LeafScaleSpread, double);
  vtkGetMacro(LeafScaleSpread, double);

  /// The one seed of all randomness (ties in the nearest-parent search, leaf sizes). Default 0.
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);

  /// Merge input (port 2): the BranchId of this tree the second tree grows from, or -1 for a second trunk standing
  /// at MergeOffset. Default 0 (the trunk).
  vtkSetMacro(MergeParentBranch, int);
  vtkGetMacro(MergeParentBranch, int);
  /// Position on that branch, [0, 1]. Default 0.5.
  vtkSetMacro(MergeU, double);
  vtkGetMacro(MergeU, double);
  /// Divergence from that branch (tilt from +Y for a second trunk), degrees, [0, 180]. Default 34.4.
  vtkSetMacro(MergeAngle, double);
  vtkGetMacro(MergeAngle, double);
  /// Rotation about that branch (about +Y for a second trunk), degrees. Default 0.
  vtkSetMacro(MergeRotation, double);
  vtkGetMacro(MergeRotation, double);
  /// Uniform scale of the second tree, (0, 1e6]. Default 1.
  vtkSetMacro(MergeScale, double);
  vtkGetMacro(MergeScale, double);
  /// Where a second trunk stands (MergeParentBranch -1). Default (0, 0, 0).
  vtkSetVector3Macro(MergeOffset, double);
  vtkGetVector3Macro(MergeOffset, double);

  /// Branch ids to delete with their subtrees.
  void ClearDeletedBranches();
  void AddDeletedBranch(int id);
  /// Rows of six: BranchId, length, radius, u, angle, rotation_angle; NaN or any value <= -1000 keeps the computed
  /// value (write -1000 in scripts you save as state files: ParaView 5.11 state files turn NaN into 0).
  void ClearBranchOverrides();
  void AddBranchOverride(double id, double length, double radius, double u, double angle, double rotation);
  /// How many numbers the BranchOverrides property held (the XML's element_count_command, pushed after the rows by
  /// vtkSICountedDoubleVectorProperty: ParaView drops a partial last row before AddBranchOverride sees it). A count
  /// that is not the rows' numbers is refused with an error naming BranchOverrides. ClearBranchOverrides resets it
  /// to -1 (not given).
  void SetBranchOverridesElementCount(int count);

  ///@{
  /**
   * The optional inputs by name: Strokes (port 0), Leaf (port 1), MergeTree (port 2); nullptr disconnects. The
   * server-manager XML connects through these, with `port_index` values 3, 4, 5 that no algorithm port has: ParaView
   * 5.11's paraview.simple connects the active source to the input property of port_index 0 of every new proxy,
   * and a source's optional inputs must stay empty unless the user sets them. The first argument (the XML's
   * port_index) is ignored.
   */
  void SetStrokesConnection(int xmlPortIndex, vtkAlgorithmOutput* output);
  void SetLeafConnection(int xmlPortIndex, vtkAlgorithmOutput* output);
  void SetMergeTreeConnection(int xmlPortIndex, vtkAlgorithmOutput* output);
  ///@}

  /**
   * What the named Preset sets (TreeType, Length, Radius, Depth, PhyllotaxisA/B, ChildCount, Ratio), one
   * "Property = value" per line, for the read-only PresetValues box of the Properties panel beside the greyed-out
   * properties it overrides; for Custom, a line saying the properties are used. Computed from Preset alone.
   */
  const char* GetPresetValues();

protected:
  vtkTreeFromSketchSource();
  ~vtkTreeFromSketchSource() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  /// With a named Preset, warns about each preset-set property changed from its default to a value the preset
  /// overrides (it is not what the output has).
  void WarnAboutPresetOverrides(const plantmorph::TreeParameters& used);
  /// Properties -> parameters (the Preset applied); "" or the message naming the property out of range.
  std::string ReadProperties(plantmorph::TreeParameters& parameters);
  /// The PlantMorph.* field data every output carries: the parameters used and the build's reports.
  void FillFieldData(plantmorph::FieldRecord& fieldData, const plantmorph::TreeParameters& parameters,
    const plantmorph::Tree& tree, std::size_t strokeCount, const plantmorph::JointReport& joints,
    const plantmorph::JunctionReport& junctions) const;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Mode = 0;
  int Preset = 1;
  int TreeType = 0;
  double Length = 12.0;
  double Radius = 0.4;
  int Depth = 4;
  int PhyllotaxisA = 3;
  int PhyllotaxisB = 8;
  int ChildCount = 8;
  double Ratio = 0.7;
  double LengthScale = 0.8;
  double MonopodialAngle = 34.4;
  double SympodialAngle = 55.6;
  int SegmentsPerBranch = 4;
  double TwigScale = 1.2;
  int Sides = 6;
  int Joints = 0;
  vtkIdType MaxSegments = 20000000;
  int StrokeControlPoints = 4;
  double StrokeLengthRatio = 0.0;
  int StrokesOnly = 0;
  int StrokeSubtreeDepth = 2;
  std::string StrokeFile;
  int Leaves = 1;
  int LeafType = 0;
  int LeafCount = 6;
  double LeafRatio = 0.6;
  double LeafScale = 1.0;
  double LeafAngle = 45.0;
  double LeafTipScale = 1.0;
  double LeafScaleSpread = 0.0;
  int Seed = 0;
  int MergeParentBranch = 0;
  double MergeU = 0.5;
  double MergeAngle = 34.4;
  double MergeRotation = 0.0;
  double MergeScale = 1.0;
  double MergeOffset[3] = { 0.0, 0.0, 0.0 };
  std::vector<int> DeletedBranches;
  std::vector<double> BranchOverrides;
  int BranchOverridesElementCount = -1;
  std::string PresetValues;

private:
  /// RequestData's body (plantmorph::RunRequestData): this piece's tree, its three ports and field data.
  void Execute(plantmorph::Run& run);

  vtkTreeFromSketchSource(const vtkTreeFromSketchSource&) = delete;
  void operator=(const vtkTreeFromSketchSource&) = delete;
};

#endif
