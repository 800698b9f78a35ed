#!/usr/bin/env bash
# Run every check: ruff over the package, tests and scripts, the import-layer contract, mypy on the
# core, then pytest (toolkit, gauge, doctests, packaging, notebooks, book build, and the
# built book in headless Chromium). Creates .venv on first use.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
source scripts/ensure-env.sh
echo "==> ruff"
ruff check dstoolkit tests benchmarks scripts
echo "==> import layers (.importlinter)"
lint-imports --no-cache
echo "==> mypy (the core and the command line; [tool.mypy] in pyproject.toml)"
mypy
echo "==> pytest"
python -m pytest --durations=20 "$@"
