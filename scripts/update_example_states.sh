#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Regenerates the shipped state files examples/states/<name>.pvsm: runs the main job (every examples/main_*.py,
# rendered, so each state keeps its figure's cameras) into a scratch folder and copies the .pvsm files it saved.
# Run after changing an example; the ctest python.example_state.* tests fail while a state file is stale. Names of
# examples as arguments (e.g. main_measured_leaf.py) regenerate only their states; the others stay as they are.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCRATCH="$(mktemp -d)"
trap 'rm -rf "$SCRATCH"' EXIT
bash "$ROOT/scripts/run.sh" "$SCRATCH" "$@"
mkdir -p "$ROOT/examples/states"
cp "$SCRATCH"/*.pvsm "$ROOT/examples/states/"
ls -l "$ROOT/examples/states"
