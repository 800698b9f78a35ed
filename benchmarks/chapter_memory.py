"""Peak memory of each chapter's kernel: what one student costs a JupyterHub node.

For every chapter with an exercise sheet, two notebooks run in a fresh ``python3`` kernel
(nbclient), one after the other:

* **chapter**: the reader's notebook of the chapter, i.e. the code cells of ``book/<stem>.md``
  as the site's notebook keeps them (glue and answer-key cells removed by
  ``scripts/chapter_notebook.py``), run in ``book/``;
* **sheet**: the teacher's edition of the exercise sheet (answers filled in, so every check
  and explorer runs), run in ``notebooks/``.

A last cell reads the kernel process's own peak resident set (``VmHWM`` of
``/proc/self/status``, the high-water mark of the kernel's memory since it started: child
processes of the checks are not counted, they end within the cell that starts them). Not
``ru_maxrss``: Linux carries it over ``exec`` from the process that forked the kernel, so
it never reads below the size of this script. Prints one row per notebook and
the largest peak; the budget a class on one node affords is 250 MiB a student.

The kernel is the class's: the ``python3`` kernel spec the grading guide installs, whose
``env`` is ``scripts/course.py``'s ``KERNEL_ENV`` (installed for this run in a temporary
folder, first on ``JUPYTER_PATH``; the kernel prints the environment it got). glibc
otherwise raises its thresholds for returning freed memory to the system after a large
array is freed (up to 32 MiB for mmap, 64 MiB for trimming), so a kernel keeps memory it no
longer uses; ``--plain`` measures the environment's own ``python3`` kernel spec instead,
which inherits this script's environment.

Run: python benchmarks/chapter_memory.py [--chapter STEM ...] [--only chapter|sheet] [--plain]
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

import jupytext
import nbformat
from ipykernel.kernelspec import install
from nbclient import NotebookClient

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

import course  # noqa: E402
import sheets  # noqa: E402
from chapter_notebook import strip_glue, strip_solution  # noqa: E402

MIB = 2**20
#: What a class of 100 on a 32 GB node leaves each student's kernel, with room for the hub.
BUDGET_MIB = 250
#: A guard against a hanging cell, not a speed requirement.
CELL_TIMEOUT = 900
PEAK = (
    "import os, sys\n"
    "with open('/proc/self/status') as _status:\n"
    "    _hwm = next(line.split()[1] for line in _status if line.startswith('VmHWM:'))\n"
    "print('PEAK_KIB', _hwm, 'numba' in sys.modules,\n"
    "      ','.join(f'{k}={os.environ[k]}' for k in sorted(os.environ) if k.startswith('MALLOC_'))"
    " or '-')"
)


def chapter_notebook(stem: str) -> nbformat.NotebookNode:
    """Return the reader's notebook of ``stem``: its code cells without glue or answer key."""
    code = [
        c.source for c in jupytext.read(ROOT / "book" / f"{stem}.md").cells if c.cell_type == "code"
    ]
    kept = [s for s in (strip_solution(s) for s in strip_glue(code)) if s.strip()]
    return nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(s) for s in kept])


def sheet_notebook(stem: str) -> nbformat.NotebookNode:
    """Return the teacher's edition of the exercise sheet of ``stem``."""
    number, title, src, labels = sheets.sheets(ROOT)[stem]
    return nbformat.from_dict(sheets.build(src, number, title, labels, True))


def install_class_kernel(folder: Path) -> None:
    """Install the class's ``python3`` kernel spec under ``folder``, first on JUPYTER_PATH."""
    install(kernel_name="python3", prefix=str(folder), env=course.KERNEL_ENV)
    share = str(folder / "share" / "jupyter")
    os.environ["JUPYTER_PATH"] = os.pathsep.join(
        [share, *filter(None, [os.environ.get("JUPYTER_PATH")])]
    )


def peak_mib(nb: nbformat.NotebookNode, cwd: Path) -> tuple[float, float, bool, str]:
    """Run ``nb`` in a fresh kernel started in ``cwd``.

    Returns the peak MiB, the seconds, whether numba was loaded and the kernel's MALLOC_
    variables.
    """
    nb.cells.append(nbformat.v4.new_code_cell(PEAK))
    env = dict(
        os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])
    )
    start = time.perf_counter()
    client = NotebookClient(
        nb, timeout=CELL_TIMEOUT, kernel_name="python3", resources={"metadata": {"path": str(cwd)}}
    )
    client.execute(env=env)
    seconds = time.perf_counter() - start
    for out in nb.cells[-1].get("outputs", []):
        if "PEAK_KIB" in out.get("text", ""):
            _, kib, numba, malloc = out["text"].split()
            return int(kib) * 1024 / MIB, seconds, numba == "True", malloc
    raise RuntimeError("the kernel printed no peak")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chapter", nargs="*", help="chapter stems (default: every one)")
    parser.add_argument("--only", choices=("chapter", "sheet"), help="run one kind only")
    parser.add_argument(
        "--plain", action="store_true", help="the environment's own python3 kernel spec"
    )
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        if not args.plain:
            install_class_kernel(Path(folder))
        return measure(args, parser)


def measure(args: argparse.Namespace, parser: argparse.ArgumentParser) -> int:
    """Print the table of the chapters ``args`` asks for."""
    stems = list(sheets.sheets(ROOT))
    for stem in args.chapter or []:
        if stem not in stems:
            parser.error(f"no chapter {stem!r}; the chapters are {', '.join(stems)}")
    numbers = {stem: sheets.sheets(ROOT)[stem][0] for stem in stems}
    kinds = [args.only] if args.only else ["chapter", "sheet"]
    kernel = "the environment's python3" if args.plain else "the class's python3 (KERNEL_ENV)"
    print(
        f"{'chapter':<24} {'notebook':<8} {'peak MiB':>9} {'seconds':>8} {'numba':>6}"
        f"  (budget {BUDGET_MIB} MiB; kernel: {kernel})"
    )
    worst = 0.0
    for stem in args.chapter or stems:
        for kind in kinds:
            nb, cwd = (
                (chapter_notebook(stem), ROOT / "book")
                if kind == "chapter"
                else (sheet_notebook(stem), ROOT / "notebooks")
            )
            mib, seconds, numba, malloc = peak_mib(nb, cwd)
            worst = max(worst, mib)
            flag = "" if mib < BUDGET_MIB else "  OVER"
            label = f"{numbers[stem]:>2} {stem}"
            print(
                f"{label:<24} {kind:<8} {mib:>9.1f} {seconds:>8.1f} "
                f"{'loaded' if numba else '-':>6}  {malloc}{flag}",
                flush=True,
            )
    print(f"largest peak: {worst:.1f} MiB (this process: "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB)")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
