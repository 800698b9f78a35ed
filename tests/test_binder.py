"""The launch (Binder) button's environment.

binder/requirements.txt installs dstoolkit with the extras the sheets and explorers use,
and binder/postBuild compiles the optional kernels once, when the image is built, into
numba's cache on disk.
"""

from __future__ import annotations

import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_binder_installs_the_teaching_and_speed_extras() -> None:
    lines = [
        line.strip()
        for line in (ROOT / "binder" / "requirements.txt").read_text(encoding="utf-8").splitlines()
        if line.strip() and not line.startswith("#")
    ]
    assert lines == [".[teaching,speed]"]


@pytest.mark.slow
@pytest.mark.extras  # numba, the extra "speed"
def test_post_build_compiles_every_kernel_into_the_cache(tmp_path: Path) -> None:
    script = ROOT / "binder" / "postBuild"
    assert script.stat().st_mode & stat.S_IXUSR, "postBuild must be executable"
    # the script's python is this one (Binder's is the image's)
    path = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "PATH": path}
    proc = subprocess.run(
        [str(script)], cwd=ROOT, env=env, capture_output=True, text=True, timeout=600, check=False
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "compiled kernels ready" in proc.stdout
    cached = {path.name.split("-")[0] for path in tmp_path.rglob("*.nbi")}
    for kernel in (
        "_compiled._fuse",
        "_compiled._merge",
        "_compiled._cluster",
        "_compiled._contract",
        "_compiled._search",
    ):
        assert kernel in cached, (kernel, sorted(cached))
