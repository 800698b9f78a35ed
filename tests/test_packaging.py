"""Contracts of the package as installed: the light core, the extras, the oldest numpy/scipy.

- The core (errors, evidence, filters, gauge, studies) installs alone, with the oldest numpy
  and scipy that ``pyproject.toml`` allows, and its tests pass there (a fresh virtual
  environment, pip from the package index: slow-ish, and it runs in CI).
- A layer used without its extra raises :class:`~dstoolkit.errors.MissingExtraError` naming
  the extra to install.
- ``import dstoolkit`` imports none of the optional dependencies.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import textwrap
import tomllib
import venv
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
OPTIONAL = ("matplotlib", "ipywidgets", "IPython", "tqdm", "sounddevice", "numba")

#: The tests of the core layers. Tests in them that need an extra carry the ``extras``
#: marker and are left out of the core-only run (they run in the full environment).
CORE_TESTS = (
    "test_evidence_basics.py",
    "test_evidence_properties.py",
    "test_exact_masses.py",
    "test_extension.py",
    "test_paper_golden.py",
    "test_read_only.py",
    "test_dependent_filter.py",
    "test_rival_filters.py",
    "test_example_systems.py",
    "test_acoustics.py",
    "test_level.py",
    "test_latency.py",
    "test_noise_characterisation.py",
    "test_tube_and_detection.py",
    "test_doctests.py",
)


def _floor(requirements: list[str], name: str) -> str:
    """Return the lower bound of ``name>=X`` in a dependency list."""
    for req in requirements:
        if req.replace(" ", "").startswith(f"{name}>="):
            return req.split(">=")[1].split(",")[0].strip()
    raise AssertionError(f"{name} has no lower bound in {requirements}")


def _run(cmd: list[str], cwd: Path, timeout: float) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    proc = subprocess.run(
        cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout, check=False
    )
    assert proc.returncode == 0, f"{' '.join(cmd)} failed:\n{proc.stdout}\n{proc.stderr}"
    return proc


def test_declared_floors_are_the_ones_tested() -> None:
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    assert sorted(d.split(">=")[0] for d in deps) == ["numpy", "scipy"]
    assert _floor(deps, "numpy") == "2.0"  # np.bitwise_count (finite frames) is numpy 2.0
    assert _floor(deps, "scipy") == "1.13"


@pytest.mark.slow
def test_core_alone_on_the_oldest_numpy_and_scipy(tmp_path: Path) -> None:
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    numpy_floor, scipy_floor = _floor(deps, "numpy"), _floor(deps, "scipy")
    # a copy of the source, so that the build leaves nothing in the checkout
    src = tmp_path / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(ROOT / name, src / name)
    shutil.copytree(
        ROOT / "dstoolkit", src / "dstoolkit", ignore=shutil.ignore_patterns("__pycache__")
    )
    env_dir = tmp_path / "core-env"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    py = str(env_dir / "bin" / "python")
    # the exact floors (X.Y.0), installed together with the package: pip refuses them if
    # pyproject.toml asked for more
    _run(
        [
            py,
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
            str(src),
            f"numpy=={numpy_floor}.0",
            f"scipy=={scipy_floor}.0",
            "pytest",
            "hypothesis",
        ],
        tmp_path,
        timeout=1200,
    )
    probe = _run(
        [
            py,
            "-c",
            textwrap.dedent("""
        import importlib.util, pathlib, numpy, scipy, dstoolkit
        assert (pathlib.Path(dstoolkit.__file__).parent / "py.typed").is_file()  # PEP 561
        print(numpy.__version__, scipy.__version__, dstoolkit.__version__, dstoolkit.__file__)
        print(*[m for m in ('matplotlib', 'ipywidgets', 'IPython', 'tqdm', 'sounddevice',
                            'numba')
                if importlib.util.find_spec(m)])
    """),
        ],
        tmp_path,
        timeout=120,
    ).stdout.splitlines()
    versions = probe[0].split()
    assert versions[:2] == [f"{numpy_floor}.0", f"{scipy_floor}.0"]
    assert versions[2] != "0+unknown" and str(env_dir) in versions[3]  # the installed copy
    assert probe[1:] == [""] or probe[1:] == [], f"optional packages installed: {probe[1:]}"

    # the core's tests, from a folder without the source (so the installed copy is tested)
    run = tmp_path / "run"
    (run / "tests").mkdir(parents=True)
    shutil.copy(ROOT / "pyproject.toml", run / "pyproject.toml")  # markers and options
    for name in CORE_TESTS:
        shutil.copy(ROOT / "tests" / name, run / "tests" / name)
    report = tmp_path / "core.xml"
    proc = subprocess.run(
        [
            py,
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "--noconftest",
            "-m",
            "not extras",
            f"--junitxml={report}",
            "tests",
        ],
        cwd=run,
        capture_output=True,
        text=True,
        timeout=2400,
        check=False,
    )
    assert proc.returncode == 0, proc.stdout[-6000:] + proc.stderr[-2000:]
    suite = ET.parse(report).getroot().find("testsuite")
    assert suite is not None
    counts = {k: int(suite.get(k, "0")) for k in ("tests", "failures", "errors", "skipped")}
    assert counts["failures"] == counts["errors"] == counts["skipped"] == 0, counts
    assert counts["tests"] >= 150, counts

    # the console script works without extras; only the figure is left out, with the reason
    out = tmp_path / "t3" / "table3.csv"
    t3 = _run(
        [
            str(env_dir / "bin" / "dstoolkit"),
            "table3",
            "--runs",
            "1",
            "--methods",
            "direct",
            "--quiet",
            "--out",
            str(out),
        ],
        tmp_path,
        timeout=600,
    )
    assert out.stat().st_size > 0 and not out.with_suffix(".png").exists()
    assert "no figure" in t3.stdout and "dstoolkit[plots]" in t3.stdout


BLOCKER = textwrap.dedent("""
    import importlib.abc, sys

    class Missing(importlib.abc.MetaPathFinder):
        '''Acts as if these top-level packages were not installed.'''
        def __init__(self, names):
            self.names = set(names)
        def find_spec(self, name, path=None, target=None):
            if name.partition('.')[0] in self.names:
                raise ModuleNotFoundError(f"No module named {name!r}", name=name)
            return None

    sys.meta_path.insert(0, Missing(sys.argv[1].split(',')))
