// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK layer: vtkLeafOutlineSource's outputs follow the data contract, pieces other than 0 stay empty, and bad
// properties give an error naming the property, with empty outputs.
#include "VtkErrorCatcher.h"
#include "vtkLeafOutlineSource.h"

#include <plantmorph/DataContract.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace
{
/// Collects the error messages an algorithm reports.
using plantmorph::testing::ErrorCatcher;

TEST(vtkLeafOutlineSource, BladeCarriesTheContractArrays)
{
  vtkNew<vtkLeafOutlineSource> source;
  source->Update();
  vtkPolyData* blade = source->GetOutput(0);
  ASSERT_GT(blade->GetNumberOfPolys(), 100);
  EXPECT_EQ(blade->GetNumberOfCells(), blade->GetNumberOfPolys());

  auto* uv = vtkDoubleArray::SafeDownCast(blade->GetPointData()->GetArray(plantmorph::arrays::LeafUV));
  ASSERT_NE(uv, nullptr);
  EXPECT_EQ(uv->GetNumberOfComponents(), 2);
  double range[2];
  uv->GetRange(range, 0);
  EXPECT_GE(range[0], -0.5);
  EXPECT_LE(range[1], 0.5);
  uv->GetRange(range, 1);
  EXPECT_GE(range[0], 0.0);
  EXPECT_LE(range[1], 1.0);

  vtkDataArray* tcoords = blade->GetPointData()->GetTCoords();
  ASSERT_NE(tcoords, nullptr);
  EXPECT_STREQ(tcoords->GetName(), plantmorph::arrays::TCoords);
  EXPECT_TRUE(vtkFloatArray::SafeDownCast(tcoords));
  tcoords->GetRange(range, 0);
  EXPECT_EQ(range[0], 0.0);
  EXPECT_EQ(range[1], 1.0);

  auto* region = vtkIntArray::SafeDownCast(blade->GetPointData()->GetArray(plantmorph::arrays::Region));
  ASSERT_NE(region, nullptr);
  region->GetRange(range);
  EXPECT_EQ(range[0], plantmorph::RegionBlade);
  EXPECT_EQ(range[1], plantmorph::RegionMargin);
  ASSERT_TRUE(vtkIntArray::SafeDownCast(blade->GetCellData()->GetArray(plantmorph::arrays::Region)));

  vtkDataArray* normals = blade->GetPointData()->GetNormals();
  ASSERT_NE(normals, nullptr);
  EXPECT_EQ(normals->GetTuple3(0)[2], 1.0);

  double bounds[6];
  blade->GetBounds(bounds);
  EXPECT_EQ(bounds[4], 0.0);
  EXPECT_EQ(bounds[5], 0.0);
  EXPECT_NEAR(bounds[2], 0.0, 1e-12); // the fan's base is the lowest point, at the origin

  auto* model = vtkStringArray::SafeDownCast(blade->GetFieldData()->GetAbstractArray("PlantMorph.Model"));
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->GetValue(0), "DeformedRectangle");
  auto* terms = vtkDoubleArray::SafeDownCast(blade->GetFieldData()->GetArray("PlantMorph.Terms"));
  ASSERT_NE(terms, nullptr);
  EXPECT_EQ(terms->GetNumberOfComponents(), 7);
  EXPECT_EQ(terms->GetNumberOfTuples(), 3); // eq. (1) has three sinusoid terms
}

TEST(vtkLeafOutlineSource, OutlineHasLeftRightAndMidveinPolylines)
{
  vtkNew<vtkLeafOutlineSource> source;
  source->SetResolution(25);
  source->Update();
  vtkPolyData* outline = source->GetOutput(1);
  ASSERT_EQ(outline->GetNumberOfLines(), 3);
  auto* region = vtkIntArray::SafeDownCast(outline->GetCellData()->GetArray(plantmorph::arrays::Region));
  ASSERT_NE(region, nullptr);
  EXPECT_EQ(region->GetValue(0), plantmorph::RegionMargin);
  EXPECT_EQ(region->GetValue(1), plantmorph::RegionMargin);
  EXPECT_EQ(region->GetValue(2), plantmorph::RegionMidvein);
  vtkNew<vtkIdList> ids;
  outline->GetCellPoints(2, ids);
  EXPECT_EQ(ids->GetNumberOfIds(), 26); // Resolution segments
  // All three run from the base to the apex.
  vtkNew<vtkIdList> left, right;
  outline->GetCellPoints(0, left);
  outline->GetCellPoints(1, right);
  EXPECT_EQ(left->GetId(0), ids->GetId(0));
  EXPECT_EQ(right->GetId(0), ids->GetId(0));
  EXPECT_EQ(left->GetId(left->GetNumberOfIds() - 1), ids->GetId(25));
  EXPECT_EQ(right->GetId(right->GetNumberOfIds() - 1), ids->GetId(25));
  // The outline's points are the blade's first points, same coordinates.
  vtkPolyData* blade = source->GetOutput(0);
  for (vtkIdType i = 0; i < outline->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    outline->GetPoint(i, a);
    blade->GetPoint(i, b);
    ASSERT_EQ(a[0], b[0]);
    ASSERT_EQ(a[1], b[1]);
  }
}

