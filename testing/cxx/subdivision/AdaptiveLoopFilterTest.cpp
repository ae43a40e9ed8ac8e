// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK layer of AdaptiveLoopFilter. The oracle: with adaptivity off (EdgeAngleThreshold 180, FlatnessThreshold 1,
// FeatureRule Loop, boundary features only) it gives vtkLoopSubdivisionFilter's points (and interpolated point
// data) on a closed sphere and an open leaf blade, several levels. Then: arrays, precision and field data on a
// LeafOutlineSource blade; Fixed keeps margin and midvein bit-identical; cell data inherited through triangulated
// quads; errors (non-manifold with ids, bad properties, refused polygons) give a message and an empty output.
#include "VtkErrorCatcher.h"
#include "vtkAdaptiveLoopFilter.h"
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
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkLoopSubdivisionFilter.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkStaticPointLocator.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace
{
using plantmorph::testing::ErrorCatcher;

/// The ginkgo blade of LeafOutlineSource, lifted into a curved surface (points in `precision`). Its size is paper
/// 000's b_y = 5, a blade 5 (1.6 + 0.05 sin(-1.5)) = 7.75 long from base to apex, for which the lift is sized.
vtkSmartPointer<vtkPolyData> CurvedBlade(int resolution = 24, int precision = VTK_DOUBLE)
{
  vtkNew<vtkLeafOutlineSource> source;
  source->SetLength(5.0 * (1.6 + 0.05 * std::sin(-1.5)));
  source->SetResolution(resolution);
  source->Update();
  auto blade = vtkSmartPointer<vtkPolyData>::New();
  blade->DeepCopy(source->GetOutput(0));
  vtkNew<vtkPoints> points;
  points->SetDataType(precision);
  points->SetNumberOfPoints(blade->GetNumberOfPoints());
  for (vtkIdType i = 0; i < blade->GetNumberOfPoints(); ++i)
  {
    double p[3];
    blade->GetPoint(i, p);
    p[2] = 0.6 * std::sin(0.8 * p[0]) * std::cos(0.5 * p[1]) + 0.05 * p[0] * p[0];
    points->SetPoint(i, p);
  }
  blade->SetPoints(points);
  return blade;
}

vtkSmartPointer<vtkPolyData> Sphere(int precision)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(16);
  sphere->SetPhiResolution(12);
  sphere->SetOutputPointsPrecision(
    precision == VTK_DOUBLE ? vtkAlgorithm::DOUBLE_PRECISION : vtkAlgorithm::SINGLE_PRECISION);
  sphere->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(sphere->GetOutput());
  // A point array to interpolate: the position itself, in double.
  vtkNew<vtkDoubleArray> copy;
  copy->SetName("Position");
  copy->SetNumberOfComponents(3);
  copy->SetNumberOfTuples(out->GetNumberOfPoints());
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
    copy->SetTuple(i, out->GetPoint(i));
  out->GetPointData()->AddArray(copy);
  return out;
}

struct FilterRun
{
  vtkSmartPointer<vtkPolyData> output;
  std::string errors;
};

FilterRun Subdivide(vtkPolyData* input, const std::function<void(vtkAdaptiveLoopFilter*)>& configure)
{
  vtkNew<vtkAdaptiveLoopFilter> filter;
  vtkNew<ErrorCatcher> catcher;
  filter->AddObserver(vtkCommand::ErrorEvent, catcher);
  filter->SetInputData(input);
  configure(filter);
  filter->Update();
  FilterRun run;
  run.output = vtkSmartPointer<vtkPolyData>::New();
  run.output->ShallowCopy(filter->GetOutput());
  run.errors = catcher->Messages;
  return run;
}

/// The two outputs have the same points, bit for bit.
void ExpectSamePoints(vtkPolyData* a, vtkPolyData* b)
{
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    a->GetPoint(i, p);
    b->GetPoint(i, q);
    ASSERT_TRUE(p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) << i;
  }
}

