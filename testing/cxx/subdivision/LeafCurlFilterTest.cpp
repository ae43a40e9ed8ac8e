// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK layer of LeafCurlFilter: on a real LeafOutlineSource blade it moves the points exactly as the core does,
// keeps their precision, passes every other array through (TCoords still the active texture coordinates), turns
// the normals with the surface, and refuses bad properties or input with an error naming them and an empty output.
#include "VtkErrorCatcher.h"
#include "vtkLeafCurlFilter.h"
#include "vtkLeafOutlineSource.h"

#include "LeafCurl.h"

#include <plantmorph/DataContract.h>

#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkPolygon.h"
#include "vtkSmartPointer.h"
#include "vtkTrivialProducer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace
{
using plantmorph::testing::ErrorCatcher;

vtkSmartPointer<vtkPolyData> Blade(int port = 0)
{
  vtkNew<vtkLeafOutlineSource> source; // the ginkgo leaf, paper 000 eq. (1)
  source->SetResolution(50);
  source->Update();
  auto blade = vtkSmartPointer<vtkPolyData>::New();
  blade->DeepCopy(source->GetOutput(port));
  return blade;
}

vtkSmartPointer<vtkPolyData> Curl(
  vtkPolyData* input, double longitudinal, double transverse, double center, std::string* errors = nullptr)
{
  vtkNew<vtkLeafCurlFilter> curl;
  vtkNew<ErrorCatcher> catcher;
  curl->AddObserver(vtkCommand::ErrorEvent, catcher);
  curl->SetInputData(input);
  curl->SetLongitudinalAngle(longitudinal);
  curl->SetTransverseAngle(transverse);
  curl->SetTransverseCenter(center);
  curl->Update();
  if (errors)
    *errors = catcher->Messages;
  else
    EXPECT_EQ(catcher->Messages, "");
  auto output = vtkSmartPointer<vtkPolyData>::New();
  output->ShallowCopy(curl->GetOutput());
  return output;
}

bool SameValues(vtkDataArray* a, vtkDataArray* b)
{
  if (!a || !b || a->GetNumberOfTuples() != b->GetNumberOfTuples() ||
    a->GetNumberOfComponents() != b->GetNumberOfComponents() || a->GetDataType() != b->GetDataType())
    return false;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    for (int c = 0; c < a->GetNumberOfComponents(); ++c)
      if (a->GetComponent(i, c) != b->GetComponent(i, c))
        return false;
  return true;
}

TEST(vtkLeafCurlFilter, MovesThePointsAsTheCoreDoesInTheInputsPrecision)
{
  const auto blade = Blade();
  const auto curled = Curl(blade, 120.0, 50.0, 0.4);
  ASSERT_EQ(curled->GetNumberOfPoints(), blade->GetNumberOfPoints());
  EXPECT_EQ(curled->GetPoints()->GetDataType(), blade->GetPoints()->GetDataType());
  const vtkIdType n = blade->GetNumberOfPoints();
  std::vector<double> xyz(3 * n), uv(2 * n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    blade->GetPoint(i, xyz.data() + 3 * i);
    blade->GetPointData()->GetArray(plantmorph::arrays::LeafUV)->GetTuple(i, uv.data() + 2 * i);
  }
  plantmorph::LeafCurlParameters p;
  p.longitudinalAngle = 120.0;
  p.transverseAngle = 50.0;
  p.transverseCenter = 0.4;
  ASSERT_EQ(plantmorph::CurlLeaf(p, static_cast<std::size_t>(n), xyz.data(), uv.data()), "");
  vtkNew<vtkPoints> expected; // the core's result stored at the input's precision
  expected->SetDataType(blade->GetPoints()->GetDataType());
  expected->SetNumberOfPoints(n);
  double maxZ = 0.0;
  for (vtkIdType i = 0; i < n; ++i)
  {
    expected->SetPoint(i, xyz.data() + 3 * i);
    maxZ = std::max(maxZ, std::abs(xyz[3 * i + 2]));
  }
  EXPECT_GT(maxZ, 0.5);
  EXPECT_TRUE(SameValues(curled->GetPoints()->GetData(), expected->GetData()));
  // Float points stay float.
  vtkNew<vtkPoints> single;
  single->SetDataTypeToFloat();
  single->DeepCopy(blade->GetPoints());
  auto floatBlade = vtkSmartPointer<vtkPolyData>::New();
  floatBlade->ShallowCopy(blade);
  vtkNew<vtkPoints> floatPoints;
  floatPoints->SetDataTypeToFloat();
  floatPoints->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i)
    floatPoints->SetPoint(i, blade->GetPoint(i));
  floatBlade->SetPoints(floatPoints);
  EXPECT_EQ(Curl(floatBlade, 120.0, 0.0, 0.5)->GetPoints()->GetDataType(), VTK_FLOAT);
}