TEST(vtkLeafOutlineSource, OnlyPieceZeroMakesTheLeaf)
{
  vtkNew<vtkLeafOutlineSource> source;
  source->UpdatePiece(0, 2, 0);
  const vtkIdType cells = source->GetOutput(0)->GetNumberOfCells();
  EXPECT_GT(cells, 0);
  source->UpdatePiece(1, 2, 0);
  EXPECT_EQ(source->GetOutput(0)->GetNumberOfCells(), 0);
  EXPECT_EQ(source->GetOutput(1)->GetNumberOfCells(), 0);
}

TEST(vtkLeafOutlineSource, CustomTermsOfEquationOneEqualTheGinkgoPreset)
{
  vtkNew<vtkLeafOutlineSource> preset;
  preset->Update();
  vtkNew<vtkLeafOutlineSource> custom;
  custom->SetPreset(0);
  custom->SetWidth(5.5);
  custom->SetLength(5.0);
  custom->AddTerm(0, 1, 1.1, 1, 1, 1, -M_PI / 2);
  custom->AddTerm(1, 1, 0.05, 2, 11, 0, -1.5);
  custom->AddTerm(1, 1, -0.6, 2, 1, 0, -M_PI / 2);
  custom->Update();
  vtkPolyData* a = preset->GetOutput();
  vtkPolyData* b = custom->GetOutput();
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    a->GetPoint(i, p);
    b->GetPoint(i, q);
    ASSERT_NEAR(p[0], q[0], 1e-12);
    ASSERT_NEAR(p[1], q[1], 1e-12);
  }
}

struct BadCase
{
  const char* expected;
  void (*apply)(vtkLeafOutlineSource*);
};

TEST(vtkLeafOutlineSource, BadPropertiesGiveAMessageAndEmptyOutputs)
{
  const BadCase cases[] = {
    { "Resolution = 1 is outside the accepted range [2, 4000]", [](vtkLeafOutlineSource* s) { s->SetResolution(1); } },
    { "Length = nan is outside the accepted range (0, 1e6]",
      [](vtkLeafOutlineSource* s) { s->SetLength(std::nan("")); } },
    { "Preset = 42 is outside the accepted range [0, 9]", [](vtkLeafOutlineSource* s) { s->SetPreset(42); } },
    { "Model = 3 is outside the accepted range {0, 1, 2}", [](vtkLeafOutlineSource* s) { s->SetModel(3); } },
    { "MeshQuality = 2", [](vtkLeafOutlineSource* s) { s->SetMeshQuality(2); } },
    { "Asymmetry = 1.5", [](vtkLeafOutlineSource* s) { s->SetAsymmetry(1.5); } },
    { "Terms: row 0, Multiplier = 7",
      [](vtkLeafOutlineSource* s) {
        s->SetPreset(0);
        s->AddTerm(0, 0, 1, 7, 1, 1, 0);
      } },
    { "fold",
      [](vtkLeafOutlineSource* s) {
        s->SetPreset(0);
        s->AddTerm(0, 0, -3, 1, 1, 1, 0);
      } },
    // What ParaView's push of Terms = [9 numbers] does: the whole row, then the raw count (the XML's
    // element_count_command).
    { "Terms = 9 numbers is outside the accepted range {0, 7, 14, ...}",
      [](vtkLeafOutlineSource* s) {
        s->SetPreset(0);
        s->ClearTerms();
        s->AddTerm(0, 0, 0.2, 0, 1, 1, 0);
        s->SetTermsElementCount(9);
      } },
  };
  for (const BadCase& bad : cases)
  {
    vtkNew<vtkLeafOutlineSource> source;
    vtkNew<ErrorCatcher> catcher;
    source->AddObserver(vtkCommand::ErrorEvent, catcher);
    bad.apply(source);
    source->Update();
    EXPECT_NE(catcher->Messages.find(bad.expected), std::string::npos)
      << "expected '" << bad.expected << "', got '" << catcher->Messages << "'";
    EXPECT_EQ(source->GetOutput(0)->GetNumberOfPoints(), 0);
    EXPECT_EQ(source->GetOutput(1)->GetNumberOfPoints(), 0);
  }
}

