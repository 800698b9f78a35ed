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

_CRAMER = np.array(
    [
        331.5024,
        0.603055,
        -0.000528,
        51.471935,
        0.1495874,
        -0.000782,
        -1.82e-7,
        3.73e-8,
        -2.93e-10,
        -85.20931,
        -0.228525,
        5.91e-5,
        -2.835149,
        -2.15e-13,
        29.179762,
        0.000486,
    ]
)


def speed_of_sound_paper(temperature_c: Any) -> np.ndarray | float:
    """Speed of sound by the paper's linear law, c = 331.3 + 0.606 T.

    Parameters
    ----------
    temperature_c : float or array_like, any shape
        Air temperature T, °C; above absolute zero.

    Returns
    -------
    numpy.ndarray or float
        The speed of sound c, m/s, with the shape of ``temperature_c``.

    Raises
    ------
    InvalidInputError
        A temperature that is not a finite real number or is at or below −273.15 °C.

    See Also
    --------
    speed_of_sound : Chooses among the three models.
    speed_of_sound_ideal_gas : The law this line is the Taylor expansion of.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (33) and §4.1.

    Examples
    --------
    >>> from dstoolkit.gauge import speed_of_sound_paper
    >>> round(float(speed_of_sound_paper(26.5)), 3)
    347.359
    """
    return 331.3 + 0.606 * _temperature(temperature_c)


def _temperature(value: Any) -> np.ndarray:
    t = real_array(value, "temperature_c")
    if np.any(t <= -273.15):
        raise InvalidInputError(
            f"temperature_c must be above absolute zero (-273.15 °C), got {t.min():g}"
        )
    return t


def speed_of_sound_ideal_gas(temperature_c: Any) -> np.ndarray | float:
    """Speed of sound in dry air as an ideal gas, c = 331.3 sqrt(1 + T/273.15).

    Parameters
    ----------
    temperature_c : float or array_like, any shape
        Air temperature T, °C; above absolute zero.

    Returns
    -------
    numpy.ndarray or float
        The speed of sound c, m/s, with the shape of ``temperature_c``.

    Raises
    ------
    InvalidInputError
        A temperature that is not a finite real number or is at or below −273.15 °C.

    See Also
    --------
    speed_of_sound_paper : Its first-order expansion about 0 °C, the paper's law.
    speed_of_sound_cramer : Humid air.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (33) (the linear law whose origin this is).

    Examples
    --------
    >>> from dstoolkit.gauge import speed_of_sound_ideal_gas
    >>> round(float(speed_of_sound_ideal_gas(0.0)), 2)
    331.3
    """
    t = _temperature(temperature_c)
    return 331.3 * np.sqrt(1.0 + t / 273.15)


