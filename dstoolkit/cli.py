"""The ``dstoolkit`` command (also ``python -m dstoolkit``): table3, measure, analyze.

``table3`` needs the core only (its figure needs the ``plots`` extra); ``measure`` plays
and records through a sound card (the ``audio`` extra) or a simulated one; ``analyze``
reads a recorded WAV file.

Examples
--------
>>> from dstoolkit.cli import build_parser
>>> args = build_parser().parse_args(["table3", "--runs", "5", "--out", "t.csv"])
>>> args.command, args.runs, args.orders
('table3', 5, 'eq43')
"""

from __future__ import annotations

import argparse
import gc
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from dstoolkit.errors import MissingExtraError
from dstoolkit.studies import METHODS, run_table3
from dstoolkit.utils.budget import check_memory
from dstoolkit.utils.console import run_command
from dstoolkit.utils.outputs import (
    atomic_write,
    check_outputs,
    figure_tag,
    made_by,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from dstoolkit.studies import Table3


def table3_outputs(out: str | Path) -> tuple[Path, Path]:
    """Name the CSV of ``table3`` and the figure beside it.

    ``t.csv`` gets ``t.png``; never the same file: a CSV named ``t.png`` gets the figure
    ``t.figure.png``.

    Parameters
    ----------
    out : str or os.PathLike
        The CSV path (``--out``).

    Returns
    -------
    csv_path : pathlib.Path
        The CSV.
    figure_path : pathlib.Path
        The figure beside it.

    Examples
    --------
    >>> from dstoolkit.cli import table3_outputs
    >>> [p.name for p in table3_outputs("out/t.csv")]
    ['t.csv', 't.png']
    >>> [p.name for p in table3_outputs("t.png")]
    ['t.png', 't.figure.png']
    """
    csv_path = Path(out)
    if csv_path.name in ("", ".", ".."):
        return csv_path, csv_path  # refused by check_outputs: a folder, not a file
    figure = csv_path.with_suffix(".png")
    if figure.name == csv_path.name:
        figure = csv_path.with_name(csv_path.stem + ".figure.png")
    return csv_path, figure


#: Memory one Monte Carlo run of ``table3`` holds while a case is computed: up to 160
#: readings (a tube's resonances in the band), their noise draws, orders and estimates.
TABLE3_BYTES_PER_RUN = 160 * 8 * 8


def table3_command(args: argparse.Namespace) -> int:
    """Reproduce Table 3: the CSV, a figure beside it (with the ``plots`` extra), and the table.

    The table is printed next to the paper's figures. The memory and the outputs are checked
    before anything is computed.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed ``table3`` arguments (:func:`build_parser`).

    Returns
    -------
    int
        The exit status, 0.

    Raises
    ------
    MemoryBudgetError
        ``--runs`` would exceed the memory budget.
    OutputPathError
        An output that cannot be written, or exists without ``--overwrite``.
    InvalidInputError
        An unknown method.

    See Also
    --------
    dstoolkit.studies.run_table3 : The computation.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), Table 3.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from dstoolkit.cli import build_parser, table3_command
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     out = str(Path(folder) / "t.csv")
    ...     args = build_parser().parse_args(["table3", "--runs", "2", "--methods", "direct",
    ...                                       "--quiet", "--out", out])
    ...     status = table3_command(args)  # doctest: +ELLIPSIS
    Table 3, frequency-level simulation, orders by eq43, seed 0
    ...
    >>> status
    0
    """
    methods = tuple(args.methods.split(",")) if args.methods else METHODS
    csv_path, figure_path = table3_outputs(args.out)
    plot_table3: Callable[[Table3], Figure] | None = None
    try:
        from dstoolkit.plots import plot_table3
    except MissingExtraError as exc:
        no_figure = str(exc)
    # before anything is made: a case's readings of every run are held at once
    check_memory(
        max(args.runs, 1) * TABLE3_BYTES_PER_RUN,
        f"table3 --runs {args.runs} (the readings of every run of a case)",
        "use fewer runs",
    )
    outputs: dict[str, str | Path] = {"the CSV (--out)": args.out}
    if plot_table3 is not None:
        outputs["the figure"] = figure_path
    # before any computing: the outputs must be writable and replace nothing unasked
    check_outputs(
        outputs,
        overwrite=args.overwrite,
        replaceable=lambda p: p == figure_path and made_by(p, "table3"),
    )
    table = run_table3(
        runs=args.runs,
        seed=args.seed,
        simulation=args.simulation,
        methods=methods,
        order_rule=args.orders,
        progress=not args.quiet,
    )
    table.write_csv(csv_path)
    print(table.format())
    if plot_table3 is None:
        print(f"\nwrote {csv_path} (no figure: {no_figure})")
        return 0
    figure = plot_table3(table)
    atomic_write(
        figure_path,
        lambda fh: figure.savefig(
            fh, format="png", dpi=120, bbox_inches="tight", metadata=figure_tag("table3")
        ),
    )
    print(f"\nwrote {csv_path} and {figure_path}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """Build the argument parser of the ``dstoolkit`` command and its three subcommands.

    Returns
    -------
    argparse.ArgumentParser
        ``table3``, ``measure`` and ``analyze``; each sets ``func`` to the function that runs
        it.

    See Also
    --------
    main : Parses and runs.

    Examples
    --------
    >>> from dstoolkit.cli import build_parser
    >>> build_parser().parse_args(["table3"]).simulation
    'frequency'
    """
    parser = argparse.ArgumentParser(
        prog="dstoolkit",
        description="Evidence-theory state estimation and the acoustic level gauge "
        "(Xu et al., Sensors 2017).",
    )
    sub = parser.add_subparsers(dest="command", required=True)

    t3 = sub.add_parser("table3", help="reproduce the paper's Table 3 by seeded Monte Carlo")
    t3.add_argument("--runs", type=int, default=100, help="Monte Carlo runs per level")
    t3.add_argument("--seed", type=int, default=0, help="seed of every random draw")
    t3.add_argument(
        "--simulation",
        choices=("frequency", "waveform"),
        default="frequency",
        help="noise from the paper's distributions, or from synthesised recordings",
    )
    t3.add_argument(
        "--orders",
        choices=("eq43", "fit", "true"),
        default="eq43",
        help="how n_k is obtained: eq. 43 (paper), the series fit, or the truth",
    )
    t3.add_argument("--methods", default="", help=f"comma-separated subset of {','.join(METHODS)}")
    t3.add_argument("--out", default="table3.csv", help="CSV path; the figure goes beside it")
    t3.add_argument("--quiet", action="store_true", help="no progress bar")
    t3.add_argument("--overwrite", action="store_true", help="replace an existing CSV or figure")
    t3.set_defaults(func=table3_command)

    from dstoolkit.audio import (
        add_analyze_arguments,
        add_measure_arguments,
        analyze_command,
        measure_command,
    )

    measure = sub.add_parser("measure", help="measure a level with a speaker and a microphone")
    add_measure_arguments(measure)
    measure.set_defaults(func=measure_command)
    analyze = sub.add_parser("analyze", help="analyse a recorded WAV file into a level")
    add_analyze_arguments(analyze)
    analyze.set_defaults(func=analyze_command)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line ``argv``.

    A package error or an OS error becomes one line on stderr (exit status 2). Ctrl-C,
    SIGTERM, SIGHUP and SIGQUIT stop the command with one line on stderr and the exit
    status 128 + the signal's number; as after any failure, the run is taken back whole
    (:func:`~dstoolkit.utils.outputs.output_run`): the files it wrote are removed and the
    files they replaced put back. Text the output's encoding cannot hold is printed in
    ASCII, and a closed standard output (``| head``) ends in an ``error:`` line once the
    command has finished, its files kept.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0, 2 after an error, 128 + the signal's number after a stop
        (130 Ctrl-C, 143 SIGTERM, 129 SIGHUP, 131 SIGQUIT).

    See Also
    --------
    build_parser : The arguments.

    Examples
    --------
    An error is one line on stderr and the status 2 (here, before any file is touched: the
    runs would not fit in memory):

    >>> import contextlib, io
    >>> from dstoolkit.cli import main
    >>> with contextlib.redirect_stderr(io.StringIO()) as err:
    ...     status = main(["table3", "--runs", "10000000000000"])
    >>> status, err.getvalue().startswith("error:")
    (2, True)
    """

    def body() -> int:
        args = build_parser().parse_args(argv)
        return int(args.func(args))

    try:
        return run_command(body)
    finally:
        # A command's figures and recordings are unreachable cycles once it returns; a
        # process that lives on after it (a notebook's kernel) would keep their memory until
        # its next full collection, which may come many large arrays later.
        gc.collect()