TEST(vtkLeafCurlFilter, EveryOtherArrayPassesThroughAndTCoordsStayActive)
{
  const auto blade = Blade();
  const auto curled = Curl(blade, 150.0, -40.0, 0.5);
  vtkPointData* in = blade->GetPointData();
  vtkPointData* out = curled->GetPointData();
  EXPECT_EQ(out->GetNumberOfArrays(), in->GetNumberOfArrays());
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    const std::string name = in->GetArrayName(a);
    if (name == plantmorph::arrays::Normals)
      continue;
    EXPECT_TRUE(SameValues(in->GetArray(a), out->GetArray(name.c_str()))) << "point array " << name;
  }
  ASSERT_NE(out->GetTCoords(), nullptr);
  EXPECT_STREQ(out->GetTCoords()->GetName(), plantmorph::arrays::TCoords);
  EXPECT_TRUE(SameValues(in->GetTCoords(), out->GetTCoords()));
  for (int a = 0; a < blade->GetCellData()->GetNumberOfArrays(); ++a)
  {
    const char* name = blade->GetCellData()->GetArrayName(a);
    EXPECT_TRUE(SameValues(blade->GetCellData()->GetArray(a), curled->GetCellData()->GetArray(name)))
      << "cell array " << name;
  }
  EXPECT_EQ(curled->GetNumberOfPolys(), blade->GetNumberOfPolys());
  // The source's parameters stay in the field data, and the curl adds its own.
  for (int a = 0; a < blade->GetFieldData()->GetNumberOfArrays(); ++a)
    EXPECT_NE(curled->GetFieldData()->GetAbstractArray(blade->GetFieldData()->GetArrayName(a)), nullptr);
  auto* angle = curled->GetFieldData()->GetArray("PlantMorph.LongitudinalAngle");
  ASSERT_NE(angle, nullptr);
  EXPECT_EQ(angle->GetComponent(0, 0), 150.0);
  // The input is untouched (its point data and field data are not the output's).
  EXPECT_EQ(blade->GetFieldData()->GetArray("PlantMorph.LongitudinalAngle"), nullptr);
}

TEST(vtkLeafCurlFilter, NormalsTurnWithTheSurface)
{
  const auto blade = Blade();
  ASSERT_NE(blade->GetPointData()->GetNormals(), nullptr);
  // Cell normals too, from ParaView's usual normals filter.
  vtkNew<vtkPolyDataNormals> withCellNormals;
  withCellNormals->SetInputData(blade);
  withCellNormals->ComputeCellNormalsOn();
  withCellNormals->SplittingOff();
  withCellNormals->ConsistencyOff();
  withCellNormals->Update();
  const auto curled = Curl(withCellNormals->GetOutput(), 140.0, 50.0, 0.5);
  vtkDataArray* normals = curled->GetPointData()->GetNormals();
  vtkDataArray* cellNormals = curled->GetCellData()->GetNormals();
  ASSERT_NE(normals, nullptr);
  ASSERT_NE(cellNormals, nullptr);
  double worstPoint = 1.0, worstCell = 1.0;
  for (vtkIdType c = 0; c < curled->GetNumberOfCells(); ++c)
  {
    vtkIdType size = 0;
    const vtkIdType* ids = nullptr;
    curled->GetCellPoints(c, size, ids);
    double face[3];
    vtkPolygon::ComputeNormal(curled->GetPoints(), static_cast<int>(size), ids, face);
    double n[3];
    cellNormals->GetTuple(c, n);
    worstCell = std::min(worstCell, face[0] * n[0] + face[1] * n[1] + face[2] * n[2]);
    for (vtkIdType k = 0; k < size; ++k)
    {
      normals->GetTuple(ids[k], n);
      worstPoint = std::min(worstPoint, face[0] * n[0] + face[1] * n[1] + face[2] * n[2]);
    }
  }
  EXPECT_GT(worstCell, 1.0 - 1e-6);
  EXPECT_GT(worstPoint, 0.98);
}

