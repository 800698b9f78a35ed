"""The exercise sheets of the evidence chapters (notebooks/00–04) and the chapters
themselves (book/*.md) execute in a fresh kernel; the sheets are stored without outputs,
their check cells say "not answered yet" as shipped and "right" with the solutions filled
in. Nothing is written back to disk."""

from __future__ import annotations

import re
from pathlib import Path

import jupytext
import nbformat
import pytest
from nbclient import NotebookClient

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
SHEETS = ["00_why_bounded_noise", "01_mass_functions", "02_combining_evidence",
          "03_dependent_evidence", "04_noise_to_evidence"]
CHAPTERS = ["why_bounded_noise", "mass_functions", "combining_evidence",
            "dependent_evidence", "noise_to_evidence"]
#: A guard against a hanging cell, not a speed requirement.
CELL_TIMEOUT = 120
CHECK = re.compile(r'check\("([^"]+)",\s*(\w+)\)')


def _execute(nb: nbformat.NotebookNode, cwd: Path) -> nbformat.NotebookNode:
    NotebookClient(nb, timeout=CELL_TIMEOUT, kernel_name="python3",
                   resources={"metadata": {"path": str(cwd)}}).execute()
    return nb


def _sheet(name: str) -> nbformat.NotebookNode:
    return nbformat.read(ROOT / "notebooks" / f"{name}.ipynb", as_version=4)


def _check_outputs(nb: nbformat.NotebookNode) -> dict[str, str]:
    """Exercise id → everything its check cell showed (printed and displayed)."""
    shown = {}
    for cell in nb.cells:
        match = CHECK.search(cell.source) if cell.cell_type == "code" else None
        if match:
            texts = [o.get("text", "") + o.get("data", {}).get("text/plain", "")
                     for o in cell.outputs]
            shown[match.group(1)] = "".join(texts)
    return shown


@pytest.mark.parametrize("name", SHEETS)
def test_sheet_is_stored_without_outputs(name: str):
    nb = _sheet(name)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code, "an exercise sheet without code cells"
    for cell in code:
        assert cell.outputs == [] and cell.execution_count is None, cell.source[:60]
    assert nb.metadata["kernelspec"]["name"] == "python3"


@pytest.mark.parametrize("name", SHEETS)
def test_sheet_runs_and_its_check_cells_give_feedback(name: str):
    """One execution per sheet: each check cell first checks the shipped answer (``...``:
    "not answered yet"), then the solution computed by dstoolkit ("right")."""
    nb = _sheet(name)
    for cell in nb.cells:
        match = CHECK.search(cell.source) if cell.cell_type == "code" else None
        if match:
            exercise_id, variable = match.groups()
            cell.source = (
                "from dstoolkit.exercises import solution\n"
                f"print('SHIPPED', check({exercise_id!r}, {variable}).message)\n"
                f"{variable} = solution({exercise_id!r})\n{cell.source}")
    shown = _check_outputs(_execute(nb, ROOT / "notebooks"))
    assert shown, "no check cell found"
    for exercise_id, text in shown.items():
        assert "SHIPPED" in text and "not answered yet" in text, (exercise_id, text)
        assert f"✔ {exercise_id}: right" in text, (exercise_id, text)


@pytest.mark.parametrize("name", CHAPTERS)
def test_chapter_executes(name: str):
    nb = jupytext.read(ROOT / "book" / f"{name}.md")
    _execute(nb, ROOT / "book")
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs
              if o.output_type == "error"]
    assert not errors