def water_vapour_fraction(
    temperature_c: Any, relative_humidity: Any, pressure_pa: Any = 101325.0
) -> np.ndarray | float:
    """Mole fraction of water vapour x_w = h f p_sv / p (Davis 1992, Cramer's appendix).

    Parameters
    ----------
    temperature_c : float or array_like
        Air temperature, °C.
    relative_humidity : float or array_like
        Relative humidity h as a fraction in [0, 1].
    pressure_pa : float or array_like, optional
        Static pressure p, Pa (default one standard atmosphere).

    Returns
    -------
    numpy.ndarray or float
        x_w, dimensionless, broadcast over the arguments.

    Raises
    ------
    InvalidInputError
        A relative humidity outside [0, 1].
    """
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
    """Speed of sound in humid air after Cramer (1993), eq. 15 and Table III.

    Valid for 0–30 °C, 75–102 kPa (a little above is harmless), x_w ≤ 0.06, x_c ≤ 0.01;
    accuracy about 300 ppm.

    Parameters
    ----------
    temperature_c : float or array_like
        Air temperature, °C, within [0, 30].
    relative_humidity : float or array_like, optional
        Relative humidity as a fraction in [0, 1] (default 0.5).
    pressure_pa : float or array_like, optional
        Static pressure, Pa (default 101325).
    co2_fraction : float or array_like, optional
        Mole fraction of CO2 (default 4e-4).

    Returns
    -------
    numpy.ndarray or float
        The speed of sound, m/s, broadcast over the arguments.

    Raises
    ------
    InvalidInputError
        A temperature outside 0–30 °C (use ``model="ideal_gas"`` there) or a relative
        humidity outside [0, 1].

    See Also
    --------
    speed_of_sound : Chooses among the three models.

    References
    ----------
    O. Cramer, "The variation of the specific heat ratio and the speed of sound in air with
    temperature, pressure, humidity, and CO2 concentration", JASA 93(5):2510 (1993).
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (33), for the paper's simpler law.

    Examples
    --------
    Humid air is faster than the paper's dry-air line:

    >>> from dstoolkit.gauge import speed_of_sound_cramer
    >>> round(float(speed_of_sound_cramer(26.5, relative_humidity=0.5)), 1)
    348.1
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
        a[0]
        + a[1] * t
        + a[2] * t**2
        + (a[3] + a[4] * t + a[5] * t**2) * xw
        + (a[6] + a[7] * t + a[8] * t**2) * p
        + (a[9] + a[10] * t + a[11] * t**2) * xc
        + a[12] * xw**2
        + a[13] * p**2
        + a[14] * xc**2
        + a[15] * xw * p * xc
    )


def speed_of_sound(
    temperature_c: Any, model: SpeedModel = "paper", **kwargs: Any
) -> np.ndarray | float:
    """Speed of sound at ``temperature_c`` by one of three models.

    Parameters
    ----------
    temperature_c : float or array_like, any shape
        Air temperature, °C.
    model : {"paper", "ideal_gas", "cramer"}, optional
        "paper" (default): 331.3 + 0.606 T, the c of the paper's eq. (33); "ideal_gas":
        331.3 sqrt(1 + T/273.15); "cramer": humid air (0–30 °C).
    **kwargs
        For "cramer" only: ``relative_humidity``, ``pressure_pa``, ``co2_fraction``.

    Returns
    -------
    numpy.ndarray or float
        c, m/s, with the shape of ``temperature_c``.

    Raises
    ------
    InvalidInputError
        An unknown model, or a temperature the model does not cover.

    See Also
    --------
    speed_of_sound_paper, speed_of_sound_ideal_gas, speed_of_sound_cramer
    fundamental_frequency : The resonance spacing c/(2L) this speed sets.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (33) and §4.1.

    Examples
    --------
    >>> from dstoolkit.gauge import speed_of_sound
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
    raise InvalidInputError(
        f"unknown speed-of-sound model {model!r}; use 'paper', 'ideal_gas' or 'cramer'"
    )


def _check_positive(name: str, value: Any) -> np.ndarray:
    v = real_array(value, name, finite=False)
    if np.any(~np.isfinite(v)) or np.any(v <= 0):
        raise InvalidInputError(f"{name} must be positive and finite, got {value}")
    return v


def fundamental_frequency(level_m: Any, c: Any) -> np.ndarray | float:
    """f_F = c/(2L): the fundamental of the tube, and the spacing of its resonances.

    Parameters
    ----------
    level_m : float or array_like
        L, the distance from the speaker to the liquid surface, m; positive.
    c : float or array_like
        Speed of sound, m/s; positive.

    Returns
    -------
    numpy.ndarray or float
        f_F, Hz, broadcast over the arguments.

    Raises
    ------
    InvalidInputError
        A level or speed that is not positive and finite.

    See Also
    --------
    level_from_fundamental : The inverse, L = c/(2 f_F).
    round_trip_time : 1/f_F.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (35).

    Examples
    --------
    >>> from dstoolkit.gauge import fundamental_frequency
    >>> float(fundamental_frequency(9.6, 345.78))
    18.009375
    """
    return _check_positive("c", c) / (2.0 * _check_positive("level_m", level_m))


def round_trip_time(level_m: Any, c: Any) -> np.ndarray | float:
    """Δ = 2L/c = 1/f_F: the delay of the echo from the liquid surface.

    Parameters
    ----------
    level_m : float or array_like
        L, m; positive.
    c : float or array_like
        Speed of sound, m/s; positive.

    Returns
    -------
    numpy.ndarray or float
        Δ, seconds, broadcast over the arguments.

    Raises
    ------
    InvalidInputError
        A level or speed that is not positive and finite.

    See Also
    --------
    fundamental_frequency : Its inverse, f_F = 1/Δ.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (28).

    Examples
    --------
    >>> from dstoolkit.gauge import round_trip_time
    >>> float(round_trip_time(1.7171, 343.42))
    0.01
    """
    return 2.0 * _check_positive("level_m", level_m) / _check_positive("c", c)


