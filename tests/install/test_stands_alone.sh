#!/usr/bin/env bash
# The repository stands alone: a user who clones it has nothing beside it, so no tracked file
# may point at a folder outside the checkout (such as a sibling folder with
# reference data, notes and specification). Run from the repository root; in a copy without git every file is read.
set -euo pipefail
pattern='shared[/]'
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  hits=$(git grep -n -I -E "$pattern" || true)
else
  hits=$(grep -rn -I -E "$pattern" . --exclude-dir=build* || true)
fi
if [ -n "$hits" ]; then
  echo "files refer to places outside the repository:" >&2
  echo "$hits" >&2
  exit 1
fi
echo "stands alone: no file refers outside the repository"