TEST(vtkLeafOutlineSource, WholeTermRowsWithTheirCountAreAccepted)
{
  // The count of whole rows, as the property pushes it, and a clear that resets it: no error, a leaf.
  vtkNew<vtkLeafOutlineSource> source;
  vtkNew<ErrorCatcher> catcher;
  source->AddObserver(vtkCommand::ErrorEvent, catcher);
  source->SetPreset(0);
  source->AddTerm(0, 0, 0.2, 0, 1, 1, 0);
  source->SetTermsElementCount(7);
  source->Update();
  EXPECT_EQ(catcher->Messages, "");
  EXPECT_GT(source->GetOutput(0)->GetNumberOfPoints(), 0);
  source->SetTermsElementCount(8);
  source->Update();
  EXPECT_NE(catcher->Messages.find("the last row has 1"), std::string::npos) << catcher->Messages;
  EXPECT_EQ(source->GetOutput(0)->GetNumberOfPoints(), 0);
  catcher->Messages.clear();
  source->ClearTerms(); // the C++ interface: no count given, none checked
  source->Update();
  EXPECT_EQ(catcher->Messages, "");
  EXPECT_GT(source->GetOutput(0)->GetNumberOfPoints(), 0);
}

} // namespace

namespace
{
vtkSmartPointer<vtkPolyData> SpaceCurveBlade(int preset, double length)
{
  vtkNew<vtkLeafOutlineSource> source;
  source->SetModel(vtkLeafOutlineSource::SPACE_CURVE);
  source->SetSpaceCurvePreset(preset);
  source->SetCurveLength(length);
  source->SetResolution(30);
  source->Update();
  vtkSmartPointer<vtkPolyData> blade = source->GetOutput(0);
  return blade;
}

TEST(vtkLeafOutlineSource, SpaceCurveModelGrowsSimilarLeavesThroughThePipeline)
{
  for (int preset : { 1, 5 })
  {
    vtkSmartPointer<vtkPolyData> small = SpaceCurveBlade(preset, 2.0);
    vtkSmartPointer<vtkPolyData> large = SpaceCurveBlade(preset, 6.0);
    ASSERT_GT(small->GetNumberOfPolys(), 100);
    ASSERT_EQ(small->GetNumberOfPoints(), large->GetNumberOfPoints());
    for (vtkIdType i = 0; i < small->GetNumberOfPoints(); ++i)
    {
      double a[3], b[3];
      small->GetPoint(i, a);
      large->GetPoint(i, b);
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(3.0 * a[k], b[k], 1e-9);
    }
    auto* model = vtkStringArray::SafeDownCast(small->GetFieldData()->GetAbstractArray("PlantMorph.Model"));
    ASSERT_NE(model, nullptr);
    EXPECT_EQ(model->GetValue(0), "SpaceCurve");
    auto* curvature = vtkDoubleArray::SafeDownCast(small->GetFieldData()->GetArray("PlantMorph.Curvature"));
    ASSERT_NE(curvature, nullptr);
    EXPECT_EQ(curvature->GetComponent(0, 1), preset == 1 ? 2.0 : 5.0); // paper 002's mu
    ASSERT_NE(small->GetPointData()->GetArray(plantmorph::arrays::LeafUV), nullptr);
    ASSERT_NE(small->GetPointData()->GetTCoords(), nullptr);
  }
  // Fig. 5 has torsion: a 3-D blade whose normals are not all +Z.
  vtkSmartPointer<vtkPolyData> twisted = SpaceCurveBlade(5, 5.0);
  double bounds[6];
  twisted->GetBounds(bounds);
  EXPECT_GT(bounds[5] - bounds[4], 0.2);
  double lowest = 1.0;
  for (vtkIdType i = 0; i < twisted->GetNumberOfPoints(); ++i)
    lowest = std::min(lowest, twisted->GetPointData()->GetNormals()->GetTuple3(i)[2]);
  EXPECT_LT(lowest, 0.99);
}

TEST(vtkLeafOutlineSource, SpaceCurveBadPropertiesGiveAMessage)
{
  vtkNew<vtkLeafOutlineSource> source;
  vtkNew<ErrorCatcher> catcher;
  source->AddObserver(vtkCommand::ErrorEvent, catcher);
  source->SetModel(vtkLeafOutlineSource::SPACE_CURVE);
  source->SetSpaceCurvePreset(0);
  source->SetCurvatureLambda(2.0);
  source->Update();
  EXPECT_NE(catcher->Messages.find("CurvatureLambda = 2 is outside the accepted range [0, 1]"), std::string::npos)
    << catcher->Messages;
  EXPECT_EQ(source->GetOutput(0)->GetNumberOfPoints(), 0);
  catcher->Messages.clear();
  source->SetCurvatureLambda(0.5);
  source->SetOpening(1.0);
  source->Update();
  EXPECT_NE(catcher->Messages.find("Opening = 1"), std::string::npos) << catcher->Messages;
  catcher->Messages.clear();
  source->SetOpening(0.0);
  source->SetSpaceCurvePreset(11);
  source->Update();
  EXPECT_NE(catcher->Messages.find("SpaceCurvePreset = 11"), std::string::npos) << catcher->Messages;
  catcher->Messages.clear();
  source->SetSpaceCurvePreset(0);
  source->SetLobes(4);
  source->Update();
  EXPECT_NE(catcher->Messages.find("Lobes = 4 is outside the accepted range {1, 3, 5}"), std::string::npos)
    << catcher->Messages;
  EXPECT_EQ(source->GetOutput(0)->GetNumberOfPoints(), 0);
  EXPECT_EQ(source->GetOutput(1)->GetNumberOfPoints(), 0);
}

TEST(vtkLeafOutlineSource, TorsionShapeParametersReachTheModel)
{
  vtkNew<vtkLeafOutlineSource> source;
  vtkNew<ErrorCatcher> catcher;
  source->AddObserver(vtkCommand::ErrorEvent, catcher);
  source->SetModel(vtkLeafOutlineSource::SPACE_CURVE);
  source->SetSpaceCurvePreset(0);
  source->SetResolution(30);
  source->SetTorsionFunction(3); // exponential
  source->SetTorsionEta(2.0);
  source->SetTorsionB1(0.05);
  source->SetTorsionU3(0.4);
  source->Update();
  ASSERT_EQ(catcher->Messages, "");
  auto* torsion = vtkDoubleArray::SafeDownCast(source->GetOutput(0)->GetFieldData()->GetArray("PlantMorph.Torsion"));
  ASSERT_NE(torsion, nullptr);
  EXPECT_EQ(torsion->GetComponent(0, 5), 0.05);
  EXPECT_EQ(torsion->GetComponent(0, 6), 0.4);
  double before[6];
  source->GetOutput(0)->GetBounds(before);
  source->SetTorsionU3(0.01);
  source->Update();
  double after[6];
  source->GetOutput(0)->GetBounds(after);
  EXPECT_GT(std::abs(after[5] - before[5]) + std::abs(after[4] - before[4]), 1e-3); // another twist, another leaf
  source->SetTorsionFunction(4);                                                    // notched apex
  source->SetTorsionAlpha4(1.5);
  source->Update();
  EXPECT_NE(catcher->Messages.find("Alpha4 = 1.5"), std::string::npos) << catcher->Messages;
  EXPECT_EQ(source->GetOutput(0)->GetNumberOfPoints(), 0);
}

TEST(vtkLeafOutlineSource, PalmateLeafHasEveryLobeMidveinOnTheOutlinePort)
{
  for (int preset : { 7, 8, 9 }) // 9: Watermelon, Fig. 8's five lobes with sub-lobes
  {
    vtkNew<vtkLeafOutlineSource> source;
    source->SetModel(vtkLeafOutlineSource::SPACE_CURVE);
    source->SetSpaceCurvePreset(preset);
    source->SetResolution(30);
    source->Update();
    vtkPolyData* blade = source->GetOutput(0);
    vtkPolyData* outline = source->GetOutput(1);
    const int lobes = preset == 7 ? 3 : 5;
    ASSERT_GT(blade->GetNumberOfPolys(), 500);
    ASSERT_EQ(outline->GetNumberOfLines(), 2 + lobes);
    auto* lineRegion = vtkIntArray::SafeDownCast(outline->GetCellData()->GetArray(plantmorph::arrays::Region));
    auto* pointRegion = vtkIntArray::SafeDownCast(blade->GetPointData()->GetArray(plantmorph::arrays::Region));
    ASSERT_NE(lineRegion, nullptr);
    ASSERT_NE(pointRegion, nullptr);
    for (vtkIdType line = 0; line < outline->GetNumberOfLines(); ++line)
    {
      EXPECT_EQ(lineRegion->GetValue(line), line < 2 ? plantmorph::RegionMargin : plantmorph::RegionMidvein);
      vtkNew<vtkIdList> ids;
      outline->GetCellPoints(line, ids);
      // Every polyline runs from the base (the origin) and its points are the blade's points with the same ids.
      double base[3];
      outline->GetPoint(ids->GetId(0), base);
      EXPECT_EQ(base[0], 0.0);
      EXPECT_EQ(base[1], 0.0);
      int tips = 0; // a margin passes the tips of the lateral lobes on its side (Region 1: the midveins own them)
      for (vtkIdType k = 1; k + 1 < ids->GetNumberOfIds(); ++k)
      {
        double a[3], b[3];
        outline->GetPoint(ids->GetId(k), a);
        blade->GetPoint(ids->GetId(k), b);
        EXPECT_EQ(a[0], b[0]);
        EXPECT_EQ(a[1], b[1]);
        const int region = pointRegion->GetValue(ids->GetId(k));
        tips += line < 2 && region == plantmorph::RegionMidvein;
        EXPECT_EQ(region == plantmorph::RegionMidvein, line >= 2 || region != plantmorph::RegionMargin);
      }
      EXPECT_EQ(tips, line < 2 ? (lobes - 1) / 2 : 0);
    }
  }
}

TEST(vtkLeafOutlineSource, SubLobesReachTheModelAndItsFieldData)
{
  // Custom SubLobes 2 / SubLobeDepth 0.5 on Fig. 8's five lobes is the Watermelon preset's blade, point for point;
  // the field data names them (and only when there are sub-lobes); SubLobes 9 is refused naming it.
  auto build = [](int preset, int subLobes) {
    vtkNew<vtkLeafOutlineSource> source;
    source->SetModel(vtkLeafOutlineSource::SPACE_CURVE);
    source->SetSpaceCurvePreset(preset);
    if (preset == 0)
    {
      source->SetCurvatureMu(3.0);
      source->SetCurvatureLambda(0.5);
      source->SetLobes(5);
      source->SetLobeStart(0.2);
      source->SetLobeAngle(40.0);
      source->SetLobeScale(0.85);
      source->SetSubLobes(subLobes);
      source->SetSubLobeDepth(0.5);
    }
    source->SetResolution(30);
    source->Update();
    vtkSmartPointer<vtkPolyData> blade = source->GetOutput(0);
    return blade;
  };
  vtkSmartPointer<vtkPolyData> preset = build(9, 0), custom = build(0, 2), entire = build(8, 0);
  ASSERT_GT(preset->GetNumberOfPoints(), 0);
  ASSERT_EQ(custom->GetNumberOfPoints(), preset->GetNumberOfPoints());
  for (vtkIdType i = 0; i < preset->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    preset->GetPoint(i, a);
    custom->GetPoint(i, b);
    ASSERT_EQ(a[0], b[0]);
    ASSERT_EQ(a[1], b[1]);
  }
  auto* count = vtkDoubleArray::SafeDownCast(preset->GetFieldData()->GetArray("PlantMorph.SubLobes"));
  ASSERT_NE(count, nullptr);
  EXPECT_EQ(count->GetValue(0), 2.0);
  EXPECT_EQ(entire->GetFieldData()->GetArray("PlantMorph.SubLobes"), nullptr);
  EXPECT_NE(entire->GetNumberOfPoints(), preset->GetNumberOfPoints());

  vtkNew<vtkLeafOutlineSource> bad;
  vtkNew<ErrorCatcher> catcher;
  bad->AddObserver(vtkCommand::ErrorEvent, catcher);
  bad->SetModel(vtkLeafOutlineSource::SPACE_CURVE);
  bad->SetSpaceCurvePreset(0);
  bad->SetLobes(5);
  bad->SetSubLobes(9);
  bad->Update();
  EXPECT_NE(catcher->Messages.find("SubLobes = 9 is outside the accepted range [0, 8]"), std::string::npos)
    << catcher->Messages;
  EXPECT_EQ(bad->GetOutput(0)->GetNumberOfPoints(), 0);
}
} // namespace

