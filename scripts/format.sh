#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Formats the tracked C++ files (.h, .hpp, .cpp, .cxx) with clang-format and the repository's .clang-format.
#   scripts/format.sh           rewrite the files in place
#   scripts/format.sh --check   change nothing; exit 1 and list the differences if a file is not formatted (CI,
#                               ctest repo.format)
# CLANG_FORMAT picks the program (default: clang-format, Debian's clang-format package, version 14).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
CLANG_FORMAT="${CLANG_FORMAT:-clang-format}"
mode=(-i)
if [ "${1:-}" = "--check" ]; then
  mode=(--dry-run -Werror)
elif [ $# -gt 0 ]; then
  echo "usage: $0 [--check]" >&2
  exit 2
fi
command -v "$CLANG_FORMAT" >/dev/null || { echo "format: $CLANG_FORMAT not found (apt-get install clang-format)" >&2; exit 2; }
cd "$ROOT"
git ls-files -z -- '*.h' '*.hpp' '*.cpp' '*.cxx' | xargs -0 -r "$CLANG_FORMAT" --style=file "${mode[@]}"
