"""Time the book build: clean, re-rendered from the execution cache, and unchanged.

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
import fcntl
import os
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BUILD = ROOT / "_build"
LOCK = BUILD / ".build-book.lock"  # the lock scripts/build-book.sh holds while it builds
WAITED = "another build of this book is running"
#: CPU seconds (user + system, the build and every kernel it starts) of each timed build.
CPU_SECONDS: list[float] = []


def remove(*paths: Path) -> None:
    """Delete build folders, but never under a build that is running (it holds LOCK)."""
    LOCK.parent.mkdir(exist_ok=True)
    with LOCK.open("w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        for path in paths:
            if path == BUILD:  # keep the lock file itself
                for child in BUILD.iterdir():
                    if child.is_dir():
                        shutil.rmtree(child)
                    elif child != LOCK:
                        child.unlink()
            else:
                shutil.rmtree(path, ignore_errors=True)


def timed_build() -> float:
    """Run scripts/build-book.sh once and return its wall time in seconds.

    Its CPU time, less sensitive to the load of a shared machine, is added to CPU_SECONDS.
    """
    cpu = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(
        ["bash", str(ROOT / "scripts" / "build-book.sh")],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    CPU_SECONDS.append(after.ru_utime + after.ru_stime - cpu.ru_utime - cpu.ru_stime)
    if result.returncode != 0:
        tail = "\n".join(result.stdout.splitlines()[-30:])
        sys.exit(f"scripts/build-book.sh failed (exit {result.returncode}):\n{tail}")
    if WAITED in result.stdout:
        print("note: this build waited for another build of the checkout; its time is too long")
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--fresh-npm", action="store_true", help="also remove node_modules (times npm ci)"
    )
    args = parser.parse_args()

    remove(BUILD, ROOT / ".jupyter_cache", *([ROOT / "node_modules"] if args.fresh_npm else []))
    clean = timed_build()

    remove(BUILD / "html", BUILD / ".doctrees")
    from_cache = timed_build()

    unchanged = timed_build()

    pages = sorted((BUILD / "html" / "book").glob("*.html"))
    npm = " including npm ci" if args.fresh_npm else ""
    print(f"book build, {len(pages)} pages in _build/html/book")
    cpu = CPU_SECONDS
    print(
        f"load average {', '.join(f'{x:.2f}' for x in os.getloadavg())} "
        "(wall times on a shared machine follow the load; CPU times less so)"
    )
    print(f"  clean build (executes every chapter{npm}): {clean:7.1f} s   CPU {cpu[0]:7.1f} s")
    print(f"  re-render from the execution cache:       {from_cache:7.1f} s   CPU {cpu[1]:7.1f} s")
    print(f"  rebuild with nothing changed:             {unchanged:7.1f} s   CPU {cpu[2]:7.1f} s")
    print_sizes(pages)


def print_sizes(pages: list[Path]) -> None:
    """Print the size of the site and of every page's HTML.

    The explorers' precomputed states are embedded in their page; budget: 6 MB a page.
    """
    site = sum(f.stat().st_size for f in (BUILD / "html").rglob("*") if f.is_file())
    print(f"site _build/html: {site / 1e6:.1f} MB")
    for page in sorted(pages, key=lambda p: -p.stat().st_size):
        size = page.stat().st_size / 1e6
        print(f"  {page.name:28s} {size:6.2f} MB{'  OVER 6 MB' if size > 6 else ''}")


if __name__ == "__main__":
    main()
