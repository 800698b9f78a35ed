"""Weigh every page of the built book: what a first visit fetches until the ``load`` event.

Serves _build/html on 127.0.0.1, opens each page of _toc.yml in headless Chromium (Debian's
/usr/bin/chromium driven by Playwright) with an empty cache, records every file fetched
until ``load``, and prints per page the number of files, their raw bytes and their bytes
gzipped (each file on its own at level 6, as a web server sends it), and whether the page
has an explorer. The budgets of the tests (tests/test_book_a11y.py) are printed beside.
Build the book first (``bash scripts/build-book.sh``). Run from the repository root:
    python benchmarks/book_weight.py [--html _build/html] [--page book/intro ...]
"""

from __future__ import annotations

import argparse
import gzip
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote, urlsplit

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from conftest import served, toc_pages  # noqa: E402  (the tests' page list and server)

CHROMIUM = "/usr/bin/chromium"
#: First-load budgets, gzipped bytes: a page with an explorer, and one without.
BUDGET = 1_500_000
BUDGET_NO_EXPLORER = 1_000_000
_EXPLORER = ".dstoolkit-explorer"  # a widget view, written as HTML by site_postbuild.py


@dataclass(frozen=True)
class Weight:
    """What a page fetches until ``load``."""

    page: str
    files: int
    raw: int  # bytes
    gzipped: int  # bytes, each file gzipped on its own
    explorer: bool
    largest: tuple[tuple[str, int], ...]  # the three largest files, gzipped bytes

    @property
    def budget(self) -> int:
        """The page's budget in gzipped bytes."""
        return BUDGET if self.explorer else BUDGET_NO_EXPLORER


def weigh(browser: object, base: str, page_name: str, html_dir: Path) -> Weight:
    """Open ``page_name`` in a fresh context of ``browser`` and weigh its first load."""
    context = browser.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()
    fetched: list[str] = []
    page.on("requestfinished", lambda request: fetched.append(request.url))
    try:
        page.goto(base + page_name + ".html", wait_until="load", timeout=60_000)
        explorer = page.locator(_EXPLORER).count() > 0
    finally:
        context.close()
    sizes: dict[str, tuple[int, int]] = {}
    for url in dict.fromkeys(fetched):
        if not url.startswith(base):
            continue
        path = html_dir / unquote(urlsplit(url).path).lstrip("/")
        if path.is_dir():
            path = path / "index.html"
        if not path.is_file():
            continue
        data = path.read_bytes()
        sizes[path.relative_to(html_dir).as_posix()] = (
            len(data),
            len(gzip.compress(data, compresslevel=6, mtime=0)),
        )
    largest = sorted(
        ((name, packed) for name, (_, packed) in sizes.items()), key=lambda item: -item[1]
    )[:3]
    return Weight(
        page_name,
        len(sizes),
        sum(raw for raw, _ in sizes.values()),
        sum(packed for _, packed in sizes.values()),
        explorer,
        tuple(largest),
    )


@contextmanager
def chromium() -> Iterator[object]:
    """Headless Chromium through Playwright."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=CHROMIUM,
            headless=True,
            args=[
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
            ],
        )
        try:
            yield browser
        finally:
            browser.close()


def main(argv: list[str] | None = None) -> int:
    """Print the weight table; exit status 1 when a page is over its budget."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--html", type=Path, default=ROOT / "_build" / "html")
    parser.add_argument("--page", action="append", help="a page of _toc.yml (default: all)")
    args = parser.parse_args(argv)
    if not (args.html / "index.html").is_file():
        print(f"no book in {args.html}: run bash scripts/build-book.sh", file=sys.stderr)
        return 2
    pages = args.page or toc_pages()
    print(
        f"{'page':<28} {'files':>5} {'raw MB':>7} {'gzip MB':>8} {'budget':>7}  "
        "explorer  largest (gzipped kB)"
    )
    over = 0
    with served(args.html) as base, chromium() as browser:
        for name in pages:
            w = weigh(browser, base, name, args.html)
            over += w.gzipped > w.budget
            largest = ", ".join(f"{Path(f).name} {b / 1e3:.0f}" for f, b in w.largest)
            print(
                f"{name:<28} {w.files:>5} {w.raw / 1e6:>7.2f} {w.gzipped / 1e6:>8.2f} "
                f"{w.budget / 1e6:>7.1f}  {'yes' if w.explorer else 'no':<8}  {largest}",
                flush=True,
            )
    print(f"{over} page(s) over budget")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
