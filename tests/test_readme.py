"""The README's Python examples run as written, and the filter example prints what it says.

The public step loop ends on the estimate that ``run`` gives, and a batch is (runs, T, n).
"""

from __future__ import annotations

import contextlib
import io
import re
import sys
import types
from collections.abc import Iterator
from pathlib import Path

import pytest

from dstoolkit.filters import register_filter, registered_filters, unregister_filter

README = Path(__file__).resolve().parents[1] / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)


@contextlib.contextmanager
def _registered() -> Iterator[None]:
    """Unregister afterwards the filters an example registered (the registry is global)."""
    before = {entry.name for entry in registered_filters()}
    try:
        yield
    finally:
        for entry in registered_filters():
            if entry.name not in before:
                unregister_filter(entry.name)


def _run(code: str) -> str:
    out = io.StringIO()
    module = types.ModuleType("__readme__")  # a module, as a user's script is (dataclasses)
    sys.modules[module.__name__] = module
    with _registered(), contextlib.redirect_stdout(out):
        exec(compile(code, str(README), "exec", dont_inherit=True), module.__dict__)
    return out.getvalue()


def test_the_readme_has_its_examples() -> None:
    assert len(BLOCKS) >= 2
    assert any("flt.step(" in block for block in BLOCKS)


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_readme_example_runs(index: int) -> None:
    assert _run(BLOCKS[index]).strip()


def test_a_filter_of_initialize_and_step_runs_and_batches() -> None:
    """The README's alpha–beta filter: at most 40 lines, one run and a batch of two."""
    block = next(b for b in BLOCKS if "class AlphaBetaFilter" in b)
    assert len(block.strip().splitlines()) <= 40
    assert "_engine" not in block
    run, shape = _run(block).strip().splitlines()
    assert shape == "(2, 4, 1)"
    assert run == "[1.    1.1   1.01  1.054]"  # x̂ = x_pred + 0.5 r on 1.0, 1.2, 0.9, 1.1
    assert "alpha_beta" not in {e.name for e in registered_filters()}  # unregistered again


def test_the_registered_filter_joins_the_comparison() -> None:
    """Registered, the README's filter runs in the studies' comparisons and has its style."""
    from dstoolkit.plots import OKABE_ITO, STYLE
    from dstoolkit.studies import all_filters, example_comparison

    block = next(b for b in BLOCKS if "class AlphaBetaFilter" in b)
    with _registered():
        _run(block.replace("register_filter(", "KEEP = (", 1))  # the classes, unregistered
        module = sys.modules["__readme__"]
        register_filter(module.KEEP)
        assert list(all_filters())[-1] == "alpha_beta"
        assert STYLE["alpha_beta"] == {
            "color": OKABE_ITO["black"],  # an Okabe–Ito name becomes its colour
            "ls": (0, (1, 1)),
            "marker": "x",
            "label": "alpha–beta",
        }
        result = example_comparison(steps=8, runs=2, methods=None)
        assert result.estimates["alpha_beta"].shape == (2, 8, 2)
        assert set(result.estimates) == {e.name for e in registered_filters()}
    assert "alpha_beta" not in STYLE


def test_the_step_loop_ends_where_run_ends() -> None:
    block = next(b for b in BLOCKS if "flt.step(" in b)
    lines = _run(block).strip().splitlines()
    assert lines[-1] == "(2, 4, 1)"
    for line in lines[:-1]:
        name, stepped, ran = re.fullmatch(r"(\w+) \[(\S+)\] (\S+)", line).groups()
        assert name in {"dependent_evidence", "kalman"}
        assert float(stepped) == pytest.approx(float(ran.strip("[]")), abs=1e-12)
