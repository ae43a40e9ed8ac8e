// SPDX-License-Identifier: GPL-3.0-or-later
// vtkVenationFilter in a VTK pipeline: the veins of LeafOutlineSource's blades carry the data contract's arrays and
// statistics, lie on the surface (flat or 3-D blades), emboss the blade when asked, repeat bit for bit, and bad
// input gives a message and empty outputs.
#include "VtkErrorCatcher.h"
#include "vtkLeafOutlineSource.h"
#include "vtkVenationFilter.h"

#include <plantmorph/DataContract.h>

#include "vtkCellData.h"
#include "vtkCellLocator.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace
{
using plantmorph::testing::ErrorCatcher;

double FieldValue(vtkPolyData* data, const char* name, int component = 0)
{
  vtkDataArray* array = data->GetFieldData()->GetArray(name);
  return array ? array->GetComponent(0, component) : std::nan("");
}

TEST(vtkVenationFilter, VeinsCarryTheContractsArraysAndStatistics)
{
  vtkNew<vtkLeafOutlineSource> leaf;
  leaf->SetPreset(2); // entire margin
  leaf->SetResolution(60);
  vtkNew<vtkVenationFilter> venation;
  venation->SetInputConnection(leaf->GetOutputPort(0));
  venation->Update();
  vtkPolyData* veins = venation->GetOutput(0);
  ASSERT_GT(veins->GetNumberOfLines(), 50);
  EXPECT_EQ(veins->GetNumberOfPolys(), 0);
  auto* order = vtkIntArray::SafeDownCast(veins->GetCellData()->GetArray(plantmorph::arrays::VeinOrder));
  auto* cellRegion = vtkIntArray::SafeDownCast(veins->GetCellData()->GetArray(plantmorph::arrays::Region));
  auto* pointRegion = vtkIntArray::SafeDownCast(veins->GetPointData()->GetArray(plantmorph::arrays::Region));
  ASSERT_TRUE(order && cellRegion && pointRegion);
  ASSERT_NE(veins->GetPointData()->GetScalars(), nullptr);
  EXPECT_STREQ(veins->GetPointData()->GetScalars()->GetName(), plantmorph::arrays::VeinWidth);
  ASSERT_NE(veins->GetPointData()->GetArray(plantmorph::arrays::LeafUV), nullptr);
  ASSERT_NE(veins->GetPointData()->GetTCoords(), nullptr);
  int orders[6] = { 0, 0, 0, 0, 0, 0 }; // VeinOrder 1-5
  for (vtkIdType c = 0; c < veins->GetNumberOfLines(); ++c)
  {
    const int o = order->GetValue(c);
    ASSERT_GE(o, 1);
    ASSERT_LE(o, 5);
    ++orders[o];
    EXPECT_EQ(cellRegion->GetValue(c), std::min(o, 3));
  }
  EXPECT_EQ(orders[1], 1); // the midvein (paper mulberry: pinnate)
  EXPECT_GT(orders[2], 10);
  EXPECT_GT(orders[3], 20);
  EXPECT_GT(orders[4], 20); // quaternaries: the reticulum that subdivides the tertiaries' areoles
  // Flat blade: veins in its plane, inside its bounds; widths positive.
  double blade[6], bounds[6];
  leaf->GetOutput(0)->GetBounds(blade);
  veins->GetBounds(bounds);
  EXPECT_EQ(bounds[4], 0.0);
  EXPECT_EQ(bounds[5], 0.0);
  EXPECT_GE(bounds[0], blade[0] - 1e-9);
  EXPECT_LE(bounds[1], blade[1] + 1e-9);
  EXPECT_GE(bounds[2], blade[2] - 1e-9);
  EXPECT_LE(bounds[3], blade[3] + 1e-9);
  double range[2];
  veins->GetPointData()->GetScalars()->GetRange(range);
  EXPECT_GT(range[0], 0.0);
  EXPECT_NEAR(range[1], 0.015 * 5.0, 1e-6); // PrimaryWidth of a 5 cm leaf at the base
  // Statistics.
  EXPECT_NEAR(FieldValue(veins, "PlantMorph.VeinLength", 0), 5.0, 1e-6); // the midvein's length
  EXPECT_GT(FieldValue(veins, "PlantMorph.AreoleCount"), 20.0);
  EXPECT_GT(FieldValue(veins, "PlantMorph.VeinDensity"), 0.0);
  EXPECT_EQ(FieldValue(veins, "PlantMorph.FreeEnds"), 0.0);
  // Ports 2 and 3: one row of the same numbers, and a histogram of every areole in AreoleHistogramBins bins.
  vtkTable* statistics = vtkTable::SafeDownCast(venation->GetOutputDataObject(2));
  vtkTable* histogram = vtkTable::SafeDownCast(venation->GetOutputDataObject(3));
  ASSERT_NE(statistics, nullptr);
  ASSERT_NE(histogram, nullptr);
  ASSERT_EQ(statistics->GetNumberOfRows(), 1);
  EXPECT_EQ(statistics->GetValueByName(0, "AreoleCount").ToDouble(), FieldValue(veins, "PlantMorph.AreoleCount"));
  EXPECT_EQ(statistics->GetValueByName(0, "VLA").ToDouble(), FieldValue(veins, "PlantMorph.VeinDensity"));
  EXPECT_EQ(histogram->GetNumberOfRows(), venation->GetAreoleHistogramBins());
  double areoles = 0.0;
  for (vtkIdType b = 0; b < histogram->GetNumberOfRows(); ++b)
    areoles += histogram->GetValueByName(b, "Count").ToDouble();
  EXPECT_EQ(areoles, FieldValue(veins, "PlantMorph.AreoleCount"));
  auto* pattern = vtkStringArray::SafeDownCast(veins->GetFieldData()->GetAbstractArray("PlantMorph.VenationPattern"));
  ASSERT_NE(pattern, nullptr);
  EXPECT_EQ(pattern->GetValue(0), "Brochidodromous");
  // Port 1: the blade passed through.
  EXPECT_EQ(venation->GetOutput(1)->GetNumberOfPoints(), leaf->GetOutput(0)->GetNumberOfPoints());
  EXPECT_EQ(venation->GetOutput(1)->GetPoints()->GetData(), leaf->GetOutput(0)->GetPoints()->GetData());
}

TEST(vtkVenationFilter, VeinsLieOnACurvedBlade)
{
  // Paper 002 Fig. 5: a 3-D space-curve leaf (torsion).
  vtkNew<vtkLeafOutlineSource> leaf;
  leaf->SetModel(vtkLeafOutlineSource::SPACE_CURVE);
  leaf->SetSpaceCurvePreset(5);
  leaf->SetResolution(40);
  vtkNew<vtkVenationFilter> venation;
  venation->SetInputConnection(leaf->GetOutputPort(0));
  venation->Update();
  vtkPolyData* veins = venation->GetOutput(0);
  ASSERT_GT(veins->GetNumberOfLines(), 20);
  auto* plane = vtkStringArray::SafeDownCast(veins->GetFieldData()->GetAbstractArray("PlantMorph.VenationPlane"));
  ASSERT_NE(plane, nullptr);
  EXPECT_EQ(plane->GetValue(0), "ScaledLeafUV");
  vtkNew<vtkCellLocator> locator;
  locator->SetDataSet(leaf->GetOutput(0));
  locator->BuildLocator();
  double size = leaf->GetOutput(0)->GetLength();
  double worst = 0.0;
  for (vtkIdType i = 0; i < veins->GetNumberOfPoints(); ++i)
  {
    double x[3], closest[3], distance2;
    vtkIdType cell;
    int sub;
    veins->GetPoint(i, x);
    locator->FindClosestPoint(x, closest, cell, sub, distance2);
    worst = std::max(worst, std::sqrt(distance2));
  }
  EXPECT_LT(worst, 1e-6 * size);
  double bounds[6];
  veins->GetBounds(bounds);
  EXPECT_GT(bounds[5] - bounds[4], 0.1); // the veins follow the blade out of the plane
}

TEST(vtkVenationFilter, EmbossRaisesTheBladeOverTheVeins)
{
  vtkNew<vtkLeafOutlineSource> leaf;
  leaf->SetPreset(2);
  leaf->SetResolution(120);
  vtkNew<vtkVenationFilter> venation;
  venation->SetInputConnection(leaf->GetOutputPort(0));
  venation->SetEmbossDepth(0.05);
  venation->Update();
  vtkPolyData* blade = venation->GetOutput(1);
  ASSERT_EQ(blade->GetNumberOfPoints(), leaf->GetOutput(0)->GetNumberOfPoints());
  double bounds[6];
  blade->GetBounds(bounds);
  EXPECT_NEAR(bounds[5], 0.05, 0.01); // the midvein's full height
  EXPECT_GE(bounds[4], 0.0);
  EXPECT_EQ(blade->GetNumberOfPolys(), leaf->GetOutput(0)->GetNumberOfPolys());
}

TEST(vtkVenationFilter, SameSeedSameVeinsOtherSeedOtherVeins)
{
  vtkNew<vtkLeafOutlineSource> leaf;
  leaf->SetPreset(2);
  leaf->SetResolution(40);
  auto grow = [&](int seed) {
    vtkNew<vtkVenationFilter> venation;
    venation->SetInputConnection(leaf->GetOutputPort(0));
    venation->SetPreset(3);
    venation->SetSeed(seed);
    venation->Update();
    vtkSmartPointer<vtkPolyData> copy = vtkSmartPointer<vtkPolyData>::New();
    copy->DeepCopy(venation->GetOutput(0));
    return copy;
  };
  vtkSmartPointer<vtkPolyData> a = grow(3), b = grow(3), c = grow(4);
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    a->GetPoint(i, x);
    b->GetPoint(i, y);
    ASSERT_EQ(x[0], y[0]);
    ASSERT_EQ(x[1], y[1]);
  }
  EXPECT_NE(a->GetNumberOfPoints(), c->GetNumberOfPoints());
}

