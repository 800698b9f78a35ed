"""Lighthouse (mobile, simulated throttling) on every page, and the slow-4G slider answer.

Serves a built site (default _build/html) on 127.0.0.1 with gzip for text files, as a static
host sends them, and runs Lighthouse (the npm devDependency in package.json, offline;
Chromium at ``CHROME_PATH``, default /usr/bin/chromium) on every page of _toc.yml with its
mobile defaults: a Moto G Power screen, simulated slow 4G and a 4x CPU slowdown. Prints one
row per page: Performance and Accessibility scores, Total Blocking Time, Time to
Interactive, First and Largest Contentful Paint (milliseconds), the first paint Chromium
actually made in the unthrottled load Lighthouse simulates from ("seen", milliseconds) and
the bytes transferred (kB, gzipped) for the first load. Lighthouse's simulation counts every
request and main-thread task before the seen first paint, so a late one (a busy machine, or
a frame Chromium was slow to produce) makes the simulated paints later and lowers the score.

Lighthouse's figures move by ten points or more between runs of the same page (the seen
first paint lands early or late), so ``--runs N`` runs it N times a page, as Lighthouse's
own guidance on variability advises, and prints the median run (the middle one by
Performance score, and by Total Blocking Time among equal scores) with the lowest and
highest Performance and Total Blocking Time of the N runs.

``--slider PAGE ...`` then measures, for each page, how long after the navigation starts a
slider first answers on the slow-4G profile (1.6 Mbps down, 150 ms round trip, 4x CPU
slowdown, by the Chrome DevTools Protocol in Playwright): the first explorer is scrolled
into view as a reader would, its first live slider is pressed (ArrowRight) as soon as it is
there, and the clock stops when the state it selects shows a loaded picture that differs
from the first one. Also prints the gzipped bytes of the page scrolled to its end.

Build the book first (``bash scripts/build-book.sh``); run from the repository root under
the machine's heavy lock (each Lighthouse run takes about 30 s)::

    python benchmarks/lighthouse.py [--html DIR] [--page book/intro ...] [--runs 3] \
        [--slider book/simulated_gauge book/estimating_level book/beyond_the_paper]
"""

from __future__ import annotations

import argparse
import functools
import gzip
import json
import os
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from conftest import toc_pages  # noqa: E402  (the tests' page list)

LIGHTHOUSE = ROOT / "node_modules" / ".bin" / "lighthouse"
CHROMIUM = os.environ.get("CHROME_PATH", "/usr/bin/chromium")
_GZIP_TYPES = (".html", ".js", ".css", ".json", ".svg", ".txt", ".map")
#: The slow-4G profile of the slider measurement: bytes per second and milliseconds.
SLOW_4G = {"download": 1_600_000 / 8, "upload": 750_000 / 8, "latency": 150, "cpu": 4}


class _GzipHandler(SimpleHTTPRequestHandler):
    """Serve files as a static host does: text gzipped (level 6) when the client accepts it."""

    def log_message(self, format: str, *args: object) -> None:  # noqa: A002
        """Stay quiet."""

    def send_head(self) -> object:  # type: ignore[override]
        """Send text files gzipped; everything else as http.server does."""
        path = Path(self.translate_path(self.path))
        if path.is_dir():
            path = path / "index.html"
        accepts = "gzip" in self.headers.get("Accept-Encoding", "")
        if not (accepts and path.is_file() and path.suffix in _GZIP_TYPES):
            return super().send_head()
        body = _gzipped(path, path.stat().st_mtime_ns)
        self.send_response(200)
        self.send_header("Content-Type", self.guess_type(str(path)))
        self.send_header("Content-Encoding", "gzip")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        import io

        return io.BytesIO(body)


@functools.lru_cache(maxsize=4096)
def _gzipped(path: Path, mtime: int) -> bytes:
    """Return the file gzipped at level 6 (cached per modification time)."""
    return gzip.compress(path.read_bytes(), compresslevel=6)


