"""The one list of the toolkit's filters: their names, labels, styles and comparison settings.

The studies (:func:`dstoolkit.studies.all_filters` and the comparisons built on it), the
figures (:data:`dstoolkit.plots.STYLE`), the explorers' readouts, the benchmark and the
interface test read :func:`registered_filters`. A new filter joins all of them by one
:func:`register_filter` call beside its module:

>>> from dstoolkit.filters import FilterEntry, KalmanFilter, register_filter, unregister_filter
>>> entry = FilterEntry(
...     "kalman_again", "Kalman again", "Kalman 2", "black", ":", "x",
...     lambda settings: KalmanFilter(),
... )
>>> register_filter(entry).label
'Kalman again'
>>> unregister_filter("kalman_again")
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from dstoolkit.errors import EvidenceError, InvalidInputError

from ._base import Filter, KernelChoice
from ._bounded_error import BoundedErrorFilter
from ._dependent import DependentEvidenceFilter
from ._kalman import KalmanFilter
from ._nassreddine import NassreddineFilter
from ._particle import ParticleFilter
from ._unscented import UnscentedKalmanFilter

_KERNEL: dict[str, KernelChoice] = {"comparisons": "auto"}


def set_comparison_kernel(kernel: KernelChoice) -> KernelChoice:
    """Choose the kernel of the filters that the comparisons make; return the previous one.

    ``"auto"`` (the default) compiles with numba where it is installed (extra ``speed``);
    ``"numpy"`` never loads numba, which keeps a notebook's kernel about half as large (the
    book's chapters and sheets choose it); ``"numba"`` requires it. Every kernel gives the
    same numbers bit for bit, so the choice changes speed and memory only.

    Parameters
    ----------
    kernel : {"auto", "numpy", "numba"}
        The ``kernel`` option given to the filters that have one.

    Returns
    -------
    str
        The kernel chosen before.

    Raises
    ------
    InvalidInputError
        Another value.

    Examples
    --------
    >>> from dstoolkit.filters import ComparisonSettings, set_comparison_kernel
    >>> before = set_comparison_kernel("numpy")
    >>> ComparisonSettings().kernel
    'numpy'
    >>> set_comparison_kernel(before)
    'numpy'
    """
    if kernel not in ("auto", "numpy", "numba"):
        raise InvalidInputError(
            f"kernel must be 'auto', 'numpy' or 'numba', got {kernel!r}; the numbers are the "
            "same with each"
        )
    before, _KERNEL["comparisons"] = _KERNEL["comparisons"], kernel
    return before


def _comparison_kernel() -> KernelChoice:
    return _KERNEL["comparisons"]


@dataclass(frozen=True)
class ComparisonSettings:
    """The settings a comparison of every filter passes to each entry's ``make``.

    Parameters
    ----------
    seed : int
        Seed of the filters that draw random numbers.
    p : int
        α-cuts of the evidential filters.
    start : str
        The paper's filter's x̂_1 (``"observation"`` or ``"mean_corrected"``).
    n_particles : int
        Particles of the particle filter.
    theta : tuple, optional
        The evidential filters' frames Θ as ``(theta_v, theta_w)`` (None: their default;
        the paper's Table 3 passes those of its Tables 1–2).
    kernel : {"auto", "numpy", "numba"}
        The kernel of the filters that have compiled kernels (by default the one
        :func:`set_comparison_kernel` chose); the numbers are the same with each.
    """

    seed: int = 0
    p: int = 3
    start: str = "observation"
    n_particles: int = 500
    theta: Any = None
    kernel: KernelChoice = field(default_factory=_comparison_kernel)


@dataclass(frozen=True)
class FilterEntry:
    """A filter of the comparisons: its name, how it is shown, and how it is made.

    Parameters
    ----------
    name : str
        The key of studies and plots (the filter's ``Filter.name``, or a variant's name).
    label : str
        Its name in figures' legends and the book (e.g. ``"Kalman"``).
    short_label : str
        Its name in readouts that must fit two lines.
    colour : str
        An Okabe–Ito colour name of :data:`dstoolkit.plots.OKABE_ITO`, or any matplotlib
        colour.
    line_style : str or tuple
        Its matplotlib line style (``"-"``, ``"--"``, ``(0, (5, 1))``...): the filters
        differ in line style and marker as well as in colour.
    marker : str
        Its matplotlib marker.
    make : callable
        ``make(settings)`` returns the filter with the comparison's
        :class:`ComparisonSettings`.
    role : str, optional
        ``"paper"`` for the paper's filter, ``"rival"`` for the filter its Figs. 10–11 set
        against it (Nassreddine's), ``""`` (default) for any other.
    table3_column : int, optional
        Its column among the methods of the paper's Table 3 (None: not in it).
    gaussian : bool, optional
        Whether it reports a Gaussian posterior: its ``lower``/``upper`` are x̂ ± 3σ of the
        covariance it computes and its diagnostics carry the NIS, so that its consistency
        (NEES, NIS) can be checked.
    """

    name: str
    label: str
    short_label: str
    colour: str
    line_style: Any
    marker: str
    make: Callable[[ComparisonSettings], Filter[Any, Any]]
    role: str = ""
    table3_column: int | None = None
    gaussian: bool = False


_REGISTRY: dict[str, FilterEntry] = {}


def register_filter(entry: FilterEntry, *, replace: bool = False) -> FilterEntry:
    """Add a filter to the comparisons, after those registered before it.

    Parameters
    ----------
    entry : FilterEntry
        The filter's name, labels, style and maker.
    replace : bool, optional
        Replace an entry of the same name (default: refuse it).

    Returns
    -------
    FilterEntry
        ``entry``.

    Raises
    ------
    EvidenceError
        Not a :class:`FilterEntry`, or a name registered already (without ``replace``).

    Examples
    --------
    >>> from dstoolkit.filters import register_filter, registered_filters
    >>> register_filter(registered_filters()[0])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    dstoolkit.errors.EvidenceError: a filter named 'dependent_evidence' is registered already...
    """
    if not isinstance(entry, FilterEntry):
        raise EvidenceError(
            f"register_filter takes a FilterEntry, got {type(entry).__name__}; build one "
            "with dstoolkit.filters.FilterEntry(name, label, short_label, colour, "
            "line_style, marker, make)"
        )
    if entry.name in _REGISTRY and not replace:
        raise EvidenceError(
            f"a filter named {entry.name!r} is registered already; pass replace=True to replace it"
        )
    _REGISTRY[entry.name] = entry
    return entry


def unregister_filter(name: str) -> None:
    """Remove the filter ``name`` from the comparisons.

    Parameters
    ----------
    name : str
        A registered name.

    Raises
    ------
    EvidenceError
        No filter of that name is registered.

    Examples
    --------
    >>> from dstoolkit.filters import unregister_filter
    >>> unregister_filter("none")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    dstoolkit.errors.EvidenceError: no filter named 'none' is registered; registered: ...
    """
    if name not in _REGISTRY:
        raise EvidenceError(
            f"no filter named {name!r} is registered; registered: {', '.join(_REGISTRY)}"
        )
    del _REGISTRY[name]


def registered_filters() -> tuple[FilterEntry, ...]:
    """Return the filters of the comparisons, in the order they were registered.

    Returns
    -------
    tuple of FilterEntry
        The toolkit's six filters first, then any registered later.

    Examples
    --------
    >>> from dstoolkit.filters import registered_filters
    >>> [entry.name for entry in registered_filters()]
    ['dependent_evidence', 'nassreddine', 'bounded_error', 'kalman', 'particle', 'unscented']
    """
    return tuple(_REGISTRY.values())


def filter_named(role: str) -> str:
    """Return the name of the registered filter of a role.

    Parameters
    ----------
    role : {"paper", "rival"}
        The paper's filter, or the one its Figs. 10–11 set against it.

    Returns
    -------
    str
        The filter's registered name.

    Raises
    ------
    EvidenceError
        No registered filter has that role.

    Examples
    --------
    >>> from dstoolkit.filters import filter_named
    >>> filter_named("paper") == registered_filters()[0].name
    True
    """
    for entry in _REGISTRY.values():
        if entry.role == role:
            return entry.name
    raise EvidenceError(
        f"no registered filter has the role {role!r}; roles: "
        f"{sorted({e.role for e in _REGISTRY.values() if e.role})}"
    )


def gaussian_filters() -> tuple[str, ...]:
    """Return the names of the registered filters that report a Gaussian posterior.

    Returns
    -------
    tuple of str
        The entries with ``gaussian=True``, in the order they were registered.

    Examples
    --------
    >>> from dstoolkit.filters import gaussian_filters
    >>> gaussian_filters()
    ('kalman', 'unscented')
    """
    return tuple(e.name for e in _REGISTRY.values() if e.gaussian)


def table3_filters() -> tuple[FilterEntry, ...]:
    """Return the registered filters of the paper's Table 3, in its column order.

    Returns
    -------
    tuple of FilterEntry
        The entries with a ``table3_column``, by that column.

    Examples
    --------
    >>> from dstoolkit.filters import table3_filters
    >>> [entry.table3_column for entry in table3_filters()]
    [0, 1, 3, 4]
    """
    chosen = [e for e in _REGISTRY.values() if e.table3_column is not None]
    return tuple(sorted(chosen, key=lambda e: e.table3_column or 0))


register_filter(
    FilterEntry(
        "dependent_evidence",
        "dependent evidence (paper)",
        "paper's filter",
        "blue",
        "-",
        "o",
        lambda s: DependentEvidenceFilter(
            p=s.p, epsilon=0.05, theta=s.theta, start=s.start, on_conflict="predict"
        ),
        role="paper",
        table3_column=0,
    )
)
register_filter(
    FilterEntry(
        "nassreddine",
        "Nassreddine",
        "Nassreddine",
        "orange",
        "--",
        "s",
        # kernel "auto" by default: compiled where numba is installed, the same numbers, faster
        lambda s: NassreddineFilter(
            p=s.p, epsilon=0.05, theta=s.theta, on_conflict="reset", kernel=s.kernel
        ),
        role="rival",
        table3_column=1,
    )
)
register_filter(
    FilterEntry(
        "bounded_error",
        "bounded error",
        "bounded error",
        "sky blue",
        (0, (3, 1, 1, 1, 1, 1)),
        "P",
        lambda s: BoundedErrorFilter(on_inconsistent="reset"),
    )
)
register_filter(
    FilterEntry(
        "kalman",
        "Kalman",
        "Kalman",
        "vermillion",
        "-.",
        "v",
        lambda s: KalmanFilter(),
        table3_column=3,
        gaussian=True,
    )
)
register_filter(
    FilterEntry(
        "particle",
        "particle",
        "particle",
        "reddish purple",
        (0, (5, 1)),
        "D",
        lambda s: ParticleFilter(
            n_particles=s.n_particles, seed=s.seed, kernel=s.kernel, on_inconsistent="reset"
        ),
        table3_column=4,
    )
)
register_filter(
    FilterEntry(
        "unscented",
        "unscented Kalman",
        "unscented",
        "bluish green",
        (0, (1, 1)),
        "^",
        lambda s: UnscentedKalmanFilter(),
        gaussian=True,
    )
)