def resonance_orders(
    level_m: float, c: float, band: tuple[float, float] = DEFAULT_BAND
) -> np.ndarray:
    """Find the orders n whose resonance n c/(2L) lies inside ``band`` (inclusive).

    Parameters
    ----------
    level_m : float
        L, m; positive.
    c : float
        Speed of sound, m/s; positive.
    band : tuple of float, optional
        (low, high) in Hz, 0 < low < high (default :data:`DEFAULT_BAND`, 1000–2500 Hz).

    Returns
    -------
    numpy.ndarray of int, shape (K,)
        The orders, ascending.

    Raises
    ------
    InvalidInputError
        A band that is not (low, high) with 0 < low < high, or a level or speed that is not
        positive.

    See Also
    --------
    resonance_frequencies : The orders with their frequencies.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (31)–(32).

    Examples
    --------
    >>> from dstoolkit.gauge import resonance_orders
    >>> resonance_orders(1.3, 343.42, band=(1000.0, 1600.0)).tolist()
    [8, 9, 10, 11, 12]
    """
    f_lo, f_hi = band
    if not 0 < f_lo < f_hi:
        raise InvalidInputError(f"band must be (low, high) with 0 < low < high, got {band}")
    f_f = float(fundamental_frequency(level_m, c))
    return np.arange(int(np.ceil(f_lo / f_f - 1e-12)), int(np.floor(f_hi / f_f + 1e-12)) + 1)


def resonance_frequencies(
    level_m: float, c: float, band: tuple[float, float] = DEFAULT_BAND
) -> tuple[np.ndarray, np.ndarray]:
    """Orders n and frequencies f_n = n c/(2L) of the resonances in ``band``.

    At L = 9.6 m, 23.9 °C and [1000, 2500] Hz this gives n = 56..138, 83 resonances; the
    paper (§4.1, with f_F rounded to 18 Hz) counts 82, n = 56..137, though 138 × 18 Hz =
    2484 Hz lies in the band too.

    Parameters
    ----------
    level_m : float
        L, m; positive.
    c : float
        Speed of sound, m/s; positive.
    band : tuple of float, optional
        (low, high) in Hz (default :data:`DEFAULT_BAND`, 1000–2500 Hz).

    Returns
    -------
    orders : numpy.ndarray of int, shape (K,)
        n, ascending.
    frequencies : numpy.ndarray of float, shape (K,)
        f_n, Hz.

    Raises
    ------
    InvalidInputError
        A band that is not (low, high) with 0 < low < high, or a level or speed that is not
        positive.

    See Also
    --------
    resonance_orders : The orders alone.
    TubeSetup.resonances : The same for a simulated tube.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (31)–(32) and §4.1.

    Examples
    --------
    >>> from dstoolkit.gauge import resonance_frequencies, speed_of_sound
    >>> n, f = resonance_frequencies(9.6, float(speed_of_sound(23.9)))
    >>> int(n[0]), int(n[-1]), n.size
    (56, 138, 83)
    """
    n = resonance_orders(level_m, c, band)
    return n, n * float(fundamental_frequency(level_m, c))


def plane_wave_cutoff(diameter_m: float, c: float) -> float:
    """Compute the frequency above which the first cross mode propagates, 1.8412 c/(π d).

    Below it only plane waves travel and the one-dimensional model of the tube holds: 2.7 kHz
    for the paper's 75 mm PVC tube, just above its 1000–2500 Hz band.

    Parameters
    ----------
    diameter_m : float
        Inner diameter d of the tube, m; positive.
    c : float
        Speed of sound, m/s; positive.

    Returns
    -------
    float
        The cutoff, Hz.

    Raises
    ------
    InvalidInputError
        A diameter or speed that is not positive and finite.

    See Also
    --------
    TubeSetup : The simulated tube, whose model holds below this frequency.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.1 (the tube and its band).

    Examples
    --------
    >>> from dstoolkit.gauge import plane_wave_cutoff
    >>> round(plane_wave_cutoff(0.075, 343.42))
    2684
    """
    return float(1.8412 * _check_positive("c", c) / (np.pi * _check_positive("d", diameter_m)))
