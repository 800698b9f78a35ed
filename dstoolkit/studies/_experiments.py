"""The paper's Table 3 reproduced by seeded Monte Carlo (§4.3), two ways.

* ``simulation="frequency"``: readings z_k = f_k − w_k with w drawn from the paper's
  triangular distribution (mode −6.9 Hz, [−10.59, −3.21] Hz), i.i.d. over k.
* ``simulation="waveform"``: a recording is synthesised for every run
  (:func:`dstoolkit.gauge.synthesize_recording`) and its resonances detected as the paper's
  detector would (no offset correction); the noise in z emerges from the physics.

Every method sees the same readings. The filters use the paper's noise evidence (Tables
1–2); the orders n_k come from eq. 43 as in the paper (or, to study the estimator, from the
series fit or the truth). The level of step k is eq. 32, L̂_k = n_k c/(2 x̂_k), and a run's
error is the mean of |L̂_k − L| over its steps, as in Fig. 11b; Table 3 averages runs.
"""

from __future__ import annotations

import csv
import io
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from dstoolkit.errors import InvalidInputError
from dstoolkit.filters import ComparisonSettings, Filter, table3_filters
from dstoolkit.gauge import (
    DEFAULT_BAND,
    PAPER_SWEEP,
    PAPER_THETA,
    RecordingConditions,
    TubeSetup,
    detect_resonances,
    fit_resonance_series,
    gauge_state_space_model,
    level_from_resonance,
    orders_eq43,
    simulate_gauge,
    speed_of_sound,
    synthesize_recording,
    typical_conditions,
)
from dstoolkit.utils.outputs import atomic_write

from ._paper_results import TABLE3_CASES, TABLE3_MEAN_ABS_ERROR_M

#: How readings are simulated: from the paper's noise distributions, or by detecting the
#: resonances of synthesised recordings.
Simulation = Literal["frequency", "waveform"]
#: How the orders n_k are obtained: eq. 43, the resonance-series fit, or the truth.
OrderRule = Literal["eq43", "fit", "true"]
#: Direct measurement's column among the methods of Table 3 (the others are filters, each
#: with its column in :func:`dstoolkit.filters.table3_filters`).
DIRECT_COLUMN = 2
#: The methods of Table 3, in its order.
METHODS: tuple[str, ...] = tuple(
    name
    for _, name in sorted(
        [(DIRECT_COLUMN, "direct")] + [(e.table3_column, e.name) for e in table3_filters()]
    )
)
#: The columns of the CSV file that :meth:`Table3.write_csv` writes.
CSV_COLUMNS = ("level_m", "temperature_c", "method", "mean_abs_error_m", "runs", "seconds_per_run")


def paper_filters(seed: int = 0) -> dict[str, Filter[Any, Any]]:
    """Make the filters of Table 3 with the paper's settings.

    p = 3 α-cuts, ε = 0.05 and the frames Θ of Tables 1–2 for the two evidential filters;
    total conflict keeps the prediction (the paper's filter) or restarts (Nassreddine's), so a
    Monte Carlo run never stops.

    Parameters
    ----------
    seed : int, optional
        Seed of the particle filter.

    Returns
    -------
    dict of str to dstoolkit.filters.Filter
        ``"dependent_evidence"``, ``"nassreddine"``, ``"kalman"`` and ``"particle"``.

    See Also
    --------
    all_filters : Every filter, with the noise frames of the model.
    run_table3 : Runs these filters.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3, Tables 1–3.

    Examples
    --------
    >>> from dstoolkit.studies import paper_filters
    >>> sorted(paper_filters())
    ['dependent_evidence', 'kalman', 'nassreddine', 'particle']
    """
    settings = ComparisonSettings(seed=seed, p=3, n_particles=500, theta=PAPER_THETA)
    return {entry.name: entry.make(settings) for entry in table3_filters()}


@dataclass
class CaseReadings:
    """Readings of one Table 3 case: runs × steps, all of one length (a batch).

    Parameters
    ----------
    level_m : float
        L, m.
    temperature_c : float
        Air temperature, °C.
    speed_of_sound : float
        c, m/s.
    readings : numpy.ndarray, shape (runs, steps)
        z, Hz.
    true_orders : numpy.ndarray of int, shape (runs, steps), optional
        The true n_k of each reading, when known.

    See Also
    --------
    table3_readings : The readings of one case of :func:`run_table3`.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3.
    """

    level_m: float
    temperature_c: float
    speed_of_sound: float
    readings: np.ndarray
    """z, shape (runs, steps) in Hz."""
    true_orders: np.ndarray | None = None
    """True n_k of each reading (runs, steps) when known."""