void PlainLoop(vtkAdaptiveLoopFilter* f, int levels)
{
  f->SetMaximumLevel(levels);
  f->SetEdgeAngleThreshold(180.0);
  f->SetFlatnessThreshold(1.0);
  f->SetFeatureRule(vtkAdaptiveLoopFilter::LOOP);
  f->MidveinFeaturesOff();
  f->LineFeaturesOff();
}

vtkSmartPointer<vtkPolyData> VtkLoop(vtkPolyData* input, int levels)
{
  vtkNew<vtkLoopSubdivisionFilter> loop;
  loop->SetInputData(input);
  loop->SetNumberOfSubdivisions(levels);
  loop->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(loop->GetOutput());
  return out;
}

/// Matches every point of `ours` to the nearest of `theirs` (must be one-to-one); returns the largest distance and
/// checks the triangles are the same under that matching, and that `array` agrees to `arrayTolerance`.
double CompareMeshes(vtkPolyData* ours, vtkPolyData* theirs, const char* array, double arrayTolerance)
{
  EXPECT_EQ(ours->GetNumberOfPoints(), theirs->GetNumberOfPoints());
  EXPECT_EQ(ours->GetNumberOfCells(), theirs->GetNumberOfCells());
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(theirs);
  locator->BuildLocator();
  std::vector<vtkIdType> match(ours->GetNumberOfPoints());
  std::set<vtkIdType> used;
  double worst = 0.0;
  for (vtkIdType i = 0; i < ours->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    ours->GetPoint(i, p);
    match[i] = locator->FindClosestPoint(p);
    theirs->GetPoint(match[i], q);
    worst = std::max(worst, std::sqrt(vtkMath::Distance2BetweenPoints(p, q)));
    used.insert(match[i]);
  }
  EXPECT_EQ(used.size(), static_cast<std::size_t>(ours->GetNumberOfPoints())) << "matching is not one-to-one";
  std::set<std::vector<vtkIdType>> ourTriangles, theirTriangles;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < ours->GetNumberOfCells(); ++c)
  {
    ours->GetCellPoints(c, ids);
    std::vector<vtkIdType> t{ match[ids->GetId(0)], match[ids->GetId(1)], match[ids->GetId(2)] };
    std::sort(t.begin(), t.end());
    ourTriangles.insert(t);
  }
  for (vtkIdType c = 0; c < theirs->GetNumberOfCells(); ++c)
  {
    theirs->GetCellPoints(c, ids);
    std::vector<vtkIdType> t{ ids->GetId(0), ids->GetId(1), ids->GetId(2) };
    std::sort(t.begin(), t.end());
    theirTriangles.insert(t);
  }
  EXPECT_TRUE(ourTriangles == theirTriangles) << "the triangles differ";
  if (array)
  {
    vtkDataArray* a = ours->GetPointData()->GetArray(array);
    vtkDataArray* b = theirs->GetPointData()->GetArray(array);
    EXPECT_TRUE(a && b) << array;
    if (a && b)
    {
      double arrayWorst = 0.0;
      for (vtkIdType i = 0; i < ours->GetNumberOfPoints(); ++i)
        for (int c = 0; c < a->GetNumberOfComponents(); ++c)
          arrayWorst = std::max(arrayWorst, std::abs(a->GetComponent(i, c) - b->GetComponent(match[i], c)));
      EXPECT_LT(arrayWorst, arrayTolerance) << array;
    }
  }
  return worst;
}

vtkIdType LastOf(vtkPolyData* data, const char* name)
{
  vtkDataArray* a = data->GetFieldData()->GetArray(name);
  return a ? static_cast<vtkIdType>(a->GetComponent(a->GetNumberOfTuples() - 1, 0)) : -1;
}

// ---------------------------------------------------------------------------------------------------------------