""")


def _without(missing: str, code: str) -> subprocess.CompletedProcess[str]:
    script = BLOCKER + textwrap.dedent(code)
    return subprocess.run(
        [sys.executable, "-c", script, missing],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
        cwd=ROOT,
    )


@pytest.mark.slow
@pytest.mark.parametrize(
    ("missing", "module", "extra"),
    [
        ("matplotlib", "dstoolkit.plots", "plots"),
        ("ipywidgets", "dstoolkit.teaching", "teaching"),
        ("matplotlib", "dstoolkit.teaching", "teaching"),
    ],
)
def test_a_layer_without_its_extra_names_the_extra(missing: str, module: str, extra: str) -> None:
    proc = _without(
        missing,
        f"""
        import importlib
        from dstoolkit.errors import DstoolkitError, MissingExtraError
        import dstoolkit, dstoolkit.studies  # the core works without the extra
        try:
            importlib.import_module({module!r})
        except MissingExtraError as exc:
            assert isinstance(exc, ImportError) and isinstance(exc, DstoolkitError)
            print(exc)
        else:
            raise SystemExit("no MissingExtraError")
    """,
    )
    assert proc.returncode == 0, proc.stderr
    assert f"pip install 'dstoolkit[{extra}]'" in proc.stdout
    assert repr(missing) in proc.stdout  # it says which package is missing


@pytest.mark.slow
def test_audio_without_sounddevice_still_imports() -> None:
    proc = _without(
        "sounddevice",
        """
        from dstoolkit.audio import audio_available
        assert audio_available() is False
    """,
    )
    assert proc.returncode == 0, proc.stderr


@pytest.mark.slow
def test_import_dstoolkit_imports_no_optional_dependency() -> None:
    code = textwrap.dedent(f"""
        import sys
        import dstoolkit, dstoolkit.evidence, dstoolkit.filters, dstoolkit.gauge
        import dstoolkit.studies, dstoolkit.errors
        print(*[m for m in {OPTIONAL!r} if m in sys.modules])
    """)
    proc = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
        cwd=ROOT,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "", f"import dstoolkit imported {proc.stdout.strip()}"
