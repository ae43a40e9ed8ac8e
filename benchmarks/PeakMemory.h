// SPDX-License-Identifier: GPL-3.0-or-later
// Peak memory of a benchmark's measured runs, shared by every benchmark program.
//
// Start() (untimed, before the timed loop) hands freed heap pages back to the kernel with malloc_trim(0), records
// the resident set (VmRSS) and resets the kernel's high-water mark VmHWM to it by writing "5" to
// /proc/self/clear_refs. After the loop, VmHWM minus that baseline is the most memory the runs added at any moment:
// the peak of the code under test, whatever it allocated and freed on the way.
#pragma once

#include <benchmark/benchmark.h>

#include <malloc.h>

#include <fstream>
#include <sstream>
#include <string>

namespace plantmorph_benchmarks
{

/// A field of /proc/self/status in bytes ("VmRSS", "VmHWM"); -1 if unavailable.
inline long long StatusBytes(const std::string& key)
{
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
  {
    if (line.compare(0, key.size() + 1, key + ":") == 0)
    {
      std::istringstream fields(line.substr(key.size() + 1));
      long long kiB = -1;
      fields >> kiB;
      return kiB < 0 ? -1 : kiB * 1024;
    }
  }
  return -1;
}

inline benchmark::Counter Bytes(double bytes)
{
  return benchmark::Counter(bytes, benchmark::Counter::kDefaults, benchmark::Counter::OneK::kIs1024);
}

class PeakMemoryProbe
{
public:
  /// Untimed: trims the heap, records the baseline resident set and resets VmHWM to it.
  void Start()
  {
    malloc_trim(0);
    this->Baseline = StatusBytes("VmRSS");
    std::ofstream clearRefs("/proc/self/clear_refs");
    clearRefs << "5";
    clearRefs.flush();
    this->Reset = static_cast<bool>(clearRefs);
  }

  /// Bytes the runs added at their peak (0 if /proc is unavailable).
  double Peak() const
  {
    const long long hwm = StatusBytes("VmHWM");
    return (hwm >= 0 && this->Baseline >= 0) ? static_cast<double>(hwm - this->Baseline) : 0.0;
  }

  /// Counters: peak_bytes, vm_hwm, peak_reset (1 when VmHWM could be reset), and with sizes given, in_bytes,
  /// out_bytes and peak_ratio = peak / (in + out).
  void Report(benchmark::State& state, double inBytes = 0.0, double outBytes = 0.0) const
  {
    const double peak = this->Peak();
    state.counters["peak_bytes"] = Bytes(peak);
    state.counters["vm_hwm"] = Bytes(static_cast<double>(StatusBytes("VmHWM")));
    state.counters["peak_reset"] = this->Reset ? 1.0 : 0.0;
    if (inBytes > 0.0)
      state.counters["in_bytes"] = Bytes(inBytes);
    if (outBytes > 0.0)
      state.counters["out_bytes"] = Bytes(outBytes);
    if (inBytes + outBytes > 0.0)
      state.counters["peak_ratio"] = peak / (inBytes + outBytes);
  }

private:
  long long Baseline = -1;
  bool Reset = false;
};

} // namespace plantmorph_benchmarks
