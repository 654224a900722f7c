#!/usr/bin/env bash
# Lint the Fortran sources with fortitude (rules in fortitude.toml); installs it into .venv.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
[ -x .venv/bin/python ] || python3 -m venv .venv
[ -x .venv/bin/fortitude ] || .venv/bin/pip install -q fortitude-lint
[ -x .venv/bin/fypp ] || .venv/bin/pip install -q fypp
# the Fortran templates (modules/**/*.fypp) are checked in their expansion, as the build makes it
generated=build/generated/fypp
mkdir -p "$generated"
find modules -name '*.fypp' | while read -r template; do
  .venv/bin/fypp --line-length=132 "$template" "$generated/$(basename "${template%.fypp}").f90"
done
.venv/bin/fortitude check modules src tools bench "$generated" "$@"