TEST(vtkLeafCurlFilter, ZeroAnglesGiveTheInputPointsBitForBit)
{
  const auto blade = Blade();
  const auto curled = Curl(blade, 0.0, 0.0, 0.2);
  ASSERT_EQ(curled->GetNumberOfPoints(), blade->GetNumberOfPoints());
  vtkDataArray* a = blade->GetPoints()->GetData();
  vtkDataArray* b = curled->GetPoints()->GetData();
  ASSERT_EQ(a->GetDataType(), b->GetDataType());
  EXPECT_EQ(std::memcmp(a->GetVoidPointer(0), b->GetVoidPointer(0),
              static_cast<std::size_t>(a->GetNumberOfValues() * a->GetDataTypeSize())),
    0);
  EXPECT_TRUE(SameValues(blade->GetPointData()->GetNormals(), curled->GetPointData()->GetNormals()));
}

TEST(vtkLeafCurlFilter, TheOutlineCurlsOntoTheCurledBlade)
{
  // The Outline port's points are the blade's first points; curled alone they land where the curled blade puts
  // them (the widest points and the mid-line are on the outline), so blade and outline can be curled separately.
  const auto blade = Curl(Blade(0), 130.0, 45.0, 0.6);
  const auto outline = Curl(Blade(1), 130.0, 45.0, 0.6);
  ASSERT_GT(outline->GetNumberOfLines(), 0);
  for (vtkIdType i = 0; i < outline->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    outline->GetPoint(i, p);
    blade->GetPoint(i, q);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(p[k], q[k], 1e-12) << "outline point " << i;
  }
}

TEST(vtkLeafCurlFilter, BadPropertiesOrInputGiveAnErrorAndAnEmptyOutput)
{
  const auto blade = Blade();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case
  {
    double longitudinal, transverse, center;
    const char* expected;
  };
  const Case cases[] = { { nan, 0.0, 0.5, "LongitudinalAngle" }, { 400.0, 0.0, 0.5, "LongitudinalAngle" },
    { 90.0, -361.0, 0.5, "TransverseAngle" }, { 90.0, 10.0, 1.5, "TransverseCenter" },
    { 90.0, 10.0, nan, "TransverseCenter" } };
  for (const Case& c : cases)
  {
    std::string errors;
    const auto output = Curl(blade, c.longitudinal, c.transverse, c.center, &errors);
    EXPECT_NE(errors.find(c.expected), std::string::npos) << errors;
    EXPECT_NE(errors.find("accepted range"), std::string::npos) << errors;
    EXPECT_EQ(output->GetNumberOfPoints(), 0);
    EXPECT_EQ(output->GetNumberOfCells(), 0);
  }
  // No LeafUV.
  auto noUV = vtkSmartPointer<vtkPolyData>::New();
  noUV->DeepCopy(blade);
  noUV->GetPointData()->RemoveArray(plantmorph::arrays::LeafUV);
  std::string errors;
  auto output = Curl(noUV, 90.0, 0.0, 0.5, &errors);
  EXPECT_NE(errors.find("LeafUV"), std::string::npos) << errors;
  EXPECT_EQ(output->GetNumberOfPoints(), 0);
  // A NaN coordinate.
  auto broken = vtkSmartPointer<vtkPolyData>::New();
  broken->DeepCopy(blade);
  broken->GetPoints()->SetPoint(3, nan, 0.0, 0.0);
  output = Curl(broken, 90.0, 0.0, 0.5, &errors);
  EXPECT_NE(errors.find("point 3"), std::string::npos) << errors;
  EXPECT_EQ(output->GetNumberOfPoints(), 0);
  // No midvein (u = 0 nowhere).
  auto noMidvein = vtkSmartPointer<vtkPolyData>::New();
  noMidvein->DeepCopy(blade);
  noMidvein->GetPointData()->GetArray(plantmorph::arrays::LeafUV)->FillComponent(0, 0.3);
  output = Curl(noMidvein, 90.0, 0.0, 0.5, &errors);
  EXPECT_NE(errors.find("midvein"), std::string::npos) << errors;
  EXPECT_EQ(output->GetNumberOfCells(), 0);
  // An empty input is an empty piece, not an error.
  vtkNew<vtkPolyData> empty;
  output = Curl(empty, 90.0, 0.0, 0.5, &errors);
  EXPECT_EQ(errors, "");
  EXPECT_EQ(output->GetNumberOfPoints(), 0);
  // The same filter recovers when the property is fixed.
  EXPECT_GT(Curl(blade, 90.0, 0.0, 0.5)->GetNumberOfPoints(), 0);
}

} // namespace
