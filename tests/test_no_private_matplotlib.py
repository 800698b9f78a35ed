"""dstoolkit uses matplotlib through its public API only.

The scan reads every module of ``dstoolkit/`` (its syntax tree, not its text) and finds
three ways of reaching into matplotlib's internals:

- reading or writing an attribute ``obj._name`` (``obj`` not ``self`` or ``cls``) whose
  name is a private name of matplotlib's (collected from its classes and from the objects
  a drawn figure holds) and that dstoolkit does not define itself;
- a class deriving from a matplotlib class that defines a method or attribute ``_name``
  (an override of a private method);
- assigning ``obj.__class__`` (swapping an object's class in place).
"""

from __future__ import annotations

import ast
import collections
import importlib
import inspect
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

#: The matplotlib modules whose classes dstoolkit's figures are made of, and their drawing.
MODULES = (
    "matplotlib.artist",
    "matplotlib.axes",
    "matplotlib.axis",
    "matplotlib.backend_bases",
    "matplotlib.backends.backend_agg",
    "matplotlib.collections",
    "matplotlib.colorbar",
    "matplotlib.colors",
    "matplotlib.figure",
    "matplotlib.font_manager",
    "matplotlib.ft2font",
    "matplotlib.gridspec",
    "matplotlib.image",
    "matplotlib.layout_engine",
    "matplotlib.legend",
    "matplotlib.lines",
    "matplotlib.mathtext",
    "matplotlib.offsetbox",
    "matplotlib.patches",
    "matplotlib.path",
    "matplotlib.scale",
    "matplotlib.spines",
    "matplotlib.text",
    "matplotlib.textpath",
    "matplotlib.ticker",
    "matplotlib.transforms",
    "matplotlib.widgets",
)
#: Public names of named tuples (matplotlib has some): not private.
NAMEDTUPLE = frozenset(dir(collections.namedtuple("Probe", "a")))
PACKAGE = Path(__file__).resolve().parents[1] / "dstoolkit"


def _is_private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def matplotlib_private_names() -> frozenset[str]:
    """Return the private names of matplotlib's classes and of a drawn figure's objects."""
    names: set[str] = set()
    for name in MODULES:
        module = importlib.import_module(name)
        for _, cls in inspect.getmembers(module, inspect.isclass):
            if cls.__module__.startswith("matplotlib"):
                for klass in cls.__mro__:
                    names.update(n for n in vars(klass) if _is_private(n))
    from matplotlib.backends import backend_agg

    for _, cls in inspect.getmembers(backend_agg, inspect.isclass):
        names.update(n for n in dir(cls) if _is_private(n))
    fig = Figure()
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.plot([0, 1], [0, 2])
    ax.set_xlabel("x")
    canvas.draw()
    objects = [*fig.findobj(), canvas, canvas.get_renderer()]
    for axis in (ax.xaxis, ax.yaxis):
        objects += [axis.get_major_locator(), axis.get_major_formatter()]
    for obj in objects:
        names.update(n for n in getattr(obj, "__dict__", {}) if _is_private(n))
    return frozenset(names - NAMEDTUPLE)


def _modules() -> list[tuple[Path, ast.Module]]:
    return [(path, ast.parse(path.read_text(encoding="utf-8"))) for path in PACKAGE.rglob("*.py")]


def own_private_names(modules: list[tuple[Path, ast.Module]]) -> frozenset[str]:
    """Return the private names dstoolkit defines: functions, classes, attributes it sets."""
    names: set[str] = set()
    for _, tree in modules:
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                names.add(node.name)
            elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
                names.add(node.attr)
            elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                names.add(node.target.id)
            elif isinstance(node, ast.Assign):
                names.update(t.id for t in node.targets if isinstance(t, ast.Name))
    return frozenset(n for n in names if _is_private(n))


def _imported(tree: ast.Module) -> tuple[set[str], set[str]]:
    """Return the local names a module binds to matplotlib, and to other libraries."""
    mpl: set[str] = set()
    other: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 0:
            into = mpl if (node.module or "").startswith("matplotlib") else other
            into.update(alias.asname or alias.name for alias in node.names)
        elif isinstance(node, ast.Import):
            for alias in node.names:
                into = mpl if alias.name.startswith("matplotlib") else other
                into.add((alias.asname or alias.name).split(".")[0])
    return mpl, other - {"dstoolkit"}


def findings(
    modules: list[tuple[Path, ast.Module]], private: frozenset[str], own: frozenset[str]
) -> list[str]:
    """Return ``path:line: what`` for every reach into matplotlib's internals."""
    found: list[str] = []
    for path, tree in modules:
        mpl_names, other_libraries = _imported(tree)
        for node in ast.walk(tree):
            where = f"{path.name}:{getattr(node, 'lineno', 0)}"
            if isinstance(node, ast.Attribute):
                receiver = node.value
                if isinstance(receiver, ast.Name) and (
                    receiver.id in {"self", "cls"} or receiver.id in other_libraries
                ):
                    continue  # dstoolkit's own objects, or another library (not matplotlib)
                if node.attr == "__class__" and isinstance(node.ctx, ast.Store):
                    found.append(f"{where}: assigns __class__")
                elif node.attr in private and node.attr not in own:
                    found.append(f"{where}: matplotlib's private {node.attr}")
            elif isinstance(node, ast.Call) and getattr(node.func, "id", None) in {
                "getattr",
                "setattr",
                "hasattr",
            }:
                if len(node.args) > 1 and isinstance(node.args[1], ast.Constant):
                    name = node.args[1].value
                    if isinstance(name, str) and name in private and name not in own:
                        found.append(f"{where}: matplotlib's private {name} by name")
            elif isinstance(node, ast.ClassDef):
                bases = {ast.unparse(b).split(".")[0] for b in node.bases}
                if bases & mpl_names:
                    for item in node.body:
                        if isinstance(item, ast.FunctionDef | ast.Assign) and _is_private(
                            getattr(item, "name", "")
                        ):
                            found.append(
                                f"{path.name}:{item.lineno}: overrides matplotlib's {item.name}"
                            )
    return found


@pytest.fixture(scope="module")
def private() -> frozenset[str]:
    names = matplotlib_private_names()
    # the scan knows the internals the removed caches used: it would have found them
    assert {"_update_ticks", "_get_ticklabel_bboxes", "_axis_map", "_major_tick_kw"} <= names
    return names


def test_no_module_of_dstoolkit_reaches_into_matplotlib(private: frozenset[str]) -> None:
    modules = _modules()
    assert len(modules) > 50  # the whole package was read
    assert findings(modules, private, own_private_names(modules)) == []


def test_the_scan_finds_each_kind_of_reach(private: frozenset[str]) -> None:
    """Code written as the old tick cache was is found, line by line."""
    source = """
from matplotlib.axis import XAxis
def remember(ax, obj, sub):
    size = ax.xaxis._major_tick_kw.get("labelsize")
    for axis in ax._axis_map.values():
        pass
    obj.__class__ = sub
    return getattr(ax, "_get_ticklabel_bboxes")
class Remembering(XAxis):
    def _update_ticks(self):
        return []
"""
    tree = ast.parse(source)
    found = findings([(Path("probe.py"), tree)], private, frozenset())
    assert sorted(int(f.split(":")[1]) for f in found) == [4, 5, 7, 8, 10]
