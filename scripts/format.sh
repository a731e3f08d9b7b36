#!/usr/bin/env bash
# Formats every C++ source of the repository with the committed .clang-format
# (--check: report files that would change and exit 1, changing nothing).
set -euo pipefail
cd "$(dirname "$0")/.."
mode=(-i)
[ "${1:-}" = "--check" ] && mode=(--dry-run -Werror)
git ls-files '*.cpp' '*.h' | xargs clang-format "${mode[@]}"
