// SPDX-License-Identifier: GPL-3.0-or-later
#include <plantmorph/RandomStream.h>

#include <cmath>

namespace plantmorph
{

std::uint64_t SplitMix64(std::uint64_t x)
{
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

RandomStream::RandomStream(std::uint64_t seed, std::uint64_t stream)
{
  // Four words of state from (seed, stream): different streams of one seed share nothing visible.
  const std::uint64_t base = SplitMix64(seed) ^ SplitMix64(stream + 0x632BE59BD9B4E019ull);
  std::seed_seq sequence{ static_cast<std::uint32_t>(base), static_cast<std::uint32_t>(base >> 32),
    static_cast<std::uint32_t>(SplitMix64(base)), static_cast<std::uint32_t>(SplitMix64(base) >> 32) };
  this->Engine.seed(sequence);
}

double RandomStream::Uniform()
{
  return static_cast<double>(this->Engine() >> 11) * 0x1.0p-53;
}

std::int64_t RandomStream::Integer(std::int64_t low, std::int64_t high)
{
  if (high <= low)
    return low;
  const std::uint64_t range = static_cast<std::uint64_t>(high) - static_cast<std::uint64_t>(low) + 1u;
  if (range == 0) // the whole 64-bit range
    return static_cast<std::int64_t>(this->Engine());
  // Reject the top partial block of 2^64 so every value is equally likely.
  const std::uint64_t limit = (~std::uint64_t(0) / range) * range;
  std::uint64_t x;
  do
  {
    x = this->Engine();
  } while (x >= limit);
  return static_cast<std::int64_t>(static_cast<std::uint64_t>(low) + x % range);
}

double RandomStream::Normal()
{
  if (this->HasSpare)
  {
    this->HasSpare = false;
    return this->Spare;
  }
  double u, v, s;
  do
  {
    u = 2.0 * this->Uniform() - 1.0;
    v = 2.0 * this->Uniform() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double factor = std::sqrt(-2.0 * std::log(s) / s);
  this->Spare = v * factor;
  this->HasSpare = true;
  return u * factor;
}

} // namespace plantmorph
