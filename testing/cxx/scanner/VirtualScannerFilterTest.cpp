// SPDX-License-Identifier: GPL-3.0-or-later
// vtkVirtualScanner: labels carried from the hit cell, HitCellId through polygons and strips, normals facing the
// scanner, the set-up port, and bad input (each error names its property; the outputs are empty).
#include "vtkVirtualScanner.h"

#include "VtkErrorCatcher.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkStringArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace
{
/// Two spheres side by side, one in front of the other as seen from -y, with cell arrays LeafId (which sphere),
/// Region (per cell, varying) and a two-component Label.
vtkSmartPointer<vtkPolyData> TwoSpheres()
{
  vtkNew<vtkAppendPolyData> append;
  for (int s = 0; s < 2; ++s)
  {
    vtkNew<vtkSphereSource> sphere;
    sphere->SetCenter(0.3 * s, 1.5 * s, 0.0);
    sphere->SetRadius(0.5);
    sphere->SetThetaResolution(48);
    sphere->SetPhiResolution(24);
    sphere->Update();
    vtkNew<vtkPolyData> piece;
    piece->DeepCopy(sphere->GetOutput());
    piece->GetPointData()->Initialize();
    const vtkIdType cells = piece->GetNumberOfCells();
    vtkNew<vtkIntArray> leaf, region;
    leaf->SetName("LeafId");
    region->SetName("Region");
    vtkNew<vtkDoubleArray> label;
    label->SetName("Label");
    label->SetNumberOfComponents(2);
    for (vtkIdType c = 0; c < cells; ++c)
    {
      leaf->InsertNextValue(s);
      region->InsertNextValue(static_cast<int>(c % 5));
      label->InsertNextTuple2(s + 0.5, static_cast<double>(c));
    }
    piece->GetCellData()->AddArray(leaf);
    piece->GetCellData()->AddArray(region);
    piece->GetCellData()->AddArray(label);
    append->AddInputData(piece);
  }
  append->Update();
  vtkSmartPointer<vtkPolyData> out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(append->GetOutput());
  return out;
}

double FieldValue(vtkPolyData* data, const char* name)
{
  vtkDataArray* a = data->GetFieldData()->GetArray(name);
  return a ? a->GetComponent(0, 0) : std::numeric_limits<double>::quiet_NaN();
}
} // namespace

