// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK layer of TrajectoryComparisonFilter: paper 001 Table 1 from tables (columns by name) and from point sets
// gives 1.76, 0.69, 2.52, 1.89, 2.92 cm and 6.1 degrees in the outputs and field data; times are carried; a missing
// column is an error naming the property and the available columns, with empty outputs. The default columns (auto)
// recognise the data file's measured_* / paper_sim_* and WiltingSimulator's TipX/Y/Z; a single sample is refused.
#include "VtkErrorCatcher.h"
#include "vtkTrajectoryComparisonFilter.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace
{
using plantmorph::testing::ErrorCatcher;

const double Measured[5][3] = { { 0.46, 19.58, -2.13 }, { -1.26, 18.51, -3.43 }, { -1.30, 13.45, -9.87 },
  { 0.10, 8.90, -14.10 }, { 0.60, 4.20, -18.40 } };
const double Simulated[5][3] = { { -1.06, 20.41, -1.79 }, { -0.86, 19.03, -3.22 }, { 1.12, 12.85, -9.49 },
  { 1.27, 9.90, -15.20 }, { 1.50, 1.70, -19.60 } };

/// The data file's layout: one table with sample, measured_* and paper_sim_* columns (float, as a CSV reader may
/// give them).
vtkSmartPointer<vtkTable> Table1()
{
  auto table = vtkSmartPointer<vtkTable>::New();
  const char* names[7] = { "sample", "measured_x", "measured_y", "measured_z", "paper_sim_x", "paper_sim_y",
    "paper_sim_z" };
  for (int c = 0; c < 7; ++c)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(names[c]);
    column->SetNumberOfTuples(5);
    for (int i = 0; i < 5; ++i)
    {
      column->SetValue(i, c == 0 ? i + 1 : (c <= 3 ? Measured[i][c - 1] : Simulated[i][c - 4]));
    }
    table->AddColumn(column);
  }
  return table;
}

vtkSmartPointer<vtkPolyData> Points(const double (*xyz)[3], int n, bool withTime)
{
  auto data = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> time;
  time->SetName("time");
  for (int i = 0; i < n; ++i)
  {
    points->InsertNextPoint(xyz[i]);
    time->InsertNextValue(2.5 * i);
  }
  data->SetPoints(points);
  if (withTime)
  {
    data->GetPointData()->AddArray(time);
  }
  return data;
}

void ExpectPaperNumbers(vtkTrajectoryComparisonFilter* filter)
{
  vtkTable* samples = vtkTable::SafeDownCast(filter->GetOutputDataObject(0));
  vtkTable* summary = vtkTable::SafeDownCast(filter->GetOutputDataObject(1));
  ASSERT_EQ(samples->GetNumberOfRows(), 5);
  const double paper[5] = { 1.76, 0.69, 2.52, 1.89, 2.92 };
  for (int i = 0; i < 5; ++i)
  {
    const double d = samples->GetValueByName(i, "ClosestDistance").ToDouble();
    EXPECT_NEAR(std::round(100 * d) / 100, paper[i], 1e-12) << d;
    EXPECT_EQ(samples->GetValueByName(i, "ClosestIndex").ToInt(), i);
    EXPECT_EQ(samples->GetValueByName(i, "MonotoneIndex").ToInt(), i);
    EXPECT_NEAR(samples->GetValueByName(i, "ClosestDX").ToDouble(), Simulated[i][0] - Measured[i][0], 1e-12);
  }
  EXPECT_NEAR(summary->GetValueByName(0, "ClosestDirectionAngle").ToDouble(), 6.1, 0.05);
  EXPECT_NEAR(summary->GetValueByName(0, "ClosestMaxDistance").ToDouble(), 2.915476, 1e-6);
  EXPECT_NEAR(summary->GetValueByName(0, "ClosestMeanDistance").ToDouble(), 1.956617, 1e-6);
  EXPECT_NEAR(samples->GetFieldData()->GetArray("ClosestDirectionAngle")->GetTuple1(0), 6.1, 0.05);
}

TEST(TrajectoryComparisonFilter, PaperTable1FromTheDataFilesColumns)
{
  vtkSmartPointer<vtkTable> table = Table1();
  vtkNew<vtkTrajectoryComparisonFilter> filter;
  filter->SetInputData(0, table);
  filter->SetSimulatedData(table);
  filter->SetMeasuredColumns("measured_x", "measured_y", "measured_z");
  filter->SetSimulatedColumns("paper_sim_x", "paper_sim_y", "paper_sim_z");
  filter->Update();
  ExpectPaperNumbers(filter);
}

