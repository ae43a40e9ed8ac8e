// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: Leaf Cloud Reader's text parser (sources/leaf_cloud/core/PointCloudText.cpp) on arbitrary bytes, read
// through the same stream path as the reader, whole and by pieces (MPI ranks' byte ranges), and the first-lines
// probe (CanReadFile). On success the values form whole rows of 3..1000 finite columns, and the pieces' values in
// order are the same; on error nothing is kept.
#include "PointCloudText.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::istringstream in(text);
  plantmorph::PointCloudText cloud;
  const std::string error = plantmorph::ReadPointCloudText(in, cloud);
  if (error.empty())
  {
    if (cloud.columns < 3 || cloud.columns > plantmorph::kMaxPointCloudColumns || cloud.values.empty() ||
      cloud.values.size() % cloud.columns != 0)
    {
      std::abort();
    }
    for (const double v : cloud.values)
    {
      if (!std::isfinite(v))
      {
        std::abort();
      }
    }
    plantmorph::SplitHeaderNames(cloud.header);
  }
  else if (cloud.columns != 0 || !cloud.values.empty())
  {
    std::abort();
  }
  // The same bytes read as pieces (as MPI ranks read them; 1-8 pieces from the first byte): every piece agrees
  // with the whole read. A whole success: no piece fails and their values, in order, are the whole's. A whole
  // failure on a line: some piece fails. Either way a failing piece keeps nothing.
  const std::size_t pieces = size ? 1 + data[0] % 8 : 1;
  std::vector<double> joined;
  bool anyFailed = false;
  for (std::size_t p = 0; p < pieces; ++p)
  {
    std::istringstream in(text);
    plantmorph::PointCloudTextPiece piece;
    piece.begin = size * p / pieces;
    piece.end = p + 1 == pieces ? UINT64_MAX : size * (p + 1) / pieces;
    plantmorph::PointCloudText part;
    const std::string pieceError = plantmorph::ReadPointCloudTextPiece(in, piece, part);
    if (!pieceError.empty() && !part.values.empty())
    {
      std::abort();
    }
    anyFailed = anyFailed || !pieceError.empty();
    joined.insert(joined.end(), part.values.begin(), part.values.end());
  }
  if (error.empty() ? (anyFailed || joined != cloud.values) : (error != "no data line" && !anyFailed))
  {
    std::abort();
  }
  std::istringstream probe(text);
  plantmorph::LooksLikePointCloudText(probe);
  return 0;
}