#include "vtkInformation.h"
#include "vtkStreamingDemandDrivenPipeline.h"

namespace
{
TEST(vtkLeafOutlineSource, GrowthAdvertisesTimeStepsAndScalesTheLeaf)
{
  for (int model : { vtkLeafOutlineSource::DEFORMED_RECTANGLE, vtkLeafOutlineSource::SPACE_CURVE })
  {
    vtkNew<vtkLeafOutlineSource> growing;
    growing->SetModel(model);
    growing->SetMeshQuality(0);
    growing->SetResolution(30);
    growing->GrowthOn();
    growing->SetGrowthTimeSteps(6);
    growing->SetGrowthInitialScale(0.25);
    growing->UpdateInformation();
    vtkInformation* info = growing->GetOutputInformation(0);
    ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
    ASSERT_EQ(info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 6);
    EXPECT_EQ(info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS())[5], 1.0);

    // At time 0.4 the leaf is the static leaf of size 0.25 + 0.75 * 0.4 = 0.55 of the full one.
    growing->UpdateTimeStep(0.4);
    vtkPolyData* grown = growing->GetOutput(0);
    vtkNew<vtkLeafOutlineSource> fixed;
    fixed->SetModel(model);
    fixed->SetMeshQuality(0);
    fixed->SetResolution(30);
    fixed->SetLength(0.55 * 5.0);
    fixed->SetCurveLength(0.55 * 5.0);
    fixed->Update();
    ASSERT_EQ(grown->GetNumberOfPoints(), fixed->GetOutput(0)->GetNumberOfPoints());
    for (vtkIdType i = 0; i < grown->GetNumberOfPoints(); ++i)
    {
      double a[3], b[3];
      grown->GetPoint(i, a);
      fixed->GetOutput(0)->GetPoint(i, b);
      ASSERT_NEAR(a[0], b[0], 1e-12);
      ASSERT_NEAR(a[1], b[1], 1e-12);
    }
    EXPECT_EQ(grown->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()), 0.4);
    // Times beyond the range are clamped to it.
    growing->UpdateTimeStep(7.0);
    double bounds[6];
    growing->GetOutput(0)->GetBounds(bounds);
    growing->UpdateTimeStep(1.0);
    double full[6];
    growing->GetOutput(0)->GetBounds(full);
    EXPECT_EQ(bounds[3], full[3]);
  }
}

