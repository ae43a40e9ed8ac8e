// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK layer of WiltingSimulator on a small triangulated plate (4 x 10 cm, LeafUV, Region, TCoords and an extra
// array): the time steps it advertises on every port, the frame at t = 0 equal to the input with every array passed
// through, the frame cache (other times are served without simulating again; a property change simulates again),
// the optional veins input (vein points follow the voxels exactly as the surface points at the same place, and their
// Region makes vein voxels), the contraction towards the base (the tip comes back and curls down), and errors
// (a message naming the property, empty outputs on every port).
#include "VtkErrorCatcher.h"
#include "vtkWiltingSimulator.h"

#include <plantmorph/DataContract.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"
#include "vtkTriangleFilter.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace
{
using plantmorph::testing::ErrorCatcher;

/// The plate x in [-2, 2], y in [0, 10], z = 0, triangulated, with LeafUV (x/4, y/10), Region (4 on the long
/// edges, else 0), its plane TCoords (active) and an array "Extra" = 7 x + y.
vtkSmartPointer<vtkPolyData> Plate()
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-2.0, 0.0, 0.0);
  plane->SetPoint1(2.0, 0.0, 0.0);
  plane->SetPoint2(-2.0, 10.0, 0.0);
  plane->SetResolution(8, 20);
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(plane->GetOutputPort());
  triangles->Update();
  auto plate = vtkSmartPointer<vtkPolyData>::New();
  plate->DeepCopy(triangles->GetOutput());
  const vtkIdType n = plate->GetNumberOfPoints();
  vtkNew<vtkDoubleArray> uv, extra;
  uv->SetName(plantmorph::arrays::LeafUV);
  uv->SetNumberOfComponents(2);
  uv->SetNumberOfTuples(n);
  extra->SetName("Extra");
  extra->SetNumberOfTuples(n);
  vtkNew<vtkIntArray> region;
  region->SetName(plantmorph::arrays::Region);
  region->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double x[3];
    plate->GetPoint(i, x);
    uv->SetTuple2(i, x[0] / 4.0, x[1] / 10.0);
    extra->SetValue(i, 7.0 * x[0] + x[1]);
    region->SetValue(i, std::abs(std::abs(x[0]) - 2.0) < 1e-9 ? plantmorph::RegionMargin : plantmorph::RegionBlade);
  }
  plate->GetPointData()->AddArray(uv);
  plate->GetPointData()->AddArray(extra);
  plate->GetPointData()->AddArray(region);
  return plate;
}

/// A midvein polyline along x = 0 through the plate's points (0, k), k = 0..10, Region 1, with a VeinWidth array.
vtkSmartPointer<vtkPolyData> Midvein()
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkIdList> ids;
  for (int k = 0; k <= 10; ++k)
  {
    ids->InsertNextId(points->InsertNextPoint(0.0, static_cast<double>(k), 0.0));
  }
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(ids);
  auto veins = vtkSmartPointer<vtkPolyData>::New();
  veins->SetPoints(points);
  veins->SetLines(lines);
  vtkNew<vtkIntArray> region;
  region->SetName(plantmorph::arrays::Region);
  vtkNew<vtkDoubleArray> width;
  width->SetName("VeinWidth");
  for (int k = 0; k <= 10; ++k)
  {
    region->InsertNextValue(plantmorph::RegionMidvein);
    width->InsertNextValue(0.1 + 0.01 * k);
  }
  veins->GetPointData()->AddArray(region);
  veins->GetPointData()->AddArray(width);
  return veins;
}

/// A quick, drooping Custom set-up: 1 cm voxels, 1 s in frames of 0.1 s, values per spring and per voxel (Units
/// Lattice: these tests are about the wrapper; physical units are WiltingPhysicalUnitsTest's).
vtkSmartPointer<vtkWiltingSimulator> Simulator(vtkPolyData* plate)
{
  auto wilt = vtkSmartPointer<vtkWiltingSimulator>::New();
  wilt->SetInputData(plate);
  wilt->SetPreset(vtkWiltingSimulator::PRESET_CUSTOM);
  wilt->SetUnits(1);
  wilt->SetVoxelSize(1.0);
  wilt->SetBladeMaterial(0.02, 2000.0, 0.0);
  wilt->SetMarginMaterial(0.02, 2000.0, 0.0);
  wilt->SetVeinMaterial(0.02, 20000.0, 0.0);
  wilt->SetDroopForce(20.0);
  wilt->SetContractionForce(0.0);
  wilt->SetLoadProfile(vtkWiltingSimulator::PROFILE_RAMP);
  wilt->SetLoadTime(0.5);
  wilt->SetAnchorRadius(1.5);
  wilt->SetDuration(1.0);
  wilt->SetFrameInterval(0.1);
  wilt->SetTimeStep(1.0 / 60.0);
  wilt->SetNewtonIterations(1);
  wilt->SetThreads(1);
  return wilt;
}