TEST(TrajectoryComparisonFilter, PaperTable1FromPointSetsWithTimes)
{
  vtkNew<vtkTrajectoryComparisonFilter> filter;
  filter->SetInputData(0, Points(Measured, 5, true));
  filter->SetSimulatedData(Points(Simulated, 5, true));
  filter->Update();
  ExpectPaperNumbers(filter);
  vtkTable* samples = vtkTable::SafeDownCast(filter->GetOutputDataObject(0));
  EXPECT_EQ(samples->GetValueByName(3, "ClosestTime").ToDouble(), 7.5);
  EXPECT_EQ(samples->GetValueByName(3, "MeasuredTime").ToDouble(), 7.5);
}

TEST(TrajectoryComparisonFilter, MissingColumnIsAnErrorWithEmptyOutputs)
{
  vtkSmartPointer<vtkTable> table = Table1();
  vtkNew<vtkTrajectoryComparisonFilter> filter;
  vtkNew<ErrorCatcher> catcher;
  filter->AddObserver(vtkCommand::ErrorEvent, catcher);
  filter->SetInputData(0, table);
  filter->SetSimulatedData(table);
  filter->SetMeasuredColumns("x", "y", "z");
  filter->Update(); // columns x, y, z do not exist
  EXPECT_NE(catcher->Messages.find("MeasuredX: "), std::string::npos) << catcher->Messages;
  EXPECT_NE(catcher->Messages.find("'measured_x'"), std::string::npos) << "lists the available columns";
  EXPECT_EQ(vtkTable::SafeDownCast(filter->GetOutputDataObject(0))->GetNumberOfRows(), 0);
  EXPECT_EQ(vtkTable::SafeDownCast(filter->GetOutputDataObject(1))->GetNumberOfColumns(), 0);
  // NaN coordinate.
  table->GetColumnByName("measured_y")->SetVariantValue(2, std::nan(""));
  filter->SetMeasuredColumns("measured_x", "measured_y", "measured_z");
  filter->SetSimulatedColumns("paper_sim_x", "paper_sim_y", "paper_sim_z");
  catcher->Messages.clear();
  filter->Update();
  EXPECT_NE(catcher->Messages.find("non-finite"), std::string::npos) << catcher->Messages;
  EXPECT_EQ(vtkTable::SafeDownCast(filter->GetOutputDataObject(0))->GetNumberOfRows(), 0);
}

TEST(TrajectoryComparisonFilter, OneColumnMenuEachAndTheOlderThreeNamesWhereAMenuIsAuto)
{
  // The panel's menus (SetMeasuredX ...) name the columns; the three-name setter of older scripts fills in the
  // columns whose menu is auto, in either order.
  vtkSmartPointer<vtkTable> table = Table1();
  vtkNew<vtkTrajectoryComparisonFilter> filter;
  filter->SetInputData(0, table);
  filter->SetSimulatedData(table);
  filter->SetSimulatedX("paper_sim_x");
  filter->SetSimulatedY("paper_sim_y");
  filter->SetSimulatedZ("paper_sim_z");
  filter->SetMeasuredColumns("nope", "measured_y", "nope");
  filter->SetMeasuredX("measured_x");
  filter->SetMeasuredZ("measured_z");
  EXPECT_EQ(filter->GetMeasuredColumn(0), "measured_x");
  EXPECT_EQ(filter->GetMeasuredColumn(1), "measured_y");
  EXPECT_EQ(filter->GetSimulatedColumn(2), "paper_sim_z");
  filter->Update();
  ExpectPaperNumbers(filter);
  filter->SetMeasuredX("auto"); // back to the three-name setting's "nope"
  EXPECT_EQ(filter->GetMeasuredColumn(0), "nope");
  vtkNew<vtkTrajectoryComparisonFilter> fresh;
  EXPECT_EQ(fresh->GetMeasuredColumn(0), "auto");
}

