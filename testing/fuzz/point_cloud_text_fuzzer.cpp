// libFuzzer harness: Leaf Cloud Reader's text parser (comparison/core/PointCloudText.cpp) on arbitrary bytes, read
// through the same stream path as the reader, and the first-lines probe (CanReadFile). On success the values form
// whole rows of 3..1000 finite columns; on error nothing is kept.
#include "PointCloudText.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

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
  std::istringstream probe(text);
  plantmorph::LooksLikePointCloudText(probe);
  return 0;
}
