// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkLeafOutlineSource
 * @brief   A leaf blade and its outline from the published outline models (docs/methods/leaf-outline.md).
 *
 * Related publications:
 * - [P000] Lu Ling, Wang Lei, "Visual modelling of plant leaf venation" (in Chinese; venue not known): sec. 1,
 *   eq. (1), Figs. 1-2 (Model A);
 * - [P002] Yuan Xiujiu, Liu Dong, Wang Shengyong, Yang Rong, Zhao Xuejun, "Plant leaf shapes from space-curve
 *   theory" (in Chinese), Journal of Air Force Engineering University (Natural Science Edition), 2011(3):78-83:
 *   eqs. (1)-(10), Figs. 1-8 (Model B, palmate leaves);
 * - [P003] Lu Shenglian, Guo Xinyu, Li Changfeng, "Accurate modelling and rendering of 3-D plant leaves" (in
 *   Chinese), Journal of Image and Graphics 14(4):731-737, 2009: secs. 2.1, 2.2, 2.4, eq. (6) (Model C, TCoords).
 * Full references: docs/references.md. What the code does, and where and why it departs from the paper:
 * docs/methods/leaf-outline.md.
 *
 * Output port 0, **Blade**: the flat triangulated blade (XY plane, base at the origin, midvein along +Y, normals
 * +Z) with point arrays `LeafUV` (double x2, the point's (u, v) on the canonical leaf), `TCoords` (float x2,
 * paper 003 eq. (6), the active texture coordinates), `Region` (int: 1 midvein, 4 margin, 0 elsewhere),
 * `Normals` (active normals), and cell array `Region` (0). Output port 1, **Outline**: three polylines, left margin,
 * right margin and midvein, each from the base to the apex, with cell `Region` 4, 4, 1 and the same point arrays
 * (palmate leaves: then each further lobe's midvein, base to its tip, `Region` 1).
 * Both outputs carry the parameters as field data (`PlantMorph.Model`, `PlantMorph.Preset`, `PlantMorph.Terms`...),
 * so a saved file says how it was made.
 *
 * Model A, the deformed rectangle (paper 000 eq. (1)): the rectangle u in [-0.5, 0.5],
 * v in [0, 1] mapped by a sum of sinusoid terms (see plantmorph::DeformedRectangleModel for the term rows). A
 * `Preset` other than Custom supplies the terms and the width; `Length` always sets the size. The blade is meshed
 * with CGAL's constrained Delaunay triangulation with the midvein as a constraint (`MeshQuality` 0: the paper's
 * plain triangulation of the samples; 1: Delaunay refinement of the interior to a 20.7 degree minimum angle and
 * edges about the midvein spacing, never splitting margin or midvein). The midvein's two end points (base and
 * apex) are Region 1: the vein owns them.
 *
 * Model B, the space curve (paper 002): a half-margin integrated from the Frenet-Serret equations with the chosen
 * curvature and torsion functions, mirrored in the symmetry plane (Opening), the midvein from its projection, and
 * quad strips from margin to midvein split into triangles (see plantmorph::BuildSpaceCurveLeaf). With torsion or
 * Opening the blade is 3-D; its normals are area-weighted vertex normals. `Lobes` 3 or 5 builds the palmate leaf of
 * paper 002 Fig. 8: the union of lobes, each a scaled and turned copy starting on the previous lobe's margin, meshed
 * as one blade by CGAL with every lobe's midvein as a feature line (see plantmorph::BuildPalmateLeaf).
 *
 * The source generates the whole leaf as piece 0 and leaves other pieces empty, so it appears once under MPI.
 * Bad parameters produce an error naming the property and its accepted range, and empty outputs.
 *
 * Presets: the properties a named preset sets are used only when it is Custom. One changed from its default while a
 * named preset is on is not what the output has, so a warning names it and says to choose Custom (the same in
 * pvpython, the GUI and a loaded state file, whose outputs are unchanged).
 */
#ifndef vtkLeafOutlineSource_h
#define vtkLeafOutlineSource_h

