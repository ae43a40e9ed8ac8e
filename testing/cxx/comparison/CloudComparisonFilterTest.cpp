// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK layer of CloudComparisonFilter: every cell layout of a measured cloud (one poly-vertex as vtkPointSource
// makes it, one vertex per point, no cells, an unstructured grid) gives the same distances, equal to VTK's own exact
// closest-point search (vtkStaticCellLocator) and to vtkDistancePolyDataFilter; a cloud sampled from the reference
// is at distance 0; a quad plane offset by +t / -t gives SignedDistance +t / -t; Hausdorff and Chamfer are
// symmetric under swapping the inputs; histogram counts add up to Count; the cut-off counts outliers; ICP recovers a
// known rigid transform; bad input gives an error naming the property and three empty outputs.
#include "VtkErrorCatcher.h"
#include "vtkCloudComparisonFilter.h"
#include "vtkLeafOutlineSource.h"

#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDistancePolyDataFilter.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkGenericCell.h"
#include "vtkIdTypeArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPointSource.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkStaticCellLocator.h"
#include "vtkTable.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVertexGlyphFilter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace
{

/// The ginkgo blade (Resolution 40), bent into an asymmetric dome ICP cannot slide along: the registration tests'
/// reference surface.
vtkSmartPointer<vtkPolyData> BentGinkgo()
{
  vtkNew<vtkLeafOutlineSource> leaf;
  leaf->SetResolution(40);
  leaf->Update();
  vtkNew<vtkPolyData> bent;
  bent->DeepCopy(leaf->GetOutput(0));
  for (vtkIdType i = 0; i < bent->GetNumberOfPoints(); ++i)
  {
    double p[3];
    bent->GetPoint(i, p);
    p[2] = 0.4 * std::sin(0.9 * p[0] + 0.3) * std::cos(0.5 * p[1]) + 0.08 * p[0] * p[0];
    bent->GetPoints()->SetPoint(i, p);
  }
  return bent;
}
using plantmorph::testing::ErrorCatcher;

vtkSmartPointer<vtkPolyData> SphereSurface(int resolution = 40)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(1.0);
  sphere->SetThetaResolution(resolution);
  sphere->SetPhiResolution(resolution);
  sphere->Update();
  return sphere->GetOutput();
}

/// vtkPointSource's random ball: ONE poly-vertex cell holding every point.
vtkSmartPointer<vtkPolyData> RandomBall(int count, double radius = 1.5)
{
  vtkNew<vtkPointSource> source;
  source->SetNumberOfPoints(count);
  source->SetRadius(radius);
  source->SetDistributionToUniform();
  source->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  source->Update();
  return source->GetOutput();
}

struct Result
{
  vtkSmartPointer<vtkPolyData> points;
  vtkSmartPointer<vtkTable> histogram;
  vtkSmartPointer<vtkTable> statistics;
  std::string errors;
  double Stat(const char* name) const
  {
    vtkAbstractArray* a = statistics->GetColumnByName(name);
    return a ? vtkDataArray::SafeDownCast(a)->GetTuple1(0) : std::numeric_limits<double>::quiet_NaN();
  }
};

template <typename Configure>
Result Compare(vtkDataObject* measured, vtkDataObject* reference, Configure configure)
{
  vtkNew<vtkCloudComparisonFilter> filter;
  vtkNew<ErrorCatcher> catcher;
  filter->AddObserver(vtkCommand::ErrorEvent, catcher);
  filter->SetInputData(0, measured);
  filter->SetReferenceData(reference);
  configure(filter.Get());
  filter->Update();
  Result r;
  r.points = filter->GetOutput(0);
  r.histogram = vtkTable::SafeDownCast(filter->GetOutputDataObject(1));
  r.statistics = vtkTable::SafeDownCast(filter->GetOutputDataObject(2));
  r.errors = catcher->Messages;
  return r;
}

Result Compare(vtkDataObject* measured, vtkDataObject* reference)
{
  return Compare(measured, reference, [](vtkCloudComparisonFilter*) {});
}

vtkDataArray* Array(vtkPolyData* data, const char* name)
{
  return data->GetPointData()->GetArray(name);
}