@contextmanager
def serve_gzip(directory: Path) -> Iterator[str]:
    """Serve ``directory`` with gzip on 127.0.0.1 while the block runs; yield its base URL."""
    handler = functools.partial(_GzipHandler, directory=str(directory))
    server = ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()


def lighthouse(url: str) -> dict[str, float]:
    """Run Lighthouse (mobile, simulated throttling) on ``url``; return the figures."""
    with tempfile.TemporaryDirectory() as tmp:
        report = Path(tmp) / "report.json"
        subprocess.run(
            [
                str(LIGHTHOUSE),
                url,
                "--quiet",
                "--output=json",
                f"--output-path={report}",
                "--only-categories=performance,accessibility",
                "--chrome-flags=--headless=new --no-sandbox --disable-gpu --disable-dev-shm-usage",
            ],
            check=True,
            env={**os.environ, "CHROME_PATH": CHROMIUM},
            capture_output=True,
            timeout=300,
        )
        data = json.loads(report.read_text(encoding="utf-8"))
    audits = data["audits"]
    return {
        "performance": round(100 * (data["categories"]["performance"]["score"] or 0)),
        "accessibility": round(100 * (data["categories"]["accessibility"]["score"] or 0)),
        "tbt": audits["total-blocking-time"]["numericValue"],
        "tti": audits["interactive"]["numericValue"],
        "fcp": audits["first-contentful-paint"]["numericValue"],
        "lcp": audits["largest-contentful-paint"]["numericValue"],
        "seen": audits["metrics"]["details"]["items"][0]["observedFirstContentfulPaint"],
        "bytes": audits["total-byte-weight"]["numericValue"],
    }


_SLIDER = ".dstoolkit-states"  # the stack a live control switches (dstoolkit.teaching)
_SHOWN_PICTURE = """() => {
  const stacks = [...document.querySelectorAll('.dstoolkit-states')];
  for (const stack of stacks) {
    const img = [...stack.querySelectorAll('img')].find(
      i => i.offsetParent !== null && i.complete && i.naturalWidth > 0);
    if (img) return img.currentSrc || img.src;
  }
  return null;
}"""


def slider_answer(browser: object, url: str) -> tuple[float, int]:
    """Measure how long a slider takes to answer on slow 4G, and what the page weighs.

    Returns the seconds from the navigation to the first slider answer, and the gzipped
    bytes fetched once the page is scrolled to its end.
    """
    context = browser.new_context(viewport={"width": 412, "height": 823}, device_scale_factor=1.75)
    page = context.new_page()
    sizes: dict[str, int] = {}

    def on_finished(request: object) -> None:
        try:
            sizes[request.url] = request.sizes()["responseBodySize"] + 300  # + headers
        except Exception:  # noqa: BLE001  (a request without sizes: count headers only)
            sizes[request.url] = 300

    page.on("requestfinished", on_finished)
    cdp = context.new_cdp_session(page)
    cdp.send("Network.enable")
    cdp.send(
        "Network.emulateNetworkConditions",
        {
            "offline": False,
            "latency": SLOW_4G["latency"],
            "downloadThroughput": SLOW_4G["download"],
            "uploadThroughput": SLOW_4G["upload"],
        },
    )
    cdp.send("Emulation.setCPUThrottlingRate", {"rate": SLOW_4G["cpu"]})
    start = time.monotonic()
    page.goto(url, wait_until="commit", timeout=120_000)
    answered = float("nan")
    first: str | None = None
    pressed = False
    deadline = start + 120
    while time.monotonic() < deadline:
        try:
            page.evaluate(
                "() => { const v = document.querySelector('.dstoolkit-explorer');"
                " if (v) v.scrollIntoView(); }"
            )
            shown = page.evaluate(_SHOWN_PICTURE)
            handle = page.locator('.dstoolkit-explorer input[type="range"][data-switches]').first
            if first is None and shown:
                first = shown
            if first is not None and not pressed and handle.count():
                handle.focus(timeout=1000)
                page.keyboard.press("ArrowRight")
                pressed = True
            elif pressed and shown and shown != first:
                answered = time.monotonic() - start
                break
        except Exception:  # noqa: BLE001  (the page is still loading: try again)
            pass
        time.sleep(0.05)
    # scroll to the end (fetches what is lazy), unthrottled, and weigh the page
    cdp.send(
        "Network.emulateNetworkConditions",
        {"offline": False, "latency": 0, "downloadThroughput": -1, "uploadThroughput": -1},
    )
    cdp.send("Emulation.setCPUThrottlingRate", {"rate": 1})
    page.wait_for_load_state("load", timeout=120_000)
    height = page.evaluate("document.documentElement.scrollHeight")
    for y in range(0, height + 800, 600):
        page.evaluate(f"window.scrollTo(0, {y})")
        time.sleep(0.05)
    page.wait_for_load_state("networkidle", timeout=60_000)
    context.close()
    return answered, sum(sizes.values())