TEST(vtkLeafOutlineSource, BadGrowthPropertiesGiveAMessage)
{
  vtkNew<vtkLeafOutlineSource> source;
  vtkNew<ErrorCatcher> catcher;
  source->AddObserver(vtkCommand::ErrorEvent, catcher);
  source->GrowthOn();
  source->SetGrowthInitialScale(0.0);
  source->Update();
  EXPECT_NE(catcher->Messages.find("GrowthInitialScale = 0 is outside the accepted range (0, 1]"), std::string::npos)
    << catcher->Messages;
  EXPECT_EQ(source->GetOutput(0)->GetNumberOfPoints(), 0);
}
} // namespace

namespace
{
TEST(vtkLeafOutlineSource, BSplineModelFromControlPointsAndGrowingAboutTheBase)
{
  vtkNew<vtkLeafOutlineSource> source;
  source->SetModel(vtkLeafOutlineSource::B_SPLINE);
  source->SetBSplinePreset(0);
  source->SetResolution(30);
  source->SetMeshQuality(0);
  for (double y : { 0.0, 3.0, 6.0 })
    source->AddMidveinPoint(1.0, 2.0 + y, 0.0); // base at (1, 2)
  source->AddLeftMarginPoint(-1.0, 4.0, 0.0);
  source->AddLeftMarginPoint(-0.5, 6.5, 0.0);
  source->AddRightMarginPoint(3.0, 4.5, 0.0);
  source->Update();
  vtkPolyData* blade = source->GetOutput(0);
  ASSERT_GT(blade->GetNumberOfPolys(), 20);
  double bounds[6];
  blade->GetBounds(bounds);
  EXPECT_NEAR(bounds[2], 2.0, 1e-12); // the base is the lowest point here
  EXPECT_NEAR(bounds[3], 8.0, 1e-12); // the apex the highest
  auto* model = vtkStringArray::SafeDownCast(blade->GetFieldData()->GetAbstractArray("PlantMorph.Model"));
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->GetValue(0), "BSpline");
  auto* midvein = vtkDoubleArray::SafeDownCast(blade->GetFieldData()->GetArray("PlantMorph.MidveinPoints"));
  ASSERT_NE(midvein, nullptr);
  EXPECT_EQ(midvein->GetNumberOfTuples(), 3);

