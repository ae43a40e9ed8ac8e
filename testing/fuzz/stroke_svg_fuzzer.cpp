// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: ParseStrokeSvg (sources/tree/core/StrokeFiles.cpp) on arbitrary bytes. It must return (no crash,
// hang, leak or undefined behaviour), and either an error with no strokes or strokes of finite points.
#include "StrokeFiles.h"
#include "StrokeFuzzChecks.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::vector<Eigen::Vector3d>> strokes;
  std::vector<std::string> origins; // where each stroke comes from: one per stroke, none on error
  const std::string error = plantmorph::ParseStrokeSvg(text, strokes, &origins);
  CheckStrokeOrigins(strokes, origins);
  if (!error.empty() && !strokes.empty())
  {
    std::abort(); // an error leaves no strokes
  }
  for (const auto& stroke : strokes)
  {
    for (const auto& p : stroke)
    {
      if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || p.z() != 0.0)
      {
        std::abort();
      }
    }
  }
  return 0;
}