TEST(VirtualScanner, EveryPointCarriesItsHitCellsLabels)
{
  vtkSmartPointer<vtkPolyData> scene = TwoSpheres();
  vtkNew<vtkVirtualScanner> scanner;
  scanner->SetInputData(scene);
  scanner->ClearPositions();
  scanner->AddPosition(0.0, -4.0, 0.2);
  scanner->AddPosition(3.0, 0.75, 0.5);
  scanner->SetLookAt(0.15, 0.75, 0.0);
  scanner->SetHorizontalFieldOfView(50);
  scanner->SetVerticalFieldOfView(30);
  scanner->SetAngularStep(0.5);
  scanner->Update();
  vtkPolyData* cloud = scanner->GetOutput(0);
  const vtkIdType n = cloud->GetNumberOfPoints();
  ASSERT_GT(n, 1000);
  EXPECT_EQ(cloud->GetNumberOfVerts(), n);
  vtkPointData* pd = cloud->GetPointData();
  auto* hitCell = vtkIdTypeArray::SafeDownCast(pd->GetArray("HitCellId"));
  auto* leaf = vtkIntArray::SafeDownCast(pd->GetArray("LeafId"));
  auto* region = vtkIntArray::SafeDownCast(pd->GetArray("Region"));
  vtkDataArray* label = pd->GetArray("Label");
  vtkDataArray* normals = pd->GetNormals();
  vtkDataArray* range = pd->GetArray("Range");
  vtkDataArray* pose = pd->GetArray("ScanPosition");
  ASSERT_TRUE(hitCell && leaf && region && label && normals && range && pose && pd->GetArray("Intensity"));
  EXPECT_EQ(label->GetNumberOfComponents(), 2);
  const double positions[2][3] = { { 0.0, -4.0, 0.2 }, { 3.0, 0.75, 0.5 } };
  int seen[2][2] = { { 0, 0 }, { 0, 0 } }; // [scan][sphere]
  for (vtkIdType i = 0; i < n; ++i)
  {
    const vtkIdType cell = hitCell->GetValue(i);
    ASSERT_GE(cell, 0);
    ASSERT_LT(cell, scene->GetNumberOfCells());
    EXPECT_EQ(leaf->GetValue(i), scene->GetCellData()->GetArray("LeafId")->GetComponent(cell, 0));
    EXPECT_EQ(region->GetValue(i), scene->GetCellData()->GetArray("Region")->GetComponent(cell, 0));
    EXPECT_EQ(
      label->GetComponent(i, 1), static_cast<double>(cell) - (leaf->GetValue(i) ? scene->GetNumberOfCells() / 2 : 0));
    // The point lies on its hit cell's plane, within the cell's reach, and on the side facing its scanner.
    double x[3], n3[3], a[3], b[3], c[3];
    cloud->GetPoint(i, x);
    normals->GetTuple(i, n3);
    vtkIdType size;
    const vtkIdType* ids;
    scene->GetCellPoints(cell, size, ids);
    scene->GetPoint(ids[0], a);
    scene->GetPoint(ids[1], b);
    scene->GetPoint(ids[2], c);
    const double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] }, e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    double m[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0] };
    const double length = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    EXPECT_NEAR(std::abs((x[0] - a[0]) * m[0] + (x[1] - a[1]) * m[1] + (x[2] - a[2]) * m[2]) / length, 0.0, 1e-6);
    EXPECT_NEAR(std::abs(n3[0] * m[0] + n3[1] * m[1] + n3[2] * m[2]) / length, 1.0, 1e-6);
    const int s = static_cast<int>(pose->GetComponent(i, 0));
    ASSERT_TRUE(s == 0 || s == 1);
    const double* o = positions[s];
    const double toScanner[3] = { o[0] - x[0], o[1] - x[1], o[2] - x[2] };
    EXPECT_GT(n3[0] * toScanner[0] + n3[1] * toScanner[1] + n3[2] * toScanner[2], 0.0);
    EXPECT_NEAR(range->GetComponent(i, 0),
      std::sqrt(toScanner[0] * toScanner[0] + toScanner[1] * toScanner[1] + toScanner[2] * toScanner[2]), 1e-9);
    ++seen[s][leaf->GetValue(i)];
  }
  // From -y the front sphere hides most of the back one; from +x both are seen.
  EXPECT_GT(seen[0][0], seen[0][1]);
  EXPECT_GT(seen[1][0], 100);
  EXPECT_GT(seen[1][1], 100);
  EXPECT_EQ(FieldValue(cloud, "PlantMorph.Returns"), static_cast<double>(n));
  EXPECT_GT(FieldValue(cloud, "PlantMorph.Beams"), static_cast<double>(n));
  // The set-up: five lines per position (the central beam and four corners), each with its position.
  vtkPolyData* setup = scanner->GetOutput(1);
  EXPECT_EQ(setup->GetNumberOfLines(), 10);
  ASSERT_NE(setup->GetCellData()->GetArray("ScanPosition"), nullptr);
}

