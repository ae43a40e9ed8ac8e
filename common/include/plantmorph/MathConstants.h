// SPDX-License-Identifier: GPL-3.0-or-later
// Mathematical constants the algorithm layers share (C++17 has no std::numbers). Plain C++, no VTK.
#pragma once

namespace plantmorph
{

/// pi to double precision.
inline constexpr double Pi = 3.14159265358979323846;

} // namespace plantmorph
