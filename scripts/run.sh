#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The main job: set up and build if needed, then run the example pipelines (every examples/main_*.py) in pvbatch,
# writing .vtp files, PNG renders and state files into output/ (or the folder given as the first argument). Names
# after the folder run only those examples (e.g. `run.sh out main_measured_leaf.py`). It builds only the plugin
# (CMake target PlantMorph), not the tests and benchmarks: scripts/test.sh builds those.
set -euo pipefail
PLANTMORPH_TARGETS=PlantMorph
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/setup.sh"
OUTPUT="$(mkdir -p "${1:-$PLANTMORPH_ROOT/output}" && cd "${1:-$PLANTMORPH_ROOT/output}" && pwd)"
MAIN_EXAMPLES=""
for name in "${@:2}"; do
  [ -f "$PLANTMORPH_ROOT/examples/$(basename "$name")" ] || { echo "run: no examples/$(basename "$name")" >&2; exit 1; }
  MAIN_EXAMPLES+="$PLANTMORPH_ROOT/examples/$(basename "$name")"$'\n'
done
MAIN_EXAMPLES="${MAIN_EXAMPLES:-$(printf '%s\n' "$PLANTMORPH_ROOT"/examples/main_*.py)}"  # one a line
# pvbatch renders only with an X server: use the one we have, or one private Xvfb server for all the examples
# (testing/python/virtual_display.py: Xvfb picks its display itself; xvfb-run -a races with other X servers
# starting on the machine, "bad X server connection").
# On this kind of machine a render window's connection to Xvfb now and then fails ("bad X server connection",
# pvbatch aborts at once); an example that aborts is run again, up to six times.
EXAMPLES='set -uo pipefail
while IFS= read -r example; do
  [ -n "$example" ] || continue
  for attempt in 1 2 3 4 5 6; do
    echo "run: $(basename "$example")"
    pvbatch "$example" --plugin "$PLANTMORPH_PLUGIN" --output "$OUTPUT" < /dev/null && break
    [ "$attempt" = 6 ] && exit 1
    echo "run: $(basename "$example") failed, running it again"
  done
done <<< "$MAIN_EXAMPLES"'
export PLANTMORPH_ROOT PLANTMORPH_PLUGIN OUTPUT MAIN_EXAMPLES
if [ -n "${DISPLAY:-}" ]; then
  bash -c "$EXAMPLES"
else
  python3 "$PLANTMORPH_ROOT/testing/python/virtual_display.py" -- bash -c "$EXAMPLES"
fi
echo "run: results written to $OUTPUT"
echo "run: pictures"
ls -1 "$OUTPUT"/*.png
echo "run: data (.vtp), state files (.pvsm) and tables"
ls -1 "$OUTPUT" | grep -v '\.png$' || true
