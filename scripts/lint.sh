#!/usr/bin/env bash
# Lint the Fortran sources with fortitude (rules in fortitude.toml); installs it into .venv.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
[ -x .venv/bin/python ] || python3 -m venv .venv
[ -x .venv/bin/fortitude ] || .venv/bin/pip install -q fortitude-lint
.venv/bin/fortitude check modules src tools bench "$@"
