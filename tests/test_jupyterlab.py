"""JupyterLab itself, in headless Chromium: the book's notebooks run as a reader runs them.

``jupyter lab`` is started headless on 127.0.0.1 (an ephemeral port, a token, a temporary
folder holding one generated chapter notebook from the built site and the chapter's exercise
sheet). For each notebook the test opens it, runs all cells from the menu, saves it and
checks that no cell raised; then it moves the explorer's slider with the keyboard and checks
that the figure changes; and it checks that no solution of the chapter is on the page while
its exercises are, and that no raw MyST shows. Screenshots before and after moving the
slider go to test-artifacts/jupyterlab/.

Needs /usr/bin/chromium (see conftest.chromium): skips without it, except when
DSTOOLKIT_REQUIRE_BROWSER=1 (CI), where it fails.
"""

from __future__ import annotations

import json
import os
import re
import secrets
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest
from conftest import ARTIFACTS, ROOT, BookBuild
from test_chapter_notebooks import RAW_MYST, directive_phrases

pytestmark = [pytest.mark.browser, pytest.mark.slow]

#: The chapter whose notebook and exercise sheet are run: both hold its explorer.
CHAPTER = "mass_functions"
SHOTS = ARTIFACTS / "jupyterlab"
STARTUP_S = 180
RUN_ALL_S = 600
FIGURE_S = 60


def _free_port() -> int:
    """Return an ephemeral port on 127.0.0.1 that is free now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _lab_settings(folder: Path) -> None:
    """User settings: every cell in the page (no windowing), no news fetched."""
    settings = {
        "@jupyterlab/notebook-extension/tracker.jupyterlab-settings": {"windowingMode": "none"},
        "@jupyterlab/apputils-extension/notification.jupyterlab-settings": {
            "fetchNews": "false",
            "checkForUpdates": False,
        },
    }
    for name, value in settings.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(value), encoding="utf-8")


@pytest.fixture(scope="module")
def lab_folder(tmp_path_factory: pytest.TempPathFactory, built_book: BookBuild) -> Path:
    """Make a folder with the built chapter notebook and the chapter's exercise sheet."""
    folder = tmp_path_factory.mktemp("lab")
    chapter = sorted((built_book.html_dir / "notebooks").glob(f"chapter_*_{CHAPTER}.ipynb"))
    sheet = sorted((ROOT / "notebooks").glob(f"*_{CHAPTER}.ipynb"))
    assert chapter, f"the built book has no notebooks/chapter_*_{CHAPTER}.ipynb"
    assert sheet, f"no exercise sheet notebooks/*_{CHAPTER}.ipynb"
    for path in (chapter[0], sheet[0]):
        shutil.copyfile(path, folder / path.name)
    return folder


@pytest.fixture(scope="module")
def jupyterlab(
    lab_folder: Path, tmp_path_factory: pytest.TempPathFactory, chromium: object
) -> Iterator[str]:
    """``jupyter lab`` on 127.0.0.1 serving ``lab_folder``; yields its URL with the token."""
    home = tmp_path_factory.mktemp("lab-home")
    _lab_settings(home / "settings")
    env = {
        **os.environ,
        "JUPYTER_CONFIG_DIR": str(home / "config"),
        "JUPYTER_RUNTIME_DIR": str(home / "runtime"),
        "JUPYTERLAB_SETTINGS_DIR": str(home / "settings"),
        "JUPYTERLAB_WORKSPACES_DIR": str(home / "workspaces"),
        "JUPYTER_PLATFORM_DIRS": "1",
    }
    port, token = _free_port(), secrets.token_hex(16)
    SHOTS.mkdir(parents=True, exist_ok=True)
    log = (SHOTS / "jupyterlab.log").open("w", encoding="utf-8")
    server = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "jupyterlab",
            "--no-browser",
            "--ServerApp.ip=127.0.0.1",
            f"--ServerApp.port={port}",
            "--ServerApp.port_retries=0",
            f"--IdentityProvider.token={token}",
            f"--ServerApp.root_dir={lab_folder}",
            "--allow-root",
            "--LabApp.news_url=None",
            "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate",
        ],
        cwd=lab_folder,
        env=env,
        stdout=log,
        stderr=subprocess.STDOUT,
    )
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + STARTUP_S
        while True:
            assert server.poll() is None, f"jupyter lab exited; see {SHOTS / 'jupyterlab.log'}"
            try:
                with urllib.request.urlopen(f"{url}/api/status?token={token}", timeout=5):
                    break
            except OSError:
                assert time.monotonic() < deadline, f"jupyter lab not up after {STARTUP_S} s"
                time.sleep(1)
        yield f"{url}/lab/tree/{{name}}?reset&token={token}"
    finally:
        server.terminate()
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
        log.close()