// VTK stores its Loop output in float points every level. Running our filter one level at a time on float points
// rounds at the same places, so the two agree to 1e-9 (in practice bit for bit) over several levels.
TEST(AdaptiveLoopFilter, OracleEqualsVtkLoopLevelByLevelOnFloatPoints)
{
  for (const bool closed : { true, false })
  {
    vtkSmartPointer<vtkPolyData> input = closed ? Sphere(VTK_FLOAT) : CurvedBlade(16, VTK_FLOAT);
    vtkSmartPointer<vtkPolyData> ours = input;
    for (int level = 1; level <= 3; ++level)
    {
      const FilterRun run = Subdivide(ours, [](vtkAdaptiveLoopFilter* f) { PlainLoop(f, 1); });
      ASSERT_EQ(run.errors, "");
      ours = run.output;
      EXPECT_EQ(ours->GetPoints()->GetDataType(), VTK_FLOAT);
      const vtkSmartPointer<vtkPolyData> theirs = VtkLoop(input, level);
      const double worst = CompareMeshes(ours, theirs, closed ? "Position" : "LeafUV", 1e-9);
      EXPECT_LT(worst, 1e-9) << (closed ? "sphere" : "blade") << " level " << level;
    }
  }
}

// On double points in one run VTK's float rounding is the only difference: agreement to float precision.
TEST(AdaptiveLoopFilter, OracleEqualsVtkLoopOnDoublePointsToFloatPrecision)
{
  for (const bool closed : { true, false })
  {
    vtkSmartPointer<vtkPolyData> input = closed ? Sphere(VTK_DOUBLE) : CurvedBlade(16, VTK_DOUBLE);
    for (int levels = 1; levels <= 3; ++levels)
    {
      const FilterRun run = Subdivide(input, [levels](vtkAdaptiveLoopFilter* f) { PlainLoop(f, levels); });
      ASSERT_EQ(run.errors, "");
      EXPECT_EQ(run.output->GetPoints()->GetDataType(), VTK_DOUBLE);
      const double worst = CompareMeshes(run.output, VtkLoop(input, levels), nullptr, 0.0);
      EXPECT_LT(worst, 2e-6) << levels;
      EXPECT_EQ(LastOf(run.output, "AdaptiveLoop.TrianglesPerLevel"), input->GetNumberOfCells() << (2 * levels));
    }
  }
}

TEST(AdaptiveLoopFilter, BladeArraysPrecisionAndFieldData)
{
  const vtkSmartPointer<vtkPolyData> input = CurvedBlade(30);
  const FilterRun run = Subdivide(input, [](vtkAdaptiveLoopFilter* f) {
    f->SetMaximumLevel(3);
    f->SetEdgeAngleThreshold(176.0);
    f->SetFlatnessThreshold(0.998);
  });
  ASSERT_EQ(run.errors, "");
  vtkPolyData* out = run.output;
  const vtkIdType n = out->GetNumberOfPoints();
  EXPECT_GT(out->GetNumberOfCells(), input->GetNumberOfCells());
  EXPECT_LT(out->GetNumberOfCells(), 64 * input->GetNumberOfCells()); // adaptive, not uniform
  EXPECT_EQ(out->GetPoints()->GetDataType(), input->GetPoints()->GetDataType());
  EXPECT_EQ(out->GetNumberOfPolys(), out->GetNumberOfCells());

  vtkPointData* pd = out->GetPointData();
  vtkDataArray* uv = pd->GetArray(plantmorph::arrays::LeafUV);
  ASSERT_TRUE(uv && vtkDoubleArray::SafeDownCast(uv) && uv->GetNumberOfComponents() == 2);
  ASSERT_TRUE(pd->GetTCoords() && vtkFloatArray::SafeDownCast(pd->GetTCoords()));
  EXPECT_STREQ(pd->GetTCoords()->GetName(), plantmorph::arrays::TCoords);
  vtkDataArray* region = pd->GetArray(plantmorph::arrays::Region);
  ASSERT_TRUE(region && vtkIntArray::SafeDownCast(region));
  ASSERT_TRUE(pd->GetNormals());
  EXPECT_EQ(uv->GetNumberOfTuples(), n);
  EXPECT_EQ(region->GetNumberOfTuples(), n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double nn[3];
    pd->GetNormals()->GetTuple(i, nn);
    ASSERT_NEAR(vtkMath::Norm(nn), 1.0, 1e-6);
    const int r = static_cast<int>(region->GetComponent(i, 0));
    ASSERT_TRUE(r == 0 || r == 1 || r == 4) << r;
    const double u = uv->GetComponent(i, 0), v = uv->GetComponent(i, 1);
    ASSERT_TRUE(u >= -0.5 - 1e-9 && u <= 0.5 + 1e-9 && v >= -1e-9 && v <= 1.0 + 1e-9) << u << " " << v;
  }
  vtkDataArray* cellRegion = out->GetCellData()->GetArray(plantmorph::arrays::Region);
  ASSERT_TRUE(cellRegion);
  EXPECT_EQ(cellRegion->GetNumberOfTuples(), out->GetNumberOfCells());
  EXPECT_EQ(LastOf(out, "AdaptiveLoop.TrianglesPerLevel"), out->GetNumberOfCells());
  EXPECT_EQ(LastOf(out, "AdaptiveLoop.PointsPerLevel"), n);
  EXPECT_TRUE(out->GetFieldData()->GetAbstractArray("PlantMorph.Model")); // the source's field data passed on
}