TEST(CloudComparisonFilter, EveryCellLayoutGivesVtkExactDistances)
{
  vtkSmartPointer<vtkPolyData> surface = SphereSurface();
  vtkSmartPointer<vtkPolyData> ball = RandomBall(3000);
  ASSERT_EQ(ball->GetNumberOfCells(), 1);
  ASSERT_EQ(ball->GetVerts()->GetCellSize(0), 3000); // one poly-vertex

  vtkNew<vtkVertexGlyphFilter> glyphs; // one vertex per point
  glyphs->SetInputData(ball);
  glyphs->Update();
  vtkNew<vtkPolyData> bare; // no cells at all
  bare->SetPoints(ball->GetPoints());
  vtkNew<vtkUnstructuredGrid> grid; // not even poly data
  grid->SetPoints(ball->GetPoints());

  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(surface);
  locator->BuildLocator();
  vtkNew<vtkGenericCell> cell;

  const Result reference = Compare(ball, surface);
  ASSERT_EQ(reference.errors, "");
  vtkDataArray* distance = Array(reference.points, "Distance");
  ASSERT_NE(distance, nullptr);
  ASSERT_EQ(distance->GetNumberOfTuples(), 3000);
  EXPECT_EQ(reference.points->GetNumberOfCells(), 1); // the poly-vertex is kept
  for (vtkIdType i = 0; i < 3000; ++i)
  {
    double p[3], closest[3], d2 = 0;
    vtkIdType cellId = -1;
    int subId = 0;
    ball->GetPoint(i, p);
    locator->FindClosestPoint(p, closest, cell, cellId, subId, d2);
    ASSERT_NEAR(distance->GetTuple1(i), std::sqrt(d2), 1e-9) << i;
    // Sign: the sphere's triangles face outwards.
    const double r = vtkMath::Norm(p);
    if (std::fabs(r - 1.0) > 0.01)
    {
      ASSERT_EQ(Array(reference.points, "SignedDistance")->GetTuple1(i) > 0, r > 1.0) << r;
    }
  }
  for (vtkDataObject* layout : { static_cast<vtkDataObject*>(glyphs->GetOutput()),
         static_cast<vtkDataObject*>(bare.Get()), static_cast<vtkDataObject*>(grid.Get()) })
  {
    const Result r = Compare(layout, surface);
    ASSERT_EQ(r.errors, "");
    vtkDataArray* d = Array(r.points, "Distance");
    ASSERT_NE(d, nullptr) << layout->GetClassName();
    for (vtkIdType i = 0; i < 3000; ++i)
    {
      ASSERT_EQ(d->GetTuple1(i), distance->GetTuple1(i));
    }
    EXPECT_GT(r.points->GetNumberOfCells(), 0) << "drawable output for " << layout->GetClassName();
  }
}

TEST(CloudComparisonFilter, AgreesWithVtkDistancePolyDataFilter)
{
  vtkSmartPointer<vtkPolyData> surface = SphereSurface(24);
  vtkNew<vtkVertexGlyphFilter> glyphs; // vtkDistancePolyDataFilter crashes on one poly-vertex: give it vertices
  glyphs->SetInputData(RandomBall(400));
  glyphs->Update();
  vtkNew<vtkDistancePolyDataFilter> vtkDistance;
  vtkDistance->SetInputData(0, glyphs->GetOutput());
  vtkDistance->SetInputData(1, surface);
  vtkDistance->ComputeSecondDistanceOff();
  vtkDistance->SignedDistanceOn();
  vtkDistance->Update();
  vtkDataArray* expected = vtkDistance->GetOutput()->GetPointData()->GetArray("Distance");
  const Result r = Compare(glyphs->GetOutput(), surface);
  vtkDataArray* d = Array(r.points, "Distance");
  vtkDataArray* s = Array(r.points, "SignedDistance");
  for (vtkIdType i = 0; i < 400; ++i)
  {
    EXPECT_NEAR(d->GetTuple1(i), std::fabs(expected->GetTuple1(i)), 1e-9);
    // vtkImplicitPolyDataDistance is negative inside a closed outward surface, like ours.
    if (std::fabs(expected->GetTuple1(i)) > 1e-6)
    {
      EXPECT_EQ(s->GetTuple1(i) > 0, expected->GetTuple1(i) > 0) << i;
    }
  }
}

TEST(CloudComparisonFilter, SelfSampledCloudIsAtZero)
{
  vtkNew<vtkLeafOutlineSource> leaf;
  leaf->SetResolution(40);
  leaf->Update();
  vtkPolyData* blade = leaf->GetOutput(0);
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(blade->GetPoints());
  const Result r = Compare(cloud, blade, [](vtkCloudComparisonFilter* f) { f->SymmetricOn(); });
  ASSERT_EQ(r.errors, "");
  EXPECT_LT(r.Stat("Maximum"), 1e-9);
  EXPECT_LT(r.Stat("SymmetricHausdorff"), 1e-9);
  EXPECT_EQ(r.Stat("Count"), blade->GetNumberOfPoints());
}