vtkPolyData* LeafAt(vtkWiltingSimulator* wilt, double time)
{
  wilt->UpdateTimeStep(time);
  return vtkPolyData::SafeDownCast(wilt->GetOutputDataObject(0));
}

int FieldCount(vtkPolyData* leaf)
{
  vtkDataArray* runs = leaf->GetFieldData()->GetArray("WiltingSimulator.SimulationCount");
  return runs ? static_cast<int>(runs->GetTuple1(0)) : -1;
}
} // namespace

TEST(vtkWiltingSimulator, AdvertisesOneTimeStepPerFrameOnEveryPort)
{
  auto plate = Plate();
  auto wilt = Simulator(plate);
  wilt->UpdateInformation();
  for (int port = 0; port < 4; ++port)
  {
    vtkInformation* info = wilt->GetOutputInformation(port);
    ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS())) << "port " << port;
    const int count = info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    ASSERT_EQ(count, 11) << "port " << port;
    const double* times = info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    for (int k = 0; k < count; ++k)
    {
      EXPECT_NEAR(times[k], 0.1 * k, 1e-12);
    }
    const double* range = info->Get(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
    EXPECT_EQ(range[0], 0.0);
    EXPECT_NEAR(range[1], 1.0, 1e-12);
  }
  // Nothing simulated just to answer the time question.
  EXPECT_EQ(wilt->GetSimulationCount(), 0);
  // A longer Duration advertises more frames.
  wilt->SetDuration(2.0);
  wilt->UpdateInformation();
  EXPECT_EQ(wilt->GetOutputInformation(0)->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 21);
}

TEST(vtkWiltingSimulator, FrameZeroIsTheInputWithEveryArrayPassedThrough)
{
  auto plate = Plate();
  auto wilt = Simulator(plate);
  vtkPolyData* leaf = LeafAt(wilt, 0.0);
  ASSERT_EQ(leaf->GetNumberOfPoints(), plate->GetNumberOfPoints());
  ASSERT_EQ(leaf->GetNumberOfPolys(), plate->GetNumberOfPolys());
  EXPECT_EQ(leaf->GetPoints()->GetDataType(), plate->GetPoints()->GetDataType());
  for (vtkIdType i = 0; i < plate->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    leaf->GetPoint(i, a);
    plate->GetPoint(i, b);
    ASSERT_EQ(a[0], b[0]);
    ASSERT_EQ(a[1], b[1]);
    ASSERT_EQ(a[2], b[2]);
  }
  for (const char* name : { "Extra", plantmorph::arrays::Region, plantmorph::arrays::LeafUV })
  {
    vtkDataArray* in = plate->GetPointData()->GetArray(name);
    vtkDataArray* out = leaf->GetPointData()->GetArray(name);
    ASSERT_NE(out, nullptr) << name;
    ASSERT_EQ(out->GetNumberOfComponents(), in->GetNumberOfComponents());
    for (vtkIdType i = 0; i < in->GetNumberOfTuples(); ++i)
    {
      for (int c = 0; c < in->GetNumberOfComponents(); ++c)
      {
        ASSERT_EQ(out->GetComponent(i, c), in->GetComponent(i, c)) << name;
      }
    }
  }
  ASSERT_NE(leaf->GetPointData()->GetTCoords(), nullptr);
  EXPECT_EQ(leaf->GetPointData()->GetTCoords()->GetNumberOfTuples(), plate->GetNumberOfPoints());
  vtkDataArray* displacement = leaf->GetPointData()->GetArray("Displacement");
  ASSERT_NE(displacement, nullptr);
  double largest = 0.0;
  for (vtkIdType i = 0; i < displacement->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      largest = std::max(largest, std::abs(displacement->GetComponent(i, c)));
    }
  }
  EXPECT_EQ(largest, 0.0);
}