TEST(AdaptiveLoopFilter, FixedRuleKeepsMarginAndMidveinBitIdentical)
{
  const vtkSmartPointer<vtkPolyData> input = CurvedBlade(24);
  const FilterRun run = Subdivide(input, [](vtkAdaptiveLoopFilter* f) {
    f->SetMaximumLevel(3);
    f->SetEdgeAngleThreshold(180.0);
    f->SetFlatnessThreshold(1.0);
    f->SetFeatureRule(vtkAdaptiveLoopFilter::FIXED);
  });
  ASSERT_EQ(run.errors, "");
  vtkDataArray* region = input->GetPointData()->GetArray(plantmorph::arrays::Region);
  int checked = 0;
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    const int r = static_cast<int>(region->GetComponent(i, 0));
    if (r != 1 && r != 4)
      continue;
    double p[3], q[3];
    input->GetPoint(i, p);
    run.output->GetPoint(i, q);
    ASSERT_EQ(p[0], q[0]);
    ASSERT_EQ(p[1], q[1]);
    ASSERT_EQ(p[2], q[2]);
    ++checked;
  }
  EXPECT_GT(checked, 50);
  vtkDataArray* outRegion = run.output->GetPointData()->GetArray(plantmorph::arrays::Region);
  int outFeature = 0;
  for (vtkIdType i = 0; i < run.output->GetNumberOfPoints(); ++i)
  {
    const int r = static_cast<int>(outRegion->GetComponent(i, 0));
    outFeature += (r == 1 || r == 4) ? 1 : 0;
  }
  EXPECT_EQ(outFeature, checked); // no new margin or midvein point
}

