"""The filters are named in one place: the registry (dstoolkit/filters/_registry.py).

Outside dstoolkit/filters/, the package's code must not name a registered filter (its
registered name as a string, or its class), except in docstrings and comments (prose) and
in the few places listed in :data:`ALLOWED`, each of which uses one filter for what only
that filter does. A list of filters written anywhere else would miss a newly registered one.
"""

from __future__ import annotations

import ast
from pathlib import Path

from dstoolkit.filters import ComparisonSettings, registered_filters

PACKAGE = Path(__file__).resolve().parents[1] / "dstoolkit"

#: Module (relative to dstoolkit/) → the filter names or classes its code may use, and why.
ALLOWED: dict[str, tuple[set[str], str]] = {
    "__init__.py": (
        {"BoundedErrorFilter", "DependentEvidenceFilter", "KalmanFilter", "NassreddineFilter"}
        | {"ParticleFilter"},
        "re-exports the public classes at the top of the package",
    ),
    "studies/_estimation.py": (
        {"BoundedErrorFilter", "DependentEvidenceFilter", "bounded_error"},
        "studies of one filter: where the strict bounded-error filter fails, and the "
        "paper's filter's two starts x̂_1",
    ),
    "studies/_filter_runs.py": (
        {"DependentEvidenceFilter"},
        "runs the paper's filter with the options only it has (mass rule, start)",
    ),
    "studies/_paper_results.py": (
        {"dependent_evidence", "nassreddine"},
        "the numbers the paper prints (Table 3), by its columns",
    ),
    "plots/_studies.py": (
        {"bounded_error"},
        "the bound-scale figure marks where the strict bounded-error filter fails",
    ),
    "teaching/_variants.py": (
        {"dependent_evidence"},
        "the chapter's file name dependent_evidence.md, not the filter",
    ),
    "teaching/_ex_coding.py": (
        {"DependentEvidenceFilter"},
        "an exercise checks a student's step against the paper's filter",
    ),
    "teaching/_ex_filter.py": (
        {"DependentEvidenceFilter"},
        "the noise evidence of the paper's filter (its Step 1)",
    ),
    "teaching/_ex_gauge.py": (
        {"DependentEvidenceFilter"},
        "the noise evidence of the paper's filter (its Step 1)",
    ),
    "studies/_level_cells.py": (
        {"DependentEvidenceFilter"},
        "runs the paper's filter's Steps 1–5 with another combination in its Step 6",
    ),
    "teaching/_ex_recursion.py": (
        {"kalman"},
        "exercises ask for the Kalman filter's NEES and NIS on the gauge",
    ),
    "teaching/_explorers_recursion.py": (
        {"kalman"},
        "the consistency explorer reads out the Kalman filter's NEES and NIS",
    ),
    "teaching/_explorers_bounded.py": (
        {"BoundedErrorFilter"},
        "the bounded-error chapter's explorer shows that filter's boxes",
    ),
}


def _registered() -> set[str]:
    settings = ComparisonSettings()
    names = set()
    for entry in registered_filters():
        names.add(entry.name)
        names.add(type(entry.make(settings)).__name__)
    return names


def _docstrings(tree: ast.AST) -> set[int]:
    """Return the ids of the string constants that are docstrings."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                found.add(id(body[0].value))
    return found


def filter_names_in_code(source: str, names: set[str]) -> set[str]:
    """Return the registered names and classes ``source``'s code (not its prose) uses."""
    tree = ast.parse(source)
    prose = _docstrings(tree)
    used = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            if id(node) not in prose and node.value in names:
                used.add(node.value)
        elif isinstance(node, ast.Name) and node.id in names:
            used.add(node.id)
        elif isinstance(node, ast.Attribute) and node.attr in names:
            used.add(node.attr)
        elif isinstance(node, ast.alias) and node.name in names:
            used.add(node.name)
    return used


def test_the_checker_finds_a_list_of_filters_in_code_and_not_in_prose() -> None:
    names = _registered()
    code = '"""A docstring naming kalman."""\nMETHODS = ("kalman", "particle")\n'
    assert filter_names_in_code(code, names) == {"kalman", "particle"}
    assert filter_names_in_code("from x import KalmanFilter\n", names) == {"KalmanFilter"}
    assert filter_names_in_code('"""kalman, KalmanFilter"""\n# kalman\n', names) == set()


def test_no_module_outside_the_registry_names_a_filter_in_code() -> None:
    names = _registered()
    offenders = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).as_posix()
        if rel.startswith("filters/"):
            continue
        used = filter_names_in_code(path.read_text(encoding="utf-8"), names)
        used -= ALLOWED.get(rel, (set(), ""))[0]
        if used:
            offenders[rel] = sorted(used)
    assert not offenders, (
        f"filters named outside the registry: {offenders}; read them from "
        "dstoolkit.filters.registered_filters / filter_named / table3_filters"
    )


def test_every_allowance_is_still_needed() -> None:
    """An allowance no module uses any more is removed, so the list does not grow stale."""
    names = _registered()
    for rel, (allowed, _) in ALLOWED.items():
        used = filter_names_in_code((PACKAGE / rel).read_text(encoding="utf-8"), names)
        assert allowed <= used, (rel, sorted(allowed - used))


def test_the_comparisons_kernel_is_chosen_once_and_reaches_every_filter_that_has_one():
    import pytest

    from dstoolkit.errors import InvalidInputError
    from dstoolkit.filters import set_comparison_kernel

    before = set_comparison_kernel("numpy")
    try:
        assert ComparisonSettings().kernel == "numpy"
        made = [entry.make(ComparisonSettings()) for entry in registered_filters()]
        kernels = {type(f).__name__: f.kernel for f in made if hasattr(f, "kernel")}
        assert {"NassreddineFilter", "ParticleFilter"} <= set(kernels)
        assert set(kernels.values()) == {"numpy"}, kernels
        assert ComparisonSettings(kernel="auto").kernel == "auto"
        with pytest.raises(InvalidInputError, match="kernel must be"):
            set_comparison_kernel("fast")  # type: ignore[arg-type]
    finally:
        set_comparison_kernel(before)
    assert ComparisonSettings().kernel == before == "auto"
