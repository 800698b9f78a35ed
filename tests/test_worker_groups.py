"""The groups of tests that run in one worker (tests/conftest.py's scheduler)."""

from __future__ import annotations

import re
from pathlib import Path

from conftest import AUDIO_MODULES, BOOK_MODULES, worker_group


def test_the_book_and_the_audio_modules_each_share_one_group() -> None:
    assert {worker_group(f"tests/{m}::test_x") for m in BOOK_MODULES} == {"book"}
    assert {worker_group(f"tests/{m}::test_x[a]") for m in AUDIO_MODULES} == {"audio"}
    assert worker_group("tests/test_errors.py::test_x") is None  # its module: xdist's scope


def test_every_module_that_reads_the_built_book_is_in_the_book_group() -> None:
    """A module elsewhere would wait, in the other worker, for the whole build."""
    here = Path(__file__).resolve().parent
    readers = {
        path.name
        for path in here.glob("test_*.py")
        if re.search(r"\bbuilt_book\s*[:,)]", path.read_text(encoding="utf-8"))  # a parameter
    }
    assert readers and readers <= set(BOOK_MODULES), readers - set(BOOK_MODULES)
