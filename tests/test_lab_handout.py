"""The printable lab handout: a PDF built with the book, with four parts and the package's numbers.

* Its numbers (tube diameter, sweep band and rate, chirp, speed of sound, cutoff, shortest
  usable level) come from ``dstoolkit``, and a changed number reaches the page.
* After the book's build, ``_build/handout/lab-handout.pdf`` exists, its text
  (``pdftotext``) holds the parts list, the wiring, the data sheet and the report rubric,
  and the lab and teaching pages link it.
* Without LaTeX the build says what to install.

Needs XeLaTeX, latexmk and poppler-utils for the built PDF; without them those tests
skip, except when DSTOOLKIT_REQUIRE_PDF=1 (CI), where they fail.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT, BookBuild

from answer_key import solution
from dstoolkit.gauge import PAPER_SWEEP, TubeSetup, plane_wave_cutoff, resonance_orders

sys.path.insert(0, str(ROOT / "scripts"))
import lab_handout  # noqa: E402

PARTS = ("Parts list", "Wiring", "Data sheet", "Report rubric")
PDF = ROOT / "_build" / "handout" / "lab-handout.pdf"
REQUIRE_PDF = os.environ.get("DSTOOLKIT_REQUIRE_PDF") == "1"


def test_the_numbers_come_from_the_package() -> None:
    n = lab_handout.handout_numbers()
    assert n["diameter_mm"] == pytest.approx(TubeSetup(level_m=1.0).diameter_m * 1000)
    assert (n["f_lo"], n["f_hi"]) == tuple(PAPER_SWEEP.band)
    assert n["rate"] == pytest.approx(PAPER_SWEEP.rate)
    assert n["cutoff"] == pytest.approx(plane_wave_cutoff(n["diameter_mm"] / 1000, n["c"]))
    band = tuple(PAPER_SWEEP.band)
    # from the shortest level up, every level (to the millimetre, up to 12 m) holds enough
    longer = np.arange(round(n["shortest"] * 1000), 12001) / 1000
    assert min(resonance_orders(level, n["c"], band).size for level in longer) >= n["need"]
    # and it is the level of the lab chapter's exercise, rounded up to the millimetre
    assert n["shortest"] == math.ceil(1000 * solution("lab.shortest-tube")) / 1000
    # 0.5 m is in the table with too few resonances, as in the lab chapter
    assert [count for level, _, count in n["rows"] if level == 0.5][0] < n["need"]


def test_groups_are_of_four_with_the_chapters_roles() -> None:
    tex = lab_handout.handout_tex(lab_handout.handout_numbers())
    assert "groups of four" in tex and "groups of three" not in tex
    lab = (ROOT / "book" / "lab.md").read_text(encoding="utf-8")
    assert "A gauge serves a group of four" in lab
    roles = re.findall(r"^- \*\*([a-z ]+)\*\*", lab, flags=re.M)
    assert len(roles) == 4, roles
    for role in roles:
        assert role in tex, role


def test_the_source_has_the_four_parts_and_the_numbers() -> None:
    n = lab_handout.handout_numbers()
    tex = lab_handout.handout_tex(n)
    for part in PARTS:
        assert re.search(rf"\\section\*\{{\d\. {part}\}}", tex), part
    assert "tikzpicture" in tex
    for shown in (
        f"{n['diameter_mm']:.0f} mm",
        f"{n['f_lo']:.0f}--{n['f_hi']:.0f} Hz",
        f"{n['cutoff']:.0f} Hz",
        f"{n['shortest']:.3f} m",
    ):
        assert shown in tex, shown
    changed = lab_handout.handout_tex({**n, "cutoff": 1234.0})
    assert "1234 Hz" in changed and "1234 Hz" not in tex


def test_without_latex_the_build_says_what_to_install(tmp_path, monkeypatch) -> None:
    monkeypatch.setattr(lab_handout.shutil, "which", lambda tool: None)
    with pytest.raises(RuntimeError, match="latexmk and xelatex.*apt-get install"):
        lab_handout.build(tmp_path)


@pytest.fixture(scope="module")
def handout_text(built_book: BookBuild) -> str:
    missing = [t for t in ("xelatex", "latexmk", "pdftotext") if shutil.which(t) is None]
    if missing:
        reason = f"the lab handout needs {missing}"
        if REQUIRE_PDF:
            pytest.fail(reason + " (DSTOOLKIT_REQUIRE_PDF=1)")
        pytest.skip(reason)
    assert built_book.returncode == 0, built_book.tail()
    assert PDF.exists(), f"no {PDF} after the book's build"
    return subprocess.run(
        ["pdftotext", "-layout", str(PDF), "-"], check=True, capture_output=True, text=True
    ).stdout


@pytest.mark.slow
def test_the_built_handout_holds_its_four_parts(handout_text: str) -> None:
    for part in PARTS:
        assert part in handout_text, part
    n = lab_handout.handout_numbers()
    assert f"{n['f_lo']:.0f} Hz to {n['f_hi']:.0f} Hz" in handout_text
    assert "criterion" in handout_text and "points" in handout_text


@pytest.mark.slow
@pytest.mark.parametrize("page", ["lab", "teaching"])
def test_the_pages_link_the_handout(handout_text: str, built_book: BookBuild, page: str) -> None:
    html = (built_book.html_dir / "book" / f"{page}.html").read_text(encoding="utf-8")
    links = re.findall(r'href="(\.\./_downloads/[^"]+/lab-handout\.pdf)"', html)
    assert links, f"{page}.html does not link the handout"
    assert (built_book.html_dir / "book" / links[0]).resolve().exists()
