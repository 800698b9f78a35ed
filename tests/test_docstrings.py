"""Every public callable carries a numpydoc docstring, as scipy's do.

The public callables are the names in each public package's ``__all__`` and, for classes,
their public methods and properties. numpydoc's own validator checks each one:

- GL08: there is a docstring;
- PR01 / PR02: every parameter is documented, and nothing documented that is not one;
- RT01: a callable that returns something has a *Returns* section;
- EX01: every function and class a package exports (not their methods, not plain data
  classes or errors) has an *Examples* section
  (run as doctests by ``tests/test_doctests.py``).

Run ``python tests/test_docstrings.py [package ...]`` to list what is missing.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import re
import sys
import typing
from pathlib import Path

import pytest
from numpydoc.validate import validate

PACKAGES = (
    "dstoolkit.errors",
    "dstoolkit.utils.checks",
    "dstoolkit.utils.budget",
    "dstoolkit.utils.outputs",
    "dstoolkit.utils.signals",
    "dstoolkit.utils.console",
    "dstoolkit.evidence",
    "dstoolkit.filters",
    "dstoolkit.gauge",
    "dstoolkit.studies",
    "dstoolkit.plots",
    "dstoolkit.audio",
    "dstoolkit.teaching",
)
#: Checked on every public callable.
EVERY = ("GL08", "PR01", "PR02", "RT01")
#: Checked on the names a package exports, not on their methods.
EXPORTED = ("EX01",)


def _members(cls: type) -> list[str]:
    names = []
    for attr, value in vars(cls).items():
        if attr.startswith("_"):
            continue
        if inspect.isfunction(value) or isinstance(value, (property, classmethod, staticmethod)):
            names.append(attr)
    return names


def public_callables(package: str) -> list[tuple[str, bool]]:
    """``(qualified name, exported)`` for every public callable of ``package``."""
    module = importlib.import_module(package)
    found: list[tuple[str, bool]] = []
    for name in getattr(module, "__all__", []):
        obj = getattr(module, name)
        # Type aliases (Literal[...] and the like) are callable but not functions: their
        # ``#:`` comment documents them.
        if not callable(obj) or typing.get_origin(obj) is not None:
            continue
        # Plain data (records, states, results) and error classes need no example of their own.
        plain = inspect.isclass(obj) and (
            dataclasses.is_dataclass(obj) or issubclass(obj, BaseException)
        )
        found.append((f"{package}.{name}", not plain))
        if inspect.isclass(obj) and not issubclass(obj, BaseException):
            found += [(f"{package}.{name}.{attr}", False) for attr in _members(obj)]
    return found


def problems(qualname: str, exported: bool) -> list[str]:
    """Return the numpydoc errors of ``qualname`` among the checked codes, as ``CODE message``."""
    codes = EVERY + (EXPORTED if exported else ())
    report = validate(qualname)
    return [f"{code} {message}" for code, message in report["errors"] if code in codes]


ALL = [item for package in PACKAGES for item in public_callables(package)]


def test_the_check_covers_the_api() -> None:
    # Every package exports something, and classes contribute their methods.
    assert len(ALL) > 300
    assert ("dstoolkit.filters.DependentEvidenceFilter.step", False) in ALL


@pytest.mark.parametrize(("qualname", "exported"), ALL, ids=[q for q, _ in ALL])
def test_numpydoc_docstring(qualname: str, exported: bool) -> None:
    found = problems(qualname, exported)
    assert not found, f"{qualname}: " + "; ".join(found)


#: A parameter written ``name`` then ``*type*. description``: numpydoc's form is ``name : type``.
OLD_STYLE = re.compile(r"^( +)[*\w][\w, *]*\n\1    \*[^*\n]+\*\.(?: |$)", re.M)


def test_one_parameter_style_in_every_module() -> None:
    root = Path(__file__).resolve().parents[1] / "dstoolkit"
    old = {
        path.relative_to(root).as_posix()
        for path in root.rglob("*.py")
        if OLD_STYLE.search(path.read_text(encoding="utf-8"))
    }
    assert not old, f"parameters written *type*. in {sorted(old)}"
    assert OLD_STYLE.search("    lo, hi\n        *ndarray*. The ends.\n")  # the scan finds it


if __name__ == "__main__":
    chosen = sys.argv[1:] or list(PACKAGES)
    missing = 0
    for package in chosen:
        for qualname, exported in public_callables(package):
            found = problems(qualname, exported)
            if found:
                missing += 1
                print(f"{qualname}: " + "; ".join(found))
    print(f"{missing} callables with missing parts", file=sys.stderr)
    sys.exit(1 if missing else 0)