def frequency_readings(
    level_m: float,
    temperature_c: float,
    runs: int,
    seed: int,
    band: tuple[float, float] = DEFAULT_BAND,
) -> list[CaseReadings]:
    """Draw readings with the paper's triangular w (the frequency-level simulation).

    Parameters
    ----------
    level_m : float
        L, m.
    temperature_c : float
        Air temperature, °C.
    runs : int
        Number of runs.
    seed : int
        Seed of the draws.
    band : tuple of float, optional
        (low, high) in Hz.

    Returns
    -------
    list of CaseReadings
        One batch, readings (runs, steps), with the true orders.
    """
    seq = simulate_gauge(level_m, temperature_c, band, runs=runs, seed=seed)
    orders = np.broadcast_to(seq.orders, (runs, seq.orders.size))
    return [CaseReadings(level_m, temperature_c, seq.speed_of_sound, seq.readings[..., 0], orders)]


def waveform_readings(
    level_m: float,
    temperature_c: float,
    runs: int,
    seed: int,
    conditions: RecordingConditions | None = None,
    progress: Callable[[int], Any] | None = None,
) -> list[CaseReadings]:
    """Detect readings in synthesised recordings (the waveform-level simulation).

    Detection misses a resonance now and then, so runs are grouped by their number of
    readings, one batch per length. The detector works as the paper's (no offset correction),
    so z carries the sweep-rate and latency offsets the paper's w absorbs.

    Parameters
    ----------
    level_m : float
        L, m.
    temperature_c : float
        Air temperature, °C.
    runs : int
        Number of recordings.
    seed : int
        Seed of the recordings' noises.
    conditions : RecordingConditions, optional
        The recordings' conditions (default :func:`~dstoolkit.gauge.typical_conditions`).
    progress : callable, optional
        Called with 1 after each recording.

    Returns
    -------
    list of CaseReadings
        One batch per number of readings, without the true orders.
    """
    cond = typical_conditions() if conditions is None else conditions
    setup = TubeSetup(level_m, temperature_c)
    rng = np.random.default_rng(seed)
    by_length: dict[int, list[np.ndarray]] = {}
    for _ in range(runs):
        rec = synthesize_recording(setup, PAPER_SWEEP, cond, seed=rng)
        det = detect_resonances(rec, correct_sweep_rate=False, correct_latency=False)
        by_length.setdefault(det.frequencies.size, []).append(det.frequencies)
        if progress is not None:
            progress(1)
    c = float(speed_of_sound(temperature_c))
    return [
        CaseReadings(level_m, temperature_c, c, np.stack(group))
        for _, group in sorted(by_length.items())
    ]


def estimate_orders(case: CaseReadings, rule: OrderRule = "eq43") -> np.ndarray:
    """Estimate the orders n_k, k = 1..K−1, of every run of a case.

    Parameters
    ----------
    case : CaseReadings
        The readings, (runs, K).
    rule : {"eq43", "fit", "true"}, optional
        Eq. (43) (default, the paper's), the resonance-series fit
        (:func:`~dstoolkit.gauge.fit_resonance_series`) or the truth.

    Returns
    -------
    numpy.ndarray of int, shape (runs, K−1)
        The orders.

    Raises
    ------
    InvalidInputError
        An unknown rule, or ``"true"`` for readings whose true orders are unknown.

    See Also
    --------
    dstoolkit.gauge.orders_eq43, dstoolkit.gauge.fit_resonance_series

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (43).

    Examples
    --------
    >>> from dstoolkit.studies import estimate_orders, table3_readings
    >>> (case,) = table3_readings(1.3, 27.0, runs=2)
    >>> estimate_orders(case, "true").shape == (2, case.readings.shape[1] - 1)
    True
    """
    z = case.readings
    if rule == "eq43":
        return np.stack([orders_eq43(row) for row in z])
    if rule == "fit":
        return np.stack([fit_resonance_series(row, offset_hz=None).orders[:-1] for row in z])
    if rule == "true":
        if case.true_orders is None:
            raise InvalidInputError("true orders are known only in the frequency-level simulation")
        return np.asarray(case.true_orders)[:, :-1]
    raise InvalidInputError(f"order rule must be 'eq43', 'fit' or 'true', got {rule!r}")


