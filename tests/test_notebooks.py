"""Every classroom notebook (notebooks/*.ipynb) is stored without outputs, keeps its cells
short, and executes in a fresh kernel: each check cell says "not answered yet" for the
shipped answer and "right" for the solution computed by dstoolkit, and the explorers
display their widgets. Nothing is written back to disk."""

from __future__ import annotations

import re

import nbformat
import pytest
from conftest import ROOT, execute_notebook

SHEETS = sorted(p.stem for p in (ROOT / "notebooks").glob("*.ipynb"))
CHECK = re.compile(r'^check\("([^"]+)",\s*(\w+)\)\s*$', re.MULTILINE)
WIDGET = "application/vnd.jupyter.widget-view+json"


def _sheet(name: str) -> nbformat.NotebookNode:
    return nbformat.read(ROOT / "notebooks" / f"{name}.ipynb", as_version=4)


def test_every_chapter_has_a_sheet():
    assert len(SHEETS) >= 11, SHEETS


@pytest.mark.parametrize("name", SHEETS)
def test_sheet_is_stored_without_outputs_and_short_cells(name: str):
    nb = _sheet(name)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code, "a notebook without code cells"
    for cell in code:
        assert cell.outputs == [] and cell.execution_count is None, cell.source[:60]
        assert len(cell.source.splitlines()) <= 15, cell.source[:60]
    assert nb.metadata["kernelspec"]["name"] == "python3"


@pytest.mark.slow
@pytest.mark.parametrize("name", SHEETS)
def test_sheet_runs_and_its_check_cells_give_feedback(name: str):
    """One execution per sheet: each check line first checks the shipped answer (``...``:
    "not answered yet"), then the solution ("right")."""
    nb = _sheet(name)
    checked = []
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        for eid, var in CHECK.findall(cell.source):
            checked.append(eid)
            cell.source = cell.source.replace(
                f'check("{eid}", {var})',
                "from dstoolkit.teaching import solution\n"
                f"print('SHIPPED', check({eid!r}, {var}).message)\n"
                f"{var} = solution({eid!r})\nprint(check({eid!r}, {var}).message)")
    assert checked, "no check cell found"
    execute_notebook(nb, ROOT / "notebooks")
    shown = "".join(o.get("text", "") for c in nb.cells if c.cell_type == "code"
                    for o in c.outputs)
    for eid in checked:
        assert f"{eid}: not answered yet" in shown, eid
        assert f"✔ {eid}: right" in shown, eid
    widgets = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs
               if WIDGET in o.get("data", {})]
    assert widgets, "the sheet's explorer displayed no widget"
