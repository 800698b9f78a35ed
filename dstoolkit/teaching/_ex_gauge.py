"""Checked exercises of the gauge chapters.

The level gauge, the lab, estimating the level, beyond the paper.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from dstoolkit.gauge import (
    fundamental_frequency,
    latency_offset,
    level_from_resonance,
    orders_eq43,
    resonance_orders,
    speed_of_sound,
    sweep_rate_offset,
)

from ._checking import REGISTRY, exercise
from ._ex_filter import PAPER_Z1
from ._variants import book_data, data

# -- the acoustic level gauge (book/level_gauge.md, notebooks/07_level_gauge.ipynb) -----------

#: Table 3's 4.6 m case (the paper's Figs. 6–7) and its longest, 9.6 m: (level m, °C).
GAUGE_CASE, LONG_CASE = (4.6, 26.5), (9.6, 23.9)
#: The filter's band (paper §4.1) and the paper's sweep rate (1000 → 2400 Hz in 5 s), Hz/s.
GAUGE_BAND, SWEEP_RATE = (1000.0, 2500.0), 280.0
#: Audio latency of the offset exercise, s.
GAUGE_LATENCY = 0.010
#: Errors (Hz) of the two readings in the eq. 43 exercise: z_1 = 57 f_F + e_1,
#: z_2 = 58 f_F + e_2 at LONG_CASE.
EQ43_ORDERS, EQ43_ERRORS = (57, 58), (0.2, -0.2)
#: Frequency (Hz) at which the eq. 43 tolerance is asked, at LONG_CASE.
EQ43_TOLERANCE_AT = 2000.0
#: Thermometer error (°C) of the temperature exercise, at LONG_CASE.
THERMOMETER_ERROR = 1.0


book_data(
    "gauge",
    {
        "case_l": 4.6,
        "case_t": 26.5,
        "long_l": 9.6,
        "long_t": 23.9,
        "latency_ms": 10,
        # the simulated gauge's sheet: the levels between which its prediction moves the slider
        "spacing_low": 1.6,
        "spacing_high": 9.6,
    },
)


def _case() -> tuple[float, float]:
    """Return the (level m, °C) of the speed and offset exercises (the book's: GAUGE_CASE)."""
    d = data("gauge")
    return float(d["case_l"]), float(d["case_t"])


def _long() -> tuple[float, float]:
    """Return the (level m, °C) of the long tube's exercises (the book's: LONG_CASE)."""
    d = data("gauge")
    return float(d["long_l"]), float(d["long_t"])


def _latency() -> float:
    """Return the audio latency of the offset exercise, s (the book's: GAUGE_LATENCY)."""
    return float(data("gauge")["latency_ms"]) / 1000.0


def _c(case: tuple[float, float]) -> float:
    return float(speed_of_sound(case[1]))


def _fundamental(case: tuple[float, float]) -> float:
    return float(fundamental_frequency(case[0], _c(case)))


def eq43_readings() -> np.ndarray:
    """Return the two readings of the eq. 43 exercise.

    Returns
    -------
    numpy.ndarray, shape (2,)
        z_1 = 57 f_F + 0.2 and z_2 = 58 f_F − 0.2 at the sheet's long tube (the book's:
        9.6 m and 23.9 °C), Hz.

    Examples
    --------
    >>> from dstoolkit.teaching import eq43_readings
    >>> eq43_readings().shape
    (2,)
    """
    return np.array(EQ43_ORDERS) * _fundamental(_long()) + np.array(EQ43_ERRORS)


@exercise(
    "gauge.speed",
    varies=True,
    hint="The paper's law: c = 331.3 + 0.606 T, T in °C.",
    mistakes=((lambda: 331.3, "That is c at 0 °C; add 0.606 m/s per °C."),),
)
def _() -> float:
    return _c(_case())


@exercise(
    "gauge.fundamental",
    varies=True,
    hint="f_F = c/(2L), c at 23.9 °C by the paper's law.",
    mistakes=(
        (lambda: _c(_long()) / _long()[0], "That is c/L: the echo travels down and back, 2L."),
    ),
)
def _() -> float:
    return _fundamental(_long())


@exercise(
    "gauge.count",
    varies=True,
    atol=0.0,
    rtol=0.0,
    hint="Count the whole numbers n with 1000 ≤ n f_F ≤ 2500: from ⌈1000/f_F⌉ to ⌊2500/f_F⌋.",
    mistakes=(
        (
            lambda: 82,
            "That is the paper's count (n = 56..137, with f_F rounded to "
            "18 Hz); check whether 138 f_F is still below 2500 Hz.",
        ),
    ),
)
def _() -> int:
    return int(resonance_orders(_long()[0], _c(_long()), GAUGE_BAND).size)


@exercise(
    "gauge.offset",
    varies=True,
    atol=5e-3,
    hint="The envelope peaks κ L/c above n c/(2L); the latency adds κ τ.",
    mistakes=(
        (
            lambda: SWEEP_RATE * 2 * _case()[0] / _c(_case()) + SWEEP_RATE * _latency(),
            "You used k·2L/c: the peak sits where the *mean* frequency of wave and "
            "echo is n c/(2L), half a delay back: κ L/c.",
        ),
        (
            lambda: float(sweep_rate_offset(SWEEP_RATE, _fundamental(_case()))),
            "That is the sweep's offset κ L/c alone; the latency adds κ τ.",
        ),
    ),
)
def _() -> float:
    return float(sweep_rate_offset(SWEEP_RATE, _fundamental(_case()))) + latency_offset(
        SWEEP_RATE, _latency()
    )


@exercise(
    "gauge.eq43",
    varies=True,
    atol=5e-3,
    hint="n_1 = round(z_1/(z_2 − z_1)) (eq. 43), then L = n_1 c/(2 z_1) (eq. 32). Answer (n_1, L).",
    mistakes=(
        (
            lambda: (EQ43_ORDERS[0], _long()[0]),
            "That is the true order and level; eq. 43 only sees the two readings: "
            "compute z_1/(z_2 − z_1).",
        ),
    ),
)
def _() -> tuple[int, float]:
    z = eq43_readings()
    n = int(orders_eq43(z)[0])
    return n, float(level_from_resonance(z[0], n, _c(_long())))


@exercise(
    "gauge.tolerance",
    varies=True,
    atol=2e-3,
    hint="n = z/(f_F + δ) ≈ (z/f_F)(1 − δ/f_F) rounds to the right order while "
    "(z/f_F)·|δ|/f_F < 1/2.",
    mistakes=(
        (
            lambda: 0.5 * _fundamental(_long()),
            "f_F/2 is how far one reading may wander before it is matched to the "
            "wrong resonance; eq. 43 divides by a difference, which must be far "
            "more precise.",
        ),
    ),
)
def _() -> float:
    return _fundamental(_long()) ** 2 / (2.0 * EQ43_TOLERANCE_AT)


@exercise(
    "gauge.thermometer",
    varies=True,
    atol=2e-4,
    hint="L = c/(2 f_F): a relative error of c is the same relative error of L.",
    mistakes=(
        (
            lambda: -_long()[0] * 0.606 * THERMOMETER_ERROR / _c(_long()),
            "Check the sign: a thermometer that reads high makes c, and so L, too large.",
        ),
    ),
)
def _() -> float:
    c_read = float(speed_of_sound(_long()[1] + THERMOMETER_ERROR))
    return _long()[0] * (c_read - _c(_long())) / _c(_long())


# -- the lab (book/lab.md, notebooks/08_lab.ipynb) ---------------------------------------------

#: Where the calibration chirp is found (samples after it was played) and the sample rate.
LAB_LAG_SAMPLES, LAB_SAMPLERATE = 6042, 44100
#: The paper's sweep, Hz, and the lab's air temperature in the exercises, °C.
LAB_BAND, LAB_TEMPERATURE = (1000.0, 2400.0), 20.0
#: Resonances the detector needs (dstoolkit.gauge.detect_resonances, min_resonances).
LAB_MIN_RESONANCES = 5
#: Inner diameter of the narrow pipe of the cutoff exercise, m.
LAB_CUTOFF_DIAMETER = 0.040
#: (level m, largest level error m) of the thermometer exercise.
LAB_TOLERANCE_CASE = (3.0, 0.005)
#: Parts of a level's uncertainty (fit, offsets, temperature), mm.
LAB_UNCERTAINTIES_MM = (0.4, 1.5, 2.2)


book_data(
    "lab",
    {
        "lag": LAB_LAG_SAMPLES,
        "temperature": LAB_TEMPERATURE,
        "diameter_mm": round(1e3 * LAB_CUTOFF_DIAMETER, 6),
        "tolerance_level": LAB_TOLERANCE_CASE[0],
        "tolerance_mm": round(1e3 * LAB_TOLERANCE_CASE[1], 6),
        "u_fit": LAB_UNCERTAINTIES_MM[0],
        "u_offsets": LAB_UNCERTAINTIES_MM[1],
        "u_temperature": LAB_UNCERTAINTIES_MM[2],
    },
)


def _lab(name: str) -> Any:
    """Return a datum of the lab's exercises in the current variant (the book's: LAB_*)."""
    return data("lab")[name]


def _lab_c() -> float:
    return float(speed_of_sound(_lab("temperature")))


def _lab_tau() -> float:
    return _lab("lag") / LAB_SAMPLERATE


def _diameter() -> float:
    return _lab("diameter_mm") / 1e3


def _tolerance_case() -> tuple[float, float]:
    return float(_lab("tolerance_level")), _lab("tolerance_mm") / 1e3


def _uncertainties() -> tuple[float, float, float]:
    return _lab("u_fit"), _lab("u_offsets"), _lab("u_temperature")


@exercise(
    "lab.latency-offset",
    varies=True,
    atol=5e-3,
    hint="τ = lag / f_s (in ms: × 1000); every reading moves by κ τ with κ = 280 Hz/s "
    "and τ in seconds. Answer (τ in ms, κ τ in Hz).",
    mistakes=(
        (
            lambda: (
                _lab_tau(),
                SWEEP_RATE * _lab_tau(),
            ),
            "Give τ in milliseconds (the offset κ τ is right).",
        ),
    ),
)
def _() -> tuple[float, float]:
    tau = _lab_tau()
    return 1e3 * tau, latency_offset(SWEEP_RATE, tau)


@exercise(
    "lab.shortest-tube",
    varies=True,
    hint="Five spacings fit in the band when 5 f_F ≤ f_stop − f_start; then L = c/(2 f_F).",
    mistakes=(
        (
            lambda: LAB_MIN_RESONANCES * _lab_c() / (LAB_BAND[1] - LAB_BAND[0]),
            "That is c/f_F: the sound goes down and back, L = c/(2 f_F).",
        ),
    ),
)
def _() -> float:
    f_f = (LAB_BAND[1] - LAB_BAND[0]) / LAB_MIN_RESONANCES
    return _lab_c() / (2.0 * f_f)


@exercise(
    "lab.cutoff",
    varies=True,
    hint="The first cross mode of a round tube starts at 1.8412 c/(π d).",
    mistakes=(
        (
            lambda: 1.8412 * _lab_c() / (np.pi * 2 * _diameter()),
            "1.8412 c/(π d) takes the diameter d, not twice it.",
        ),
        (
            lambda: 1.8412 * _lab_c() / (np.pi * 0.075),
            "That is the cutoff of the paper's 75 mm tube; this pipe is narrower.",
        ),
    ),
)
def _() -> float:
    from dstoolkit.gauge import plane_wave_cutoff

    return plane_wave_cutoff(_diameter(), _lab_c())


@exercise(
    "lab.thermometer-tolerance",
    varies=True,
    hint="δL = L · 0.606 δT / c (c = 331.3 + 0.606 T): solve for δT.",
    mistakes=(
        (
            lambda: _tolerance_case()[1] * _lab_c() / _tolerance_case()[0],
            "c changes by 0.606 m/s per °C, not by 1: divide by 0.606 too.",
        ),
    ),
)
def _() -> float:
    level, tolerance = _tolerance_case()
    c_per_degree = float(speed_of_sound(_lab("temperature") + 1.0)) - _lab_c()
    return tolerance * _lab_c() / (c_per_degree * level)


@exercise(
    "lab.uncertainty",
    varies=True,
    hint="Independent parts of an uncertainty add in quadrature: "
    "the square root of the sum of their squares.",
    mistakes=(
        (
            lambda: float(sum(_uncertainties())),
            "That is their plain sum: independent parts add in quadrature.",
        ),
        (
            lambda: float(max(_uncertainties())),
            "That is only the largest part; the others add to it, in quadrature.",
        ),
    ),
)
def _() -> float:
    return float(np.sqrt(np.sum(np.square(_uncertainties()))))


# -- estimating the level (book/estimating_level.md, notebooks/09_estimating_level.ipynb) -------

#: The paper's Figs. 6–11 case (L m, T °C) and the order n_1 of its first reading PAPER_Z1
#: reading's order n_1 (1023.3/37.76 ≈ 27).
FIG10_CASE, PAPER_N1 = (4.6, 26.5), 27
#: A reading that is too high by the mode of the paper's w (Hz): z = f − w, w = −6.9.
READING_BIAS = 6.9
#: The Monte Carlo of the improvement exercise: runs, seed, case.
IMPROVEMENT_RUNS, IMPROVEMENT_SEED = 30, 0


#: The case and band of the outlier exercise: Table 3's 1.3 m row and the filter's band.
OUTLIER_CASE = (1.3, 27.0)


book_data(
    "estimating",
    {
        "z1": PAPER_Z1,
        "n1": PAPER_N1,
        "bias": READING_BIAS,
        "outlier_level": OUTLIER_CASE[0],
        "outlier_t": OUTLIER_CASE[1],
        "band_lo": int(GAUGE_BAND[0]),
        "band_hi": int(GAUGE_BAND[1]),
        "imp_level": FIG10_CASE[0],
        "imp_t": FIG10_CASE[1],
        "imp_runs": IMPROVEMENT_RUNS,
        "imp_seed": IMPROVEMENT_SEED,
    },
)


def _first() -> tuple[float, int]:
    """Return the first reading (Hz) and its order (the book's: PAPER_Z1, PAPER_N1)."""
    d = data("estimating")
    return float(d["z1"]), int(d["n1"])


def _level_of_reading(z: float, n: int, case: tuple[float, float]) -> float:
    return float(level_from_resonance(z, n, _c(case)))


@exercise(
    "estimating.first-level",
    varies=True,
    atol=5e-4,
    hint="Eq. 32: L = n c/(2 z) with c = 331.3 + 0.606 T at 26.5 °C.",
    mistakes=(
        (
            lambda: 2 * _level_of_reading(*_first(), FIG10_CASE),
            "The echo travels down and back: divide by 2 z, not z.",
        ),
    ),
)
def _() -> float:
    return _level_of_reading(*_first(), FIG10_CASE)


@exercise(
    "estimating.bias",
    varies=True,
    atol=2e-4,
    hint="The resonance of order n is at n c/(2L); the reading is the bias above it. Put the "
    "reading and the true order into eq. 32 and subtract the true level.",
    mistakes=(
        (
            lambda: -float(_bias_error()),
            "Check the sign: a reading that is too high gives a level that is too short.",
        ),
    ),
)
def _bias_error() -> float:
    n, bias = _first()[1], float(data("estimating")["bias"])
    return _level_of_reading(n * _fundamental(FIG10_CASE) + bias, n, FIG10_CASE) - FIG10_CASE[0]


def _outlier_case() -> tuple[tuple[float, float], tuple[float, float]]:
    """Return the (level m, °C) of the outlier exercise (a Table 3 row) and its band, Hz."""
    d = data("estimating")
    return (float(d["outlier_level"]), float(d["outlier_t"])), (
        float(d["band_lo"]),
        float(d["band_hi"]),
    )


@exercise(
    "estimating.outlier-orders",
    varies=True,
    rtol=1e-2,
    atol=0.0,
    hint="A unit error of n_k costs L/n_k in eq. 32. Average L/n over the orders of "
    "the resonances in the band at the case's level and temperature, and divide the "
    "paper's direct-measurement error at that level by it.",
)
def _() -> float:
    from dstoolkit.studies import TABLE3_MEAN_ABS_ERROR_M

    case, band = _outlier_case()
    orders = resonance_orders(case[0], _c(case), band)
    return TABLE3_MEAN_ABS_ERROR_M[case[0]]["direct"] / float(np.mean(case[0] / orders))


def _improvement_case() -> tuple[tuple[float, float], int, int]:
    """Return the (level m, °C), runs and seed of the improvement exercise."""
    d = data("estimating")
    return (float(d["imp_level"]), float(d["imp_t"])), int(d["imp_runs"]), int(d["imp_seed"])


def improvement_table() -> Any:
    """Return the Table 3 row of the improvement exercise, in the current variant.

    The book's: 4.6 m, true orders, the paper's filter and direct measurement,
    IMPROVEMENT_RUNS runs from seed IMPROVEMENT_SEED.
    """
    from dstoolkit.filters import filter_named
    from dstoolkit.studies import run_table3

    case, runs, seed = _improvement_case()
    return run_table3(
        runs=runs,
        seed=seed,
        cases=[case],
        methods=(filter_named("paper"), "direct"),
        order_rule="true",
        progress=False,
    )


@exercise(
    "estimating.improvement",
    varies=True,
    rtol=1e-6,
    atol=0.0,
    hint="Divide the direct measurement's mean level error by the paper's filter's, "
    "both from table.error(4.6, method).",
    mistakes=(
        (
            lambda: 1.0 / float(_improvement()),
            "That is the inverse: direct ÷ paper's filter is larger than 1.",
        ),
    ),
)
def _improvement() -> float:
    from dstoolkit.filters import filter_named

    level = _improvement_case()[0][0]
    table = improvement_table()
    return table.error(level, "direct") / table.error(level, filter_named("paper"))


# -- beyond the paper (book/beyond_the_paper.md, notebooks/10_beyond_the_paper.ipynb) -----------

#: Bounds scale, runs and seed of the bounded-error failure exercise.
FAILURE_SCALE, FAILURE_RUNS, FAILURE_SEED = 0.75, 20, 0
#: Cuts per component of the products exercise (the predator–prey example).
PRODUCTS_CUTS = 3
#: The paper's measured σ of w, Hz (§4.3): its bounds are the mode ± 3σ.
PAPER_SIGMA_W = 1.23
#: Nassreddine's correction by hand: the prediction's and the reading's evidence (g the
#: identity), as rows (lo, hi, mass).
NASSREDDINE_PREDICTION = ((0.0, 2.0, 0.6), (1.0, 4.0, 0.4))
NASSREDDINE_READING = ((1.5, 2.5, 0.7), (3.0, 5.0, 0.3))


def _book_beyond() -> None:
    from dstoolkit.gauge import GAUGE_OBS_NOISE

    (p1, p2), (r1, r2) = NASSREDDINE_PREDICTION, NASSREDDINE_READING
    book_data(
        "beyond",
        {
            "w_the": "The paper's",
            "w_whose": "the paper's",
            "w_note": "\n(`GAUGE_OBS_NOISE`)",  # the sheet's line break, as it was
            "w_lo": float(GAUGE_OBS_NOISE.lower[0]),
            "w_mode": float(GAUGE_OBS_NOISE.mode[0]),
            "w_hi": float(GAUGE_OBS_NOISE.upper[0]),
            "w_sigma": PAPER_SIGMA_W,
            "cuts": PRODUCTS_CUTS,
            "side": PRODUCTS_CUTS + 1,
            "cuts_word": "three",
            **{f"np1_{k}": v for k, v in zip(("lo", "hi", "m"), p1, strict=True)},
            **{f"np2_{k}": v for k, v in zip(("lo", "hi", "m"), p2, strict=True)},
            **{f"nr1_{k}": v for k, v in zip(("lo", "hi", "m"), r1, strict=True)},
            **{f"nr2_{k}": v for k, v in zip(("lo", "hi", "m"), r2, strict=True)},
            "fail_level": FIG10_CASE[0],
            "fail_t": FIG10_CASE[1],
            "fail_runs": FAILURE_RUNS,
            "fail_seed": FAILURE_SEED,
            "fail_scale": FAILURE_SCALE,
            "off_l": LONG_CASE[0],
            "off_t": LONG_CASE[1],
            "off_tau_ms": round(1e3 * GAUGE_LATENCY, 6),
        },
    )


_book_beyond()


def _beyond(name: str) -> Any:
    """Return a datum of the chapter's exercises in the current variant."""
    return data("beyond")[name]


def _paper_w() -> Any:
    """Return the observation noise w of the current variant (the book's: Table 2's)."""
    from dstoolkit.filters import BoundedNoise

    return BoundedNoise(_beyond("w_lo"), _beyond("w_mode"), _beyond("w_hi"))


@exercise(
    "beyond.start-error",
    varies=True,
    atol=1e-3,
    hint="z_1 = x_1 − w_1, so x̂_1 − x_1 = −w_1; take its expectation. The mean of a "
    "triangular density is (a + b + c)/3.",
    mistakes=(
        (
            lambda: float(_paper_w().mean[0]),
            "Check the sign: z = x − w, and w is negative, so the reading is high.",
        ),
    ),
)
def _() -> float:
    return -float(_paper_w().mean[0])


@exercise(
    "beyond.kalman-sigma",
    varies=True,
    atol=1e-3,
    hint="Var = (a² + b² + c² − ab − ac − bc)/18 for the triangle with support [a, b] "
    "and mode c; take its square root.",
    mistakes=(
        (
            lambda: float(_beyond("w_sigma")),
            "That is the σ of the measured errors from which the "
            "bounds were made (±3σ); the triangle on those bounds has another σ.",
        ),
    ),
)
def _() -> float:
    return float(np.sqrt(_paper_w().variance[0]))


def _example_sizes(p: int) -> tuple[int, int]:
    """(focal elements of E_v, of E_w) of the predator–prey example with p cuts."""
    from dstoolkit.filters import DependentEvidenceFilter, lotka_volterra

    noise = DependentEvidenceFilter(p=p).noise_evidence(lotka_volterra())
    return len(noise.state), len(noise.observation)


@exercise(
    "beyond.products",
    varies=True,
    atol=0.0,
    rtol=0.0,
    hint="Count per step: state boxes |E_v|, predicted boxes |E_v|·|E_v|, Step 4 "
    "products predicted × |E_w|, Step 6 products (Step 4's) × (predicted).",
    mistakes=(
        (
            lambda: int(_beyond("side")) ** 5,
            "That is the count for a scalar state: in two dimensions every evidence has "
            "(cuts + 1) × (cuts + 1) boxes.",
        ),
    ),
)
def _() -> int:
    n_v, n_w = _example_sizes(int(_beyond("cuts")))
    predicted = n_v * n_v
    return predicted * n_w * predicted


def _nassreddine_rows(
    which: str,
) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """Return the two rows (lo, hi, mass) of the prediction (``"np"``) or the reading (``"nr"``)."""
    d = data("beyond")
    first, second = (tuple(float(d[f"{which}{i}_{k}"]) for k in ("lo", "hi", "m")) for i in (1, 2))
    return first, second  # type: ignore[return-value]


def _nassreddine_correction(renormalise: bool = True) -> tuple[float, float]:
    """(K, x̂) of the correction of the prediction by the reading (the book's: NASSREDDINE_*).

    Without ``renormalise``, x̂ is the expectation of the kept products left unscaled.
    """
    from dstoolkit.evidence import IntervalEvidence, conflict, dempster

    def evidence(rows: tuple[tuple[float, float, float], ...]) -> IntervalEvidence:
        lo, hi, mass = zip(*rows, strict=True)
        return IntervalEvidence(list(lo), list(hi), list(mass))

    pred, reading = evidence(_nassreddine_rows("np")), evidence(_nassreddine_rows("nr"))
    k = conflict(pred, reading)
    estimate = float(dempster(pred, reading).pignistic_expectation()[0])
    return float(k), estimate if renormalise else estimate * (1.0 - float(k))


@exercise(
    "beyond.nassreddine-correction",
    varies=True,
    atol=5e-4,
    hint="Intersect every predicted interval with every interval of the reading; a product "
    "has the mass m_i · m_j. The empty ones make up K; divide the others by 1 − K, then take "
    "Σ m (lo + hi)/2 (eq. 20). Answer (K, x̂).",
    mistakes=(
        (
            lambda: _nassreddine_correction(renormalise=False),
            "The kept masses add up to 1 − K, not 1: divide them by 1 − K before the "
            "expectation (Dempster's rule, eq. 1).",
        ),
    ),
)
def _() -> tuple[float, float]:
    return _nassreddine_correction()


@exercise(
    "beyond.failures",
    varies=True,
    atol=1e-9,
    hint="Build the model with the scaled bounds (scaled_noise), run "
    "BoundedErrorFilter(on_inconsistent='raise') on each run, count the runs that raise "
    "InconsistentDataError and divide by the number of runs.",
)
def _() -> float:
    from dstoolkit.gauge import gauge_state_space_model
    from dstoolkit.studies import bounded_error_failures, scaled_noise, tracking_data

    level, t, runs, seed, scale = (
        _beyond(k) for k in ("fail_level", "fail_t", "fail_runs", "fail_seed", "fail_scale")
    )
    runs_data = tracking_data(float(level), float(t), runs=int(runs), seed=int(seed))
    model = gauge_state_space_model(
        scaled_noise(runs_data.state_noise, float(scale)),
        scaled_noise(runs_data.obs_noise, float(scale)),
    )
    return bounded_error_failures(model, runs_data)[0]


def _offset_case() -> tuple[tuple[float, float], float]:
    """Return the (level m, °C) and the latency (s) of the offset exercise."""
    return (float(_beyond("off_l")), float(_beyond("off_t"))), _beyond("off_tau_ms") / 1e3


@exercise(
    "beyond.offset-ratio",
    varies=True,
    atol=2e-3,
    hint="b = κL/c + κτ with κ = 280 Hz/s and τ in seconds; f_F = c/(2L). Divide.",
    mistakes=(
        (
            lambda: (
                SWEEP_RATE
                * _offset_case()[0][0]
                / _c(_offset_case()[0])
                / _fundamental(_offset_case()[0])
            ),
            "You left out the latency's κ τ.",
        ),
    ),
)
def _() -> float:
    case, latency = _offset_case()
    b = float(sweep_rate_offset(SWEEP_RATE, _fundamental(case))) + latency_offset(
        SWEEP_RATE, latency
    )
    return b / _fundamental(case)


#: The choices of the improvement prediction: direct ÷ filter error is closest to which?
IMPROVEMENT_CHOICES = (1, 2, 5, 10)


@exercise(
    "estimating.improvement-choice",
    varies=True,
    distinct=False,
    atol=0.0,
    rtol=0.0,
    hint="The filter averages the reading with the prediction; how much can that gain "
    "over one reading, when the orders are right?",
    mistakes=(
        (
            lambda: 1,
            "A ratio of 1 is what eq. 43's wrong orders leave; with the "
            "true orders the filter's averaging shows.",
        ),
        (
            lambda: 10,
            "Too optimistic: compare the two mean errors in the explorer with the true orders.",
        ),
    ),
)
def _() -> int:
    ratio = float(REGISTRY["estimating.improvement"]._expected())
    return min(IMPROVEMENT_CHOICES, key=lambda c: abs(np.log(c / ratio)))


#: The choices of the failure prediction: in what share of the runs does the strict
#: bounded-error filter fail with the scaled bounds?
FAILURE_CHOICES = ("none", "under half", "half or more", "all")


def _failure_share(fraction: float) -> str:
    if fraction == 0.0:
        return FAILURE_CHOICES[0]
    if fraction == 1.0:
        return FAILURE_CHOICES[3]
    return FAILURE_CHOICES[1] if fraction < 0.5 else FAILURE_CHOICES[2]


@exercise(
    "beyond.failures-choice",
    varies=True,
    distinct=False,
    hint=f"Answer one of {FAILURE_CHOICES}. A run fails when at some step the reading "
    "and the prediction, with the narrowed bounds, no longer meet.",
    mistakes=(
        (
            lambda: "none",
            "Narrower bounds than the true ones can exclude the truth: "
            "when the reading's and the prediction's boxes both miss it, they may "
            "miss each other too.",
        ),
        (
            lambda: "all",
            "Not every run: the scaled bounds still hold at most steps, "
            "and a run fails only if one step's boxes miss each other.",
        ),
    ),
)
def _() -> str:
    return _failure_share(float(REGISTRY["beyond.failures"]._expected()))


def _spacing_levels() -> tuple[float, float]:
    """Return the two levels (m) between which the spacing prediction moves the slider."""
    d = data("gauge")
    return float(d["spacing_low"]), float(d["spacing_high"])


@exercise(
    "gauge.spacing-ratio",
    varies=True,
    atol=1e-4,
    hint="f_F = c/(2L) at a fixed temperature: the spacing goes as 1/L. Answer "
    "f_F(longer level)/f_F(shorter level).",
    mistakes=(
        (
            lambda: _spacing_levels()[1] / _spacing_levels()[0],
            "That is the ratio of the levels; a longer tube has its resonances "
            "closer together, so f_F shrinks.",
        ),
    ),
)
def _() -> float:
    t = GAUGE_CASE[1]
    low, high = _spacing_levels()
    return _fundamental((high, t)) / _fundamental((low, t))