TEST(CloudComparisonFilter, OffsetQuadPlaneGivesPlusAndMinusT)
{
  vtkNew<vtkPlaneSource> plane; // quads, normal +Z
  plane->SetResolution(7, 5);
  plane->Update();
  vtkNew<vtkPointSource> source;
  source->SetNumberOfPoints(2000);
  source->SetRadius(0.45);
  source->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  source->Update();
  for (double t : { 0.001, 0.25, 3.0 })
  {
    for (int side : { 1, -1 })
    {
      vtkNew<vtkPoints> points;
      points->SetDataTypeToDouble();
      for (vtkIdType i = 0; i < 2000; ++i)
      {
        double p[3];
        source->GetOutput()->GetPoint(i, p);
        points->InsertNextPoint(p[0], p[1], side * t); // inside the unit square, moved off it by t
      }
      vtkNew<vtkPolyData> cloud;
      cloud->SetPoints(points);
      const Result r = Compare(cloud, plane->GetOutput());
      vtkDataArray* d = Array(r.points, "Distance");
      vtkDataArray* s = Array(r.points, "SignedDistance");
      for (vtkIdType i = 0; i < 2000; ++i)
      {
        ASSERT_NEAR(d->GetTuple1(i), t, 1e-12);
        ASSERT_NEAR(s->GetTuple1(i), side * t, 1e-12);
      }
      EXPECT_NEAR(r.Stat("StandardDeviation"), 0.0, 1e-12);
    }
  }
}

TEST(CloudComparisonFilter, HausdorffAndChamferAreSymmetricUnderSwapping)
{
  vtkSmartPointer<vtkPolyData> a = RandomBall(700, 1.0);
  vtkSmartPointer<vtkPolyData> b = RandomBall(500, 1.3);
  vtkNew<vtkTransform> shift;
  shift->Translate(0.2, -0.1, 0.05);
  vtkNew<vtkTransformPolyDataFilter> moved;
  moved->SetInputData(b);
  moved->SetTransform(shift);
  moved->Update();
  vtkSmartPointer<vtkPolyData> sphere = SphereSurface(20);
  auto symmetric = [](vtkCloudComparisonFilter* f) { f->SymmetricOn(); };
  // Two clouds, and a cloud against a surface.
  for (vtkPolyData* other : { moved->GetOutput(), sphere.Get() })
  {
    const Result ab = Compare(a, other, symmetric);
    const Result ba = Compare(other, a, symmetric);
    ASSERT_EQ(ab.errors + ba.errors, "");
    EXPECT_DOUBLE_EQ(ab.Stat("SymmetricHausdorff"), ba.Stat("SymmetricHausdorff"));
    EXPECT_DOUBLE_EQ(ab.Stat("Chamfer"), ba.Stat("Chamfer"));
    EXPECT_DOUBLE_EQ(ab.Stat("Hausdorff"), ba.Stat("ReverseHausdorff"));
    EXPECT_DOUBLE_EQ(ab.Stat("ReverseHausdorff"), ba.Stat("Hausdorff"));
    EXPECT_GT(ab.Stat("SymmetricHausdorff"), 0.0);
  }
}

TEST(CloudComparisonFilter, HistogramStatisticsAndCutOff)
{
  vtkSmartPointer<vtkPolyData> surface = SphereSurface(20);
  vtkSmartPointer<vtkPolyData> ball = RandomBall(5000, 2.0);
  const Result all = Compare(ball, surface, [](vtkCloudComparisonFilter* f) { f->SetHistogramBins(17); });
  ASSERT_EQ(all.histogram->GetNumberOfRows(), 17);
  double total = 0;
  for (vtkIdType b = 0; b < 17; ++b)
  {
    total += all.histogram->GetValueByName(b, "bin_values").ToDouble();
  }
  EXPECT_EQ(total, 5000);
  EXPECT_EQ(all.Stat("Count"), 5000);
  EXPECT_NEAR(all.Stat("RMS") * all.Stat("RMS"),
    all.Stat("Mean") * all.Stat("Mean") + all.Stat("StandardDeviation") * all.Stat("StandardDeviation"), 1e-12);
  EXPECT_EQ(all.points->GetFieldData()->GetArray("Mean")->GetTuple1(0), all.Stat("Mean"));
  // Brute-force count of points beyond 0.5.
  vtkDataArray* d = Array(all.points, "Distance");
  int beyond = 0;
  for (vtkIdType i = 0; i < 5000; ++i)
  {
    beyond += d->GetTuple1(i) > 0.5;
  }
  const Result cut = Compare(ball, surface, [](vtkCloudComparisonFilter* f) {
    f->UseMaximumDistanceOn();
    f->SetMaximumDistance(0.5);
  });
  EXPECT_EQ(cut.Stat("Outliers"), beyond);
  EXPECT_EQ(cut.Stat("Count"), 5000 - beyond);
  EXPECT_LE(cut.Stat("Maximum"), 0.5);
  ASSERT_NE(Array(cut.points, "Outlier"), nullptr);
}