TEST(vtkVenationFilter, BadInputGivesAMessageAndEmptyOutputs)
{
  vtkNew<vtkLeafOutlineSource> leaf;
  leaf->SetResolution(30);
  struct Case
  {
    void (*set)(vtkVenationFilter*);
    const char* expected;
  };
  const Case cases[] = {
    { [](vtkVenationFilter* f) { f->SetPreset(7); }, "Preset = 7 is outside the accepted range [0, 6]" },
    { [](vtkVenationFilter* f) {
       f->SetPreset(0);
       f->SetPattern(12);
     },
      "Pattern = 12" },
    { [](vtkVenationFilter* f) {
       f->SetPreset(0);
       f->SetAreoleSize(std::nan(""));
     },
      "AreoleSize" },
    { [](vtkVenationFilter* f) { f->SetEmbossDepth(std::nan("")); }, "EmbossDepth" },
    { [](vtkVenationFilter* f) { f->SetMaxSegments(10); }, "MaxSegments = 10" },
    { [](vtkVenationFilter* f) {
       f->SetPreset(0);
       f->SetAreoleSize(0.001);
       f->SetMaxSegments(1000);
     },
      "MaxSegments" },
    { [](vtkVenationFilter* f) { f->SetAreoleHistogramBins(0); }, "AreoleHistogramBins = 0 is outside" },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkVenationFilter> venation;
    vtkNew<ErrorCatcher> catcher;
    venation->AddObserver(vtkCommand::ErrorEvent, catcher);
    venation->SetInputConnection(leaf->GetOutputPort(0));
    c.set(venation);
    venation->Update();
    EXPECT_NE(catcher->Messages.find(c.expected), std::string::npos) << catcher->Messages;
    EXPECT_EQ(venation->GetOutput(0)->GetNumberOfPoints(), 0);
    EXPECT_EQ(venation->GetOutput(1)->GetNumberOfPoints(), 0);
    EXPECT_EQ(vtkTable::SafeDownCast(venation->GetOutputDataObject(2))->GetNumberOfRows(), 0);
    EXPECT_EQ(vtkTable::SafeDownCast(venation->GetOutputDataObject(3))->GetNumberOfRows(), 0);
  }
  // A surface without LeafUV.
  vtkNew<vtkPolyData> bare;
  bare->ShallowCopy(leaf->GetOutput(0));
  bare->GetPointData()->RemoveArray(plantmorph::arrays::LeafUV);
  vtkNew<vtkVenationFilter> venation;
  vtkNew<ErrorCatcher> catcher;
  venation->AddObserver(vtkCommand::ErrorEvent, catcher);
  venation->SetInputData(bare);
  venation->Update();
  EXPECT_NE(catcher->Messages.find("LeafUV"), std::string::npos) << catcher->Messages;
  EXPECT_EQ(venation->GetOutput(0)->GetNumberOfPoints(), 0);
  // An empty input (another MPI piece): empty outputs, no error.
  vtkNew<vtkPolyData> empty;
  catcher->Messages.clear();
  venation->SetInputData(empty);
  venation->Update();
  EXPECT_EQ(catcher->Messages, "");
  EXPECT_EQ(venation->GetOutput(0)->GetNumberOfPoints(), 0);
}

} // namespace
