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
# and the modules written as Fortran templates are documented in their expansion (ford.md src_dir)
[ -x .venv/bin/fypp ] || .venv/bin/pip install -q fypp
mkdir -p build/generated/fypp
find modules -name '*.fypp' | while read -r template; do
  .venv/bin/fypp --line-length=132 "$template" "build/generated/fypp/$(basename "${template%.fypp}").f90"
done
.venv/bin/ford ford.md "$@"
echo "API documentation: $root/docs/api/index.html"
