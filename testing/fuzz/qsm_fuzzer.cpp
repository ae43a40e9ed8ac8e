// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: the QSM cylinder table reader (sources/formats/core/QsmTable.cpp) on arbitrary bytes. On success
// every cylinder has a finite start, end and radius and the columns fill whole rows; the cylinders and every column,
// written by WriteQsmTable, read back with the same starts, ends and radii bit for bit. On error nothing is kept.
#include "QsmTable.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace
{
void Require(bool condition)
{
  if (!condition)
  {
    std::abort();
  }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  plantmorph::QsmTable table;
  if (!plantmorph::ReadQsmTable(in, table).empty())
  {
    Require(table.Rows() == 0 && table.start.empty() && table.names.empty());
    return 0;
  }
  const std::size_t rows = table.Rows();
  Require(rows > 0 && table.columns == table.names.size() && table.values.size() == rows * table.columns);
  Require(table.start.size() == rows && table.end.size() == rows && table.radius.size() == rows);
  std::vector<plantmorph::QsmCylinder> cylinders(rows);
  for (std::size_t i = 0; i < rows; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      Require(std::isfinite(table.start[i][static_cast<std::size_t>(k)]));
      Require(std::isfinite(table.end[i][static_cast<std::size_t>(k)]));
    }
    Require(std::isfinite(table.radius[i]));
    cylinders[i].id = table.id[i];
    cylinders[i].parent = table.parent[i];
    cylinders[i].start = table.start[i];
    cylinders[i].end = table.end[i];
    cylinders[i].radius = table.radius[i];
  }
  std::vector<std::string> extra;
  for (std::size_t c = 0; c < table.columns; ++c)
  {
    extra.push_back("column" + std::to_string(c)); // names that are none of the standard columns
  }
  std::ostringstream out;
  Require(plantmorph::WriteQsmTable(out, cylinders, extra, table.values).empty());
  std::istringstream again(out.str());
  plantmorph::QsmTable back;
  Require(plantmorph::ReadQsmTable(again, back).empty());
  Require(back.Rows() == rows && back.start == table.start && back.end == table.end && back.radius == table.radius);
  return 0;
}