def _run_all(page, path: Path) -> dict:
    """Run every cell from the Run menu; save until the file shows every code cell run.

    Returns the saved notebook. Fails at once on an error output (Run All stops there).
    """
    page.get_by_role("menuitem", name="Run", exact=True).click()
    page.get_by_role("menuitem", name="Run All Cells", exact=True).click()
    deadline = time.monotonic() + RUN_ALL_S
    while True:
        page.wait_for_timeout(3000)
        page.keyboard.press("Control+s")
        page.wait_for_timeout(1000)
        nb = json.loads(path.read_text(encoding="utf-8"))
        code = [cell for cell in nb["cells"] if cell["cell_type"] == "code"]
        errors = [
            f"{o['ename']}: {o['evalue']}"
            for cell in code
            for o in cell.get("outputs", [])
            if o["output_type"] == "error"
        ]
        assert not errors, f"{path.name} raised when run: {errors}"
        if all(cell["execution_count"] for cell in code):
            return nb
        assert time.monotonic() < deadline, f"{path.name} did not finish in {RUN_ALL_S} s"


def _figures(cell) -> list[str]:
    """Return the images an explorer's cell shows (their data URLs)."""
    return cell.locator("img").evaluate_all("imgs => imgs.map(i => i.src)")


@pytest.mark.parametrize("kind", ["chapter", "sheet"])
def test_notebook_runs_in_jupyterlab(
    chromium: object, jupyterlab: str, lab_folder: Path, kind: str
) -> None:
    pattern = f"chapter_*_{CHAPTER}.ipynb" if kind == "chapter" else f"[0-9]*_{CHAPTER}.ipynb"
    path = next(lab_folder.glob(pattern))
    source = (ROOT / "book" / f"{CHAPTER}.md").read_text(encoding="utf-8")
    context = chromium.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()
    try:
        page.goto(jupyterlab.format(name=path.name), timeout=STARTUP_S * 1000)
        page.locator(".jp-Notebook .jp-Cell").first.wait_for(timeout=STARTUP_S * 1000)
        # The kernel has started when the status bar names it and says it is idle.
        page.get_by_text(re.compile(r"\(ipykernel\) \| Idle")).first.wait_for(
            timeout=STARTUP_S * 1000
        )
        _run_all(page, path)

        notebook = page.locator(".jp-NotebookPanel:not(.lm-mod-hidden) .jp-Notebook")
        text = " ".join(notebook.text_content().split())
        raw = RAW_MYST.findall(notebook.text_content())
        assert not raw, f"raw MyST in {path.name}: {raw[:5]}"
        shown = [p for p in directive_phrases(source, "solution") if " ".join(p.split()) in text]
        assert not shown, f"{path.name} shows solutions: {shown[:3]}"
        if kind == "chapter":
            exercises = directive_phrases(source, "exercise")
            assert exercises and all(" ".join(p.split()) in text for p in exercises), (
                "the chapter notebook lost the text of an exercise"
            )
            assert "Exercise" in text

        cell = notebook.locator(".jp-CodeCell", has=page.locator(".jp-OutputArea [role='slider']"))
        slider = cell.first.locator("[role='slider']").first
        cell = cell.first
        slider.scroll_into_view_if_needed()
        before = _figures(cell)
        assert before, "the explorer shows no figure"
        page.screenshot(path=str(SHOTS / f"{kind}-before.png"))
        value = slider.get_attribute("aria-valuenow")
        slider.focus()
        page.keyboard.press("ArrowRight")
        page.wait_for_function(
            "([cell, before]) => [...cell.querySelectorAll('img')].map(i => i.src).join()"
            " !== before.join()",
            arg=[cell.element_handle(), before],
            polling=500,
            timeout=FIGURE_S * 1000,
        )
        assert slider.get_attribute("aria-valuenow") != value
        page.screenshot(path=str(SHOTS / f"{kind}-after.png"))
        page.set_viewport_size({"width": 768, "height": 900})
        page.screenshot(path=str(SHOTS / f"{kind}-after-768.png"))
    except Exception:
        page.screenshot(path=str(SHOTS / f"{kind}-failed.png"))
        raise
    finally:
        context.close()
