"""Shared pytest fixtures and helpers.

Keep this file to fixtures that more than one test module needs, grouped by topic.
"""

from __future__ import annotations

import fcntl
import functools
import json
import os
import re
import subprocess
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import nbformat
import pytest
import yaml
from nbclient import NotebookClient

ROOT = Path(__file__).resolve().parents[1]
# kernels started by the tests (chapters, teacher's sheets) import the checkout's answer_key/
os.environ["PYTHONPATH"] = os.pathsep.join(
    [str(ROOT), *(p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p)]
)
ARTIFACTS = ROOT / "test-artifacts"

# --------------------------------------------------------------------------------------
# Two workers (pytest-xdist, `-n 2 --dist loadscope` in scripts/test.sh)
# --------------------------------------------------------------------------------------

#: Modules that read the built book (or build it, or its PDF, in the same _build folder):
#: one worker runs them all, in this order, so the book is built once and nothing rewrites
#: _build while a browser reads it. They go first, so the build starts at once while the
#: other worker runs everything else.
BOOK_MODULES = (
    "test_book_build.py",
    "test_lab_handout.py",
    "test_book_a11y.py",
    "test_book_browser.py",
    "test_book_slides.py",
    "test_book_layout.py",
    "test_explorers_browser.py",
    "test_chapter_notebooks.py",
    "test_printed_numbers.py",
    "test_jupyterlab.py",
    "test_book_pdf.py",
    "test_exam_site.py",
    "test_book_siteperf.py",
    "test_book_api_page.py",
    # the post-build's purge runs PurgeCSS from node_modules, which the build's `npm ci`
    # (re)creates: run after the build, in its worker
    "test_site_postbuild.py",
)
#: Modules that start PulseAudio loopbacks: one worker runs them, one after the other.
AUDIO_MODULES = ("test_audio_loopback.py", "test_audio_faults.py")


def _module(nodeid: str) -> str:
    return nodeid.split("::", 1)[0].rsplit("/", 1)[-1]