#include "PlantMorphLeafVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for error messages
#include <vector> // for the term list

class vtkPolyData;
namespace plantmorph
{
class FieldRecord;
class Run;
struct LeafGeometry;
struct LeafMeshParameters;
}

class PLANTMORPHLEAFVTK_EXPORT vtkLeafOutlineSource : public vtkPolyDataAlgorithm
{
public:
  static vtkLeafOutlineSource* New();
  vtkTypeMacro(vtkLeafOutlineSource, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum ModelType
  {
    DEFORMED_RECTANGLE = 0,
    SPACE_CURVE = 1,
    B_SPLINE = 2
  };

  ///@{
  /**
   * Outline model: DEFORMED_RECTANGLE (0, paper 000; properties Preset ... Asymmetry), SPACE_CURVE (1, paper
   * 002; properties SpaceCurvePreset ... StripColumns) or B_SPLINE (2, paper 003; properties BSplinePreset ...
   * RightMarginPoints). Default: deformed rectangle.
   */
  vtkSetMacro(Model, int);
  vtkGetMacro(Model, int);
  ///@}

  ///@{
  /**
   * Preset (plantmorph::DeformedRectanglePreset): 0 Custom (Width and Terms as given), 1 Ginkgo (eq. (1)),
   * 2 Entire, 3 Serrate, 4 Lobed, 5 Parted (Fig. 1), 6 acute base/acute apex, 7 rounded/acuminate,
   * 8 cordate/rounded, 9 acuminate/emarginate (Fig. 2). Default: Ginkgo.
   */
  vtkSetMacro(Preset, int);
  vtkGetMacro(Preset, int);
  ///@}

  ///@{
  /**
   * The blade's length from base to apex (the chord of the midvein), in model units (cm for the presets), for every
   * preset and Custom: the rectangle is built at b_y = Length (a_x: the preset's proportion, or Width), then a_x and
   * b_y are scaled together so the blade is Length long (the same shape). The a_x and b_y used are in the field
   * data as PlantMorph.RectangleWidth and PlantMorph.RectangleHeight (paper 000's own Length = 5 ginkgo is
   * b_y = 5, a blade 7.75 long). The bounding box can be longer: a cordate base's lobes reach below the base, the
   * ginkgo's erose margin above the apex. Range (0, 1e6]. Default 5.
   */
  vtkSetMacro(Length, double);
  vtkGetMacro(Length, double);
  ///@}

  ///@{
  /**
   * Custom preset only: a_x, the initial rectangle's width when its height b_y is Length (the proportion a_x : b_y
   * is Width : Length; the blade is then scaled to be Length long). Presets fix their own proportion. Range
   * [0, 1e6]. Default 5.5 (the ginkgo fan's 1.1 * Length).
   */
  vtkSetMacro(Width, double);
  vtkGetMacro(Width, double);
  ///@}

  ///@{
  /**
   * Sinusoid terms (Custom preset only), rows of seven numbers [Target (0 x, 1 y), Scale (0 Width, 1 Length),
   * Amplitude, Multiplier (0: 1, 1: u, 2: v, 3: u*v), Frequency, Variable (0 u, 1 v), Phase (radians)], each adding
   * Amplitude * Scale * Multiplier * sin(Frequency * pi * Variable + Phase) to x or y.
   */
  void ClearTerms();
  void AddTerm(
    double target, double scale, double amplitude, double multiplier, double frequency, double variable, double phase);
  int GetNumberOfTerms() const { return static_cast<int>(this->Terms.size() / 7); }
  /**
   * How many numbers the Terms property held (the server-manager XML's element_count_command, pushed after the
   * rows by vtkSICountedDoubleVectorProperty; ParaView drops a partial last row before AddTerm sees it). A count
   * that is not the rows' numbers is refused with an error naming Terms. ClearTerms resets it to -1 (not given).
   */
  void SetTermsElementCount(int count);
  ///@}

  ///@{
  /**
   * Bending: adds Bending * Length * v^2 to x, bending the midvein sideways. Range [-10, 10]. Default 0.
   */
  vtkSetMacro(Bending, double);
  vtkGetMacro(Bending, double);
  ///@}

  ///@{
  /**
   * Asymmetry: widens the right half by (1 + Asymmetry) and narrows the left by (1 - Asymmetry), smoothly, keeping
   * the midvein. Range (-1, 1). Default 0.
   */
  vtkSetMacro(Asymmetry, double);
  vtkGetMacro(Asymmetry, double);
  ///@}

  ///@{
  /**
   * Number of segments along the midvein; the margins are sampled at the same spacing, and quality mode keeps
   * every edge no longer than it. Range [2, 4000]. Default 60.
   */
  vtkSetMacro(Resolution, int);
  vtkGetMacro(Resolution, int);
  ///@}

  ///@{
  /**
   * 0: paper mode, the plain constrained Delaunay triangulation of the samples. 1 (default): quality mode, CGAL
   * Delaunay refinement of the interior (minimum angle about 20.7 degrees, edges up to the midvein spacing, up to
   * 1.5 times that next to the outline). Margin and midvein are never split: their vertices are exactly the
   * samples in both modes, so the Outline port is exactly the blade's boundary and feature line.
   */
  vtkSetMacro(MeshQuality, int);
  vtkGetMacro(MeshQuality, int);
  ///@}

  ///@{
  /**
   * Most vertices quality refinement may create before it stops with an error (a memory guard). Default 2e7.
   */
  vtkSetMacro(MaxVertices, int);
  vtkGetMacro(MaxVertices, int);
  ///@}

  ///@{
  /**
   * Space-curve model (paper 002). SpaceCurvePreset: 0 Custom (the Curvature*, Torsion* and Midvein* properties),
   * 1-6 paper 002 Figs. 1-6, 7 and 8 Fig. 8's palmate 3- and 5-lobed leaves (plantmorph::SpaceCurvePreset); a preset sets the curvature, torsion and midvein
   * stretches, and CurveLength, Opening, InitialAngle, IntegrationMethod, Resolution and StripColumns still apply.
   * CurveLength is the half-margin's arc length S; the Mu/Eta properties are peak times S, so changing S alone
   * grows a similar leaf. See plantmorph::CurvatureFamily for the families and their parameters.
   */
  vtkSetMacro(SpaceCurvePreset, int);
  vtkGetMacro(SpaceCurvePreset, int);
  vtkSetMacro(CurveLength, double);
  vtkGetMacro(CurveLength, double);
  vtkSetMacro(CurvatureFunction, int);
  vtkGetMacro(CurvatureFunction, int);
  vtkSetMacro(CurvatureMu, double);
  vtkGetMacro(CurvatureMu, double);
  vtkSetMacro(CurvatureLambda, double);
  vtkGetMacro(CurvatureLambda, double);
  vtkSetMacro(CurvatureN1, double);
  vtkGetMacro(CurvatureN1, double);
  vtkSetMacro(CurvatureN2, double);
  vtkGetMacro(CurvatureN2, double);
  vtkSetMacro(CurvatureB1, double);
  vtkGetMacro(CurvatureB1, double);
  vtkSetMacro(CurvatureU3, double);
  vtkGetMacro(CurvatureU3, double);
  vtkSetMacro(CurvatureBeta, double);
  vtkGetMacro(CurvatureBeta, double);
  vtkSetMacro(CurvatureAlpha4, double);
  vtkGetMacro(CurvatureAlpha4, double);
  vtkSetMacro(CurvatureLambda2, double);
  vtkGetMacro(CurvatureLambda2, double);
  vtkSetMacro(TorsionFunction, int);
  vtkGetMacro(TorsionFunction, int);
  vtkSetMacro(TorsionEta, double);
  vtkGetMacro(TorsionEta, double);
  vtkSetMacro(TorsionLambda, double);
  vtkGetMacro(TorsionLambda, double);
  vtkSetMacro(TorsionN1, double);
  vtkGetMacro(TorsionN1, double);
  vtkSetMacro(TorsionN2, double);
  vtkGetMacro(TorsionN2, double);
  vtkSetMacro(TorsionB1, double);
  vtkGetMacro(TorsionB1, double);
  vtkSetMacro(TorsionU3, double);
  vtkGetMacro(TorsionU3, double);
  vtkSetMacro(TorsionBeta, double);
  vtkGetMacro(TorsionBeta, double);
  vtkSetMacro(TorsionAlpha4, double);
  vtkGetMacro(TorsionAlpha4, double);
  vtkSetMacro(TorsionLambda2, double);
  vtkGetMacro(TorsionLambda2, double);
  vtkSetMacro(Opening, double);
  vtkGetMacro(Opening, double);
  vtkSetMacro(MidveinStretchZ, double);
  vtkGetMacro(MidveinStretchZ, double);
  vtkSetMacro(MidveinStretchXY, double);
  vtkGetMacro(MidveinStretchXY, double);
  vtkSetMacro(InitialAngle, double);
  vtkGetMacro(InitialAngle, double);
  vtkSetMacro(IntegrationMethod, int);
  vtkGetMacro(IntegrationMethod, int);
  vtkSetMacro(StripColumns, int);
  vtkGetMacro(StripColumns, int);
  ///@}

  ///@{
  /**
   * Palmate leaves of the space-curve model (paper 002 sec. 4, Fig. 8; plantmorph::BuildPalmateLeaf). Lobes: 1 (a
   * simple leaf), 3 or 5. With Custom curvature these apply; the Fig. 8 presets set them. LobeStart (0, 1): where a
   * lobe starts on the previous lobe's half-margin, as an arc-length fraction. LobeAngle (0, 90] degrees: how much
   * further out a lobe's initial tangent turns. LobeScale (0, 1.5]: a lobe's size relative to the previous one.
   * Palmate blades are flat (TorsionEta 0, Opening 0) and meshed with CGAL (MeshQuality applies, not
   * StripColumns); every lobe's midvein is a Region 1 feature line and a polyline of the Outline port.
   */
  vtkSetMacro(Lobes, int);
  vtkGetMacro(Lobes, int);
  vtkSetMacro(LobeStart, double);
  vtkGetMacro(LobeStart, double);
  vtkSetMacro(LobeAngle, double);
  vtkGetMacro(LobeAngle, double);
  vtkSetMacro(LobeScale, double);
  vtkGetMacro(LobeScale, double);
  /**
   * Sub-lobes of a palmate leaf (plantmorph::SpaceCurveParameters::subLobes, PalmateLeaf.h): SubLobes [0, 8] on
   * each side of every lobe (0, the default: entire lobes), spread evenly between LobeStart and the lobe's tip;
   * SubLobeDepth (0, 0.9]: the sinuses' depth as a fraction of the lobe's half-width there. The Watermelon preset
   * sets them.
   */
  vtkSetMacro(SubLobes, int);
  vtkGetMacro(SubLobes, int);
  vtkSetMacro(SubLobeDepth, double);
  vtkGetMacro(SubLobeDepth, double);
  ///@}

  ///@{
  /**
   * Palmate leaves: SinusDepth [0, 0.95] cuts every sinus between neighbouring lobes towards the base, to
   * (1 - SinusDepth) of the shorter lobe's length from it (plantmorph::SpaceCurveParameters::sinusDepth, PalmateLeaf.h); 0 (the default) keeps
   * the lobes' union. The pinnatifid Watermelon preset sets it.
   */
  vtkSetMacro(SinusDepth, double);
  vtkGetMacro(SinusDepth, double);
  ///@}

  ///@{
  /**
   * B-spline model (paper 003). BSplinePreset: 0 Custom (MidveinPoints, LeftMarginPoints, RightMarginPoints),
   * 1 Elliptic (ControlPointCount points per margin), 2 Cucumber, 3 Pin oak (plantmorph::BSplinePreset), 4 the
   * ControlPoints input's polylines; the
   * presets sized by BladeLength (along +Y) and BladeWidth. Control points are x, y, z triples; the curves pass
   * through them; margins that do not start at the midvein's first point (the base) or end at its last (the apex)
   * get them added. Curves out of a plane are meshed in their least-squares plane and the blade lifted onto
   * them (see plantmorph::BuildBSplineLeaf). MeshQuality applies as for the deformed rectangle.
   *
   * Input port 0 (optional, "ControlPoints"), used only when BSplinePreset is 4 ("ControlPoints input"; the
   * spec puts the input first, but pvpython and the GUI connect the active pipeline object to a new source's
   * input on their own, so using it only on request keeps a preset from silently turning into someone else's
   * polylines): polylines, either labelled by a cell array `Region` (the first Region 1 cell is the
   * midvein, the first two Region 4 cells the margins, told left from right by their side of the midvein) or,
   * unlabelled, exactly three polylines in the order the Outline port writes them: left margin, right margin,
   * midvein. A margin drawn from the apex to the base is reversed. So a traced set of polylines, or another
   * LeafOutlineSource's Outline, drives the leaf.
   */
  vtkSetMacro(BSplinePreset, int);
  vtkGetMacro(BSplinePreset, int);
  vtkSetMacro(BladeLength, double);
  vtkGetMacro(BladeLength, double);
  vtkSetMacro(BladeWidth, double);
  vtkGetMacro(BladeWidth, double);
  vtkSetMacro(ControlPointCount, int);
  vtkGetMacro(ControlPointCount, int);
  void ClearMidveinPoints();
  void AddMidveinPoint(double x, double y, double z);
  void ClearLeftMarginPoints();
  void AddLeftMarginPoint(double x, double y, double z);
  void ClearRightMarginPoints();
  void AddRightMarginPoint(double x, double y, double z);
  ///@}

  ///@{
  /**
   * Growth over time. With Growth on, the source advertises GrowthTimeSteps time values from 0 to 1 (the growth
   * fraction; ParaView's animation plays them) and at time t outputs the leaf scaled by
   * s = GrowthInitialScale + (1 - GrowthInitialScale) * t: deformed rectangle: Length (and Width for the Custom
   * preset) times s, the shape fixed (a similar leaf); space curve: CurveLength times s with Mu and Eta held, the
   * paper's similarity (except the exponential family with its fixed U3, which turns as it grows); B-spline: the
   * control points scaled about the base (presets: BladeLength and BladeWidth scaled). Requests
   * between or beyond the time values are clamped to [0, 1]. Defaults: off, 11 steps, initial scale 0.2.
   */
  vtkSetMacro(Growth, int);
  vtkGetMacro(Growth, int);
  vtkBooleanMacro(Growth, int);
  vtkSetMacro(GrowthTimeSteps, int);
  vtkGetMacro(GrowthTimeSteps, int);
  vtkSetMacro(GrowthInitialScale, double);
  vtkGetMacro(GrowthInitialScale, double);
  ///@}

  /**
   * The optional ControlPoints input (port 0); nullptr disconnects. The server-manager XML connects through this,
   * with a `port_index` of 1 that no algorithm port has: ParaView 5.11's paraview.simple connects the active source
   * to the input property of port_index 0 of every new proxy, and a source's optional input must stay empty unless
   * the user sets it. The first argument (the XML's port_index) is ignored.
   */
  void SetControlPointsConnection(int xmlPortIndex, vtkAlgorithmOutput* output);

  /**
   * For the read-only PresetValues box of the Properties panel: with a named preset of the current Model (Preset,
   * SpaceCurvePreset or BSplinePreset), the parameters the last update made the leaf with, one "Name = value" a
   * line (the outputs' PlantMorph.* field data: what the preset chose instead of the greyed-out properties); for
   * Custom, a line saying the properties are used. ParaView refreshes the box after each update.
   */
  const char* GetPresetValues();

protected:
  vtkLeafOutlineSource();
  ~vtkLeafOutlineSource() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Model = DEFORMED_RECTANGLE;
  int Preset = 1;
  double Length = 5.0;
  double Width = 5.5;
  std::vector<double> Terms;
  int TermsElementCount = -1;
  std::string LastParameters; // FormatParameters of the last leaf made, "" after an error
  std::string PresetValues;
  double Bending = 0.0;
  double Asymmetry = 0.0;
  int Resolution = 60;
  int MeshQuality = 1;
  int MaxVertices = 20000000;

  // Space-curve model, defaults: paper 002 Fig. 1.
  int SpaceCurvePreset = 1;
  double CurveLength = 5.0;
  int CurvatureFunction = 1;
  double CurvatureMu = 2.0;
  double CurvatureLambda = 0.7;
  double CurvatureN1 = 1.0;
  double CurvatureN2 = 1.0;
  double CurvatureB1 = 0.001;
  double CurvatureU3 = 0.001;
  double CurvatureBeta = 2.0;
  double CurvatureAlpha4 = 0.3;
  double CurvatureLambda2 = 0.5;
  int TorsionFunction = 1;
  double TorsionEta = 0.0;
  double TorsionLambda = 0.7;
  double TorsionN1 = 1.0;
  double TorsionN2 = 1.0;
  double TorsionB1 = 0.001;
  double TorsionU3 = 0.001;
  double TorsionBeta = 2.0;
  double TorsionAlpha4 = 0.3;
  double TorsionLambda2 = 0.5;
  double Opening = 0.0;
  double MidveinStretchZ = 1.0;
  double MidveinStretchXY = 0.0;
  double InitialAngle = -45.0;
  int IntegrationMethod = 1;
  int StripColumns = 6;
  int Lobes = 1;
  double LobeStart = 0.2;
  double LobeAngle = 45.0;
  double LobeScale = 0.85;
  int SubLobes = 0;
  double SubLobeDepth = 0.5;
  double SinusDepth = 0.0;

  int BSplinePreset = 2;
  double BladeLength = 8.0;
  double BladeWidth = 7.0;
  int ControlPointCount = 7;
  std::vector<double> MidveinPoints;
  std::vector<double> LeftMarginPoints;
  std::vector<double> RightMarginPoints;

  int Growth = 0;
  int GrowthTimeSteps = 11;
  double GrowthInitialScale = 0.2;

private:
  /// RequestData's body (plantmorph::RunRequestData): checks the properties, builds the leaf, writes both ports.
  void Execute(plantmorph::Run& run);
  /// Builds the chosen model's leaf and describes its parameters as field data; returns an error message or "".
  std::string BuildLeaf(
    plantmorph::LeafGeometry& leaf, plantmorph::FieldRecord& parameters, double scale, vtkPolyData* controlPoints);
  /// The three models' leaves, one each (BuildLeaf picks by Model); `scale` converts Units to the output's.
  std::string BuildDeformedRectangle(plantmorph::LeafGeometry& leaf, plantmorph::FieldRecord& parameters, double scale);
  std::string BuildSpaceCurve(plantmorph::LeafGeometry& leaf, plantmorph::FieldRecord& parameters, double scale);
  std::string BuildBSpline(
    plantmorph::LeafGeometry& leaf, plantmorph::FieldRecord& parameters, double scale, vtkPolyData* controlPoints);
  /// Mesh settings of the CGAL-meshed models (Resolution, MeshQuality, MaxVertices, progress and abort).
  std::string MeshParameters(plantmorph::LeafMeshParameters& settings);
  /// Empty when the growth properties are valid, else the message.
  std::string ValidateGrowth() const;
  /// With a named preset of the chosen model, warns about each property only Custom uses that was changed from
  /// its default (it is not what the output has).
  void WarnAboutPresetOverrides();

  vtkLeafOutlineSource(const vtkLeafOutlineSource&) = delete;
  void operator=(const vtkLeafOutlineSource&) = delete;
};

#endif
