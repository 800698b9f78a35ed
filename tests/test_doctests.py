"""The examples in the docstrings run, and give what they show (doctest).

Every module of every layer (errors, utils, evidence, filters, gauge, studies, plots, audio,
teaching) and the command line is searched; the main public functions must carry an example
(``tests/test_docstrings.py`` asks it of every exported function and class).
"""

from __future__ import annotations

import doctest
import importlib
import importlib.util
import pkgutil

import pytest

CORE = (
    "dstoolkit.utils",
    "dstoolkit.evidence",
    "dstoolkit.filters",
    "dstoolkit.gauge",
    "dstoolkit.studies",
)
#: Layers that need an optional extra (plots, audio, teaching): left out of the core-only run.
WITH_EXTRAS = ("dstoolkit.plots", "dstoolkit.audio", "dstoolkit.teaching")


def _modules() -> list[object]:
    names: list[object] = ["dstoolkit", "dstoolkit.errors", "dstoolkit.cli"]
    for package in CORE + WITH_EXTRAS:
        # find_spec does not import the package itself, so collecting needs no extra
        spec = importlib.util.find_spec(package)
        assert spec is not None and spec.submodule_search_locations is not None, package
        found = [package] + [
            f"{package}.{info.name}"
            for info in pkgutil.iter_modules(spec.submodule_search_locations)
        ]
        marks = [pytest.mark.extras] if package in WITH_EXTRAS else []
        names += [pytest.param(name, marks=marks, id=name) for name in found]
    return names


@pytest.mark.parametrize("name", _modules())
def test_docstring_examples(name: str) -> None:
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS, report=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed"


@pytest.mark.parametrize(
    "qualname",
    [
        "dstoolkit.evidence.dempster",
        "dstoolkit.evidence.combine_dependent",
        "dstoolkit.evidence.dependence",
        "dstoolkit.evidence.energy",
        "dstoolkit.evidence.triangular_evidence",
        "dstoolkit.evidence.IntervalEvidence",
        "dstoolkit.evidence.MassFunction",
        "dstoolkit.filters.BoundedNoise",
        "dstoolkit.filters.Filter",
        "dstoolkit.filters.BatchResult",
        "dstoolkit.filters.DependentEvidenceFilter",
        "dstoolkit.filters.NassreddineFilter",
        "dstoolkit.filters.BoundedErrorFilter",
        "dstoolkit.filters.KalmanFilter",
        "dstoolkit.filters.ParticleFilter",
        "dstoolkit.gauge.speed_of_sound",
        "dstoolkit.gauge.level_from_resonance",
        "dstoolkit.gauge.level_from_fundamental",
        "dstoolkit.gauge.orders_eq43",
        "dstoolkit.gauge.direct_levels",
        "dstoolkit.gauge.state_transition",
        "dstoolkit.gauge.estimate_latency",
    ],
)
def test_main_functions_show_an_example(qualname: str) -> None:
    obj = pkgutil.resolve_name(qualname)
    tests = doctest.DocTestFinder(recurse=False).find(obj, qualname)
    assert tests and tests[0].examples, f"{qualname} has no example in its docstring"