def median_run(runs: list[dict[str, float]]) -> dict[str, float]:
    """Pick the median run: the middle one by Performance score (by TBT among equal scores)."""
    ordered = sorted(runs, key=lambda run: (run["performance"], -run["tbt"]))
    return ordered[(len(ordered) - 1) // 2]


def main() -> None:
    """Run the measurements and print the tables."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--html", type=Path, default=ROOT / "_build" / "html")
    parser.add_argument("--page", nargs="*", help="pages (e.g. book/intro); default: all")
    parser.add_argument("--slider", nargs="*", default=[], help="pages for the slider answer")
    parser.add_argument("--runs", type=int, default=1, help="Lighthouse runs a page (the median)")
    parser.add_argument("--no-lighthouse", action="store_true")
    args = parser.parse_args()
    if not LIGHTHOUSE.is_file():
        sys.exit("benchmarks/lighthouse.py: run `npm ci` first (node_modules/.bin/lighthouse).")
    pages = args.page or toc_pages()
    with serve_gzip(args.html) as base:
        if not args.no_lighthouse:
            print(
                f"Lighthouse {args.html} (mobile, simulated slow 4G, 4x CPU; "
                f"the median of {args.runs} run(s) a page)"
            )
            print(
                f"{'page':<28}{'Perf':>5}{'A11y':>5}{'TBT ms':>8}{'TTI ms':>8}"
                f"{'FCP ms':>8}{'LCP ms':>8}{'seen ms':>8}{'kB':>7}"
                f"{'Perf range':>12}{'TBT range':>12}"
            )
            for name in pages:
                runs = [lighthouse(base + name + ".html") for _ in range(args.runs)]
                row = median_run(runs)
                perf = sorted(run["performance"] for run in runs)
                tbt = sorted(run["tbt"] for run in runs)
                print(
                    f"{name:<28}{row['performance']:>5}{row['accessibility']:>5}"
                    f"{row['tbt']:>8.0f}{row['tti']:>8.0f}{row['fcp']:>8.0f}{row['lcp']:>8.0f}"
                    f"{row['seen']:>8.0f}"
                    f"{row['bytes'] / 1000:>7.0f}"
                    f"{f'{perf[0]:.0f}-{perf[-1]:.0f}':>12}{f'{tbt[0]:.0f}-{tbt[-1]:.0f}':>12}",
                    flush=True,
                )
        if args.slider:
            from playwright.sync_api import sync_playwright

            print("\nslow 4G (1.6 Mbps, 150 ms RTT, 4x CPU): a slider answers after opening")
            print(f"{'page':<28}{'answer s':>9}{'scrolled kB gz':>16}")
            with sync_playwright() as playwright:
                browser = playwright.chromium.launch(
                    executable_path=CHROMIUM,
                    args=["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"],
                )
                for name in args.slider:
                    seconds, weight = slider_answer(browser, base + name + ".html")
                    print(f"{name:<28}{seconds:>9.1f}{weight / 1000:>16.0f}", flush=True)
                browser.close()


if __name__ == "__main__":
    main()
