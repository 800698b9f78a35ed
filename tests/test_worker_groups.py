"""Every test carries the xdist group its worker is chosen by (``--dist loadgroup``)."""

from __future__ import annotations

import pytest
from conftest import AUDIO_MODULES, BOOK_MODULES, worker_group


def test_a_module_is_one_group(request: pytest.FixtureRequest) -> None:
    groups = [mark.args for mark in request.node.iter_markers("xdist_group")]
    assert groups == [("test_worker_groups.py",)]


def test_the_book_and_the_audio_modules_each_share_one_group() -> None:
    assert {worker_group(f"tests/{m}::test_x") for m in BOOK_MODULES} == {"book"}
    assert {worker_group(f"tests/{m}::test_x[a]") for m in AUDIO_MODULES} == {"audio"}
    assert worker_group("tests/test_errors.py::test_x") == "test_errors.py"