  // Growing: at time 0 every point is the full leaf's point scaled by 0.5 about the base (1, 2).
  source->GrowthOn();
  source->SetGrowthInitialScale(0.5);
  source->UpdateTimeStep(1.0);
  vtkNew<vtkPolyData> full;
  full->DeepCopy(source->GetOutput(0));
  source->UpdateTimeStep(0.0);
  vtkPolyData* young = source->GetOutput(0);
  ASSERT_EQ(young->GetNumberOfPoints(), full->GetNumberOfPoints());
  for (vtkIdType i = 0; i < young->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    young->GetPoint(i, a);
    full->GetPoint(i, b);
    ASSERT_NEAR(a[0], 1.0 + 0.5 * (b[0] - 1.0), 1e-9);
    ASSERT_NEAR(a[1], 2.0 + 0.5 * (b[1] - 2.0), 1e-9);
  }
}

TEST(vtkLeafOutlineSource, BSplineBadControlPointsGiveAMessage)
{
  vtkNew<vtkLeafOutlineSource> source;
  vtkNew<ErrorCatcher> catcher;
  source->AddObserver(vtkCommand::ErrorEvent, catcher);
  source->SetModel(vtkLeafOutlineSource::B_SPLINE);
  source->SetBSplinePreset(0);
  source->AddMidveinPoint(0, 0, 0);
  source->Update();
  EXPECT_NE(catcher->Messages.find("MidveinPoints: control points: need at least 2, got 1"), std::string::npos)
    << catcher->Messages;
  EXPECT_EQ(source->GetOutput(0)->GetNumberOfPoints(), 0);
  catcher->Messages.clear();
  source->SetBSplinePreset(1);
  source->SetBladeWidth(-1.0);
  source->Update();
  EXPECT_NE(catcher->Messages.find("BladeWidth = -1"), std::string::npos) << catcher->Messages;
}
} // namespace