TEST(TrajectoryComparisonFilter, DefaultColumnsRecogniseTheKnownLayouts)
{
  // The data file's table with itself: measured_* for the Input, paper_sim_* for Simulated, no names typed.
  vtkSmartPointer<vtkTable> table = Table1();
  vtkNew<vtkTrajectoryComparisonFilter> filter;
  vtkNew<ErrorCatcher> catcher;
  filter->AddObserver(vtkCommand::ErrorEvent, catcher);
  filter->SetInputData(0, table);
  filter->SetSimulatedData(table);
  filter->Update();
  EXPECT_EQ(catcher->Messages, "");
  ExpectPaperNumbers(filter);

  // WiltingSimulator's Trajectory layout (Time, TipX, TipY, TipZ) as the simulated input: its Time is carried.
  vtkNew<vtkTable> tip;
  const char* names[4] = { "Time", "TipX", "TipY", "TipZ" };
  for (int c = 0; c < 4; ++c)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(names[c]);
    for (int i = 0; i < 5; ++i)
    {
      column->InsertNextValue(c == 0 ? 2.5 * i : Simulated[i][c - 1]);
    }
    tip->AddColumn(column);
  }
  filter->SetSimulatedData(tip);
  filter->Update();
  EXPECT_EQ(catcher->Messages, "");
  ExpectPaperNumbers(filter);
  EXPECT_EQ(vtkTable::SafeDownCast(filter->GetOutputDataObject(0))->GetValueByName(3, "ClosestTime").ToDouble(), 7.5);

  // A table with none of the known layouts: an error listing them and its columns, empty outputs.
  vtkNew<vtkTable> other;
  for (const char* name : { "a", "b", "c" })
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name);
    column->SetNumberOfTuples(3);
    column->Fill(1.0);
    other->AddColumn(column);
  }
  filter->SetInputData(0, other);
  filter->Update();
  EXPECT_NE(catcher->Messages.find("MeasuredX/Y/Z: auto found none"), std::string::npos) << catcher->Messages;
  EXPECT_NE(catcher->Messages.find("'a' 'b' 'c'"), std::string::npos) << catcher->Messages;
  EXPECT_EQ(vtkTable::SafeDownCast(filter->GetOutputDataObject(0))->GetNumberOfRows(), 0);

  // Text columns named like a known layout: the message names the column that is not numeric.
  vtkNew<vtkTable> text;
  for (const char* name : { "x", "y", "z" })
  {
    vtkNew<vtkStringArray> column;
    column->SetName(name);
    column->SetNumberOfValues(3);
    for (vtkIdType i = 0; i < 3; ++i)
      column->SetValue(i, "1,5");
    text->AddColumn(column);
  }
  catcher->Messages.clear();
  filter->SetInputData(0, text);
  filter->Update();
  EXPECT_NE(catcher->Messages.find("MeasuredX/Y/Z: the "), std::string::npos) << catcher->Messages;
  EXPECT_NE(catcher->Messages.find("column 'x' is not numeric (a vtkStringArray"), std::string::npos)
    << catcher->Messages;
  EXPECT_EQ(vtkTable::SafeDownCast(filter->GetOutputDataObject(0))->GetNumberOfRows(), 0);
}

TEST(TrajectoryComparisonFilter, OneSampleIsAnErrorNotANaNAngle)
{
  vtkNew<vtkTrajectoryComparisonFilter> filter;
  vtkNew<ErrorCatcher> catcher;
  filter->AddObserver(vtkCommand::ErrorEvent, catcher);
  filter->SetInputData(0, Points(Measured, 1, false));
  filter->SetSimulatedData(Points(Simulated, 5, false));
  filter->Update();
  EXPECT_NE(catcher->Messages.find("Input (measured)"), std::string::npos) << catcher->Messages;
  EXPECT_NE(catcher->Messages.find("at least 2"), std::string::npos) << catcher->Messages;
  EXPECT_EQ(vtkTable::SafeDownCast(filter->GetOutputDataObject(1))->GetNumberOfRows(), 0);
}

/// Points with the given times (a "time" point array).
vtkSmartPointer<vtkPolyData> TimedPoints(const double (*xyz)[3], const double* times, const int* order, int n)
{
  auto data = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> time;
  time->SetName("time");
  for (int i = 0; i < n; ++i)
  {
    points->InsertNextPoint(xyz[order[i]]);
    time->InsertNextValue(times[order[i]]);
  }
  data->SetPoints(points);
  data->GetPointData()->AddArray(time);
  return data;
}