TEST(vtkWiltingSimulator, ServesOtherTimesFromTheCacheAndDroops)
{
  auto plate = Plate();
  auto wilt = Simulator(plate);
  vtkNew<vtkPolyData> last;
  last->DeepCopy(LeafAt(wilt, 1.0));
  EXPECT_EQ(wilt->GetSimulationCount(), 1);
  EXPECT_EQ(FieldCount(last), 1);
  // The leaf droops: lower than the flat plate, the tip lowest of all.
  double bounds[6];
  last->GetBounds(bounds);
  EXPECT_LT(bounds[4], -0.5);
  // Other times, and the first again: no new simulation, and the same frame bit for bit.
  vtkNew<vtkPolyData> middle;
  middle->DeepCopy(LeafAt(wilt, 0.5));
  LeafAt(wilt, 0.25);
  vtkPolyData* again = LeafAt(wilt, 1.0);
  EXPECT_EQ(wilt->GetSimulationCount(), 1);
  EXPECT_EQ(FieldCount(again), 1);
  double lowMiddle = 0.0, lowLast = 0.0;
  for (vtkIdType i = 0; i < again->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3], m[3];
    again->GetPoint(i, a);
    last->GetPoint(i, b);
    middle->GetPoint(i, m);
    ASSERT_EQ(a[2], b[2]);
    lowMiddle = std::min(lowMiddle, m[2]);
    lowLast = std::min(lowLast, b[2]);
  }
  EXPECT_LT(lowLast, lowMiddle); // later is lower (the load ramps up to 0.5 s, then it settles)
  EXPECT_LT(lowMiddle, 0.0);
  // A time between frames is interpolated and reported.
  vtkPolyData* between = LeafAt(wilt, 0.55);
  EXPECT_NEAR(between->GetFieldData()->GetArray("WiltingSimulator.FrameTime")->GetTuple1(0), 0.55, 1e-12);
  // The trajectory table has every frame; the voxel grid's fixed nodes never move.
  wilt->UpdateTimeStep(1.0);
  vtkTable* table = vtkTable::SafeDownCast(wilt->GetOutputDataObject(2));
  ASSERT_EQ(table->GetNumberOfRows(), 11);
  EXPECT_LT(table->GetValueByName(10, "TipZ").ToDouble(), table->GetValueByName(0, "TipZ").ToDouble() - 0.5);
  vtkUnstructuredGrid* voxels = vtkUnstructuredGrid::SafeDownCast(wilt->GetOutputDataObject(1));
  ASSERT_EQ(voxels->GetNumberOfCells(), 40); // the 4 x 10 cm plate in 1 cm cubes, one layer
  vtkDataArray* fixed = voxels->GetPointData()->GetArray("Fixed");
  vtkDataArray* nodeDisplacement = voxels->GetPointData()->GetArray("Displacement");
  int fixedCount = 0;
  for (vtkIdType n = 0; n < voxels->GetNumberOfPoints(); ++n)
  {
    if (fixed->GetTuple1(n) != 0.0)
    {
      ++fixedCount;
      for (int c = 0; c < 3; ++c)
      {
        ASSERT_EQ(nodeDisplacement->GetComponent(n, c), 0.0);
      }
    }
  }
  EXPECT_GT(fixedCount, 0);
  EXPECT_EQ(wilt->GetSimulationCount(), 1);
  // A property change simulates again.
  wilt->SetDroopForce(30.0);
  vtkPolyData* stronger = LeafAt(wilt, 1.0);
  EXPECT_EQ(wilt->GetSimulationCount(), 2);
  EXPECT_EQ(FieldCount(stronger), 2);
  EXPECT_LT(stronger->GetBounds()[4], bounds[4]);
}

