#!/usr/bin/env bash
# Run every check: ruff (lint and format) over the package, tests and scripts, the
# import-layer contract, mypy over every layer, then pytest (toolkit, gauge, doctests, packaging, notebooks, book build, and the
# built book in headless Chromium). Creates .venv on first use.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
source scripts/ensure-env.sh
echo "==> ruff"
ruff check dstoolkit tests benchmarks scripts
ruff format --check dstoolkit tests benchmarks scripts
echo "==> import layers (.importlinter)"
lint-imports --no-cache
echo "==> mypy (every layer; [tool.mypy] in pyproject.toml)"
mypy
# Two workers: the book's modules (built once) in one, the rest in the other (whole modules
# per worker; tests/conftest.py groups them). DSTOOLKIT_TEST_WORKERS=0 runs in one process.
workers="${DSTOOLKIT_TEST_WORKERS:-2}"
echo "==> pytest ($workers workers)"
if [ "$workers" = 0 ]; then
  python -m pytest --durations=20 "$@"
else
  python -m pytest -n "$workers" --dist loadscope --no-loadscope-reorder --durations=20 "$@"
fi
