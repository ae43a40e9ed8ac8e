// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: the LAS reader (sources/las/core/LasRead.cpp) on arbitrary bytes, read through a stream as
// LASReader reads a file, and the writer (LasWrite.cpp) on what it read. On success the cloud is whole (3 coordinates
// per point, every field `components` values per point), and the pieces MPI ranks read are, in order, the whole;
// on error nothing is kept. A cloud read is written as LAS
// 1.4 and read again: the write either succeeds or says why, and a written file reads back with the same points
// and the same standard attributes, bit for bit.
#include "LasFile.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace
{
void CheckWhole(const plantmorph::LasCloud& cloud)
{
  if (cloud.xyz.size() % 3 != 0)
  {
    std::abort();
  }
  for (const plantmorph::LasField& field : cloud.fields)
  {
    if (field.components < 1 || field.values.size() != cloud.Size() * static_cast<std::size_t>(field.components))
    {
      std::abort();
    }
  }
}

bool SameBits(const std::vector<double>& a, const std::vector<double>& b)
{
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  std::istringstream in(bytes);
  plantmorph::LasCloud cloud;
  const std::string error = plantmorph::ReadLas(in, size, cloud);
  if (!error.empty())
  {
    if (!cloud.xyz.empty() || !cloud.fields.empty())
    {
      std::abort();
    }
    return 0;
  }
  CheckWhole(cloud);
  // The same bytes read by pieces (MPI ranks' shares of the records, 1-4 pieces): in order, the whole read.
  const int pieces = 1 + data[size / 2] % 4;
  std::vector<double> xyz;
  for (int p = 0; p < pieces; ++p)
  {
    std::istringstream again(bytes);
    plantmorph::LasCloud part;
    if (!plantmorph::ReadLas(again, size, part, {}, plantmorph::LasPiece{ p, pieces }).empty() ||
      part.fields.size() != cloud.fields.size())
    {
      std::abort();
    }
    CheckWhole(part);
    xyz.insert(xyz.end(), part.xyz.begin(), part.xyz.end());
  }
  if (!SameBits(xyz, cloud.xyz))
  {
    std::abort();
  }
  std::ostringstream out;
  if (!plantmorph::WriteLas(out, cloud, plantmorph::LasWriteOptions()).empty())
  {
    return 0; // refused with a reason (coordinates beyond a double, too many extra bytes)
  }
  const std::string written = out.str();
  std::istringstream again(written);
  plantmorph::LasCloud back;
  if (!plantmorph::ReadLas(again, written.size(), back).empty() || back.Size() != cloud.Size())
  {
    std::abort();
  }
  CheckWhole(back);
  for (const plantmorph::LasField& field : cloud.fields)
  {
    const plantmorph::LasField* read = back.Find(field.name);
    if (!field.extra && (!read || !SameBits(read->values, field.values)))
    {
      std::abort();
    }
  }
  return 0;
}
