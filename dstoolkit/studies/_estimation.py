"""One gauge run (the paper's Figs. 10–11) and the studies beyond the paper's Table 3.

The chapters *Estimating the level* and *Beyond the paper* call these; every function
reuses the Table 3 machinery of :mod:`dstoolkit.studies` (the same readings, the same
order rules, the same filters with the paper's settings) so that a single run, a study and
Table 3 cannot disagree about what a method is.

* :func:`gauge_run`: one sweep at one level, the frequency estimates of every method per
  step (Fig. 10) and the level of every step by eq. 32 (Fig. 11), with the true orders and
  frequencies known to the simulation.
* :func:`table3_rows`, :func:`table3_readings`, :func:`filter_level_errors`: Table 3 beside
  the paper's figures, the very readings of one of its cases, and Table 3's figure for
  filters with other settings (another start, the restart variant of Nassreddine's).
* :func:`tracking_data` and :func:`noise_mismatch`: the gauge's eqs. 39–40 simulated with
  the paper's noises, filtered by methods that assume other noise bounds.
* :func:`start_study`: the paper's start x̂_1 = z_1 against a start corrected by E[w].
* :func:`order_rule_study`: how n_k is estimated (eq. 43, series fit, truth) against the
  level error, for both simulations.
* :func:`example_comparison`: every filter on the two-dimensional predator–prey example of
  :mod:`dstoolkit.filters`.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from dstoolkit._reprs import ShortFloatDict
from dstoolkit.errors import InconsistentDataError, InvalidInputError
from dstoolkit.filters import (
    BoundedErrorFilter,
    BoundedNoise,
    ComparisonSettings,
    DependentEvidenceFilter,
    Filter,
    StateSpaceModel,
    filter_named,
    registered_filters,
    simulate_lotka_volterra,
)
from dstoolkit.gauge import (
    GAUGE_OBS_NOISE,
    GAUGE_STATE_NOISE,
    PAPER_SWEEP,
    fit_resonance_series,
    gauge_state_space_model,
    level_from_resonance,
    resonance_frequencies,
    speed_of_sound,
    typical_conditions,
)

from ._experiments import (
    CaseReadings,
    OrderRule,
    Simulation,
    Table3,
    estimate_levels,
    estimate_orders,
    frequency_readings,
    paper_filters,
    waveform_readings,
)
from ._paper_results import TABLE3_CASES, TABLE3_MEAN_ABS_ERROR_M

#: The methods of the paper's Figs. 10–11 (the readings are drawn too).
FIG10_METHODS: tuple[str, ...] = (filter_named("paper"), filter_named("rival"))
#: The methods of the paper's Table 3: its two filters and the direct measurement.
TABLE3_METHODS: tuple[str, ...] = (*FIG10_METHODS, "direct")
#: The toolkit's own filters, by the names the plots know (the first entries of
#: :func:`dstoolkit.filters.registered_filters`; the comparisons run every registered one).
ALL_FILTERS: tuple[str, ...] = tuple(entry.name for entry in registered_filters())


def _methods(methods: Sequence[str] | None) -> Sequence[str]:
    """Return ``methods``, or the names of every registered filter when None."""
    return [entry.name for entry in registered_filters()] if methods is None else methods


# -- one run: the paper's Figs. 10 and 11 ------------------------------------------------------


@dataclass(frozen=True)
class GaugeRun:
    """One simulated sweep filtered by several methods (the paper's Figs. 10–11).

    Made by :func:`gauge_run`. Arrays are per reading k = 1..K.

    Parameters
    ----------
    level_m : float
        L, m.
    temperature_c : float
        Air temperature, °C.
    simulation : str
        ``"frequency"`` or ``"waveform"``.
    order_rule : str
        How the orders were obtained: ``"eq43"``, ``"fit"`` or ``"true"``.
    speed_of_sound : float
        c, m/s.
    truth : numpy.ndarray, shape (K,)
        f_k = n_k c/(2L) of the resonance behind each reading, Hz.
    readings : numpy.ndarray, shape (K,)
        z_k, Hz.
    true_orders : numpy.ndarray of int, shape (K,)
        The true n_k.
    orders : numpy.ndarray of int, shape (K−1,)
        The orders the rule gives, used by eqs. (39) and (32).
    estimates : dict of str to numpy.ndarray, optional
        Method to x̂_k, shape (K,), Hz.

    See Also
    --------
    gauge_run : Makes it.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), Figs. 10–11.
    """

    level_m: float
    temperature_c: float
    simulation: str
    order_rule: str
    speed_of_sound: float
    truth: np.ndarray
    readings: np.ndarray
    true_orders: np.ndarray
    orders: np.ndarray
    estimates: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def wrong_orders(self) -> float:
        """Fraction of the steps whose n_k differs from the true order."""
        return float(np.mean(self.orders != self.true_orders[:-1]))

    def levels(self) -> dict[str, np.ndarray]:
        """Compute the level of every step, L̂_k = n_k c/(2 x̂_k), k = 1..K−1.

        Returns
        -------
        dict of str to numpy.ndarray
            ``"direct"`` (x̂ = z) and each method to L̂, shape (K−1,), m.

        References
        ----------
        Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (32), Fig. 11.
        """
        out = {"direct": level_from_resonance(self.readings[:-1], self.orders, self.speed_of_sound)}
        for name, x in self.estimates.items():
            out[name] = level_from_resonance(x[:-1], self.orders, self.speed_of_sound)
        return out

    def frequency_errors(self) -> dict[str, np.ndarray]:
        """|x̂_k − f_k| per step; ``"direct"`` is |z_k − f_k|.

        Returns
        -------
        dict of str to numpy.ndarray
            Method to the errors, shape (K,), Hz.

        References
        ----------
        Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), Fig. 10.
        """
        out = {"direct": np.abs(self.readings - self.truth)}
        out.update({name: np.abs(x - self.truth) for name, x in self.estimates.items()})
        return out

    def summary(self) -> dict[str, float]:
        """Mean |x̂ − f| (Hz) and mean |L̂ − L| (m) of every method, and the wrong orders.

        Returns
        -------
        dict of str to float
            Label (with its unit) to value.
        """
        freq = {
            f"{m}: mean |x̂ − f| (Hz)": float(e.mean()) for m, e in self.frequency_errors().items()
        }
        lev = {
            f"{m}: mean |L̂ − L| (m)": float(np.mean(np.abs(v - self.level_m)))
            for m, v in self.levels().items()
        }
        return ShortFloatDict({**freq, **lev, "wrong orders": self.wrong_orders})


def _with_true_orders(case: CaseReadings) -> CaseReadings:
    """Add the true order of each reading of synthesised recordings.

    Table 3's waveform simulation keeps only z.

    The detector leaves the sweep-rate and latency offsets in (as the paper's), so a
    reading of order n sits near n f_F + κL/c + κτ; the simulation knows both offsets and
    gives each reading the order of the nearest n f_F once they are removed (the echo shift
    left over is a few hertz, below f_F/2 at every Table 3 level).
    """
    latency = typical_conditions().latency_s
    offset = PAPER_SWEEP.rate * (case.level_m / case.speed_of_sound + latency)
    f_f = case.speed_of_sound / (2.0 * case.level_m)
    orders = np.rint((case.readings - offset) / f_f).astype(int)
    return CaseReadings(
        case.level_m, case.temperature_c, case.speed_of_sound, case.readings, orders
    )


def filter_states(
    method: str,
    case: CaseReadings,
    orders: np.ndarray,
    filters: Mapping[str, Filter[Any, Any]],
    model: StateSpaceModel | None = None,
) -> np.ndarray:
    """x̂_k of every run by one of ``filters`` on the gauge model.

    Parameters
    ----------
    method : str
        A key of ``filters``.
    case : CaseReadings
        The readings, (runs, K).
    orders : numpy.ndarray of int, shape (runs, K−1)
        The orders n_k.
    filters : mapping of str to dstoolkit.filters.Filter
        The filters by name.
    model : dstoolkit.filters.StateSpaceModel, optional
        The model (default :func:`~dstoolkit.gauge.gauge_state_space_model`).

    Returns
    -------
    numpy.ndarray, shape (runs, K)
        x̂_k, Hz.
    """
    model = gauge_state_space_model() if model is None else model
    return (
        filters[method].run_batch(model, case.readings[..., None], inputs=orders).estimates[..., 0]
    )


def gauge_run(
    level_m: float = 4.6,
    temperature_c: float = 26.5,
    simulation: Simulation = "frequency",
    order_rule: OrderRule = "eq43",
    seed: int = 0,
    methods: Sequence[str] = FIG10_METHODS,
) -> GaugeRun:
    """One sweep at ``level_m`` filtered by ``methods`` (the paper's Figs. 10–11).

    The filters have the paper's settings (:func:`paper_filters`). The true orders are known
    in both simulations, so ``order_rule="true"`` works for either.

    Parameters
    ----------
    level_m : float, optional
        L, m (default 4.6).
    temperature_c : float, optional
        Air temperature, °C (default 26.5).
    simulation : {"frequency", "waveform"}, optional
        As in :func:`run_table3`.
    order_rule : {"eq43", "fit", "true"}, optional
        As in :func:`run_table3`.
    seed : int, optional
        Seed of the readings and of the particle filter.
    methods : sequence of str, optional
        Keys of :func:`paper_filters` (default the two of Fig. 10,
        ``("dependent_evidence", "nassreddine")``).

    Returns
    -------
    GaugeRun
        The readings, the truth and every method's estimates.

    Raises
    ------
    InvalidInputError
        An unknown simulation, order rule or method.

    See Also
    --------
    run_table3 : The same on many runs and levels.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (32), (39)–(43), Figs. 10–11.

    Examples
    --------
    >>> from dstoolkit.studies import gauge_run
    >>> run = gauge_run(4.6, 26.5, methods=("dependent_evidence",))
    >>> run.readings.shape, run.orders.shape, sorted(run.levels())
    ((40,), (39,), ['dependent_evidence', 'direct'])
    """
    if simulation == "frequency":
        (case,) = frequency_readings(level_m, temperature_c, 1, seed)
    elif simulation == "waveform":
        (case,) = (_with_true_orders(b) for b in waveform_readings(level_m, temperature_c, 1, seed))
    else:
        raise InvalidInputError(f"simulation must be 'frequency' or 'waveform', got {simulation!r}")
    orders = estimate_orders(case, order_rule)
    filters = paper_filters(seed)
    unknown = set(methods) - set(filters)
    if unknown:
        raise InvalidInputError(f"unknown methods {sorted(unknown)}; choose from {sorted(filters)}")
    estimates = {m: filter_states(m, case, orders, filters)[0] for m in methods}
    true_orders = np.asarray(case.true_orders)[0]
    return GaugeRun(
        level_m=float(level_m),
        temperature_c=float(temperature_c),
        simulation=simulation,
        order_rule=order_rule,
        speed_of_sound=case.speed_of_sound,
        truth=true_orders * case.speed_of_sound / (2.0 * level_m),
        readings=case.readings[0],
        true_orders=true_orders,
        orders=orders[0],
        estimates=estimates,
    )


def table3_rows(table: Table3, methods: Sequence[str] = TABLE3_METHODS) -> list[list[Any]]:
    """Rows ``[L, T, ours, paper, ours, paper, ...]`` of Table 3 for ``methods``.

    Parameters
    ----------
    table : Table3
        The reproduced table.
    methods : sequence of str, optional
        Methods of the table, in the order wanted (default the three the paper prints).

    Returns
    -------
    list of list
        Per case: the level and temperature as text, then each method's error (m) beside the
        paper's printed value (or "—" where it has none).

    Raises
    ------
    KeyError
        A method the table does not hold.

    See Also
    --------
    run_table3 : Makes the table.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), Table 3.

    Examples
    --------
    >>> from dstoolkit.studies import run_table3, table3_rows
    >>> table = run_table3(runs=2, cases=[(1.3, 27.0)], methods=("direct",), progress=False)
    >>> row = table3_rows(table, methods=("direct",))[0]
    >>> row[:2], row[3]
    (['1.3', '27.0'], 0.238)
    """
    rows = []
    for level, temp in dict.fromkeys((r.level_m, r.temperature_c) for r in table.rows):
        row: list[Any] = [f"{level:.1f}", f"{temp:.1f}"]
        for m in methods:
            row += [table.error(level, m), TABLE3_MEAN_ABS_ERROR_M.get(level, {}).get(m, "—")]
        rows.append(row)
    return rows


# -- the filters with assumed noises -----------------------------------------------------------


def all_filters(
    seed: int = 0, *, p: int = 3, start: str = "observation", n_particles: int = 500
) -> dict[str, Any]:
    """Every registered filter with the paper's settings and the rivals' defaults.

    The evidential filters use p cuts, ε = 0.05 and Θ = mode ± 100σ of the noise the model
    assumes, and fall back instead of raising on total conflict, as in Table 3; the
    bounded-error filter restarts from the reading when its box becomes empty
    (:func:`noise_mismatch` also runs it strictly to count the runs where it fails).

    Parameters
    ----------
    seed : int, optional
        Seed of the particle filter.
    p : int, optional
        α-cuts of the evidential filters (default 3).
    start : str, optional
        The paper's filter's x̂_1 (default ``"observation"``).
    n_particles : int, optional
        Particles of the particle filter (default 500).

    Returns
    -------
    dict of str to dstoolkit.filters.Filter
        The filters of :func:`dstoolkit.filters.registered_filters`, by their names
        (:data:`ALL_FILTERS` first).

    See Also
    --------
    paper_filters : The filters of Table 3.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3.

    Examples
    --------
    >>> from dstoolkit.studies import ALL_FILTERS, all_filters
    >>> tuple(all_filters()) == ALL_FILTERS
    True
    """
    settings = ComparisonSettings(seed=seed, p=p, start=start, n_particles=n_particles)
    return {entry.name: entry.make(settings) for entry in registered_filters()}


@dataclass(frozen=True)
class TrackingData:
    """Runs of the gauge's eqs. (39)–(40) with both noises. Made by :func:`tracking_data`.

    Parameters
    ----------
    level_m : float
        L, m.
    temperature_c : float
        Air temperature, °C.
    truth : numpy.ndarray, shape (runs, K)
        The states x_k, Hz.
    readings : numpy.ndarray, shape (runs, K)
        z_k, Hz.
    orders : numpy.ndarray of int, shape (runs, K−1)
        The true orders n_1..n_{K−1} that drive eq. (39).
    state_noise : dstoolkit.filters.BoundedNoise
        The true v, Hz.
    obs_noise : dstoolkit.filters.BoundedNoise
        The true w, Hz.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (39)–(40).
    """

    level_m: float
    temperature_c: float
    truth: np.ndarray
    readings: np.ndarray
    orders: np.ndarray
    state_noise: BoundedNoise
    obs_noise: BoundedNoise


def tracking_data(
    level_m: float = 4.6,
    temperature_c: float = 26.5,
    runs: int = 20,
    seed: int = 0,
    state_noise: BoundedNoise = GAUGE_STATE_NOISE,
    obs_noise: BoundedNoise = GAUGE_OBS_NOISE,
) -> TrackingData:
    """Simulate the gauge's eqs. (39)–(40) from the first resonance of the band.

    x_{k+1} = x_k (n_k + 1)/n_k + v_k, z_k = x_k − w_k, with the true orders (the estimator
    of n_k is studied apart) and the given true noises.

    Parameters
    ----------
    level_m : float, optional
        L, m (default 4.6).
    temperature_c : float, optional
        Air temperature, °C (default 26.5).
    runs : int, optional
        Number of runs (default 20).
    seed : int, optional
        Seed of the noises.
    state_noise : dstoolkit.filters.BoundedNoise, optional
        The true v, Hz (default the paper's).
    obs_noise : dstoolkit.filters.BoundedNoise, optional
        The true w, Hz (default the paper's).

    Returns
    -------
    TrackingData
        Truth and readings (runs, K), Hz, and the orders (runs, K−1).

    See Also
    --------
    noise_mismatch : Filters the data with other assumed noises.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (39)–(40), Tables 1–2.

    Examples
    --------
    >>> from dstoolkit.studies import tracking_data
    >>> data = tracking_data(runs=3)
    >>> data.readings.shape, data.orders.shape
    ((3, 40), (3, 39))
    """
    c = float(speed_of_sound(temperature_c))
    n, f = resonance_frequencies(level_m, c)
    model = gauge_state_space_model(state_noise, obs_noise)
    x, z = model.simulate([f[0]], n.size, np.random.default_rng(seed), inputs=n[:-1], runs=runs)
    return TrackingData(
        float(level_m),
        float(temperature_c),
        x[..., 0],
        z[..., 0],
        np.broadcast_to(n[:-1], (runs, n.size - 1)),
        state_noise,
        obs_noise,
    )


@dataclass(frozen=True)
class MismatchResult:
    """Errors of every method on :class:`TrackingData` under assumed noises.

    Made by :func:`noise_mismatch`.

    Parameters
    ----------
    errors : dict of str to numpy.ndarray
        Method to |x̂ − x|, shape (runs, K), Hz. The bounded-error filter's are those of the
        variant that restarts from the reading.
    seconds : dict of str to float
        Method to its wall time over all runs, s.
    inconsistent_runs : float, optional
        Fraction of runs in which the strict bounded-error filter raised
        :class:`~dstoolkit.errors.InconsistentDataError`.
    message : str, optional
        The first such message ("" when it never failed).
    """

    errors: dict[str, np.ndarray]
    seconds: dict[str, float]
    inconsistent_runs: float = 0.0
    message: str = ""

    def mean_errors(self) -> dict[str, float]:
        """Mean |x̂ − x| of each method over runs and steps.

        Returns
        -------
        dict of str to float
            Method to the mean error, Hz.
        """
        return {m: float(e.mean()) for m, e in self.errors.items()}

    def worst_errors(self) -> dict[str, float]:
        """Largest |x̂ − x| of each method over runs and steps.

        Returns
        -------
        dict of str to float
            Method to the largest error, Hz.
        """
        return {m: float(e.max()) for m, e in self.errors.items()}


def bounded_error_failures(
    model: StateSpaceModel, data: TrackingData, resets: np.ndarray | None = None
) -> tuple[float, str]:
    """How often the strict bounded-error filter finds the data inconsistent with the bounds.

    A strict run fails exactly where the filter that restarts from the reading first restarts
    (both compute the same boxes until then), so the runs are filtered once, in a batch, by
    the restarting filter (or its ``resets`` are passed); only the first failed run is filtered
    strictly again, for its message.

    Parameters
    ----------
    model : dstoolkit.filters.StateSpaceModel
        The model with the assumed bounds.
    data : TrackingData
        The runs.
    resets : numpy.ndarray of bool, shape (runs, K), optional
        The restarting filter's resets, if already computed.

    Returns
    -------
    fraction : float
        Fraction of the runs that fail.
    message : str
        The first failure's message ("" when none fails).

    See Also
    --------
    dstoolkit.filters.BoundedErrorFilter

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §1 (set-membership estimation under bounded noise).

    Examples
    --------
    Bounds half as wide as the noise's make the data inconsistent:

    >>> from dstoolkit.gauge import GAUGE_OBS_NOISE, GAUGE_STATE_NOISE, gauge_state_space_model
    >>> from dstoolkit.studies import bounded_error_failures, scaled_noise, tracking_data
    >>> data = tracking_data(runs=3)
    >>> model = gauge_state_space_model(scaled_noise(GAUGE_STATE_NOISE, 0.5),
    ...                                 scaled_noise(GAUGE_OBS_NOISE, 0.5))
    >>> fraction, message = bounded_error_failures(model, data)
    >>> fraction, message.startswith("inconsistent data")
    (1.0, True)
    """
    if resets is None:
        resets = (
            BoundedErrorFilter(on_inconsistent="reset")
            .run_batch(model, data.readings, inputs=data.orders)
            .diagnostics["resets"]
        )
    failed = np.flatnonzero(np.any(resets, axis=1))
    message = ""
    if failed.size:
        try:
            BoundedErrorFilter(on_inconsistent="raise").run(
                model, data.readings[failed[0]], inputs=data.orders[failed[0]]
            )
        except InconsistentDataError as exc:
            message = str(exc)
    return failed.size / data.readings.shape[0], message


def noise_mismatch(
    data: TrackingData,
    state_noise: BoundedNoise,
    obs_noise: BoundedNoise,
    methods: Sequence[str] | None = None,
    seed: int = 0,
    start: str = "observation",
) -> MismatchResult:
    """Filter ``data`` (made with the true noises) by methods that assume other noises.

    Parameters
    ----------
    data : TrackingData
        The runs.
    state_noise : dstoolkit.filters.BoundedNoise
        The v the methods assume, Hz.
    obs_noise : dstoolkit.filters.BoundedNoise
        The w the methods assume, Hz.
    methods : sequence of str, optional
        Names of :func:`all_filters` (default: every registered filter).
    seed : int, optional
        Seed of the particle filter.
    start : str, optional
        The paper's filter's x̂_1.

    Returns
    -------
    MismatchResult
        The errors (runs, K), Hz, and wall times of every method, and how often the strict
        bounded-error filter fails.

    See Also
    --------
    bound_scale_study : This study over a range of bound scales.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (39)–(40), Tables 1–2.

    Examples
    --------
    >>> from dstoolkit.gauge import GAUGE_OBS_NOISE, GAUGE_STATE_NOISE
    >>> from dstoolkit.studies import noise_mismatch, tracking_data
    >>> data = tracking_data(runs=3)
    >>> result = noise_mismatch(data, GAUGE_STATE_NOISE, GAUGE_OBS_NOISE,
    ...                         methods=("kalman", "bounded_error"))
    >>> result.errors["kalman"].shape, result.inconsistent_runs
    ((3, 40), 0.0)
    """
    model = gauge_state_space_model(state_noise, obs_noise)
    filters = all_filters(seed, start=start)
    methods = _methods(methods)
    errors, seconds, resets = {}, {}, None
    for m in methods:
        began = time.perf_counter()
        result = filters[m].run_batch(model, data.readings, inputs=data.orders)
        x = result.estimates[..., 0]
        if m == "bounded_error":  # its restarts also tell where the strict filter fails
            resets = result.diagnostics["resets"]
        seconds[m] = time.perf_counter() - began
        errors[m] = np.abs(x - data.truth)
    failed, message = (
        bounded_error_failures(model, data, resets) if "bounded_error" in methods else (0.0, "")
    )
    return MismatchResult(errors, seconds, failed, message)


def scaled_noise(noise: BoundedNoise, scale: float, mode_shift: float = 0.0) -> BoundedNoise:
    """Scale a noise's bounds about its mode by ``scale``, and shift it by ``mode_shift``.

    Parameters
    ----------
    noise : dstoolkit.filters.BoundedNoise
        A one-dimensional noise.
    scale : float
        Factor on the distances of the bounds from the mode.
    mode_shift : float, optional
        Shift of the mode and the bounds, in the noise's unit (default 0).

    Returns
    -------
    dstoolkit.filters.BoundedNoise
        The scaled noise.

    Raises
    ------
    EvidenceError
        A negative scale (the bounds would cross the mode).

    Examples
    --------
    >>> from dstoolkit.filters import BoundedNoise
    >>> from dstoolkit.studies import scaled_noise
    >>> noise = scaled_noise(BoundedNoise(-1.0, 0.0, 2.0), 2.0, mode_shift=1.0)
    >>> float(noise.lower[0]), float(noise.mode[0]), float(noise.upper[0])
    (-1.0, 1.0, 5.0)
    """
    c = noise.mode + mode_shift
    return BoundedNoise(
        c - scale * (noise.mode - noise.lower), c, c + scale * (noise.upper - noise.mode)
    )


def bound_scale_study(
    data: TrackingData,
    scales: Sequence[float],
    methods: Sequence[str] | None = None,
    seed: int = 0,
    start: str = "observation",
) -> dict[float, MismatchResult]:
    """:func:`noise_mismatch` with both noises' bounds scaled about their modes.

    Parameters
    ----------
    data : TrackingData
        The runs.
    scales : sequence of float
        The factors on the bounds' distances from the modes.
    methods : sequence of str, optional
        Names of :func:`all_filters` (default: every registered filter).
    seed : int, optional
        Seed of the particle filter.
    start : str, optional
        The paper's filter's x̂_1.

    Returns
    -------
    dict of float to MismatchResult
        Scale to the result.

    See Also
    --------
    scaled_noise, noise_mismatch

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), Tables 1–2.

    Examples
    --------
    >>> from dstoolkit.studies import bound_scale_study, tracking_data
    >>> study = bound_scale_study(tracking_data(runs=2), [1.0, 2.0], methods=("kalman",))
    >>> sorted(study)
    [1.0, 2.0]
    """
    return {
        float(s): noise_mismatch(
            data,
            scaled_noise(data.state_noise, s),
            scaled_noise(data.obs_noise, s),
            methods,
            seed,
            start,
        )
        for s in scales
    }


# -- the start value -------------------------------------------------------------------------


def start_study(
    data: TrackingData, starts: Sequence[str] = ("observation", "mean_corrected")
) -> dict[str, np.ndarray]:
    """|x̂_k − x_k| of the paper's filter started from z_1 (the paper) and from z_1 + E[w].

    The model assumes the data's true noises.

    Parameters
    ----------
    data : TrackingData
        The runs.
    starts : sequence of str, optional
        The starts to compare (default ``"observation"`` and ``"mean_corrected"``).

    Returns
    -------
    dict of str to numpy.ndarray
        Start to the errors, shape (runs, K), Hz.

    See Also
    --------
    dstoolkit.filters.DependentEvidenceFilter

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §3.2 (the start x̂_1).

    Examples
    --------
    >>> from dstoolkit.studies import start_study, tracking_data
    >>> errors = start_study(tracking_data(runs=2))
    >>> sorted(errors), errors["observation"].shape
    (['mean_corrected', 'observation'], (2, 40))
    """
    model = gauge_state_space_model(data.state_noise, data.obs_noise)
    return {
        s: np.abs(
            DependentEvidenceFilter(start=s, on_conflict="predict")
            .run_batch(model, data.readings, inputs=data.orders)
            .estimates[..., 0]
            - data.truth
        )
        for s in starts
    }


# -- the estimator of n_k ----------------------------------------------------------------------


@dataclass(frozen=True)
class OrderRuleStudy:
    """Level errors per order rule and method at every level, for one simulation.

    Made by :func:`order_rule_study`.

    Parameters
    ----------
    simulation : str
        ``"frequency"`` or ``"waveform"``.
    levels : numpy.ndarray, shape (C,)
        The levels of the cases, m.
    errors : dict of str to dict of str to numpy.ndarray
        Rule to method to the mean absolute level error per case, shape (C,), m.
    wrong : dict of str to numpy.ndarray
        Rule to the fraction of wrong orders per case, shape (C,).
    slope : numpy.ndarray, shape (C,)
        Mean absolute error of the series fit's own level c/(2 f_F) (no orders needed), m.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (32) and (43).
    """

    simulation: str
    levels: np.ndarray
    errors: dict[str, dict[str, np.ndarray]]
    wrong: dict[str, np.ndarray]
    slope: np.ndarray


def order_rule_study(
    simulation: Simulation = "frequency",
    runs: int = 30,
    seed: int = 0,
    rules: Sequence[OrderRule] = ("eq43", "fit", "true"),
    methods: Sequence[str] = ("direct", FIG10_METHODS[0]),
    cases: Sequence[tuple[float, float]] = TABLE3_CASES,
) -> OrderRuleStudy:
    """Level errors of ``methods`` with n_k from each rule, on the same readings.

    The readings are Table 3's (the same seeds). In the waveform simulation the true orders
    come from the known offsets, as in :func:`gauge_run`.

    Parameters
    ----------
    simulation : {"frequency", "waveform"}, optional
        As in :func:`run_table3`.
    runs : int, optional
        Runs per case (default 30).
    seed : int, optional
        Seed, as in :func:`run_table3`.
    rules : sequence of str, optional
        Order rules (default ``"eq43"``, ``"fit"``, ``"true"``).
    methods : sequence of str, optional
        ``"direct"`` and names of :func:`paper_filters`.
    cases : sequence of (float, float), optional
        (level in m, temperature in °C) (default :data:`TABLE3_CASES`).

    Returns
    -------
    OrderRuleStudy
        The errors per rule, method and case, and the wrong orders per rule.

    See Also
    --------
    dstoolkit.gauge.orders_eq43, dstoolkit.gauge.fit_resonance_series

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (32) and (43), Table 3.

    Examples
    --------
    >>> from dstoolkit.studies import order_rule_study
    >>> study = order_rule_study(runs=2, cases=[(1.3, 27.0)], methods=("direct",))
    >>> sorted(study.errors), study.errors["true"]["direct"].shape
    (['eq43', 'fit', 'true'], (1,))
    """
    filters = paper_filters(seed)
    seeds = np.random.SeedSequence(seed).generate_state(len(cases))
    errors: dict[str, dict[str, np.ndarray]] = {
        r: {m: np.empty(len(cases)) for m in methods} for r in rules
    }
    wrong: dict[str, np.ndarray] = {r: np.empty(len(cases)) for r in rules}
    slope = np.empty(len(cases))
    for i, ((level, temp), s) in enumerate(zip(cases, seeds, strict=True)):
        if simulation == "frequency":
            batches = frequency_readings(level, temp, runs, int(s))
        else:
            batches = [_with_true_orders(b) for b in waveform_readings(level, temp, runs, int(s))]
        slope[i] = np.mean(
            [
                abs(fit_resonance_series(row, offset_hz=None).level(b.speed_of_sound) - level)
                for b in batches
                for row in b.readings
            ]
        )
        for r in rules:
            orders = [estimate_orders(b, r) for b in batches]
            wrong[r][i] = np.mean(
                np.concatenate(
                    [
                        (n != np.asarray(b.true_orders)[:, :-1]).ravel()
                        for b, n in zip(batches, orders, strict=True)
                    ]
                )
            )
            for m in methods:
                errors[r][m][i] = np.mean(
                    np.concatenate(
                        [
                            np.mean(np.abs(estimate_levels(m, b, n, filters) - level), axis=1)
                            for b, n in zip(batches, orders, strict=True)
                        ]
                    )
                )
    return OrderRuleStudy(simulation, np.array([c[0] for c in cases]), errors, wrong, slope)


def table3_readings(
    level_m: float,
    temperature_c: float,
    runs: int,
    seed: int = 0,
    simulation: Simulation = "frequency",
    cases: Sequence[tuple[float, float]] = TABLE3_CASES,
) -> list[CaseReadings]:
    """Draw the readings :func:`run_table3` draws for one case, with the true orders.

    The same ``runs``, ``seed`` and ``cases`` give the same readings (the case's seed is its
    entry of ``SeedSequence(seed)``), in both simulations.

    Parameters
    ----------
    level_m : float
        L, m: one of the levels of ``cases``.
    temperature_c : float
        Air temperature, °C.
    runs : int
        Runs.
    seed : int, optional
        Seed, as in :func:`run_table3`.
    simulation : {"frequency", "waveform"}, optional
        As in :func:`run_table3`.
    cases : sequence of (float, float), optional
        The cases (default :data:`TABLE3_CASES`).

    Returns
    -------
    list of CaseReadings
        One batch per number of readings (one in the frequency simulation).

    Raises
    ------
    InvalidInputError
        A level that is not one of the cases.

    See Also
    --------
    filter_level_errors : Table 3's figure for other filters on these readings.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), Table 3.

    Examples
    --------
    >>> from dstoolkit.studies import table3_readings
    >>> (case,) = table3_readings(1.3, 27.0, runs=2)
    >>> case.readings.shape == case.true_orders.shape
    True
    """
    levels = [c[0] for c in cases]
    if level_m not in levels:
        raise InvalidInputError(f"level {level_m} m is not one of the cases {levels}")
    case_seed = int(np.random.SeedSequence(seed).generate_state(len(cases))[levels.index(level_m)])
    if simulation == "frequency":
        return frequency_readings(level_m, temperature_c, runs, case_seed)
    return [
        _with_true_orders(b) for b in waveform_readings(level_m, temperature_c, runs, case_seed)
    ]


def filter_level_errors(
    filters: Mapping[str, Filter[Any, Any]],
    batches: Sequence[CaseReadings],
    order_rule: OrderRule = "true",
) -> dict[str, float]:
    """Table 3's figure for every filter of ``filters`` (any settings) on the same readings.

    Parameters
    ----------
    filters : mapping of str to dstoolkit.filters.Filter
        The filters by name.
    batches : sequence of CaseReadings
        The readings (:func:`table3_readings`).
    order_rule : {"eq43", "fit", "true"}, optional
        How n_k is obtained (default ``"true"``).

    Returns
    -------
    dict of str to float
        Name to the mean over runs of the mean |L̂_k − L|, m.

    See Also
    --------
    run_table3 : The paper's filters on every case.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (32), Table 3.

    Examples
    --------
    >>> from dstoolkit.filters import KalmanFilter
    >>> from dstoolkit.studies import filter_level_errors, table3_readings
    >>> errors = filter_level_errors({"kalman": KalmanFilter()}, table3_readings(1.3, 27.0, 2))
    >>> sorted(errors)
    ['kalman']
    """
    orders = [estimate_orders(b, order_rule) for b in batches]
    return {
        name: float(
            np.mean(
                np.concatenate(
                    [
                        np.mean(np.abs(estimate_levels(name, b, n, filters) - b.level_m), axis=1)
                        for b, n in zip(batches, orders, strict=True)
                    ]
                )
            )
        )
        for name in filters
    }


# -- the two-dimensional example ---------------------------------------------------------------


@dataclass(frozen=True)
class ExampleComparison:
    """Every filter on the predator–prey example. Made by :func:`example_comparison`.

    Parameters
    ----------
    model : dstoolkit.filters.StateSpaceModel
        The example's model.
    truth : numpy.ndarray, shape (runs, T, 2)
        The states (log-populations).
    readings : numpy.ndarray, shape (runs, T, 2)
        The readings.
    estimates : dict of str to numpy.ndarray
        Method to x̂, shape (runs, T, 2).
    seconds_per_run : dict of str to float
        Method to its wall time per run, s.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §3 (the filter on a general model).
    """

    model: StateSpaceModel
    truth: np.ndarray
    readings: np.ndarray
    estimates: dict[str, np.ndarray]
    seconds_per_run: dict[str, float]

    def rms_errors(self) -> dict[str, float]:
        """Root mean square of |x̂ − x| (Euclidean, log-populations) over runs and steps.

        Returns
        -------
        dict of str to float
            Method to the RMS error.
        """
        return {
            m: float(np.sqrt(np.mean(np.sum((x - self.truth) ** 2, axis=-1))))
            for m, x in self.estimates.items()
        }

    def step_errors(self, run: int = 0) -> dict[str, np.ndarray]:
        """|x̂_k − x_k| (Euclidean) per step of one run.

        Parameters
        ----------
        run : int, optional
            The run (default 0).

        Returns
        -------
        dict of str to numpy.ndarray
            Method to the errors, shape (T,).
        """
        return {
            m: np.linalg.norm(x[run] - self.truth[run], axis=-1) for m, x in self.estimates.items()
        }


def example_comparison(
    steps: int = 60,
    runs: int = 4,
    seed: int = 0,
    p: int = 2,
    methods: Sequence[str] | None = None,
) -> ExampleComparison:
    """Run every filter on :func:`~dstoolkit.filters.simulate_lotka_volterra`.

    The paper's filter fuses (p + 1)^10 products per step on a two-dimensional state
    (1 048 576 for p = 3), so the chapter uses p = 2.

    Parameters
    ----------
    steps : int, optional
        Steps T (default 60).
    runs : int, optional
        Runs (default 4).
    seed : int, optional
        Seed of the simulation and the particle filter.
    p : int, optional
        α-cuts of both evidential filters (default 2).
    methods : sequence of str, optional
        Names of :func:`all_filters` (default: every registered filter).

    Returns
    -------
    ExampleComparison
        Truth, readings and every method's estimates, (runs, T, 2).

    See Also
    --------
    dstoolkit.filters.simulate_lotka_volterra

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §3.

    Examples
    --------
    >>> from dstoolkit.studies import example_comparison
    >>> result = example_comparison(steps=10, runs=2, methods=("kalman",))
    >>> result.estimates["kalman"].shape
    (2, 10, 2)
    """
    model, x, z = simulate_lotka_volterra(steps=steps, runs=runs, seed=seed)
    filters = all_filters(seed, p=p)
    estimates, seconds = {}, {}
    for m in _methods(methods):
        start = time.perf_counter()
        estimates[m] = filters[m].run_batch(model, z).estimates
        seconds[m] = (time.perf_counter() - start) / runs
    return ExampleComparison(model, x, z, estimates, seconds)


__all__ = [
    "ALL_FILTERS",
    "FIG10_METHODS",
    "ExampleComparison",
    "GaugeRun",
    "MismatchResult",
    "OrderRuleStudy",
    "TrackingData",
    "all_filters",
    "bound_scale_study",
    "bounded_error_failures",
    "example_comparison",
    "filter_level_errors",
    "filter_states",
    "gauge_run",
    "noise_mismatch",
    "order_rule_study",
    "scaled_noise",
    "start_study",
    "table3_readings",
    "table3_rows",
    "tracking_data",
]