TEST(VirtualScanner, HitCellIdCountsVertsLinesPolygonsAndStrips)
{
  // One vertex, one line, a quad at z = 0 for x < 0 and a strip of two triangles at z = 0 for x > 0.
  vtkNew<vtkPolyData> surface;
  vtkNew<vtkPoints> points;
  for (double x : { -1.0, 0.0, 1.0 })
    for (double y : { -1.0, 1.0 })
      points->InsertNextPoint(x, y, 0.0);
  surface->SetPoints(points);
  vtkNew<vtkCellArray> verts, lines, polys, strips;
  const vtkIdType v[1] = { 0 }, l[2] = { 0, 1 }, q[4] = { 0, 2, 3, 1 }, s[4] = { 2, 4, 3, 5 };
  verts->InsertNextCell(1, v);
  lines->InsertNextCell(2, l);
  polys->InsertNextCell(4, q);
  strips->InsertNextCell(4, s);
  surface->SetVerts(verts);
  surface->SetLines(lines);
  surface->SetPolys(polys);
  surface->SetStrips(strips);
  // Point arrays: a linear height (interpolated exactly), an integer corner label (the nearest vertex's), and a
  // point array named like a cell array (the cell's wins).
  vtkNew<vtkDoubleArray> height;
  height->SetName("Height");
  vtkNew<vtkIntArray> corner, pointLabel, cellLabel;
  corner->SetName("Corner");
  pointLabel->SetName("Label");
  cellLabel->SetName("Label");
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    height->InsertNextValue(x[0] + 2 * x[1] + 3);
    corner->InsertNextValue(static_cast<int>(i));
    pointLabel->InsertNextValue(-1);
  }
  for (int c = 0; c < 4; ++c)
    cellLabel->InsertNextValue(10 + c);
  surface->GetPointData()->AddArray(height);
  surface->GetPointData()->AddArray(corner);
  surface->GetPointData()->AddArray(pointLabel);
  surface->GetCellData()->AddArray(cellLabel);
  vtkNew<vtkVirtualScanner> scanner;
  scanner->SetInputData(surface);
  scanner->SetScannerType(2);
  scanner->ClearPositions();
  scanner->AddPosition(0.01, 0.02, 4.0);
  scanner->SetLookAt(0.01, 0.02, 0.0);
  scanner->SetUp(0, 1, 0);
  scanner->SetHorizontalFieldOfView(40);
  scanner->SetVerticalFieldOfView(40);
  scanner->SetResolution(40, 40);
  scanner->Update();
  vtkPolyData* cloud = scanner->GetOutput(0);
  // The image (half-width 4 tan 20 = 1.46) holds the whole 2 x 2 surface: the pixels inside it hit.
  ASSERT_GT(cloud->GetNumberOfPoints(), 1600 * 0.4);
  ASSERT_LT(cloud->GetNumberOfPoints(), 1600 * 0.55);
  vtkDataArray* hitCell = cloud->GetPointData()->GetArray("HitCellId");
  vtkDataArray* heightAt = cloud->GetPointData()->GetArray("Height");
  vtkDataArray* cornerAt = cloud->GetPointData()->GetArray("Corner");
  vtkDataArray* labelAt = cloud->GetPointData()->GetArray("Label");
  ASSERT_TRUE(heightAt && cornerAt && labelAt);
  EXPECT_TRUE(cornerAt->IsA("vtkIntArray"));
  int nearVertex = 0;
  for (vtkIdType i = 0; i < cloud->GetNumberOfPoints(); ++i)
  {
    double x[3];
    cloud->GetPoint(i, x);
    EXPECT_NEAR(x[2], 0.0, 1e-12);
    EXPECT_NEAR(heightAt->GetComponent(i, 0), x[0] + 2 * x[1] + 3, 1e-12);
    EXPECT_EQ(labelAt->GetComponent(i, 0), 10 + hitCell->GetComponent(i, 0));
    // The corner label is a vertex of the hit cell, and the vertex itself when the hit is next to it.
    const auto label = static_cast<vtkIdType>(cornerAt->GetComponent(i, 0));
    vtkIdType size;
    const vtkIdType* ids;
    surface->GetCellPoints(static_cast<vtkIdType>(hitCell->GetComponent(i, 0)), size, ids);
    EXPECT_NE(std::find(ids, ids + size, label), ids + size);
    for (vtkIdType k = 0; k < size; ++k)
    {
      double p[3];
      surface->GetPoint(ids[k], p);
      if (std::hypot(p[0] - x[0], p[1] - x[1]) < 0.1)
      {
        EXPECT_EQ(label, ids[k]);
        ++nearVertex;
      }
    }
    EXPECT_LE(std::abs(x[0]), 1.0 + 1e-12);
    EXPECT_LE(std::abs(x[1]), 1.0 + 1e-12);
    if (std::abs(x[0]) > 1e-9)
    {
      EXPECT_EQ(hitCell->GetComponent(i, 0), x[0] < 0 ? 2.0 : 3.0) << "point at x = " << x[0];
    }
  }
  EXPECT_GT(nearVertex, 4);
}

