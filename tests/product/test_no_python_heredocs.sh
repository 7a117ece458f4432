#!/usr/bin/env bash
# Python lives in Python files: no tracked shell script under bench/, scripts/, tools/ or .ci/
# feeds Python to an interpreter through a heredoc (python3 - <<'PY' ... PY). Benchmark drivers
# are modules under bench/; a shell script may only call them.
# Usage: test_no_python_heredocs.sh [SOURCE_DIR]. Exit 0 clean, 1 found, 77 skipped (not a git
# checkout).
set -euo pipefail
root=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}

# Prints file:line of every heredoc whose body has a Python statement (import, from-import, def,
# class, print(...)); the heredoc may start on a continuation line of the command.
scan() {
  awk '
    function report() { if (!found) { print FILENAME ":" start; found = 1 } }
    FNR == 1 { delim = "" }
    delim != "" {
      line = $0
      if (strip) sub(/^\t+/, "", line)
      if (line == delim) { delim = ""; next }
      if ($0 ~ /^[ \t]*(import [A-Za-z_]|from [A-Za-z_.]+ import |def [A-Za-z_]+\(|class [A-Za-z_]+[(:]|print\()/) report()
      next
    }
    match($0, /<<-?[ \t]*["\047]?[A-Za-z_][A-Za-z0-9_]*["\047]?/) {
      tag = substr($0, RSTART, RLENGTH)
      strip = (tag ~ /^<<-/)
      gsub(/^<<-?[ \t]*/, "", tag); gsub(/["\047]/, "", tag)
      delim = tag; start = FNR; found = 0
    }
  ' "$@"
}

# The scan must catch what it is meant to catch (otherwise this test could never fail).
sample=$(mktemp)
trap 'rm -f "$sample"' EXIT
printf '%s\n' '#!/bin/bash' '"$python" - "$1" \' '  "$2" <<'"'"'PY'"'" 'import json, sys' 'print(1)' 'PY' \
  'cat <<EOF' 'plain text' 'EOF' >"$sample"
if [[ $(scan "$sample") != "$sample:3" ]]; then
  echo "FAIL: the scan does not find the Python heredoc of its sample (or finds the text one)" >&2
  exit 1
fi

if ! command -v git >/dev/null || ! git -C "$root" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  echo "SKIP: $root is not a git checkout, so its tracked files cannot be listed"
  exit 77
fi

files=()
while IFS= read -r f; do
  # Shell scripts: *.sh, or a shebang naming a shell (tools and CI entry points without suffix).
  if [[ $f == *.sh || $f == *.sbatch ]] || head -n1 "$root/$f" | grep -qE '^#!.*\b(ba|z|da)?sh\b'; then
    files+=("$root/$f")
  fi
done < <(git -C "$root" ls-files bench scripts tools .ci)

if [[ ${#files[@]} -gt 0 ]] && hits=$(scan "${files[@]}") && [[ -n $hits ]]; then
  echo "FAIL: Python in a heredoc (make it a module under bench/ or python/ and call it):" >&2
  echo "${hits//$root\//}" >&2
  exit 1
fi
echo "ok: ${#files[@]} shell scripts under bench/ scripts/ tools/ .ci/, no Python heredocs"
