"""The examples in the docstrings of the teaching layer's exercise side run as shown.

They cover the checks, the graded tests, the time limit and the variants, and give what
they show.
"""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = (
    "_checking",
    "_coding",
    "_handin",
    "_sandbox",
    "_limits",
    "_variants",
    "_ex_evidence",
    "_ex_gauge",
    "_ex_filter",
    "_ex_coding",
)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name: str) -> None:
    module = importlib.import_module(f"dstoolkit.teaching.{name}")
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS, report=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed"