def worker_group(nodeid: str) -> str | None:
    """Return the group of tests that must run in one worker ("book", "audio"), or None."""
    module = _module(nodeid)
    if module in BOOK_MODULES:
        return "book"
    if module in AUDIO_MODULES:
        return "audio"
    return None


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Under xdist, put the book's modules first (in BOOK_MODULES order).

    Its worker then starts the build at once; alone, keep the usual order (quick tests
    first).
    """
    if getattr(config.option, "numprocesses", None):
        rank = {name: i for i, name in enumerate(BOOK_MODULES)}
        items.sort(key=lambda item: rank.get(_module(item.nodeid), len(rank)))


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config: pytest.Config, log: object) -> object:
    """Schedule whole modules per worker (their module fixtures run once).

    The groups of :func:`worker_group` are each kept in one worker. xdist's ``--dist
    loadgroup`` with ``xdist_group`` marks would say this through public API, but it does
    not group under pytest ≥ 9.2: xdist 3.8's worker appends the group to the test id by
    assigning ``item._nodeid``, which pytest 9.2 no longer reads (the id is now the
    structured ``Node._id``), so every test keeps its plain id and is handed out alone.
    Four modules marked ``pytestmark = pytest.mark.xdist_group("g")``, four tests each,
    run with ``-n 2 --dist loadgroup``: no id ends in ``@g`` and each module's tests run in
    both workers. Upstream: https://github.com/pytest-dev/pytest-xdist/issues/1386 (fix
    proposed in pull request 1388). Until a released xdist groups again, this hook
    overrides the scope split of xdist's own ``LoadScopeScheduling``.
    """
    from xdist.scheduler import LoadScopeScheduling

    class _Groups(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return worker_group(nodeid) or super()._split_scope(nodeid)

    return _Groups(config, log)


# --------------------------------------------------------------------------------------
# The book: built once per session with the same command a user runs
# --------------------------------------------------------------------------------------

BUILD_SCRIPT = ROOT / "scripts" / "build-book.sh"
#: Line printed by scripts/build-book.sh just before it runs jupyter-book.
JUPYTER_BOOK_MARKER = "==> jupyter-book build"
_ANSI = re.compile(r"\x1b\[[0-9;]*m")


@dataclass(frozen=True)
class BookBuild:
    """Result of one run of scripts/build-book.sh."""

    returncode: int
    log: str  # stdout and stderr of the script, colour codes removed
    html_dir: Path

    @property
    def jupyter_book_log(self) -> str:
        """The part of the log written by `jupyter-book build` (empty if it never ran)."""
        _, found, rest = self.log.partition(JUPYTER_BOOK_MARKER)
        return rest if found else ""

    def tail(self, lines: int = 60) -> str:
        """Return the last lines of the log, for assertion messages."""
        return "\n".join(self.log.splitlines()[-lines:])


def toc_pages(toc_file: Path = ROOT / "_toc.yml") -> list[str]:
    """Every page of the book's table of contents, root first, as paths without suffix.

    Walks the jb-book format: ``root`` plus every ``file`` entry under ``parts``,
    ``chapters`` and ``sections``, at any depth.
    """
    toc = yaml.safe_load(toc_file.read_text(encoding="utf-8"))
    pages = [toc["root"]]

    def walk(node: object) -> None:
        if isinstance(node, dict):
            if "file" in node:
                pages.append(node["file"])
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for item in node:
                walk(item)

    walk({key: value for key, value in toc.items() if key != "root"})
    suffixes = {".md", ".ipynb", ".rst"}
    return [page.rsplit(".", 1)[0] if Path(page).suffix in suffixes else page for page in pages]


def _build_book() -> BookBuild:
    """Run ``bash scripts/build-book.sh``; save its log to test-artifacts/book-build.log."""
    result = subprocess.run(
        ["bash", str(BUILD_SCRIPT)],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        timeout=3600,
        env=os.environ.copy(),
    )
    log = _ANSI.sub("", result.stdout)
    ARTIFACTS.mkdir(exist_ok=True)
    (ARTIFACTS / "book-build.log").write_text(log, encoding="utf-8")
    return BookBuild(result.returncode, log, ROOT / "_build" / "html")


@pytest.fixture(scope="session")
def built_book() -> BookBuild:
    """Build the book in place (``bash scripts/build-book.sh``) once per test session.

    The log is also saved to test-artifacts/book-build.log. Under pytest-xdist the build
    runs once per test run, whichever worker asks first: the others wait on a file lock
    and read its result (scripts/test.sh keeps the book's modules in one worker anyway).
    """
    run = os.environ.get("PYTEST_XDIST_TESTRUNUID")
    if run is None:
        return _build_book()
    build_dir = ROOT / "_build"
    build_dir.mkdir(exist_ok=True)
    shared = build_dir / f".book-build-{run}.json"
    with open(build_dir / ".book-build-session.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
        if shared.is_file():
            done = json.loads(shared.read_text(encoding="utf-8"))
            return BookBuild(done["returncode"], done["log"], build_dir / "html")
        for old in build_dir.glob(".book-build-*.json"):  # results of earlier runs
            old.unlink()
        result = _build_book()
        shared.write_text(
            json.dumps({"returncode": result.returncode, "log": result.log}), encoding="utf-8"
        )
        return result


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    """Parametrize any test that asks for ``toc_page`` with every page of _toc.yml."""
    if "toc_page" in metafunc.fixturenames:
        pages = toc_pages()
        metafunc.parametrize("toc_page", pages, ids=pages)


class _QuietHandler(SimpleHTTPRequestHandler):
    def log_message(self, fmt: str, *args: object) -> None:
        pass


@contextmanager
def served(directory: Path) -> Iterator[str]:
    """Serve ``directory`` by an http.server thread on 127.0.0.1 while the block runs.

    Yield its base URL.
    """
    handler = functools.partial(_QuietHandler, directory=str(directory))
    server = ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()


# --------------------------------------------------------------------------------------
# Notebooks and chapters executed in a fresh kernel (nothing is written back to disk)
# --------------------------------------------------------------------------------------

#: A guard against a hanging cell, not a speed requirement.
CELL_TIMEOUT = 300


def execute_notebook(nb: nbformat.NotebookNode, cwd: Path) -> nbformat.NotebookNode:
    """Execute ``nb`` in place in a python3 kernel started in ``cwd``."""
    NotebookClient(
        nb, timeout=CELL_TIMEOUT, kernel_name="python3", resources={"metadata": {"path": str(cwd)}}
    ).execute()
    return nb


def glued(nb: nbformat.NotebookNode) -> dict[str, object]:
    """Every value a notebook glued (myst_nb.glue): floats where they parse, else text."""
    out: dict[str, object] = {}
    for cell in nb.cells:
        for o in cell.get("outputs", []):
            name = o.get("metadata", {}).get("scrapbook", {}).get("name")
            if name:
                text = o["data"]["application/papermill.record/text/plain"]
                try:
                    out[name] = float(text)
                except ValueError:
                    out[name] = text.strip("'\"")
    return out


_CHAPTERS: dict[str, nbformat.NotebookNode] = {}


def executed_chapter(name: str) -> nbformat.NotebookNode:
    """book/<name>.md executed once per test session (shared by the tests that read it)."""
    if name not in _CHAPTERS:
        import jupytext

        _CHAPTERS[name] = execute_notebook(
            jupytext.read(ROOT / "book" / f"{name}.md"), ROOT / "book"
        )
    return _CHAPTERS[name]


# --------------------------------------------------------------------------------------
# Explorers driven through a kernel: build, print their state, change a control, print again
# --------------------------------------------------------------------------------------

_EXPLORER_SETUP = """
import hashlib, io, json
from dstoolkit import studies
from dstoolkit import teaching as w

def state(ex):
    buf = io.BytesIO()
    ex.figure.savefig(buf, format="png")
    return json.dumps({"numbers": {k: str(v) for k, v in ex.numbers.items()},
                       "figure": hashlib.sha1(buf.getvalue()).hexdigest()})
"""


@dataclass(frozen=True)
class ExplorerRun:
    """A kernel run of :func:`drive_explorers`.

    It holds the executed notebook and the tagged lines it printed (``"BEFORE i"``,
    ``"AFTER i"`` and the tags of the extra cells).
    """

    notebook: nbformat.NotebookNode
    printed: dict[str, str]

    @property
    def outputs_with_png(self) -> int:
        """How many Output widgets hold a PNG in the stored widget state."""
        return sum("image/png" in mimes for mimes in output_widget_mimes(self.notebook))


def drive_explorers(
    changes: dict[str, tuple[str, object]], extra_cells: tuple[str, ...] = ()
) -> ExplorerRun:
    """Drive each explorer call ``w.<call>`` (key i of ``changes``) in a kernel.

    Display it and print its state, then set ``controls[name].value`` and print the state
    again; then run the ``extra_cells`` (which see the explorers as ``ex0, ex1, …``).
    Widget state is stored in the notebook's metadata, as in the built book.
    """
    cells = [nbformat.v4.new_code_cell(_EXPLORER_SETUP)]
    for i, call in enumerate(changes):
        cells.append(
            nbformat.v4.new_code_cell(f"ex{i} = w.{call}\nprint('BEFORE {i}', state(ex{i}))\nex{i}")
        )
    for i, (control, value) in enumerate(changes.values()):
        cells.append(
            nbformat.v4.new_code_cell(
                f"ex{i}.controls[{control!r}].value = {value!r}\nprint('AFTER {i}', state(ex{i}))"
            )
        )
    cells += [nbformat.v4.new_code_cell(source) for source in extra_cells]
    nb = nbformat.v4.new_notebook(cells=cells)
    nb.metadata["kernelspec"] = {
        "name": "python3",
        "display_name": "Python 3",
        "language": "python",
    }
    NotebookClient(
        nb, timeout=CELL_TIMEOUT, kernel_name="python3", store_widget_state=True
    ).execute()
    printed: dict[str, str] = {}
    for cell in nb.cells:
        # A long line may reach the notebook in several stream messages: join them first.
        text = "".join(
            out["text"]
            for out in cell.get("outputs", [])
            if out.get("output_type") == "stream" and out.get("name") == "stdout"
        )
        for line in text.splitlines():
            tag, _, rest = line.partition(" ")
            if tag in {"BEFORE", "AFTER"}:
                index, _, payload = rest.partition(" ")
                printed[f"{tag} {index}"] = payload
            elif tag.isupper():
                printed[tag] = rest
    return ExplorerRun(nb, printed)


def printed_json(cells: list[str]) -> tuple[list[dict], nbformat.NotebookNode]:
    """Execute ``cells`` in a fresh kernel started at the repository root (widget state stored).

    Return the JSON each cell printed last on stdout (None for a cell that printed nothing),
    and the notebook.
    """
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in cells])
    NotebookClient(
        nb,
        timeout=CELL_TIMEOUT,
        kernel_name="python3",
        store_widget_state=True,
        resources={"metadata": {"path": str(ROOT)}},
    ).execute()
    out = []
    for cell in nb.cells:
        text = "".join(
            o.get("text", "")
            for o in cell.outputs
            if o.output_type == "stream" and o.name == "stdout"
        ).strip()
        out.append(json.loads(text.splitlines()[-1]) if text else None)
    return out, nb


def output_widget_mimes(nb: nbformat.NotebookNode) -> list[list[str]]:
    """List the MIME types each Output widget in the stored widget state shows.

    The stored widget state is what the book embeds.
    """
    state = nb.metadata["widgets"]["application/vnd.jupyter.widget-state+json"]["state"]
    return [
        [mime for o in model["state"].get("outputs", []) for mime in o.get("data", {})]
        for model in state.values()
        if model["model_name"] == "OutputModel"
    ]


# --------------------------------------------------------------------------------------
# Headless Chromium (Debian's /usr/bin/chromium driven by Playwright; no `playwright install`)
# --------------------------------------------------------------------------------------

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
REQUIRE_BROWSER = os.environ.get("DSTOOLKIT_REQUIRE_BROWSER") == "1"


def browser_unavailable(reason: str) -> None:
    """Skip, or fail when the environment says a browser is required."""
    if REQUIRE_BROWSER:
        pytest.fail(f"{reason} (DSTOOLKIT_REQUIRE_BROWSER=1: the browser test must run)")
    pytest.skip(reason)


@pytest.fixture(scope="session")
def chromium() -> Iterator[object]:
    """Launch a headless Debian Chromium driven by Playwright, once for the session.

    Every page visit of the session uses it (each test opens its own context or page in
    it).
    """
    if not (CHROMIUM.is_file() and os.access(CHROMIUM, os.X_OK)):
        browser_unavailable(f"{CHROMIUM} not found: apt-get install chromium")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        browser_unavailable("Playwright for Python is not installed: pip install -e '.[test]'")
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=str(CHROMIUM), args=CHROMIUM_ARGS, headless=True
        )
        yield browser
        browser.close()
