"""Every test carries the xdist group its worker is chosen by (``--dist loadgroup``)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import AUDIO_MODULES, BOOK_MODULES, worker_group


def test_a_module_is_one_group(request: pytest.FixtureRequest) -> None:
    groups = [mark.args for mark in request.node.iter_markers("xdist_group")]
    assert groups == [("test_worker_groups.py",)]


def test_the_book_and_the_audio_modules_each_share_one_group() -> None:
    assert {worker_group(f"tests/{m}::test_x") for m in BOOK_MODULES} == {"book"}
    assert {worker_group(f"tests/{m}::test_x[a]") for m in AUDIO_MODULES} == {"audio"}
    assert worker_group("tests/test_errors.py::test_x") == "test_errors.py"


def test_every_module_that_reads_the_built_book_is_in_the_book_group() -> None:
    """A module elsewhere would wait, in the other worker, for the whole build."""
    here = Path(__file__).resolve().parent
    readers = {
        path.name
        for path in here.glob("test_*.py")
        if re.search(r"\bbuilt_book\s*[:,)]", path.read_text(encoding="utf-8"))  # a parameter
    }
    assert readers and readers <= set(BOOK_MODULES), readers - set(BOOK_MODULES)