namespace
{
/// Three polylines (left margin, right margin, midvein), optionally labelled with a cell Region array.
vtkSmartPointer<vtkPolyData> TracedPolylines(bool labelled, bool reverseLeft)
{
  const double left[][2] = { { -2, 2 }, { -1.5, 4.5 } }, right[][2] = { { 2.2, 2.5 } },
               midvein[][2] = { { 0, 0 }, { 0.3, 3 }, { 0, 6 } };
  auto polydata = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble(); // float would round 0.3 and 2.2, and the curves would differ
  vtkNew<vtkCellArray> lines;
  auto addLine = [&](const double(*xy)[2], int n, bool reverse) {
    lines->InsertNextCell(n);
    for (int i = 0; i < n; ++i)
    {
      const int k = reverse ? n - 1 - i : i;
      lines->InsertCellPoint(points->InsertNextPoint(xy[k][0], xy[k][1], 0.0));
    }
  };
  // Labelled: the midvein first, to show that the order does not matter then.
  if (labelled)
    addLine(midvein, 3, false);
  addLine(left, 2, reverseLeft);
  addLine(right, 1, false);
  if (!labelled)
    addLine(midvein, 3, false);
  polydata->SetPoints(points);
  polydata->SetLines(lines);
  if (labelled)
  {
    vtkNew<vtkIntArray> region;
    region->SetName(plantmorph::arrays::Region);
    for (int r : { 1, 4, 4 })
      region->InsertNextValue(r);
    polydata->GetCellData()->AddArray(region);
  }
  return polydata;
}

TEST(vtkLeafOutlineSource, BSplineControlPointsFromTheInputPort)
{
  // The same control points as properties: the reference.
  vtkNew<vtkLeafOutlineSource> typed;
  typed->SetModel(vtkLeafOutlineSource::B_SPLINE);
  typed->SetBSplinePreset(0);
  typed->SetResolution(25);
  const double midvein[3][2] = { { 0, 0 }, { 0.3, 3 }, { 0, 6 } };
  for (const auto& p : midvein)
    typed->AddMidveinPoint(p[0], p[1], 0);
  typed->AddLeftMarginPoint(-2, 2, 0);
  typed->AddLeftMarginPoint(-1.5, 4.5, 0);
  typed->AddRightMarginPoint(2.2, 2.5, 0);
  typed->Update();
  const vtkIdType expected = typed->GetOutput(0)->GetNumberOfPoints();
  ASSERT_GT(expected, 20);

  for (bool labelled : { false, true })
  {
    for (bool reverse : { false, true })
    {
      vtkNew<vtkLeafOutlineSource> traced;
      traced->SetModel(vtkLeafOutlineSource::B_SPLINE);
      traced->SetBSplinePreset(4); // the ControlPoints input
      traced->SetResolution(25);
      traced->SetInputData(TracedPolylines(labelled, reverse));
      traced->Update();
      vtkPolyData* blade = traced->GetOutput(0);
      ASSERT_EQ(blade->GetNumberOfPoints(), expected) << "labelled " << labelled << " reversed " << reverse;
      for (vtkIdType i = 0; i < expected; ++i)
      {
        double a[3], b[3];
        blade->GetPoint(i, a);
        typed->GetOutput(0)->GetPoint(i, b);
        ASSERT_EQ(a[0], b[0]);
        ASSERT_EQ(a[1], b[1]);
      }
    }
  }
}

TEST(vtkLeafOutlineSource, AnOutlineDrivesAnotherLeaf)
{
  vtkNew<vtkLeafOutlineSource> first;
  first->SetModel(vtkLeafOutlineSource::B_SPLINE);
  first->SetBSplinePreset(3); // pin oak
  first->SetResolution(60);
  vtkNew<vtkLeafOutlineSource> second;
  second->SetModel(vtkLeafOutlineSource::B_SPLINE);
  second->SetBSplinePreset(4);
  second->SetResolution(60);
  second->SetInputConnection(first->GetOutputPort(1));
  second->Update();
  double a[6], b[6];
  first->GetOutput(0)->GetBounds(a);
  second->GetOutput(0)->GetBounds(b);
  for (int k = 0; k < 4; ++k)
    EXPECT_NEAR(a[k], b[k], 1e-3 * 8.0) << "bound " << k; // a spline through the samples of a spline
}

TEST(vtkLeafOutlineSource, BadControlPointsInputGivesAMessage)
{
  vtkNew<vtkPolyData> two;
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  for (int k = 0; k < 2; ++k)
  {
    lines->InsertNextCell(2);
    lines->InsertCellPoint(points->InsertNextPoint(k, 0, 0));
    lines->InsertCellPoint(points->InsertNextPoint(k, 1, 0));
  }
  two->SetPoints(points);
  two->SetLines(lines);
  vtkNew<vtkLeafOutlineSource> source;
  vtkNew<ErrorCatcher> catcher;
  source->AddObserver(vtkCommand::ErrorEvent, catcher);
  source->SetModel(vtkLeafOutlineSource::B_SPLINE);
  source->SetBSplinePreset(4);
  source->SetInputData(two);
  source->Update();
  EXPECT_NE(catcher->Messages.find("ControlPoints input: without a Region cell array it needs exactly 3 polylines"),
    std::string::npos)
    << catcher->Messages;
  EXPECT_EQ(source->GetOutput(0)->GetNumberOfPoints(), 0);
}
} // namespace

