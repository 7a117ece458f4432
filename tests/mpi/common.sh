# Sourced by the tests of this folder, after their own `set` and checks of the environment:
# Debian's Python unless KANESENS_PYTHON names another, $here (this folder), $configs (the
# repository's configs/) and a scratch folder $work, removed on exit.
: "${KANESENS_PYTHON:=/usr/bin/python3}"
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
configs=$(cd "$here/../../configs" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
