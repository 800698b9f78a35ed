"""The browser's main-thread work to open each page of the built book, from a Chromium trace.

Lighthouse's score moves by ten points or more between runs of the same page (it simulates
a phone from one quick load, and where the first paint of that load lands decides much of
it). This script measures what the score depends on and what the site controls, the main
thread's work, directly: it opens each page in headless Chromium (a phone's viewport,
412 x 823 CSS px, no CPU slowdown, served with gzip as ``benchmarks/lighthouse.py`` serves
it), records a trace until two and a half seconds after the ``load`` event, and prints,
as the median of ``--runs`` loads (milliseconds of the renderer's main thread):

* ``style``: recalculating styles; ``layout``: laying boxes out; ``script``: running the
  page's scripts (including the layouts they force);
* ``long``: the time over 12.5 ms of every task after the first paint, which is what
  Lighthouse's Total Blocking Time counts at its 4x CPU slowdown (50 ms there);
* ``boxes``: the elements of the page that have a layout box once it is loaded.

Build the book first (``bash scripts/build-book.sh``); run from the repository root under
the machine's heavy lock::

    python benchmarks/page_work.py [--html DIR] [--page book/intro ...] [--runs 3]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))
from conftest import toc_pages  # noqa: E402  (the tests' page list)
from lighthouse import serve_gzip  # noqa: E402  (the same server as Lighthouse's runs)

CHROMIUM = os.environ.get("CHROME_PATH", "/usr/bin/chromium")
CATEGORIES = "devtools.timeline,disabled-by-default-devtools.timeline,loading"
#: A task longer than this (1x CPU) blocks at Lighthouse's 4x slowdown (50 ms there).
LONG_TASK_MS = 12.5
_TASKS = ("RunTask", "ThreadControllerImpl::RunTask")
_SCRIPT = ("EvaluateScript", "FunctionCall", "TimerFire", "FireAnimationFrame")
_BOXES_JS = "() => [...document.querySelectorAll('*')].filter(e => e.checkVisibility()).length"


def _trace_load(browser: object, url: str) -> tuple[list[dict], int]:
    """Open ``url`` once with tracing on; return the trace events and the laid-out elements."""
    context = browser.new_context(viewport={"width": 412, "height": 823})
    page = context.new_page()
    cdp = context.new_cdp_session(page)
    events: list[dict] = []
    done: list[bool] = []
    cdp.on("Tracing.dataCollected", lambda payload: events.extend(payload["value"]))
    cdp.on("Tracing.tracingComplete", lambda payload: done.append(True))
    cdp.send("Tracing.start", {"categories": CATEGORIES, "transferMode": "ReportEvents"})
    try:
        page.goto(url, wait_until="load")
        page.wait_for_timeout(2500)
        boxes = page.evaluate(_BOXES_JS)
        cdp.send("Tracing.end")
        while not done:
            page.wait_for_timeout(50)
    finally:
        context.close()
    return events, boxes


def _figures(events: list[dict]) -> dict[str, float]:
    """Sum the renderer main thread's style, layout, script and long-task time (ms)."""
    threads = Counter((e["pid"], e["tid"]) for e in events if e.get("name") == "Layout")
    pid, tid = threads.most_common(1)[0][0]
    main = [e for e in events if e["pid"] == pid and e["tid"] == tid and e.get("ph") == "X"]
    paints = [
        e["ts"] for e in events if e["pid"] == pid and e.get("name") == "firstContentfulPaint"
    ]
    first_paint = min(paints) if paints else main[0]["ts"]

    def total(names: tuple[str, ...]) -> float:
        # nested events of the same kind (a script calling a script) are counted once
        spans = sorted((e["ts"], e["ts"] + e["dur"]) for e in main if e["name"] in names)
        covered, end = 0, -1
        for start, stop in spans:
            if stop > end:
                covered += stop - max(start, end)
                end = stop
        return covered / 1000

    tasks = [e["dur"] / 1000 for e in main if e["name"] in _TASKS and e["ts"] >= first_paint]
    return {
        "style": total(("UpdateLayoutTree",)),
        "layout": total(("Layout",)),
        "script": total(_SCRIPT),
        "long": sum(d - LONG_TASK_MS for d in tasks if d > LONG_TASK_MS),
    }


def main() -> None:
    """Print the main thread's work for every page (or those given)."""
    from playwright.sync_api import sync_playwright

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--html", type=Path, default=ROOT / "_build" / "html")
    parser.add_argument("--page", nargs="*", help="pages (e.g. book/intro); default: all")
    parser.add_argument("--runs", type=int, default=3, help="loads per page (the median)")
    args = parser.parse_args()
    pages = args.page or ["index", *toc_pages()]
    print(f"{'page':34s} {'style':>7s} {'layout':>7s} {'script':>7s} {'long':>7s} {'boxes':>6s}")
    with sync_playwright() as playwright, serve_gzip(args.html) as base:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        for name in pages:
            loads = [_trace_load(browser, f"{base}{name}.html") for _ in range(args.runs)]
            figures = [_figures(events) for events, _ in loads]
            med = {k: statistics.median(f[k] for f in figures) for k in figures[0]}
            boxes = statistics.median(b for _, b in loads)
            print(
                f"{name:34s} {med['style']:7.0f} {med['layout']:7.0f} {med['script']:7.0f} "
                f"{med['long']:7.0f} {boxes:6.0f}",
                flush=True,
            )
        browser.close()


if __name__ == "__main__":
    main()
