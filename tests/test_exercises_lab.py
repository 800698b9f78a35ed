"""Exercises of the lab (ids "lab.*"), its sheet notebooks/NN_lab.ipynb, and the chapter.

Every solution is accepted, every listed mistake is rejected with its own hint, a plainly
wrong answer gets the generic hint, and the solutions agree with numbers worked by hand.
The sheet is stored without outputs, says "not answered yet" as shipped and "right" with
the solutions filled in, shows the measuring station, and plays no sound (MEASURE is
False). The chapter executes, and the claims its prose makes hold for the numbers it glues.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import nbformat
import numpy as np
import pytest
from conftest import execute_notebook, executed_chapter, glued

from answer_key import solution
from dstoolkit.teaching import (
    LAB_BAND,
    LAB_CUTOFF_DIAMETER,
    LAB_LAG_SAMPLES,
    LAB_SAMPLERATE,
    LAB_TOLERANCE_CASE,
    LAB_UNCERTAINTIES_MM,
    REGISTRY,
    exercises,
)

ROOT = Path(__file__).resolve().parents[1]
SHEET = next((ROOT / "notebooks").glob("*_lab.ipynb"))
LAB_IDS = [
    "lab.cutoff",
    "lab.latency-offset",
    "lab.shortest-tube",
    "lab.thermometer-tolerance",
    "lab.uncertainty",
]
CHECK = re.compile(r'check\("(lab\.[a-z0-9-]+)"')


def test_the_lab_exercises_are_registered() -> None:
    assert exercises("lab.") == LAB_IDS


def test_every_lab_exercise_lists_a_common_mistake() -> None:
    assert all(REGISTRY[e].mistakes for e in LAB_IDS)


def test_solutions_agree_with_hand_computation() -> None:
    c20 = 331.3 + 0.606 * 20.0  # the paper's law
    tau_ms, offset = solution("lab.latency-offset")
    assert tau_ms == pytest.approx(1e3 * 6042 / 44100, rel=1e-12)
    assert offset == pytest.approx(280.0 * 6042 / 44100, rel=1e-12)
    assert solution("lab.shortest-tube") == pytest.approx(c20 / (2 * 1400 / 5), rel=1e-12)
    assert solution("lab.cutoff") == pytest.approx(1.8412 * c20 / (math.pi * 0.040), rel=1e-12)
    assert solution("lab.thermometer-tolerance") == pytest.approx(
        0.005 * c20 / (0.606 * 3.0), rel=1e-9
    )
    assert solution("lab.uncertainty") == pytest.approx(math.sqrt(0.4**2 + 1.5**2 + 2.2**2))


# -- the sheet ------------------------------------------------------------------------------


def _execute(nb: nbformat.NotebookNode) -> nbformat.NotebookNode:
    return execute_notebook(nb, SHEET.parent)


def _check_messages(nb: nbformat.NotebookNode) -> dict[str, str]:
    out = {}
    for cell in nb.cells:
        ids = CHECK.findall(cell.source) if cell.cell_type == "code" else []
        if ids:
            (eid,) = ids
            out[eid] = "".join(str(o.get("data", {}).get("text/plain", "")) for o in cell.outputs)
    return out


def test_the_sheet_states_the_exercises_data() -> None:
    """The sheet's prose gives the numbers the solvers use."""
    text = " ".join(" ".join(c.source for c in nbformat.read(SHEET, as_version=4).cells).split())
    assert f"{LAB_LAG_SAMPLES} samples" in text and f"{LAB_SAMPLERATE} samples" in text
    assert f"{LAB_BAND[0]:.0f} → {LAB_BAND[1]:.0f} Hz" in text
    assert f"{1e3 * LAB_CUTOFF_DIAMETER:.0f} mm" in text
    level, tolerance = LAB_TOLERANCE_CASE
    assert f"{level:g} m level" in text and f"{1e3 * tolerance:g} mm" in text
    fit, offsets, temperature = LAB_UNCERTAINTIES_MM
    assert f"fit {fit} mm, offsets {offsets} mm, temperature {temperature} mm" in text


