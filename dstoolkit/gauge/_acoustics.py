"""Speed of sound and the resonances of a closed tube (paper §4.1, eqs. 30–35).

A tube closed by the liquid surface at distance L below the speaker resonates where the
round trip 2L holds a whole number of wavelengths (eq. 30), at

    f_n = n c / (2 L),   n = 1, 2, ...,   fundamental f_F = c / (2 L)   (eqs. 31–32, 35).

The paper takes c = 331.3 + 0.606 T (T in °C), which gives 347.3 m/s at 26.5 °C and
f_F ≈ 18 Hz at L = 9.6 m, 23.9 °C. That line is the first-order Taylor expansion of the
ideal-gas law c = 331.3 sqrt(1 + T/273.15) (dc/dT at 0 °C = 331.3/546.3 = 0.6065 m/s/K);
at 26.5 °C it is 0.35 m/s (0.1 %) faster, which alone moves a 9.6 m level by 1 cm.
Cramer's formula (JASA 93(5), 1993) adds humidity, pressure and CO2: at 25 °C air at 50 %
relative humidity is 0.9 m/s faster than dry air, and at 26.5 °C, 50 % it gives 348.1 m/s,
0.7 m/s (0.2 %, 2 cm at 9.6 m) above the paper's line.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np

from dstoolkit.errors import InvalidInputError
from dstoolkit.utils.checks import real_array

#: The speed-of-sound models of :func:`speed_of_sound`.
SpeedModel = Literal["paper", "ideal_gas", "cramer"]

#: Band the filter works in (paper §4.1); the paper's experiment swept 1000 → 2400 Hz.
DEFAULT_BAND: tuple[float, float] = (1000.0, 2500.0)

_CRAMER = np.array([
    331.5024, 0.603055, -0.000528, 51.471935, 0.1495874, -0.000782, -1.82e-7, 3.73e-8,
    -2.93e-10, -85.20931, -0.228525, 5.91e-5, -2.835149, -2.15e-13, 29.179762, 0.000486,
])


def speed_of_sound_paper(temperature_c: Any) -> np.ndarray | float:
    """c = 331.3 + 0.606 T (m/s), the paper's linear law (T in °C)."""
    return 331.3 + 0.606 * _temperature(temperature_c)


def _temperature(value: Any) -> np.ndarray:
    t = real_array(value, "temperature_c")
    if np.any(t <= -273.15):
        raise InvalidInputError(f"temperature_c must be above absolute zero (-273.15 °C), got "
                                f"{t.min():g}")
    return t


def speed_of_sound_ideal_gas(temperature_c: Any) -> np.ndarray | float:
    """c = 331.3 sqrt(1 + T/273.15) (m/s): dry air as an ideal gas, c ∝ sqrt(T_kelvin)."""
    t = _temperature(temperature_c)
    return 331.3 * np.sqrt(1.0 + t / 273.15)


def water_vapour_fraction(
    temperature_c: Any, relative_humidity: Any, pressure_pa: Any = 101325.0
) -> np.ndarray | float:
    """Mole fraction of water vapour x_w = h f p_sv / p (Davis 1992, Cramer's appendix)."""
    t = np.asarray(temperature_c, dtype=float)
    h = np.asarray(relative_humidity, dtype=float)
    p = np.asarray(pressure_pa, dtype=float)
    if np.any((h < 0) | (h > 1)):
        raise InvalidInputError(f"relative_humidity is a fraction in [0, 1], got {h}")
    tk = t + 273.15
    enhancement = 1.00062 + 3.14e-8 * p + 5.6e-7 * t**2
    p_sv = np.exp(1.2811805e-5 * tk**2 - 1.9509874e-2 * tk + 34.04926034 - 6.3536311e3 / tk)
    return h * enhancement * p_sv / p