def estimate_levels(
    method: str, case: CaseReadings, orders: np.ndarray, filters: Mapping[str, Filter[Any, Any]]
) -> np.ndarray:
    """Estimate the level of every step, L̂_k = n_k c/(2 x̂_k), by one method.

    Parameters
    ----------
    method : str
        ``"direct"`` (x̂ = z) or a key of ``filters``.
    case : CaseReadings
        The readings, (runs, K).
    orders : numpy.ndarray of int, shape (runs, K−1)
        The orders n_k (:func:`estimate_orders`).
    filters : mapping of str to dstoolkit.filters.Filter
        The filters by name (:func:`paper_filters`).

    Returns
    -------
    numpy.ndarray, shape (runs, K−1)
        L̂_k, m.

    Raises
    ------
    KeyError
        A method that is neither ``"direct"`` nor in ``filters``.

    See Also
    --------
    dstoolkit.gauge.level_from_resonance : Eq. (32).

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (32), (39)–(40).

    Examples
    --------
    >>> from dstoolkit.studies import (estimate_levels, estimate_orders, paper_filters,
    ...                                table3_readings)
    >>> (case,) = table3_readings(1.3, 27.0, runs=2)
    >>> orders = estimate_orders(case, "true")
    >>> levels = estimate_levels("dependent_evidence", case, orders, paper_filters())
    >>> levels.shape == orders.shape
    True
    """
    z = case.readings
    if method == "direct":
        x = z[:, :-1]
    else:
        model = gauge_state_space_model()
        x = filters[method].run_batch(model, z[..., None], inputs=orders).estimates[:, :-1, 0]
    return level_from_resonance(x, orders, case.speed_of_sound)


@dataclass
class Table3Row:
    """One row of Table 3: a method's mean absolute level error at one level.

    Parameters
    ----------
    level_m : float
        L, m.
    temperature_c : float
        Air temperature, °C.
    method : str
        One of :data:`METHODS`.
    mean_abs_error_m : float
        Mean over runs of the mean |L̂_k − L| over steps, m.
    runs : int
        Number of runs.
    seconds_per_run : float
        Wall time of the method over all runs divided by the runs, s.
    paper_m : float, optional
        The paper's printed figure, m (None where it has none).

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), Table 3.
    """

    level_m: float
    temperature_c: float
    method: str
    mean_abs_error_m: float
    runs: int
    seconds_per_run: float
    paper_m: float | None = None

    def as_csv(self) -> dict[str, Any]:
        """Give the row as the CSV's columns (:data:`CSV_COLUMNS`).

        Returns
        -------
        dict of str to object
            Column name to value.
        """
        return {k: getattr(self, k) for k in CSV_COLUMNS}


