"""The book's post-build step (book/_ext/dstoolkit_a11y.py) on small pages.

Explorer pictures leave the page for files beside it, the theme's markup is mended, Font
Awesome is cut to the icons the pages use, and a second run changes nothing.
"""

from __future__ import annotations

import base64
import importlib.util
import json
import sys
from pathlib import Path

from conftest import ROOT

EXT = ROOT / "book" / "_ext" / "dstoolkit_a11y.py"
PNG = base64.b64decode(
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg=="
)


def _ext() -> object:
    spec = importlib.util.spec_from_file_location("dstoolkit_a11y", EXT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def _page(tmp_path: Path) -> Path:
    data = base64.b64encode(PNG).decode()
    state = {
        "state": {
            "m1": {
                "model_name": "HTMLModel",
                "state": {
                    "value": f"<img class='dstoolkit-figure' src='data:image/png;base64,{data}' "
                    "alt='Figure for level L (m) = 9.6: estimate (m) 9.6100.'>"
                },
            }
        }
    }
    page = tmp_path / "book" / "chapter.html"
    page.parent.mkdir()
    page.write_text(
        '<html><head></head><body><img alt="A line chart." src="../_images/f.png" />'
        '<i class="fa-solid fa-magnifying-glass"></i><i class="fa-solid fa-sun fa-lg"></i>'
        '<script type="application/vnd.jupyter.widget-state+json">'
        + json.dumps(state)
        + "</script></body></html>",
        encoding="utf-8",
    )
    return page


def test_pictures_leave_the_page(tmp_path: Path) -> None:
    ext = _ext()
    page = _page(tmp_path)
    assert ext.rewrite(page)
    text = page.read_text(encoding="utf-8")
    assert "data:image/png" not in text
    files = list((page.parent / ext.STATES_DIR).glob("*.png"))
    assert len(files) == 1 and files[0].read_bytes() == PNG
    assert f"src='{ext.STATES_DIR}/{files[0].name}'" in text
    assert "alt='Figure for level L (m) = 9.6: estimate (m) 9.6100.'" in text
    assert '<img alt="A line chart." src="../_images/f.png" />' in text  # the rest as it was
    assert "<img class='dstoolkit-figure' src=" in text  # the state's JSON is untouched
    assert not ext.rewrite(page), "a second run must change nothing"


def test_font_awesome_keeps_only_the_icons_the_pages_use(tmp_path: Path) -> None:
    ext = _ext()
    page = _page(tmp_path)
    scripts = tmp_path / "_static" / "scripts"
    scripts.mkdir(parents=True)
    import pydata_sphinx_theme

    bundle = (
        Path(pydata_sphinx_theme.__file__).parent
        / "theme"
        / "pydata_sphinx_theme"
        / "static"
        / "scripts"
        / "fontawesome.js"
    )
    (scripts / "fontawesome.js").write_bytes(bundle.read_bytes())
    assert len(ext.fontawesome_icons(bundle.read_text(encoding="utf-8"))) > 1500
    kept = ext.subset_fontawesome(tmp_path / "_static", [page])
    subset = (scripts / "fontawesome.js").read_text(encoding="utf-8")
    assert kept == 2, subset[:400]
    assert '"solid:sun"' in subset and '"solid:magnifying-glass"' in subset
    assert len(subset) < 10_000
    assert ext.subset_fontawesome(tmp_path / "_static", [page]) == -1  # already a subset
