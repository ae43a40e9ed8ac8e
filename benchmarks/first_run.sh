#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# First and warm updates, ours against VTK's, each case in fresh processes (benchmarks/README.md, "first run").
#   benchmarks/first_run.sh BUILD_DIR [REPEATS]        (default 3 fresh processes per case, 3 warm updates each)
#   CASES="loop vtkloop distance vtkdistance" benchmarks/first_run.sh BUILD_DIR   (vtkdistance: VTK's
#   vtkDistancePolyDataFilter on the same 10^6 points, over ten minutes a process; off by default)
# Prints per case the median first update, the median warm update (over every warm update of every process), wall
# and CPU (the process's, every thread), first / warm in CPU time (what the first update pays, meaningful under
# load too), and the VTK peer's time over ours for both.
set -euo pipefail
program="${1:?usage: first_run.sh BUILD_DIR [REPEATS]}/bin/first_run_benchmark"
repeats="${2:-3}"
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
declare -A first warm
for case in ${CASES:-loop vtkloop distance}; do
  runs=""
  for _ in $(seq "$repeats"); do
    runs+="$("$program" "$case" 3)"$'\n'
  done
  first[$case]="$(awk '$2 == 0 { print $3 }' <<< "$runs" | median)"
  warm[$case]="$(awk '$2 > 0 { print $3 }' <<< "$runs" | median)"
  first_cpu="$(awk '$2 == 0 { print $4 }' <<< "$runs" | median)"
  warm_cpu="$(awk '$2 > 0 { print $4 }' <<< "$runs" | median)"
  echo "$case: first ${first[$case]} s, warm ${warm[$case]} s; CPU first $first_cpu s, warm $warm_cpu s," \
    "first / warm $(awk -v f="$first_cpu" -v w="$warm_cpu" 'BEGIN { printf "%.2f", f / w }')"
done
for pair in "loop vtkloop" "distance vtkdistance"; do
  read -r ours peer <<< "$pair"
  [[ -n "${first[$ours]:-}" && -n "${first[$peer]:-}" ]] || continue
  awk -v o="${first[$ours]}" -v p="${first[$peer]}" -v wo="${warm[$ours]}" -v wp="${warm[$peer]}" -v n="$ours" \
    'BEGIN { printf "%s: VTK / ours, first run %.1fx, warm %.1fx\n", n, p / o, wp / wo }'
done
