"""Every name of the package that the book and the exercise sheets mention exists.

A dotted name ``dstoolkit.something`` in prose or code, and every name of a
``from dstoolkit... import a, b`` line, must resolve: its longest importable module prefix
imports and the rest is found by attribute look-up. A reader who copies a name from the
book must not get an ImportError.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest
from conftest import ROOT

DOTTED = re.compile(r"\bdstoolkit(?:\.[A-Za-z_]\w*)+")
FROM_IMPORT = re.compile(
    r"^\s*from\s+(dstoolkit(?:\.\w+)*)\s+import\s+(\([^)]*\)|[^\n#]+)", flags=re.M
)


def sources() -> list[Path]:
    return sorted((ROOT / "book").glob("*.md")) + sorted(
        (ROOT / "notebooks" / "source").glob("*.md")
    )


def mentioned_names() -> dict[str, list[str]]:
    """Dotted names → the files and lines that mention them."""
    found: dict[str, list[str]] = {}
    for path in sources():
        text = path.read_text(encoding="utf-8")
        for number, line in enumerate(text.splitlines(), 1):
            where = f"{path.relative_to(ROOT)}:{number}"
            for name in DOTTED.findall(line):
                found.setdefault(name.rstrip("."), []).append(where)
        for match in FROM_IMPORT.finditer(text):
            number = text.count("\n", 0, match.start()) + 1
            where = f"{path.relative_to(ROOT)}:{number}"
            listed = re.sub(r"#[^\n]*", "", match.group(2)).strip("() \n")
            for item in re.split(r"[,\n]", listed):
                item = item.strip().split(" as ")[0].strip()
                if item and item != "*":
                    found.setdefault(f"{match.group(1)}.{item}", []).append(where)
    return found


def resolves(name: str) -> bool:
    parts = name.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ModuleNotFoundError:
            continue
        for attribute in parts[cut:]:
            if not hasattr(obj, attribute):
                return False
            obj = getattr(obj, attribute)
        return True
    return False


NAMES = mentioned_names()


def test_the_book_mentions_package_names() -> None:
    # the scan finds the names it must check (a broken pattern would pass everything)
    assert len(NAMES) > 30
    assert "dstoolkit.teaching.conflict_explorer" in NAMES


@pytest.mark.parametrize("name", sorted(NAMES))
def test_every_package_name_in_the_book_imports(name: str) -> None:
    assert resolves(name), f"{name} does not import; mentioned at {', '.join(NAMES[name])}"


@pytest.mark.parametrize(
    "name", ["dstoolkit.bounded_error_filter", "dstoolkit.evidence.no_such_function"]
)
def test_a_missing_name_is_caught(name: str) -> None:
    assert not resolves(name)
