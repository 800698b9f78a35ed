"""The repository address lives in one place, and no button is dead.

A tiny book (one chapter with an exercise, its solution, a labelled equation and an exercise
sheet; the page *Run this book*) is built twice with the book's own _config.yml, once with
``repository.url`` set and once empty (its one code cell runs). With the address the
chapter page has the repository button and a Binder launch button that opens the sheet, and
*Run this book* shows the address; without it neither button exists. Both builds offer the
chapter as a clean notebook and the sheet.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from conftest import ROOT

pytestmark = pytest.mark.slow

ADDRESS = "https://github.com/example-org/dstoolkit"
CHAPTER = """---
jupytext:
  text_representation:
    format_name: myst
file_format: mystnb
kernelspec:
  display_name: Python 3
  language: python
  name: python3
---

# Tiny chapter

$$
x = 1
$$ (tiny-eq)

```{code-cell} ipython3
print("tiny")
```

```{exercise}
:label: tiny-ex

Use {eq}`tiny-eq`.
```

````{solution} tiny-ex
:class: dropdown

The secret answer of the tiny chapter.
````
"""
TOC = {
    "format": "jb-book",
    "root": "book/intro",
    "parts": [
        {"caption": "Chapters", "numbered": True, "chapters": [{"file": "book/tiny"}]},
        {"caption": "Back matter", "chapters": [{"file": "book/run"}]},
    ],
}


def _build(folder: Path, address: str) -> Path:
    """Build the tiny book in ``folder`` with ``repository.url = address``; its HTML dir."""
    config = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    config["repository"]["url"] = address
    # One print: with launch buttons the theme needs the executed notebook.
    config["execute"]["execute_notebooks"] = "force"
    config["sphinx"]["local_extensions"] = {
        name: str(ROOT / path) for name, path in config["sphinx"]["local_extensions"].items()
    }
    (folder / "_config.yml").write_text(yaml.safe_dump(config), encoding="utf-8")
    (folder / "_toc.yml").write_text(yaml.safe_dump(TOC), encoding="utf-8")
    shutil.copytree(ROOT / "book" / "_static", folder / "book" / "_static")
    for name in ("references.bib", "run.md"):
        shutil.copyfile(ROOT / "book" / name, folder / "book" / name)
    (folder / "book" / "intro.md").write_text("# Tiny book\n\nSee {doc}`run`.\n")
    (folder / "book" / "tiny.md").write_text(CHAPTER, encoding="utf-8")
    (folder / "notebooks").mkdir()
    sheet = {"cells": [], "metadata": {}, "nbformat": 4, "nbformat_minor": 5}
    (folder / "notebooks" / "01_tiny.ipynb").write_text(json.dumps(sheet))
    (folder / "_build" / "_vendor").mkdir(parents=True)
    jupyter_book = Path(sys.executable).parent / "jupyter-book"
    result = subprocess.run(
        [str(jupyter_book), "build", str(folder), "-W", "-n", "--keep-going"],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return folder / "_build" / "html"


@pytest.fixture(scope="module")
def with_address(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _build(tmp_path_factory.mktemp("with-address"), ADDRESS)


@pytest.fixture(scope="module")
def without_address(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _build(tmp_path_factory.mktemp("without-address"), "")


def _header(page: str) -> str:
    """Return the header of a page: where the buttons are."""
    start = page.index('class="article-header-buttons"')
    return page[start : page.index("<article", start)]


def _text(page: str) -> str:
    """Return the text of an HTML page, tags removed."""
    return re.sub(r"<[^>]+>", "", page)


def test_address_shows_repository_and_launch_buttons(with_address: Path) -> None:
    header = _header((with_address / "book" / "tiny.html").read_text(encoding="utf-8"))
    assert re.search(
        rf'href="{ADDRESS}"[^>]*class="btn btn-sm btn-source-repository-button', header, re.DOTALL
    ), "no repository button"
    binder = "https://mybinder.org/v2/gh/example-org/dstoolkit/main?urlpath=lab/tree/"
    assert f'href="{binder}notebooks/01_tiny.ipynb"' in header, "no Binder button to the sheet"
    run = _text((with_address / "book" / "run.html").read_text(encoding="utf-8"))
    assert f"git clone {ADDRESS}" in run


def test_no_address_no_dead_button(without_address: Path) -> None:
    for name in ("tiny", "intro", "run"):
        header = _header((without_address / "book" / f"{name}.html").read_text("utf-8"))
        assert "repository-button" not in header and "launch-buttons" not in header
        assert "mybinder" not in header and "github.com" not in header
        assert not re.search(r'href="(#?)"', header), f"a button of {name} links nowhere"
    run = (without_address / "book" / "run.html").read_text(encoding="utf-8")
    assert "published without a repository address" in run


@pytest.mark.parametrize("build", ["with_address", "without_address"])
def test_tiny_chapter_is_offered_clean(build: str, request: pytest.FixtureRequest) -> None:
    html = request.getfixturevalue(build)
    page = (html / "book" / "tiny.html").read_text(encoding="utf-8")
    for name in ("chapter_01_tiny.ipynb", "01_tiny.ipynb"):
        assert f'href="../notebooks/{name}"' in page and (html / "notebooks" / name).is_file()
    text = (html / "notebooks" / "chapter_01_tiny.ipynb").read_text(encoding="utf-8")
    assert "Exercise 1.1" in text and "Use (1.1)." in text and "\\\\tag{1.1}" in text
    assert "secret answer" not in text and "{solution}" not in text
    # The theme's own download of the executed chapter (with launch buttons on) is replaced.
    for copy in (html / "_sources").rglob("*.ipynb"):
        assert "secret answer" not in copy.read_text(encoding="utf-8"), copy