TEST(AdaptiveLoopFilter, QuadsAreTriangulatedAndCellDataInheritedOrRefused)
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetResolution(4, 3);
  plane->Update();
  vtkNew<vtkPolyData> quads;
  quads->DeepCopy(plane->GetOutput());
  for (vtkIdType i = 0; i < quads->GetNumberOfPoints(); ++i)
  {
    double p[3];
    quads->GetPoint(i, p);
    p[2] = p[0] * p[0] - p[1] * p[1];
    quads->GetPoints()->SetPoint(i, p);
  }
  vtkNew<vtkIntArray> id;
  id->SetName("QuadId");
  for (vtkIdType c = 0; c < quads->GetNumberOfCells(); ++c)
    id->InsertNextValue(static_cast<int>(100 + c));
  quads->GetCellData()->AddArray(id);

  const FilterRun run = Subdivide(quads, [](vtkAdaptiveLoopFilter* f) { PlainLoop(f, 2); });
  ASSERT_EQ(run.errors, "");
  EXPECT_EQ(run.output->GetNumberOfCells(), 12 * 2 * 16);
  vtkDataArray* outId = run.output->GetCellData()->GetArray("QuadId");
  ASSERT_TRUE(outId);
  std::map<int, int> perQuad;
  for (vtkIdType c = 0; c < run.output->GetNumberOfCells(); ++c)
    ++perQuad[static_cast<int>(outId->GetComponent(c, 0))];
  EXPECT_EQ(perQuad.size(), 12u);
  for (const auto& [value, count] : perQuad)
    EXPECT_EQ(count, 32) << value;

  const FilterRun refused = Subdivide(quads, [](vtkAdaptiveLoopFilter* f) {
    PlainLoop(f, 1);
    f->TriangulateNonTrianglesOff();
  });
  EXPECT_NE(refused.errors.find("input cell 0 is a polygon with 4 points"), std::string::npos) << refused.errors;
  EXPECT_EQ(refused.output->GetNumberOfPoints(), 0);
  EXPECT_EQ(refused.output->GetNumberOfCells(), 0);
}

TEST(AdaptiveLoopFilter, NonManifoldInputIsRefusedWithPointIds)
{
  vtkNew<vtkPolyData> fin;
  vtkNew<vtkPoints> points;
  for (const auto& p :
    std::vector<std::array<double, 3>>{ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 } })
    points->InsertNextPoint(p.data());
  fin->SetPoints(points);
  vtkNew<vtkCellArray> triangles;
  for (const auto& t : std::vector<std::array<vtkIdType, 3>>{ { 0, 1, 2 }, { 1, 0, 3 }, { 0, 1, 4 } })
    triangles->InsertNextCell(3, t.data());
  fin->SetPolys(triangles);
  const FilterRun run = Subdivide(fin, [](vtkAdaptiveLoopFilter* f) { PlainLoop(f, 2); });
  EXPECT_NE(run.errors.find("non-manifold input: edge (0, 1) in 3 triangles"), std::string::npos) << run.errors;
  EXPECT_EQ(run.output->GetNumberOfPoints(), 0);
  EXPECT_EQ(run.output->GetNumberOfCells(), 0);
}

TEST(AdaptiveLoopFilter, BadPropertiesAreNamedWithTheirRangeAndGiveEmptyOutput)
{
  const vtkSmartPointer<vtkPolyData> input = CurvedBlade(12);
  const std::vector<std::pair<std::function<void(vtkAdaptiveLoopFilter*)>, std::string>> cases = {
    { [](vtkAdaptiveLoopFilter* f) { f->SetEdgeAngleThreshold(std::nan("")); },
      "EdgeAngleThreshold = nan is outside the accepted range [0, 180]" },
    { [](vtkAdaptiveLoopFilter* f) { f->SetEdgeAngleThreshold(181); },
      "EdgeAngleThreshold = 181 is outside the accepted range [0, 180]" },
    { [](vtkAdaptiveLoopFilter* f) { f->SetFlatnessThreshold(-0.5); },
      "FlatnessThreshold = -0.5 is outside the accepted range [0, 1]" },
    { [](vtkAdaptiveLoopFilter* f) { f->SetMaximumLevel(-1); },
      "MaximumLevel = -1 is outside the accepted range [0, 10]" },
    { [](vtkAdaptiveLoopFilter* f) { f->SetFeatureRule(7); },
      "FeatureRule = 7 is outside the accepted range {0, 1, 2}" },
    { [](vtkAdaptiveLoopFilter* f) { f->SetMaximumTriangles(0); },
      "MaximumTriangles = 0 is outside the accepted range [1, " },
    { [](vtkAdaptiveLoopFilter* f) { f->SetNumberOfThreads(-2); },
      "NumberOfThreads = -2 is outside the accepted range [0, 256]" },
    { [](vtkAdaptiveLoopFilter* f) { f->SetRefinementRule(3); },
      "RefinementRule = 3 is outside the accepted range {0, 1, 2} (0 Dihedral angle, 1 Surface error, 2 Chord error)" },
    { [](vtkAdaptiveLoopFilter* f) { f->SetErrorTolerance(-1.0); },
      "ErrorTolerance = -1 is outside the accepted range [0, inf]" },
    { [](vtkAdaptiveLoopFilter* f) {
       f->SetMaximumLevel(4);
       f->SetEdgeAngleThreshold(180);
       f->SetMaximumTriangles(1000);
     },
      "would make more than MaximumTriangles = 1000" },
  };
  for (const auto& [configure, expected] : cases)
  {
    const FilterRun run = Subdivide(input, configure);
    EXPECT_NE(run.errors.find(expected), std::string::npos) << "expected '" << expected << "', got: " << run.errors;
    EXPECT_EQ(run.output->GetNumberOfPoints(), 0) << expected;
    EXPECT_EQ(run.output->GetNumberOfCells(), 0) << expected;
    EXPECT_EQ(run.output->GetPointData()->GetNumberOfArrays(), 0) << expected;
  }
  // NaN coordinates.
  vtkNew<vtkPolyData> nan;
  nan->DeepCopy(input);
  nan->GetPoints()->SetPoint(5, std::nan(""), 0.0, 0.0);
  const FilterRun run = Subdivide(nan, [](vtkAdaptiveLoopFilter*) {});
  EXPECT_NE(run.errors.find("point 5 has a non-finite coordinate"), std::string::npos) << run.errors;
  EXPECT_EQ(run.output->GetNumberOfPoints(), 0);
}