TEST(VirtualScanner, BadInputIsNamedAndGivesEmptyOutputs)
{
  vtkSmartPointer<vtkPolyData> scene = TwoSpheres();
  auto run = [&](vtkVirtualScanner* scanner, vtkPolyData* input, const std::string& expected) {
    vtkNew<plantmorph::testing::ErrorCatcher> catcher;
    scanner->AddObserver(vtkCommand::ErrorEvent, catcher);
    scanner->SetInputData(input);
    scanner->Update();
    EXPECT_NE(catcher->Messages.find(expected), std::string::npos) << "got: " << catcher->Messages;
    EXPECT_EQ(scanner->GetOutput(0)->GetNumberOfPoints(), 0);
    EXPECT_EQ(scanner->GetOutput(1)->GetNumberOfPoints(), 0);
  };
  {
    vtkNew<vtkVirtualScanner> s;
    s->SetAngularStep(0.0);
    run(s, scene, "AngularStep");
  }
  {
    vtkNew<vtkVirtualScanner> s;
    s->SetHorizontalFieldOfView(400);
    run(s, scene, "HorizontalFieldOfView");
  }
  {
    vtkNew<vtkVirtualScanner> s;
    s->AddPosition(std::nan(""), 0, 0);
    run(s, scene, "Positions");
  }
  {
    vtkNew<vtkVirtualScanner> s;
    s->ClearPositions();
    run(s, scene, "Positions");
  }
  {
    vtkNew<vtkVirtualScanner> s;
    s->SetScannerType(5);
    run(s, scene, "ScannerType");
  }
  {
    vtkNew<vtkVirtualScanner> s;
    s->SetAngularStep(0.001);
    s->SetMaximumBeams(1e6);
    run(s, scene, "MaximumBeams");
  }
  {
    vtkNew<vtkVirtualScanner> s;
    vtkNew<vtkPolyData> lineOnly;
    vtkNew<vtkPoints> p;
    p->InsertNextPoint(0, 0, 0);
    p->InsertNextPoint(1, 0, 0);
    vtkNew<vtkCellArray> lines;
    const vtkIdType l[2] = { 0, 1 };
    lines->InsertNextCell(2, l);
    lineOnly->SetPoints(p);
    lineOnly->SetLines(lines);
    run(s, lineOnly, "no polygons");
  }
  {
    // After an error, good properties give a cloud again.
    vtkNew<vtkVirtualScanner> s;
    s->SetAngularStep(0.0);
    run(s, scene, "AngularStep");
    s->SetAngularStep(1.0);
    s->Update();
    EXPECT_GT(s->GetOutput(0)->GetNumberOfPoints(), 0);
  }
}

TEST(VirtualScanner, ShortInputArraysAreNamedInAWarningAndNotCarried)
{
  // A cell array with fewer tuples than cells (a malformed input) would be read past its end: it is left out and
  // named, and the rest of the cloud is as usual.
  vtkSmartPointer<vtkPolyData> scene = TwoSpheres();
  vtkNew<vtkIntArray> shortLabels;
  shortLabels->SetName("ShortLabels");
  shortLabels->SetNumberOfTuples(5);
  shortLabels->FillValue(1);
  scene->GetCellData()->AddArray(shortLabels);
  vtkNew<vtkVirtualScanner> scanner;
  vtkNew<plantmorph::testing::ErrorCatcher> catcher;
  scanner->AddObserver(vtkCommand::WarningEvent, catcher);
  scanner->SetInputData(scene);
  scanner->SetAngularStep(1.0);
  scanner->Update();
  EXPECT_NE(catcher->Messages.find("ShortLabels"), std::string::npos) << "got: " << catcher->Messages;
  vtkPolyData* cloud = scanner->GetOutput(0);
  EXPECT_GT(cloud->GetNumberOfPoints(), 100);
  EXPECT_EQ(cloud->GetPointData()->GetAbstractArray("ShortLabels"), nullptr);
  EXPECT_NE(cloud->GetPointData()->GetArray("LeafId"), nullptr);
}