@dataclass
class Table3:
    """The rows of Table 3 and how they were made. Made by :func:`run_table3`.

    Parameters
    ----------
    rows : list of Table3Row
        One row per case and method.
    simulation : str
        ``"frequency"`` or ``"waveform"``.
    seed : int
        The seed of the Monte Carlo runs.
    order_rule : str
        How n_k was obtained: ``"eq43"``, ``"fit"`` or ``"true"``.
    per_run_errors : dict, optional
        (level in m, method) to the error of every run, shape (runs,), m.

    See Also
    --------
    run_table3 : Makes it.
    table3_rows : Its rows beside the paper's.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), Table 3.
    """

    rows: list[Table3Row]
    simulation: str
    seed: int
    order_rule: str
    per_run_errors: dict[tuple[float, str], np.ndarray] = field(default_factory=dict)

    def error(self, level_m: float, method: str) -> float:
        """Look up the mean absolute level error of one method at one level.

        Parameters
        ----------
        level_m : float
            L, m, as in the table.
        method : str
            The method.

        Returns
        -------
        float
            The error, m.

        Raises
        ------
        KeyError
            No row for this level and method.
        """
        for r in self.rows:
            if r.level_m == level_m and r.method == method:
                return r.mean_abs_error_m
        raise KeyError((level_m, method))

    def write_csv(self, path: str | Path) -> Path:
        """Write the rows as CSV, atomically (a temporary file renamed over ``path``).

        Parameters
        ----------
        path : str or os.PathLike
            The CSV file (its folder is made if missing).

        Returns
        -------
        pathlib.Path
            The path written.

        Raises
        ------
        OSError
            The file cannot be written.
        """
        text = io.StringIO(newline="")
        writer = csv.DictWriter(text, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        for r in self.rows:
            writer.writerow(r.as_csv())
        return atomic_write(path, lambda fh: fh.write(text.getvalue().encode("utf-8")))

    def format(self) -> str:
        """Format the table as text, ours beside the paper's figures.

        Returns
        -------
        str
            A header line, the column names and one line per row.
        """
        head = (
            f"{'L (m)':>6} {'T (°C)':>6} {'method':<20} {'ours (m)':>10} {'paper (m)':>10}"
            f" {'s/run':>9}"
        )
        lines = [
            f"Table 3, {self.simulation}-level simulation, orders by {self.order_rule}, "
            f"seed {self.seed}",
            head,
            "-" * len(head),
        ]
        for r in self.rows:
            paper = f"{r.paper_m:>10.4f}" if r.paper_m is not None else f"{'—':>10}"
            lines.append(
                f"{r.level_m:>6.1f} {r.temperature_c:>6.1f} {r.method:<20} "
                f"{r.mean_abs_error_m:>10.4f} {paper} {r.seconds_per_run:>9.2e}"
            )
        return "\n".join(lines)


def run_table3(
    runs: int = 100,
    seed: int = 0,
    simulation: Simulation = "frequency",
    methods: Sequence[str] = METHODS,
    cases: Iterable[tuple[float, float]] = TABLE3_CASES,
    order_rule: OrderRule = "eq43",
    conditions: RecordingConditions | None = None,
    progress: bool = True,
) -> Table3:
    """Table 3 by seeded Monte Carlo: every case, every method, the same readings.

    The level of step k is eq. (32), L̂_k = n_k c/(2 x̂_k), and a run's error is the mean of
    |L̂_k − L| over its steps, as in Fig. 11b; the table averages runs.

    Parameters
    ----------
    runs : int, optional
        Monte Carlo runs per case, ≥ 1 (default 100).
    seed : int, optional
        Seed of every draw; each case gets its own entry of ``SeedSequence(seed)``.
    simulation : {"frequency", "waveform"}, optional
        Readings from the paper's noise w, or detected in synthesised recordings.
    methods : sequence of str, optional
        A subset of :data:`METHODS` (default all).
    cases : iterable of (float, float), optional
        (level in m, temperature in °C) (default :data:`TABLE3_CASES`).
    order_rule : {"eq43", "fit", "true"}, optional
        How n_k is obtained (default ``"eq43"``, the paper's).
    conditions : RecordingConditions, optional
        The recordings' conditions in the waveform simulation.
    progress : bool, optional
        Show a progress bar (needs tqdm; default True).

    Returns
    -------
    Table3
        One row per case and method; ``seconds_per_run`` is the wall time of the method over
        all runs of a case divided by the runs (the filters run vectorised over runs), reading
        synthesis not included.

    Raises
    ------
    InvalidInputError
        An unknown method, simulation or order rule, or ``runs`` below 1.

    See Also
    --------
    table3_rows : The rows beside the paper's figures.
    TABLE3_MEAN_ABS_ERROR_M : The paper's figures.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (32), (39)–(43), §4.3, Table 3, Fig. 11.

    Examples
    --------
    >>> from dstoolkit.studies import run_table3
    >>> table = run_table3(runs=2, cases=[(1.3, 27.0)], methods=("dependent_evidence", "direct"),
    ...                    progress=False)
    >>> [(row.method, row.runs, row.paper_m) for row in table.rows]
    [('dependent_evidence', 2, 0.0126), ('direct', 2, 0.238)]
    """
    unknown = set(methods) - set(METHODS)
    if unknown:
        raise InvalidInputError(f"unknown methods {sorted(unknown)}; choose from {METHODS}")
    if simulation not in ("frequency", "waveform"):
        raise InvalidInputError(f"simulation must be 'frequency' or 'waveform', got {simulation!r}")
    if runs < 1:
        raise InvalidInputError(f"runs must be >= 1, got {runs}")
    cases = list(cases)
    filters = paper_filters(seed)
    seeds = np.random.SeedSequence(seed).generate_state(len(cases))
    total = len(cases) * (len(methods) + (runs if simulation == "waveform" else 0))
    bar = _progress_bar(
        total=total, desc=f"Table 3 ({simulation})", disable=not progress, unit="step"
    )
    rows, per_run = [], {}
    for (level, temp), case_seed in zip(cases, seeds, strict=True):
        if simulation == "frequency":
            batches = frequency_readings(level, temp, runs, int(case_seed))
        else:
            batches = waveform_readings(
                level, temp, runs, int(case_seed), conditions, progress=bar.update
            )
        orders = [estimate_orders(b, order_rule) for b in batches]
        for method in methods:
            bar.set_postfix_str(f"L={level} m {method}")
            start = time.perf_counter()
            errors = np.concatenate(
                [
                    np.mean(np.abs(estimate_levels(method, b, n, filters) - level), axis=1)
                    for b, n in zip(batches, orders, strict=True)
                ]
            )
            elapsed = time.perf_counter() - start
            per_run[(level, method)] = errors
            rows.append(
                Table3Row(
                    level,
                    temp,
                    method,
                    float(errors.mean()),
                    int(errors.size),
                    elapsed / errors.size,
                    TABLE3_MEAN_ABS_ERROR_M.get(level, {}).get(method),
                )
            )
            bar.update(1)
    bar.close()
    return Table3(rows, simulation, seed, order_rule, per_run)


class _NoBar:
    """Stands in for a tqdm bar when tqdm (an optional dependency) is not installed."""

    def update(self, n: int = 1) -> None:
        pass

    def set_postfix_str(self, text: str) -> None:
        pass

    def close(self) -> None:
        pass


def _progress_bar(*, total: int, desc: str, disable: bool, unit: str) -> Any:
    """Make a tqdm progress bar when tqdm is installed and wanted, else a silent stand-in."""
    if disable:
        return _NoBar()
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return _NoBar()
    return tqdm(total=total, desc=desc, unit=unit)