@pytest.mark.slow
def test_the_sheet_runs_as_stored_and_plays_nothing() -> None:
    nb = _execute(nbformat.read(SHEET, as_version=4))
    messages = _check_messages(nb)
    assert all("not answered yet" in m for m in messages.values()), messages
    station = [c for c in nb.cells if "lab_widget(" in c.source]
    assert station and any(
        "application/vnd.jupyter.widget-view+json" in o.get("data", {}) for o in station[0].outputs
    )
    printed = "".join(o.get("text", "") for c in nb.cells for o in c.get("outputs", []))
    assert "MEASURE is False: nothing played" in printed
    assert "level L = 3.2" in printed  # the virtual 3.2 m recording, analysed


# -- the chapter ------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def chapter() -> nbformat.NotebookNode:
    return executed_chapter("lab")


def _printed(nb: nbformat.NotebookNode) -> str:
    return "".join(
        o.get("text", "")
        for c in nb.cells
        for o in c.get("outputs", [])
        if o.get("output_type") == "stream"
    )


@pytest.mark.slow
def test_the_chapter_prose_matches_its_numbers(chapter: nbformat.NotebookNode) -> None:
    g = glued(chapter)
    # "the paper's sweep suits levels from about 0.61 m"; 0.5 m is too short for it
    assert 0.5 < g["lab_shortest"] < 0.7 and g["lab_ff05"] > 280
    assert g["lab_cutoff75"] < 2800 < 4000 < g["lab_cutoff40"]
    # "kτ ... more than half the spacing of a 2.5 m tube"
    assert g["lab_ktau"] > 0.5 * g["lab_c_room"] / (2 * 2.5)
    assert g["lab_lag_off"] == 0  # the chirp is found exactly where the simulation put it
    # without the latency: the series fit unharmed, its offset term and the filters are not
    assert abs(g["lab_unc_fit_err_mm"]) < 1 and g["lab_unc_offset_mm"] > 5 * g["lab_good_offset_mm"]
    assert g["lab_unc_de_err_mm"] > 20
    # the level ± uncertainty: the parts add in quadrature, the truth is inside 2σ
    parts = np.array([g["lab_u_fit_mm"], g["lab_u_off_mm"], g["lab_u_temp_mm"]])
    assert g["lab_u_mm"] == pytest.approx(float(np.sqrt(np.sum(parts**2))))
    assert abs(g["lab_err_mm"]) < 2 * g["lab_u_mm"]
    assert g["lab_max_filter_err_mm"] < 10  # "off by up to a few mm"
    # missed resonances reported, the level still good
    assert g["lab_missed"] >= 1 and abs(g["lab_missed_err_mm"]) < 3
    # the thermometer 2 °C high: the formula explains the excess error within 1 mm
    assert abs(g["lab_warm_excess_mm"] - g["lab_dl_25_2"]) < 1
    assert g["lab_dl_96"] == pytest.approx(g["lab_dl_25"] * 9.6 / 2.5)
    # room noise: spurious peaks at −20 dBFS, error within a few mm
    assert g["lab_noise_spurious"] > 0 and g["lab_noise_worst_mm"] < 10
    assert g["lab_ex_4mm_dt"] == pytest.approx(4.0 / g["lab_dl_25"])


@pytest.mark.slow
def test_the_chapter_prints_every_message_it_promises(chapter: nbformat.NotebookNode) -> None:
    printed = _printed(chapter)
    for message in (
        "importing sounddevice failed",
        "no input device for the default",
        "silence:",
        "clipping:",
        "the recording is too short for the sweep",
        "no tube echo",
        "resonance(s) missed",
        "too few resonances",
        "figure saved to rec.png",
        "--virtual-level",
    ):
        assert message in printed, message
    assert "Traceback" not in printed
