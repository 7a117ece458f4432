#!/usr/bin/env bash
# The repository stands alone: no tracked file may read, include or cite material that lives
# outside it (a team directory beside the repository, or the team's design, style and reference
# notes; the names are spelled out in the pattern below).
# Usage: test_standalone.sh [SOURCE_DIR]. Exit 0 clean, 1 found, 77 skipped (not a git checkout).
set -euo pipefail
root=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}

# The pattern is assembled from pieces so that this file does not match it.
dots='\.\.'
names=("${dots}/shared" "/work""/shared" "DESIGN" "STYLE" "REFERENCES")
pattern="${names[0]}|${names[1]}|(${names[2]}|${names[3]}|${names[4]})\\.md|KANESENS_SHARED""_DIR"

# The pattern must catch what it is meant to catch (otherwise this test could never fail).
for sample in "see ../""shared/reference/x.csv" "DESIGN"".md §4" "STYLE"".md" "REFERENCES"".md §1" \
              "KANESENS_SHARED""_DIR" "/work/""shared/x"; do
  if ! grep -qE "$pattern" <<<"$sample"; then
    echo "FAIL: the pattern does not match '$sample'" >&2
    exit 1
  fi
done

if ! command -v git >/dev/null || ! git -C "$root" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  echo "SKIP: $root is not a git checkout, so its tracked files cannot be listed"
  exit 77
fi

if hits=$(git -C "$root" grep -n -I -E "$pattern"); then
  echo "FAIL: tracked files refer to material outside the repository (cite docs/ or the literature):" >&2
  echo "$hits" >&2
  exit 1
fi
echo "ok: no tracked file of $(git -C "$root" ls-files | wc -l) refers to material outside the repository"
