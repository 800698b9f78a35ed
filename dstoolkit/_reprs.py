"""Short reprs for results that people read: floats to 4 significant digits.

``repr(dependence(e1, e2))`` used to print ``joint_energy=0.44999999999999996``; with
:func:`short_repr` it prints ``joint_energy=0.45``. Only the printed form changes: the
fields keep their full precision.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

#: Significant digits of a float in a short repr.
DIGITS = 4


def short_number(value: Any) -> str:
    """Format a float (or array of floats) to :data:`DIGITS` significant digits; others as repr."""
    if isinstance(value, bool | np.bool_):
        return repr(bool(value))
    if isinstance(value, float | np.floating):
        text = f"{float(value):.{DIGITS}g}"
        return text + ".0" if text.lstrip("-").isdigit() else text  # 1.0, not 1
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k!r}: {short_number(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list | tuple):
        inner = ", ".join(short_number(v) for v in value)
        if isinstance(value, list):
            return f"[{inner}]"
        return f"({inner},)" if len(value) == 1 else f"({inner})"
    if isinstance(value, np.ndarray) and value.dtype.kind == "f":
        with np.printoptions(precision=DIGITS - 1, floatmode="maxprec", threshold=8, edgeitems=2):
            return np.array2string(value, separator=", ")
    return repr(value)


def short_repr(obj: Any) -> str:
    """``Name(field=value, ...)`` of a dataclass or named tuple, floats shortened."""
    if dataclasses.is_dataclass(obj):
        items = [(f.name, getattr(obj, f.name)) for f in dataclasses.fields(obj) if f.repr]
    else:
        items = list(obj._asdict().items())
    inner = ", ".join(f"{name}={short_number(value)}" for name, value in items)
    return f"{type(obj).__name__}({inner})"


class ShortFloatDict(dict):
    """A dict whose repr shows its floats to :data:`DIGITS` significant digits."""

    def __repr__(self) -> str:
        inner = ",\n ".join(f"{key!r}: {short_number(value)}" for key, value in self.items())
        return "{" + inner + "}"