TEST(AdaptiveLoopFilter, ErrorRulesFromZeroToHugeTolerance)
{
  const vtkSmartPointer<vtkPolyData> input = CurvedBlade(16);
  for (const int rule : { vtkAdaptiveLoopFilter::SURFACE_ERROR, vtkAdaptiveLoopFilter::CHORD_ERROR })
  {
    const auto byError = [rule](double tolerance) {
      return [tolerance, rule](vtkAdaptiveLoopFilter* f) {
        f->SetMaximumLevel(2);
        f->SetRefinementRule(rule);
        f->SetErrorTolerance(tolerance);
        f->SetEdgeAngleThreshold(90.0); // unused by this rule
      };
    };
    // Tolerance 0: the same output as uniform mode with the same (Fixed) feature rule, point for point.
    const FilterRun zero = Subdivide(input, byError(0.0));
    const FilterRun uniform = Subdivide(input, [](vtkAdaptiveLoopFilter* f) {
      f->SetMaximumLevel(2);
      f->SetEdgeAngleThreshold(180.0);
      f->SetFlatnessThreshold(1.0);
    });
    ASSERT_EQ(zero.errors, "");
    ASSERT_EQ(zero.output->GetNumberOfCells(), uniform.output->GetNumberOfCells());
    ExpectSamePoints(zero.output, uniform.output);
    // A moderate tolerance refines part of the blade; a huge one returns the input's surface.
    const FilterRun some = Subdivide(input, byError(1e-3));
    ASSERT_EQ(some.errors, "");
    EXPECT_GT(some.output->GetNumberOfCells(), input->GetNumberOfPolys());
    EXPECT_LT(some.output->GetNumberOfCells(), uniform.output->GetNumberOfCells());
    const FilterRun huge = Subdivide(input, byError(1e30));
    ASSERT_EQ(huge.errors, "");
    EXPECT_EQ(huge.output->GetNumberOfCells(), input->GetNumberOfPolys());
    EXPECT_EQ(huge.output->GetNumberOfPoints(), input->GetNumberOfPoints());
  }
}