TEST(CloudComparisonFilter, RigidIcpRecoversAKnownTransform)
{
  vtkSmartPointer<vtkPolyData> bent = BentGinkgo();
  vtkNew<vtkTransform> truth;
  truth->Translate(0.1, -0.2, 0.15);
  truth->RotateWXYZ(6.0, 0.3, 0.2, 1.0);
  vtkNew<vtkTransformPolyDataFilter> moved; // measured = reference vertices moved by the inverse
  moved->SetInputData(bent);
  moved->SetTransform(truth->GetInverse());
  moved->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  moved->Update();
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(moved->GetOutput()->GetPoints());
  const Result before = Compare(cloud, bent);
  const Result after = Compare(cloud, bent, [](vtkCloudComparisonFilter* f) {
    f->SetRegistration(vtkCloudComparisonFilter::REGISTRATION_RIGID);
    f->SetRegistrationTolerance(1e-12);
  });
  ASSERT_EQ(after.errors, "");
  EXPECT_GT(before.Stat("Maximum"), 0.05);
  EXPECT_LT(after.Stat("Maximum"), 1e-6);
  vtkDataArray* matrix = after.points->GetFieldData()->GetArray("PlantMorph.MeasuredTransform");
  ASSERT_NE(matrix, nullptr);
  ASSERT_EQ(matrix->GetNumberOfComponents(), 16);
  vtkMatrix4x4* expected = truth->GetMatrix();
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      EXPECT_NEAR(matrix->GetComponent(0, 4 * r + c), expected->GetElement(r, c), 1e-6) << r << "," << c;
    }
  }
  EXPECT_EQ(after.points->GetFieldData()->GetArray("PlantMorph.RegistrationConverged")->GetTuple1(0), 1.0);
}

// The Registration* field data tell what happened: RegistrationIterations = 1 used to report 2 iterations and
// Converged = 1 with a sliver of the turn recovered; measured points all on one line or all the same point cannot
// determine a transform: the identity, 0 iterations, Converged 0 and a warning saying why.
TEST(CloudComparisonFilter, RegistrationFieldDataTellWhatHappened)
{
  vtkSmartPointer<vtkPolyData> bent = BentGinkgo();
  vtkNew<vtkTransform> turn;
  turn->RotateWXYZ(0.05 * 180.0 / 3.14159265358979, 0.0, 0.0, 1.0);
  vtkNew<vtkTransformPolyDataFilter> moved;
  moved->SetInputData(bent);
  moved->SetTransform(turn);
  moved->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  moved->Update();
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(moved->GetOutput()->GetPoints());
  const auto field = [](const Result& r, const char* name) {
    vtkDataArray* a = r.points->GetFieldData()->GetArray(name);
    return a ? a->GetTuple1(0) : std::numeric_limits<double>::quiet_NaN();
  };
  const Result one = Compare(cloud, bent, [](vtkCloudComparisonFilter* f) {
    f->SetRegistration(vtkCloudComparisonFilter::REGISTRATION_RIGID);
    f->SetRegistrationIterations(1);
  });
  ASSERT_EQ(one.errors, "");
  EXPECT_EQ(field(one, "PlantMorph.RegistrationIterations"), 1.0);
  EXPECT_EQ(field(one, "PlantMorph.RegistrationConverged"), 0.0);
  for (const bool identical : { true, false })
  {
    vtkNew<vtkPoints> points;
    for (int i = 0; i < 500; ++i)
      points->InsertNextPoint(identical ? 0.3 : 0.01 * i, identical ? 0.4 : 0.5 + 0.02 * i, 0.1);
    vtkNew<vtkPolyData> degenerate;
    degenerate->SetPoints(points);
    vtkNew<vtkCloudComparisonFilter> filter;
    vtkNew<ErrorCatcher> warnings;
    filter->AddObserver(vtkCommand::WarningEvent, warnings);
    filter->SetInputData(0, degenerate);
    filter->SetReferenceData(bent);
    filter->SetRegistration(vtkCloudComparisonFilter::REGISTRATION_RIGID);
    filter->Update();
    EXPECT_NE(warnings->Messages.find(identical ? "are the same point" : "lie on one line"), std::string::npos)
      << warnings->Messages;
    vtkFieldData* fd = filter->GetOutput(0)->GetFieldData();
    ASSERT_NE(fd->GetArray("PlantMorph.RegistrationConverged"), nullptr);
    EXPECT_EQ(fd->GetArray("PlantMorph.RegistrationConverged")->GetTuple1(0), 0.0);
    EXPECT_EQ(fd->GetArray("PlantMorph.RegistrationIterations")->GetTuple1(0), 0.0);
    vtkDataArray* matrix = fd->GetArray("PlantMorph.MeasuredTransform");
    ASSERT_NE(matrix, nullptr);
    for (int k = 0; k < 16; ++k)
      EXPECT_EQ(matrix->GetComponent(0, k), k % 5 == 0 ? 1.0 : 0.0) << k;
  }
}