TEST(vtkWiltingSimulator, VeinsFollowTheVoxelsLikeTheSurfaceAndMakeVeinVoxels)
{
  auto plate = Plate();
  auto veins = Midvein();
  auto wilt = Simulator(plate);
  wilt->UpdateTimeStep(0.0);
  vtkUnstructuredGrid* voxels = vtkUnstructuredGrid::SafeDownCast(wilt->GetOutputDataObject(1));
  int veinVoxels = 0;
  vtkDataArray* cellRegion = voxels->GetCellData()->GetArray(plantmorph::arrays::Region);
  for (vtkIdType c = 0; c < voxels->GetNumberOfCells(); ++c)
  {
    veinVoxels += cellRegion->GetTuple1(c) == plantmorph::RegionMidvein ? 1 : 0;
  }
  EXPECT_EQ(veinVoxels, 0);
  EXPECT_EQ(vtkPolyData::SafeDownCast(wilt->GetOutputDataObject(3))->GetNumberOfPoints(), 0);

  wilt->SetVeinsData(veins);
  vtkPolyData* zero = LeafAt(wilt, 0.0);
  EXPECT_EQ(zero->GetNumberOfPoints(), plate->GetNumberOfPoints());
  vtkPolyData* moved = vtkPolyData::SafeDownCast(wilt->GetOutputDataObject(3));
  ASSERT_EQ(moved->GetNumberOfPoints(), veins->GetNumberOfPoints());
  for (vtkIdType i = 0; i < veins->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    moved->GetPoint(i, a);
    veins->GetPoint(i, b);
    ASSERT_EQ(a[0], b[0]);
    ASSERT_EQ(a[1], b[1]);
    ASSERT_EQ(a[2], b[2]);
  }
  voxels = vtkUnstructuredGrid::SafeDownCast(wilt->GetOutputDataObject(1));
  cellRegion = voxels->GetCellData()->GetArray(plantmorph::arrays::Region);
  for (vtkIdType c = 0; c < voxels->GetNumberOfCells(); ++c)
  {
    veinVoxels += cellRegion->GetTuple1(c) == plantmorph::RegionMidvein ? 1 : 0;
  }
  EXPECT_GE(veinVoxels, 10); // the midvein's 10 cm cross at least one voxel per cm

  vtkPolyData* leaf = LeafAt(wilt, 1.0);
  moved = vtkPolyData::SafeDownCast(wilt->GetOutputDataObject(3));
  ASSERT_EQ(moved->GetNumberOfLines(), 1);
  ASSERT_NE(moved->GetPointData()->GetArray("VeinWidth"), nullptr);
  EXPECT_EQ(moved->GetPointData()->GetArray("VeinWidth")->GetTuple1(3), 0.13);
  vtkDataArray* veinDisplacement = moved->GetPointData()->GetArray("Displacement");
  vtkDataArray* leafDisplacement = leaf->GetPointData()->GetArray("Displacement");
  ASSERT_NE(veinDisplacement, nullptr);
  // Each vein point sits on a plate point (0, k): both are bound to the same voxel at the same local coordinates.
  int matched = 0;
  for (vtkIdType i = 0; i < veins->GetNumberOfPoints(); ++i)
  {
    double v[3];
    veins->GetPoint(i, v);
    for (vtkIdType j = 0; j < plate->GetNumberOfPoints(); ++j)
    {
      double p[3];
      plate->GetPoint(j, p);
      if (p[0] == v[0] && p[1] == v[1] && p[2] == v[2])
      {
        ++matched;
        for (int c = 0; c < 3; ++c)
        {
          EXPECT_EQ(veinDisplacement->GetComponent(i, c), leafDisplacement->GetComponent(j, c));
        }
      }
    }
  }
  EXPECT_EQ(matched, 11);
  const double veinEndDrop = veinDisplacement->GetComponent(10, 2);
  EXPECT_LT(veinEndDrop, -0.5); // the vein's end droops with the tip
  // A request through the veins' port alone is served at the time asked of that port (port 0 still asks for 0).
  LeafAt(wilt, 0.0);
  wilt->GetOutputInformation(3)->Set(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP(), 1.0);
  wilt->Update(3);
  moved = vtkPolyData::SafeDownCast(wilt->GetOutputDataObject(3));
  EXPECT_EQ(moved->GetPointData()->GetArray("Displacement")->GetComponent(10, 2), veinEndDrop);
  // New veins simulate again.
  const int runs = wilt->GetSimulationCount();
  auto shorter = Midvein();
  shorter->GetPoints()->SetPoint(10, 0.0, 9.5, 0.0);
  wilt->SetVeinsData(shorter);
  LeafAt(wilt, 1.0);
  EXPECT_EQ(wilt->GetSimulationCount(), runs + 1);
}

