#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# All tests: set up and build if needed, then ctest (GoogleTest unit tests, pvpython pipeline and state-file tests,
# the MPI test). Then the C++ tests again in an AddressSanitizer + UBSan build (build-asan/); skip that with
# PLANTMORPH_SKIP_SANITIZERS=1.
set -euo pipefail
PLANTMORPH_TARGETS=all # everything: the tests, and the benchmarks (their programs must build too)
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/setup.sh"
cd "$PLANTMORPH_BUILD"
ctest --output-on-failure -j2 --timeout 900
if [ "${PLANTMORPH_SKIP_SANITIZERS:-0}" != "1" ]; then
  ASAN_BUILD="$PLANTMORPH_ROOT/build-asan"
  plantmorph_build "$ASAN_BUILD" -DPLANTMORPH_SANITIZE=ON -DPLANTMORPH_BUILD_BENCHMARKS=OFF \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo
  cd "$ASAN_BUILD"
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j2 -L unit --timeout 900
fi