// Rows out of time order (with a time column) used to be matched in the order given: a monotone mean of 3.3 and a
// direction angle of 180 degrees instead of the ordered rows' values. They are sorted by time with a warning, so the
// numbers are those of the ordered rows, and Sample / ClosestIndex give the input rows.
TEST(TrajectoryComparisonFilter, RowsOutOfTimeOrderAreSortedWithAWarning)
{
  const double times[5] = { 0.0, 2.5, 5.0, 7.5, 10.0 };
  const int inOrder[5] = { 0, 1, 2, 3, 4 }, shuffled[5] = { 3, 0, 4, 2, 1 };
  vtkNew<vtkTrajectoryComparisonFilter> ordered;
  ordered->SetInputData(0, TimedPoints(Measured, times, inOrder, 5));
  ordered->SetSimulatedData(TimedPoints(Simulated, times, inOrder, 5));
  ordered->Update();
  ExpectPaperNumbers(ordered);
  vtkNew<vtkTrajectoryComparisonFilter> filter;
  vtkNew<ErrorCatcher> warnings;
  filter->AddObserver(vtkCommand::WarningEvent, warnings);
  filter->SetInputData(0, TimedPoints(Measured, times, shuffled, 5));
  filter->SetSimulatedData(TimedPoints(Simulated, times, shuffled, 5));
  filter->Update();
  EXPECT_NE(warnings->Messages.find("Input (measured) input's rows are not in time order (row 1"), std::string::npos)
    << warnings->Messages;
  EXPECT_NE(warnings->Messages.find("Simulated input's rows are not in time order"), std::string::npos)
    << warnings->Messages;
  EXPECT_NE(warnings->Messages.find("sorted by time"), std::string::npos) << warnings->Messages;
  vtkTable* a = vtkTable::SafeDownCast(ordered->GetOutputDataObject(1));
  vtkTable* b = vtkTable::SafeDownCast(filter->GetOutputDataObject(1));
  for (const char* name : { "ClosestMeanDistance", "ClosestDirectionAngle", "MonotoneMeanDistance",
         "MonotoneMaxDistance", "MonotoneDirectionAngle" })
    EXPECT_DOUBLE_EQ(b->GetValueByName(0, name).ToDouble(), a->GetValueByName(0, name).ToDouble()) << name;
  EXPECT_NEAR(b->GetValueByName(0, "MonotoneDirectionAngle").ToDouble(), 6.1, 0.05);
  vtkTable* samples = vtkTable::SafeDownCast(filter->GetOutputDataObject(0));
  for (int i = 0; i < 5; ++i)
  {
    // Sample i (time order) is input row k with shuffled[k] == i; it matches simulated sample i, input row k too.
    const int row = static_cast<int>(std::find(shuffled, shuffled + 5, i) - shuffled);
    EXPECT_EQ(samples->GetValueByName(i, "Sample").ToInt(), row);
    EXPECT_EQ(samples->GetValueByName(i, "MonotoneIndex").ToInt(), row);
    EXPECT_EQ(samples->GetValueByName(i, "MeasuredTime").ToDouble(), times[i]);
  }
  // A time that is not finite cannot be ordered: an error naming the row.
  double bad[5] = { 0.0, 2.5, std::nan(""), 7.5, 10.0 };
  vtkNew<ErrorCatcher> errors;
  filter->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->SetInputData(0, TimedPoints(Measured, bad, inOrder, 5));
  filter->Update();
  EXPECT_NE(errors->Messages.find("time at row 2 is not finite"), std::string::npos) << errors->Messages;
  EXPECT_EQ(vtkTable::SafeDownCast(filter->GetOutputDataObject(1))->GetNumberOfRows(), 0);
}

// A trajectory that does not move has no direction: the angle used to be NaN. It is left out with a warning, and no
// summary value is NaN.
TEST(TrajectoryComparisonFilter, AStillTrajectoryHasNoDirectionAngleAndAWarning)
{
  const double still[5][3] = { { 1, 2, 3 }, { 1, 2, 3 }, { 1, 2, 3 }, { 1, 2, 3 }, { 1, 2, 3 } };
  vtkNew<vtkTrajectoryComparisonFilter> filter;
  vtkNew<ErrorCatcher> warnings, errors;
  filter->AddObserver(vtkCommand::WarningEvent, warnings);
  filter->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->SetInputData(0, Points(still, 5, false));
  filter->SetSimulatedData(Points(Simulated, 5, false));
  filter->Update();
  EXPECT_EQ(errors->Messages, "");
  EXPECT_NE(warnings->Messages.find("ClosestDirectionAngle and MonotoneDirectionAngle left out"), std::string::npos)
    << warnings->Messages;
  vtkTable* summary = vtkTable::SafeDownCast(filter->GetOutputDataObject(1));
  ASSERT_EQ(summary->GetNumberOfRows(), 1);
  EXPECT_EQ(summary->GetColumnByName("ClosestDirectionAngle"), nullptr);
  EXPECT_EQ(summary->GetColumnByName("MonotoneDirectionAngle"), nullptr);
  for (vtkIdType c = 0; c < summary->GetNumberOfColumns(); ++c)
    EXPECT_FALSE(std::isnan(summary->GetValue(0, c).ToDouble())) << summary->GetColumnName(c);
  EXPECT_GT(summary->GetValueByName(0, "ClosestMeanDistance").ToDouble(), 0.0);
}

} // namespace