namespace
{
TEST(vtkLeafOutlineSource, AConnectedInputIsIgnoredUnlessAskedFor)
{
  // pvpython and the GUI connect the active object to a new source's input: a preset must not use it.
  vtkNew<vtkLeafOutlineSource> preset;
  preset->SetModel(vtkLeafOutlineSource::B_SPLINE);
  preset->SetBSplinePreset(3);
  preset->SetResolution(20);
  preset->Update();
  vtkNew<vtkLeafOutlineSource> connected;
  connected->SetModel(vtkLeafOutlineSource::B_SPLINE);
  connected->SetBSplinePreset(3);
  connected->SetResolution(20);
  connected->SetInputData(TracedPolylines(false, false));
  connected->Update();
  EXPECT_EQ(connected->GetOutput(0)->GetNumberOfPoints(), preset->GetOutput(0)->GetNumberOfPoints());
  // Asking for the input with nothing connected is an error, not a silent preset.
  vtkNew<vtkLeafOutlineSource> unconnected;
  vtkNew<ErrorCatcher> catcher;
  unconnected->AddObserver(vtkCommand::ErrorEvent, catcher);
  unconnected->SetModel(vtkLeafOutlineSource::B_SPLINE);
  unconnected->SetBSplinePreset(4);
  unconnected->Update();
  EXPECT_NE(catcher->Messages.find("needs polylines connected to the ControlPoints input"), std::string::npos)
    << catcher->Messages;
}
} // namespace