TEST(vtkWiltingSimulator, ContractionTowardsTheBaseShortensAndCurlsTheLeaf)
{
  auto plate = Plate();
  double tipY[2], tipZ[2];
  for (int target = 0; target < 2; ++target)
  {
    auto wilt = Simulator(plate);
    wilt->SetGravity(0.0);
    wilt->SetDroopForce(0.0);
    wilt->SetContractionForce(40.0);
    wilt->SetContractionTarget(target);
    wilt->UpdateTimeStep(1.0);
    vtkTable* table = vtkTable::SafeDownCast(wilt->GetOutputDataObject(2));
    ASSERT_EQ(table->GetNumberOfRows(), 11);
    EXPECT_NEAR(table->GetValueByName(0, "TipY").ToDouble(), 10.0, 1e-12);
    tipY[target] = table->GetValueByName(10, "TipY").ToDouble();
    tipZ[target] = table->GetValueByName(10, "TipZ").ToDouble();
  }
  // Towards the base on the bottom nodes: the tip comes back and down; towards the midvein it hardly moves.
  EXPECT_LT(tipY[1], 10.0 - 0.2);
  EXPECT_LT(tipZ[1], -0.2);
  EXPECT_LT(std::abs(tipY[0] - 10.0), 0.25 * (10.0 - tipY[1]));
}

TEST(vtkWiltingSimulator, DroopAsymmetryTiltsTheLeafAndItsMirrorTiltsItBack)
{
  // The plate is symmetric about x = 0 and its 1 cm voxels are too (x in [-2, 2]: four columns): with
  // DroopAsymmetry a the +x margin sinks below the -x margin, with -a the mirror image, and 0 is level.
  auto plate = Plate();
  const vtkIdType left = 20 * 9 + 0; // the apex row's corners, x = -2 and +2
  const vtkIdType right = 20 * 9 + 8;
  double tilt[3];
  double rightZ[3], leftZ[3];
  const double asymmetry[3] = { 0.0, 0.6, -0.6 };
  for (int k = 0; k < 3; ++k)
  {
    auto wilt = Simulator(plate);
    wilt->SetDroopAsymmetry(asymmetry[k]);
    vtkPolyData* leaf = LeafAt(wilt, 1.0);
    ASSERT_EQ(leaf->GetNumberOfPoints(), plate->GetNumberOfPoints());
    rightZ[k] = leaf->GetPoint(right)[2];
    leftZ[k] = leaf->GetPoint(left)[2];
    tilt[k] = rightZ[k] - leftZ[k];
  }
  EXPECT_NEAR(tilt[0], 0.0, 1e-9);
  EXPECT_LT(tilt[1], -0.05) << "a > 0: the +x side droops more";
  EXPECT_NEAR(tilt[2], -tilt[1], 1e-9) << "-a: the mirror image";
  EXPECT_NEAR(rightZ[1], leftZ[2], 1e-9);
}

TEST(vtkWiltingSimulator, PetioleShowsInTheVoxelModelAndHoldsTheLeafAtItsEnd)
{
  // A 3 cm petiole below the plate's base (0, 0, 0): two columns of 1 cm voxels (the base lies on the face between
  // them), 3 rows, Region 5 in the voxel model; only its end face (y = -3) is Fixed, the base itself drops.
  auto plate = Plate();
  auto wilt = Simulator(plate);
  wilt->SetPetioleMaterial(0.02, 50000.0, 0.0);
  wilt->SetPetioleLength(3.0);
  wilt->SetAnchorRadius(0.0);
  vtkPolyData* leaf = LeafAt(wilt, 1.0);
  ASSERT_EQ(leaf->GetNumberOfPoints(), plate->GetNumberOfPoints()) << "the leaf output has no petiole";
  auto* grid = vtkUnstructuredGrid::SafeDownCast(wilt->GetOutputDataObject(1));
  ASSERT_NE(grid, nullptr);
  vtkDataArray* region = grid->GetCellData()->GetArray(plantmorph::arrays::Region);
  ASSERT_NE(region, nullptr);
  int petiole = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    petiole += region->GetTuple1(c) == plantmorph::RegionPetiole ? 1 : 0;
  }
  EXPECT_EQ(petiole, 6);
  vtkDataArray* fixed = grid->GetPointData()->GetArray("Fixed");
  vtkDataArray* displacement = grid->GetPointData()->GetArray("Displacement");
  ASSERT_NE(fixed, nullptr);
  ASSERT_NE(displacement, nullptr);
  int held = 0;
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    if (fixed->GetTuple1(p) != 0.0)
    {
      ++held;
      double x[3];
      grid->GetPoint(p, x);
      EXPECT_NEAR(x[1] - displacement->GetComponent(p, 1), -3.0, 1e-9) << "the end face, at rest";
      EXPECT_EQ(displacement->GetComponent(p, 2), 0.0);
    }
  }
  EXPECT_EQ(held, 6) << "3 x 2 nodes of the end face";
  EXPECT_LT(leaf->GetPoint(4)[2], -1e-3) << "the base (0, 0, 0) drops: it hangs on the petiole";
}