TEST(VirtualScanner, SameSeedSameCloud)
{
  vtkSmartPointer<vtkPolyData> scene = TwoSpheres();
  auto scan = [&](int seed) {
    vtkNew<vtkVirtualScanner> s;
    s->SetInputData(scene);
    s->SetAngularStep(0.5);
    s->SetRangeNoise(0.01);
    s->SetDropoutProbability(0.2);
    s->SetSeed(seed);
    s->Update();
    vtkSmartPointer<vtkPolyData> out = vtkSmartPointer<vtkPolyData>::New();
    out->DeepCopy(s->GetOutput(0));
    return out;
  };
  vtkSmartPointer<vtkPolyData> a = scan(3), b = scan(3), c = scan(4);
  ASSERT_GT(a->GetNumberOfPoints(), 100);
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  bool differs = a->GetNumberOfPoints() != c->GetNumberOfPoints();
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    a->GetPoint(i, x);
    b->GetPoint(i, y);
    EXPECT_EQ(x[0], y[0]);
    EXPECT_EQ(x[1], y[1]);
    EXPECT_EQ(x[2], y[2]);
    if (!differs && i < c->GetNumberOfPoints())
    {
      double z[3];
      c->GetPoint(i, z);
      differs = z[0] != x[0] || z[1] != x[1] || z[2] != x[2];
    }
  }
  EXPECT_TRUE(differs);
}

TEST(VirtualScanner, KeptCasterFollowsPropertiesAndTheInput)
{
  // The filter keeps its triangulated surface and caster between runs: a changed property re-scans it, a changed
  // input (points moved in place) rebuilds it. Each run must equal a fresh filter's cloud, bit for bit.
  vtkSmartPointer<vtkPolyData> scene = TwoSpheres();
  auto same = [](vtkPolyData* a, vtkPolyData* b) {
    if (a->GetNumberOfPoints() != b->GetNumberOfPoints() || a->GetNumberOfPoints() < 100)
      return false;
    auto* ca = vtkIdTypeArray::SafeDownCast(a->GetPointData()->GetArray("HitCellId"));
    auto* cb = vtkIdTypeArray::SafeDownCast(b->GetPointData()->GetArray("HitCellId"));
    auto* la = a->GetPointData()->GetArray("Label");
    auto* lb = b->GetPointData()->GetArray("Label");
    if (!ca || !cb || !la || !lb)
      return false;
    for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
    {
      double x[3], y[3];
      a->GetPoint(i, x);
      b->GetPoint(i, y);
      if (x[0] != y[0] || x[1] != y[1] || x[2] != y[2] || ca->GetValue(i) != cb->GetValue(i) ||
        la->GetComponent(i, 1) != lb->GetComponent(i, 1))
        return false;
    }
    return true;
  };
  auto fresh = [&](double step) {
    vtkNew<vtkVirtualScanner> s;
    s->SetInputData(scene);
    s->SetAngularStep(step);
    s->Update();
    vtkSmartPointer<vtkPolyData> out = vtkSmartPointer<vtkPolyData>::New();
    out->DeepCopy(s->GetOutput(0));
    return out;
  };
  vtkNew<vtkVirtualScanner> kept;
  kept->SetInputData(scene);
  kept->SetAngularStep(0.5);
  kept->Update();
  EXPECT_TRUE(same(kept->GetOutput(0), fresh(0.5)));
  kept->SetAngularStep(0.4);
  kept->Update();
  vtkSmartPointer<vtkPolyData> before = fresh(0.4);
  EXPECT_TRUE(same(kept->GetOutput(0), before));
  // Move the spheres 0.2 along x in place: the old caster would give the old points.
  vtkPoints* points = scene->GetPoints();
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    x[0] += 0.2;
    points->SetPoint(i, x);
  }
  points->Modified();
  kept->Update();
  vtkSmartPointer<vtkPolyData> moved = fresh(0.4);
  EXPECT_TRUE(same(kept->GetOutput(0), moved));
  EXPECT_FALSE(same(kept->GetOutput(0), before)); // the cloud really moved
}
