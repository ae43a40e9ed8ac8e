// SPDX-License-Identifier: GPL-3.0-or-later
// Deterministic random numbers from the one `Seed` property (spec README, "Randomness").
//
// A RandomStream is std::mt19937_64 seeded from (seed, stream) through SplitMix64, so independent parts of an
// algorithm (one stream per vein, per branch, per thread's block of work) draw reproducible numbers whatever order or
// thread runs them, and the same (seed, stream) gives the same numbers on every run, machine and MPI rank count.
// The distributions are written out here rather than taken from <random>: std::uniform_real_distribution and
// std::normal_distribution are allowed to differ between standard libraries, which would break bit-identical output.
#pragma once

#include <cstdint>
#include <random>

namespace plantmorph
{

class RandomStream
{
public:
  explicit RandomStream(std::uint64_t seed, std::uint64_t stream = 0);

  /// 64 uniformly random bits.
  std::uint64_t Bits() { return this->Engine(); }
  /// Uniform in [0, 1), 53 random bits.
  double Uniform();
  /// Uniform in [low, high).
  double Uniform(double low, double high) { return low + (high - low) * this->Uniform(); }
  /// Uniform integer in [low, high] (inclusive), without modulo bias; low when high < low.
  std::int64_t Integer(std::int64_t low, std::int64_t high);
  /// Standard normal (Marsaglia's polar method).
  double Normal();
  /// Normal with the given mean and standard deviation.
  double Normal(double mean, double deviation) { return mean + deviation * this->Normal(); }

private:
  std::mt19937_64 Engine;
  bool HasSpare = false;
  double Spare = 0.0;
};

/// SplitMix64 step: a well-mixed 64-bit hash of x (used to derive stream seeds).
std::uint64_t SplitMix64(std::uint64_t x);

} // namespace plantmorph
