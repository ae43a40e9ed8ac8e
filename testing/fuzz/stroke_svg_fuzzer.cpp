// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: ParseStrokeSvg (sources/tree/core/StrokeFiles.cpp) on arbitrary bytes. It must return (no crash,
// hang, leak or undefined behaviour), and either an error with no strokes or strokes of finite points.
#include "StrokeFiles.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::vector<Eigen::Vector3d>> strokes;
  const std::string error = plantmorph::ParseStrokeSvg(text, strokes);
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