TEST(AdaptiveLoopFilter, ThreadCountDoesNotChangeTheOutput)
{
  const vtkSmartPointer<vtkPolyData> input = CurvedBlade(40);
  const auto configure = [](int threads) {
    return [threads](vtkAdaptiveLoopFilter* f) {
      f->SetMaximumLevel(3);
      f->SetEdgeAngleThreshold(177.0);
      f->SetFeatureRule(vtkAdaptiveLoopFilter::LOOP);
      f->SetNumberOfThreads(threads);
    };
  };
  const FilterRun serial = Subdivide(input, configure(1));
  const FilterRun threaded = Subdivide(input, configure(0));
  ExpectSamePoints(serial.output, threaded.output);
}

TEST(AdaptiveLoopFilter, EmptyInputGivesEmptyOutputWithoutError)
{
  vtkNew<vtkPolyData> empty;
  const FilterRun run = Subdivide(empty, [](vtkAdaptiveLoopFilter*) {});
  EXPECT_EQ(run.errors, "");
  EXPECT_EQ(run.output->GetNumberOfPoints(), 0);
}

} // namespace

TEST(AdaptiveLoopFilter, AdoptedArraysEqualConvertedOnes)
{
  // Double points and one double point array: the output adopts the core's points, attribute block and triangles.
  // With a second (float) point array the attribute block is converted array by array instead: the same numbers.
  const vtkSmartPointer<vtkPolyData> alone = Sphere(VTK_DOUBLE);
  alone->GetPointData()->SetNormals(nullptr);
  while (alone->GetPointData()->GetNumberOfArrays() > 1)
    alone->GetPointData()->RemoveArray(alone->GetPointData()->GetArrayName(0) == std::string("Position") ? 1 : 0);
  ASSERT_NE(alone->GetPointData()->GetArray("Position"), nullptr);
  alone->GetPointData()->GetArray("Position")->SetComponentName(2, "height");
  auto withFloat = vtkSmartPointer<vtkPolyData>::New();
  withFloat->DeepCopy(alone);
  vtkNew<vtkFloatArray> extra;
  extra->SetName("Extra");
  extra->SetNumberOfTuples(withFloat->GetNumberOfPoints());
  for (vtkIdType i = 0; i < withFloat->GetNumberOfPoints(); ++i)
    extra->SetValue(i, static_cast<float>(i % 7));
  withFloat->GetPointData()->AddArray(extra);
  const auto configure = [](vtkAdaptiveLoopFilter* f) { PlainLoop(f, 2); };
  const FilterRun adopted = Subdivide(alone, configure);
  const FilterRun converted = Subdivide(withFloat, configure);
  ASSERT_EQ(adopted.errors, "");
  ExpectSamePoints(adopted.output, converted.output);
  EXPECT_EQ(adopted.output->GetPoints()->GetDataType(), VTK_DOUBLE);
  vtkDataArray* a = adopted.output->GetPointData()->GetArray("Position");
  vtkDataArray* c = converted.output->GetPointData()->GetArray("Position");
  ASSERT_TRUE(a && c && vtkDoubleArray::SafeDownCast(a));
  ASSERT_EQ(a->GetNumberOfComponents(), 3);
  EXPECT_STREQ(a->GetComponentName(2), "height");
  ASSERT_EQ(a->GetNumberOfTuples(), adopted.output->GetNumberOfPoints());
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(a->GetComponent(i, k), c->GetComponent(i, k)) << i;
  vtkCellArray* ta = adopted.output->GetPolys();
  vtkCellArray* tc = converted.output->GetPolys();
  ASSERT_EQ(ta->GetNumberOfCells(), tc->GetNumberOfCells());
  ASSERT_EQ(ta->GetNumberOfConnectivityIds(), 3 * ta->GetNumberOfCells());
  vtkNew<vtkIdList> ia, ic;
  for (vtkIdType t = 0; t < ta->GetNumberOfCells(); ++t)
  {
    ta->GetCellAtId(t, ia);
    tc->GetCellAtId(t, ic);
    ASSERT_EQ(ia->GetNumberOfIds(), 3);
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(ia->GetId(k), ic->GetId(k)) << t;
  }
}
