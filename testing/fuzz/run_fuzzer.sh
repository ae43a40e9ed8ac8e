#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest's short fuzz run (label `fuzz`): run_fuzzer.sh FUZZER SECONDS WORK_DIR [-libFuzzer options] [seed dirs]
# Exits 77 (ctest: skipped) when the harness was not built (no clang++ with libFuzzer on this machine). New inputs
# go to WORK_DIR (in the build tree); the seed directories are only read. A crash, hang (-timeout), leak or
# sanitizer report makes libFuzzer exit non-zero and leave the input as WORK_DIR/../<fuzzer>-crash-*.
set -euo pipefail
fuzzer="$1"
seconds="$2"
work="$3"
shift 3
# Options (-name=value) go to libFuzzer as they are; the other arguments are seed directories, only read.
options=()
seeds=()
for argument in "$@"; do
  case "$argument" in
    -*) options+=("$argument") ;;
    *) seeds+=("$argument") ;;
  esac
done
set -- "${options[@]}"
if [ ! -x "$fuzzer" ]; then
  echo "skipped: $fuzzer was not built (needs clang++ and libFuzzer: Debian clang, libclang-rt-14-dev)"
  exit 77
fi
mkdir -p "$work"
# libFuzzer writes new inputs into the FIRST corpus directory: the work directory must come before the seeds.
# -error_exitcode=1: libFuzzer's own default for a crash is 77, which ctest would report as a skip.
exec "$fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 -error_exitcode=1 \
  -artifact_prefix="$(dirname "$work")/$(basename "$fuzzer")-" "$@" "$work" "${seeds[@]}"
