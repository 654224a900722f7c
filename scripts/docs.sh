#!/usr/bin/env bash
# Build the API documentation with FORD from the sources' doc comments into docs/api/ (not
# tracked): `!>` before an entity, `!!` continuation lines, `!<` after an entity on its line.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
[ -x .venv/bin/python ] || python3 -m venv .venv
[ -x .venv/bin/ford ] || .venv/bin/pip install -q ford
# the type components of the namelist groups are generated include files (as in the build)
python3 scripts/generate_namelists.py --fortran build/generated/config
.venv/bin/ford ford.md "$@"
echo "API documentation: $root/docs/api/index.html"