TEST(CloudComparisonFilter, ScaleAndPointCloudReference)
{
  vtkSmartPointer<vtkPolyData> a = RandomBall(300, 1.0);
  vtkNew<vtkPoints> mm;
  mm->SetDataTypeToDouble();
  for (vtkIdType i = 0; i < 300; ++i)
  {
    double p[3];
    a->GetPoint(i, p);
    mm->InsertNextPoint(10 * p[0], 10 * p[1], 10 * p[2]); // the same cloud in mm
  }
  vtkNew<vtkPolyData> measured;
  measured->SetPoints(mm);
  const Result r = Compare(measured, a, [](vtkCloudComparisonFilter* f) { f->SetScale(0.1); });
  ASSERT_EQ(r.errors, "");
  EXPECT_LT(r.Stat("Maximum"), 1e-12);
  EXPECT_EQ(r.Stat("ReferenceIsSurface"), 0.0);
  EXPECT_EQ(Array(r.points, "SignedDistance"), nullptr); // no sign against a cloud
  EXPECT_NEAR(r.points->GetFieldData()->GetArray("PlantMorph.MeasuredTransform")->GetComponent(0, 0), 0.1, 0);
}

TEST(CloudComparisonFilter, BadInputGivesAnErrorAndEmptyOutputs)
{
  vtkSmartPointer<vtkPolyData> surface = SphereSurface(10);
  vtkSmartPointer<vtkPolyData> ball = RandomBall(100);
  auto expectEmpty = [](const Result& r, const char* what) {
    EXPECT_NE(r.errors.find(what), std::string::npos) << r.errors;
    EXPECT_EQ(r.points->GetNumberOfPoints(), 0) << what;
    EXPECT_EQ(r.histogram->GetNumberOfRows(), 0) << what;
    EXPECT_EQ(r.statistics->GetNumberOfColumns(), 0) << what;
  };
  expectEmpty(Compare(ball, surface, [](vtkCloudComparisonFilter* f) { f->SetScale(0.0); }), "Scale");
  expectEmpty(Compare(ball, surface, [](vtkCloudComparisonFilter* f) { f->SetScale(std::nan("")); }), "Scale");
  expectEmpty(Compare(ball, surface, [](vtkCloudComparisonFilter* f) { f->SetHistogramBins(0); }), "HistogramBins");
  expectEmpty(Compare(ball, surface,
                [](vtkCloudComparisonFilter* f) {
                  f->UseMaximumDistanceOn();
                  f->SetMaximumDistance(-1);
                }),
    "MaximumDistance");
  expectEmpty(Compare(ball, surface, [](vtkCloudComparisonFilter* f) { f->SetRegistration(7); }), "Registration");
  expectEmpty(Compare(ball, surface,
                [](vtkCloudComparisonFilter* f) {
                  f->SetRegistration(1);
                  f->SetRegistrationIterations(0);
                }),
    "RegistrationIterations");
  vtkNew<vtkPolyData> empty;
  expectEmpty(Compare(ball, empty), "Reference");
  vtkNew<vtkPolyData> nan;
  nan->DeepCopy(ball);
  nan->GetPoints()->SetPoint(42, 0.0, std::nan(""), 0.0);
  expectEmpty(Compare(nan, surface), "point 42");
  // The first non-finite point named when there are several, in different blocks of the threads' scan.
  vtkSmartPointer<vtkPolyData> big = RandomBall(150000);
  big->GetPoints()->SetPoint(140000, std::nan(""), 0.0, 0.0);
  big->GetPoints()->SetPoint(70001, 0.0, 0.0, std::numeric_limits<double>::infinity());
  expectEmpty(Compare(big, surface), "point 70001 ");
  // An empty measured piece: no error, empty outputs.
  const Result none = Compare(empty, surface);
  EXPECT_EQ(none.errors, "");
  EXPECT_EQ(none.points->GetNumberOfPoints(), 0);
}

} // namespace
