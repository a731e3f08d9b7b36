#!/usr/bin/env bash
# Formats every C++ source of the repository with the committed .clang-format
# (--check: report files that would change and exit 1, changing nothing).
set -euo pipefail
cd "$(dirname "$0")/.."
mode=(-i)
[ "${1:-}" = "--check" ] && mode=(--dry-run -Werror)
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  git ls-files -z '*.cpp' '*.h' | xargs -0 clang-format "${mode[@]}"
else
  find daemon gles_renderer tests shaders_es -name '*.cpp' -o -name '*.h' | xargs clang-format "${mode[@]}"
fi
