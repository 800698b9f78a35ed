"""Time the book build (issue 5): clean, re-rendered from the execution cache, and unchanged.

1. clean: _build/ removed, including the execution cache _build/.jupyter_cache (and a root
   .jupyter_cache if one exists): every chapter is executed. node_modules is kept unless
   --fresh-npm is given, so `npm ci` is timed only on request.
2. from cache: _build/html and _build/.doctrees removed, the execution cache kept: every page
   is parsed and written again, no notebook is executed (what a config change costs).
3. unchanged: the build run again with nothing changed (what a chapter author waits for
   when nothing is stale; Sphinx re-reads only changed pages).

Each run is `bash scripts/build-book.sh`, the user's command. Run from the repository root:
    python benchmarks/book_build.py [--fresh-npm]
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BUILD = ROOT / "_build"


def timed_build() -> float:
    """Run scripts/build-book.sh once and return its wall time in seconds."""
    start = time.perf_counter()
    result = subprocess.run(
        ["bash", str(ROOT / "scripts" / "build-book.sh")],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    elapsed = time.perf_counter() - start
    if result.returncode != 0:
        tail = "\n".join(result.stdout.splitlines()[-30:])
        sys.exit(f"scripts/build-book.sh failed (exit {result.returncode}):\n{tail}")
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--fresh-npm", action="store_true", help="also remove node_modules (times npm ci)"
    )
    args = parser.parse_args()

    shutil.rmtree(BUILD, ignore_errors=True)
    shutil.rmtree(ROOT / ".jupyter_cache", ignore_errors=True)
    if args.fresh_npm:
        shutil.rmtree(ROOT / "node_modules", ignore_errors=True)
    clean = timed_build()

    shutil.rmtree(BUILD / "html", ignore_errors=True)
    shutil.rmtree(BUILD / ".doctrees", ignore_errors=True)
    from_cache = timed_build()

    unchanged = timed_build()

    pages = len(list((BUILD / "html" / "book").glob("*.html")))
    npm = " including npm ci" if args.fresh_npm else ""
    print(f"book build, {pages} pages in _build/html/book")
    print(f"  clean build (executes every chapter{npm}): {clean:7.1f} s")
    print(f"  re-render from the execution cache:       {from_cache:7.1f} s")
    print(f"  rebuild with nothing changed:             {unchanged:7.1f} s")


if __name__ == "__main__":
    main()
