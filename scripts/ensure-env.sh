#!/usr/bin/env bash
# Create (once) the project's virtual environment in .venv and install dstoolkit with every
# extra into it. Re-installs only when pyproject.toml changed. Sourced by the other scripts.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$root/.venv"
# DSTOOLKIT_VENV names an environment that is already set up (e.g. the main checkout's, used
# from a second git worktree): it is used as it is, and nothing is installed into it.
if [ -n "${DSTOOLKIT_VENV:-}" ]; then
  [ -x "$DSTOOLKIT_VENV/bin/python" ] || { echo "ensure-env.sh: DSTOOLKIT_VENV=$DSTOOLKIT_VENV has no bin/python" >&2; exit 2; }
  export PATH="$DSTOOLKIT_VENV/bin:$PATH"
  return 0 2>/dev/null || exit 0
fi
py="${PYTHON:-python3}"
if [ ! -x "$venv/bin/python" ]; then
  echo "==> creating $venv"
  "$py" -m venv "$venv"
  "$venv/bin/python" -m pip install --quiet --upgrade pip
fi
stamp="$venv/.dstoolkit-installed"
want="$(sha256sum "$root/pyproject.toml" | cut -d' ' -f1)"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ]; then
  echo "==> installing dstoolkit[book,test,audio,lab,speed,teach] into $venv"
  "$venv/bin/python" -m pip install --quiet -e "$root[book,test,audio,lab,speed,teach]"
  "$venv/bin/python" -m ipykernel install --sys-prefix --name python3 >/dev/null
  echo "$want" > "$stamp"
fi
export PATH="$venv/bin:$PATH"