def speed_of_sound_cramer(
    temperature_c: Any,
    relative_humidity: Any = 0.5,
    pressure_pa: Any = 101325.0,
    co2_fraction: Any = 4.0e-4,
) -> np.ndarray | float:
    """Speed of sound in humid air after Cramer (1993), eq. 15 and Table III (m/s).

    Valid for 0–30 °C, 75–102 kPa (a little above is harmless), x_w ≤ 0.06, x_c ≤ 0.01;
    accuracy about 300 ppm. Outside 0–30 °C a ``ValueError`` asks for another model.
    """
    t = _temperature(temperature_c)
    if np.any((t < 0.0) | (t > 30.0)):
        raise InvalidInputError(
            f"Cramer's formula holds for 0–30 °C, got {t}; use model='ideal_gas' outside"
        )
    p = np.asarray(pressure_pa, dtype=float)
    xw = water_vapour_fraction(t, relative_humidity, p)
    xc = np.asarray(co2_fraction, dtype=float)
    a = _CRAMER
    return (
        a[0] + a[1] * t + a[2] * t**2
        + (a[3] + a[4] * t + a[5] * t**2) * xw
        + (a[6] + a[7] * t + a[8] * t**2) * p
        + (a[9] + a[10] * t + a[11] * t**2) * xc
        + a[12] * xw**2 + a[13] * p**2 + a[14] * xc**2 + a[15] * xw * p * xc
    )


def speed_of_sound(
    temperature_c: Any, model: SpeedModel = "paper", **kwargs: Any
) -> np.ndarray | float:
    """Speed of sound (m/s) at ``temperature_c`` by ``model``: "paper" (default, the
    paper's 331.3 + 0.606 T, eq. 33's c), "ideal_gas" or "cramer" (extra keywords:
    relative_humidity, pressure_pa, co2_fraction).

    Examples
    --------
    >>> float(speed_of_sound(20.0))
    343.42
    >>> speed_of_sound([0.0, 20.0]).tolist()
    [331.3, 343.42]
    >>> round(float(speed_of_sound(20.0, "ideal_gas")), 2)
    343.21
    """
    if model == "paper":
        return speed_of_sound_paper(temperature_c)
    if model == "ideal_gas":
        return speed_of_sound_ideal_gas(temperature_c)
    if model == "cramer":
        return speed_of_sound_cramer(temperature_c, **kwargs)
    raise InvalidInputError(f"unknown speed-of-sound model {model!r}; use 'paper', 'ideal_gas' or "
                     "'cramer'")


def _check_positive(name: str, value: Any) -> np.ndarray:
    v = real_array(value, name, finite=False)
    if np.any(~np.isfinite(v)) or np.any(v <= 0):
        raise InvalidInputError(f"{name} must be positive and finite, got {value}")
    return v


def fundamental_frequency(level_m: Any, c: Any) -> np.ndarray | float:
    """f_F = c / (2 L) (eq. 35): the spacing of the resonances, Hz."""
    return _check_positive("c", c) / (2.0 * _check_positive("level_m", level_m))


def round_trip_time(level_m: Any, c: Any) -> np.ndarray | float:
    """Δ = 2 L / c = 1 / f_F: delay of the surface echo (eq. 28), seconds."""
    return 2.0 * _check_positive("level_m", level_m) / _check_positive("c", c)


def resonance_orders(
    level_m: float, c: float, band: tuple[float, float] = DEFAULT_BAND
) -> np.ndarray:
    """The orders n with f_n = n c/(2L) inside ``band`` (inclusive), ascending."""
    f_lo, f_hi = band
    if not 0 < f_lo < f_hi:
        raise InvalidInputError(f"band must be (low, high) with 0 < low < high, got {band}")
    f_f = float(fundamental_frequency(level_m, c))
    return np.arange(int(np.ceil(f_lo / f_f - 1e-12)), int(np.floor(f_hi / f_f + 1e-12)) + 1)


def resonance_frequencies(
    level_m: float, c: float, band: tuple[float, float] = DEFAULT_BAND
) -> tuple[np.ndarray, np.ndarray]:
    """Orders n and frequencies f_n = n c/(2L) (eqs. 31–32) of the resonances in ``band``.

    At L = 9.6 m, 23.9 °C and [1000, 2500] Hz this gives n = 56..138, 83 resonances; the
    paper (§4.1, with f_F rounded to 18 Hz) counts 82, n = 56..137, though 138 × 18 Hz =
    2484 Hz lies in the band too.
    """
    n = resonance_orders(level_m, c, band)
    return n, n * float(fundamental_frequency(level_m, c))


def plane_wave_cutoff(diameter_m: float, c: float) -> float:
    """Frequency above which the first cross mode propagates, 1.8412 c/(π d), Hz.

    Below it only plane waves travel and the 1-D model holds: 2.7 kHz for the paper's
    75 mm PVC tube, just above its 1000–2500 Hz band.
    """
    return float(1.8412 * _check_positive("c", c) / (np.pi * _check_positive("d", diameter_m)))
