"""Consistency of the filters on the simulated gauge: NEES, NIS and enclosure.

The Gaussian filters (Kalman, unscented) report a covariance: their NEES and NIS, averaged
over runs, are checked against their χ² bands (:func:`dstoolkit.filters.chi2_band`). The
others report bounds (the bounded-error filter's box, the evidential filters' hull of
focal elements, the particle filter's hull of weighted particles): for them the check is
whether the truth lies inside what they report.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dstoolkit.errors import EvidenceError
from dstoolkit.filters import chi2_band, gaussian_filters, registered_filters
from dstoolkit.gauge import gauge_state_space_model, orders_eq43
from dstoolkit.utils.checks import real_number

from ._estimation import ComparisonSettings, scaled_noise, tracking_data

#: The sources of the gauge's orders n_k: the simulation's true orders, or the paper's eq. 43.
CONSISTENCY_ORDERS: tuple[str, ...] = ("true", "eq43")


@dataclass(frozen=True)
class ConsistencyStudy:
    """NEES, NIS and enclosure of filters on runs of the gauge (made by :func:`gauge_consistency`).

    Parameters
    ----------
    level_m, temperature_c : float
        The case: L (m) and T (°C).
    runs : int
        N, the runs averaged.
    scale : float
        The assumed noises' bounds, as multiples of the true ones' distance from the mode.
    orders : str
        ``"true"`` or ``"eq43"``: the inputs n_k given to f.
    nees : dict of str to ndarray, shape (T,)
        Average NEES over the runs, per step, of each Gaussian filter.
    nis : dict of str to ndarray, shape (T,)
        Average NIS over the runs, per step (NaN at the first step).
    nees_band, nis_band : tuple of float
        The 95 % bands of an average of N χ²(1) values.
    enclosure : dict of str to float
        The share of (run, step) pairs whose truth lies in [lower, upper], per filter.
    rmse : dict of str to float
        Root mean squared error over runs and steps, Hz.
    width : dict of str to float
        Mean width of [lower, upper] over runs and steps, Hz.
    """

    level_m: float
    temperature_c: float
    runs: int
    scale: float
    orders: str
    nees: dict[str, np.ndarray]
    nis: dict[str, np.ndarray]
    nees_band: tuple[float, float]
    nis_band: tuple[float, float]
    enclosure: dict[str, float]
    rmse: dict[str, float]
    width: dict[str, float]

    def share(self, name: str, where: str = "inside", what: str = "nees") -> float:
        """Return the share of steps whose average NEES (or NIS) is inside, above or below its band.

        Parameters
        ----------
        name : str
            A Gaussian filter of the study.
        where : {"inside", "above", "below"}
            Which part of the band.
        what : {"nees", "nis"}
            Which statistic.

        Returns
        -------
        float
            The share of steps (for the NIS, of the steps after the first).
        """
        values = self.nees[name] if what == "nees" else self.nis[name][1:]
        low, high = self.nees_band if what == "nees" else self.nis_band
        pick = {
            "inside": (values >= low) & (values <= high),
            "above": values > high,
            "below": values < low,
        }
        if where not in pick:
            raise EvidenceError(f"where must be 'inside', 'above' or 'below', got {where!r}")
        return float(pick[where].mean())


def gauge_consistency(
    level_m: float = 4.6,
    temperature_c: float = 26.5,
    *,
    runs: int = 50,
    seed: int = 0,
    scale: float = 1.0,
    orders: str = "true",
    methods: tuple[str, ...] | None = None,
) -> ConsistencyStudy:
    """Run filters on simulated gauge runs and check their consistency.

    The runs follow eqs. (39)–(40) with the paper's noises (:func:`tracking_data`); the
    filters assume the noises with bounds scaled by ``scale`` about their modes
    (:func:`scaled_noise`: variances times scale²).

    Parameters
    ----------
    level_m, temperature_c : float, optional
        The case (default the paper's 4.6 m at 26.5 °C).
    runs : int, optional
        N, the runs averaged (default 50).
    seed : int, optional
        Seed of the runs' noises (and of the particle filter).
    scale : float, optional
        The assumed noises' scale, > 0 (default 1: the true noises).
    orders : {"true", "eq43"}, optional
        The orders n_k fed to f: the true ones, or eq. (43)'s from the readings.
    methods : tuple of str, optional
        Registered filters to run (default the Gaussian ones,
        :func:`dstoolkit.filters.gaussian_filters`). NEES and NIS are computed for the
        Gaussian ones, the enclosure for all.

    Returns
    -------
    ConsistencyStudy
        The averages per step, their bands, the enclosure and the RMSE.

    Raises
    ------
    EvidenceError
        An unknown method or order source, or a scale that is not positive.

    Examples
    --------
    >>> study = gauge_consistency(runs=5)
    >>> sorted(study.nees), study.nees["kalman"].shape
    (['kalman', 'unscented'], (40,))
    """
    s = real_number(scale, "scale", low=0.0, low_open=True, error=EvidenceError)
    if orders not in CONSISTENCY_ORDERS:
        raise EvidenceError(f"orders must be 'true' or 'eq43', got {orders!r}")
    entries = {entry.name: entry for entry in registered_filters()}
    gaussian = gaussian_filters()
    methods = gaussian if methods is None else tuple(methods)
    unknown = [m for m in methods if m not in entries]
    if unknown:
        raise EvidenceError(
            f"no registered filter named {unknown[0]!r}; registered: {', '.join(entries)}"
        )
    data = tracking_data(level_m, temperature_c, runs=runs, seed=seed)
    model = gauge_state_space_model(
        scaled_noise(data.state_noise, s), scaled_noise(data.obs_noise, s)
    )
    inputs = (
        data.orders if orders == "true" else np.array([orders_eq43(run) for run in data.readings])
    )
    settings = ComparisonSettings(seed=seed)
    nees_avg, nis_avg, enclosure, rmse, width = {}, {}, {}, {}, {}
    for name in methods:
        result = (
            entries[name]
            .make(settings)
            .run_batch(model, data.readings[..., None], inputs[..., None])
        )
        x, lo, hi = result.estimates[..., 0], result.lower[..., 0], result.upper[..., 0]
        err = data.truth - x
        enclosure[name] = float(np.mean((data.truth >= lo) & (data.truth <= hi)))
        rmse[name] = float(np.sqrt(np.mean(err**2)))
        width[name] = float(np.mean(hi - lo))
        if name in gaussian:
            sigma = (hi - lo) / 6.0  # lower/upper are x̂ ± 3σ
            nees_avg[name] = np.mean((err / sigma) ** 2, axis=0)
            nis_avg[name] = np.mean(result.diagnostics["nis"], axis=0)
    band = chi2_band(1, runs)
    return ConsistencyStudy(
        level_m,
        temperature_c,
        runs,
        s,
        orders,
        nees_avg,
        nis_avg,
        band,
        band,
        enclosure,
        rmse,
        width,
    )