TEST(vtkWiltingSimulator, ErrorsNameThePropertyAndEmptyEveryOutput)
{
  auto plate = Plate();
  struct Case
  {
    const char* property;
    void (*spoil)(vtkWiltingSimulator*);
  };
  const Case cases[] = {
    { "Duration", [](vtkWiltingSimulator* w) { w->SetDuration(-1.0); } },
    { "Preset", [](vtkWiltingSimulator* w) { w->SetPreset(9); } },
    { "ContractionTarget", [](vtkWiltingSimulator* w) { w->SetContractionTarget(3); } },
    { "DroopAsymmetry", [](vtkWiltingSimulator* w) { w->SetDroopAsymmetry(1.5); } },
    { "ContractionAsymmetry", [](vtkWiltingSimulator* w) { w->SetContractionAsymmetry(std::nan("")); } },
    { "ShrinkageAsymmetry", [](vtkWiltingSimulator* w) { w->SetShrinkageAsymmetry(2.0); } },
    { "CurlStrain", [](vtkWiltingSimulator* w) { w->SetCurlStrain(0.5); } },
    { "CurlDirection", [](vtkWiltingSimulator* w) { w->SetCurlDirection(2); } },
    { "CurlRelaxation", [](vtkWiltingSimulator* w) { w->SetCurlRelaxation(-0.1); } },
    { "ShrinkageTime", [](vtkWiltingSimulator* w) { w->SetShrinkageTime(std::nan("")); } },
    { "PetioleLength", [](vtkWiltingSimulator* w) { w->SetPetioleLength(-2.0); } },
    { "TimeStep", [](vtkWiltingSimulator* w) { w->SetTimeStep(std::nan("")); } },
    { "BladeDensity", [](vtkWiltingSimulator* w) { w->SetBladeMaterial(0.0, 1000.0, 0.0); } },
  };
  for (const Case& c : cases)
  {
    auto wilt = Simulator(plate);
    wilt->SetVeinsData(Midvein());
    vtkNew<ErrorCatcher> catcher;
    wilt->AddObserver(vtkCommand::ErrorEvent, catcher);
    c.spoil(wilt);
    wilt->UpdateTimeStep(0.0);
    EXPECT_NE(catcher->Messages.find(c.property), std::string::npos) << c.property << ": " << catcher->Messages;
    EXPECT_EQ(vtkPolyData::SafeDownCast(wilt->GetOutputDataObject(0))->GetNumberOfPoints(), 0) << c.property;
    EXPECT_EQ(vtkUnstructuredGrid::SafeDownCast(wilt->GetOutputDataObject(1))->GetNumberOfCells(), 0) << c.property;
    EXPECT_EQ(vtkTable::SafeDownCast(wilt->GetOutputDataObject(2))->GetNumberOfRows(), 0) << c.property;
    EXPECT_EQ(vtkPolyData::SafeDownCast(wilt->GetOutputDataObject(3))->GetNumberOfPoints(), 0) << c.property;
  }
  // An input without triangles (the veins alone): an error, empty outputs.
  auto wilt = Simulator(plate);
  wilt->SetInputData(Midvein());
  vtkNew<ErrorCatcher> catcher;
  wilt->AddObserver(vtkCommand::ErrorEvent, catcher);
  wilt->UpdateTimeStep(0.0);
  EXPECT_FALSE(catcher->Messages.empty());
  EXPECT_EQ(vtkPolyData::SafeDownCast(wilt->GetOutputDataObject(0))->GetNumberOfPoints(), 0);
  EXPECT_EQ(vtkTable::SafeDownCast(wilt->GetOutputDataObject(2))->GetNumberOfRows(), 0);
}
