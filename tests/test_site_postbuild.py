"""scripts/site_postbuild.py writes widget views as plain HTML with native controls.

Small widget states written by hand, as myst-nb writes them into a page: a Stack of Stacks
switched by two sliders, a live Dropdown, a disabled slider described by its explorer's
note, a disabled check box and button, an Output with a printed line; and a whole page
rewritten (no widget state, no widget script left).
"""

from __future__ import annotations

import importlib.util
import json
import re
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import pytest
from conftest import ROOT


def _load() -> Any:
    spec = importlib.util.spec_from_file_location(
        "site_postbuild", ROOT / "scripts" / "site_postbuild.py"
    )
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


postbuild = _load()


def _model(name: str, **state: Any) -> dict[str, Any]:
    return {"model_name": name, "state": state}


def _leaf(models: dict[str, Any], key: str, said: str, picture: str) -> str:
    models[key + "r"] = _model(
        "HTMLModel",
        value=f"<table><tr><th>L</th></tr></table><p class='dstoolkit-said' hidden>{said}</p>",
    )
    models[key + "p"] = _model(
        "HTMLModel",
        value=f"<img class='dstoolkit-figure' src='_states/{picture}.png' "
        f"alt='Figure for {said}' style='max-width:100%;height:auto'>",
    )
    models[key] = _model("VBoxModel", children=[f"IPY_MODEL_{key}r", f"IPY_MODEL_{key}p"])
    return f"IPY_MODEL_{key}"


def explorer_state() -> dict[str, Any]:
    """Return an explorer with two live sliders (a 2 x 2 Stack of Stacks) and other controls."""
    m: dict[str, Any] = {}
    m["wide"] = _model("LayoutModel", width="320px")
    m["s1"] = _model(
        "SelectionSliderModel",
        description="level L (m)",
        _options_labels=["1.6", "2.6"],
        index=1,
        layout="IPY_MODEL_wide",
    )
    m["s2"] = _model(
        "SelectionSliderModel", description="discount ε", _options_labels=["0.00", "0.05"], index=0
    )
    m["off"] = _model(
        "FloatSliderModel",
        description="noise (dB SPL)",
        disabled=True,
        value=50.0,
        min=30.0,
        max=100.0,
        step=5.0,
        readout_format=".0f",
    )
    m["box"] = _model("CheckboxModel", description="with devices", disabled=True, value=False)
    m["btn"] = _model("ButtonModel", description="Record", disabled=True, tooltip="record it")
    m["note"] = _model(
        "HTMLModel",
        value="<p class='dstoolkit-site-note'><i>On this page "
        "level L (m) and discount ε answer; see Run this book.</i></p>",
    )
    inner = []
    for i in range(2):
        leaves = [_leaf(m, f"l{i}{j}", f"Level {i} eps {j}", f"p{i}{j}") for j in range(2)]
        m[f"in{i}"] = _model(
            "StackModel", children=leaves, selected_index=0, _dom_classes=["dstoolkit-states"]
        )
        inner.append(f"IPY_MODEL_in{i}")
    m["out"] = _model(
        "StackModel", children=inner, selected_index=1, _dom_classes=["dstoolkit-states"]
    )
    m["say"] = _model("HTMLModel", value="", _dom_classes=["dstoolkit-announce"])
    m["print"] = _model(
        "OutputModel",
        outputs=[{"output_type": "stream", "name": "stdout", "text": "computed 4 states\n"}],
    )
    m["root"] = _model(
        "VBoxModel",
        children=[
            "IPY_MODEL_s1",
            "IPY_MODEL_s2",
            "IPY_MODEL_off",
            "IPY_MODEL_box",
            "IPY_MODEL_btn",
            "IPY_MODEL_note",
            "IPY_MODEL_out",
            "IPY_MODEL_say",
            "IPY_MODEL_print",
        ],
    )
    m["k1"] = _model(
        "LinkModel", source=["IPY_MODEL_s1", "index"], target=["IPY_MODEL_out", "selected_index"]
    )
    for i in range(2):
        m[f"k2{i}"] = _model(
            "LinkModel",
            source=["IPY_MODEL_s2", "index"],
            target=[f"IPY_MODEL_in{i}", "selected_index"],
        )
    return m


def dropdown_state() -> dict[str, Any]:
    """Return a live Dropdown switching a Stack of two HTML states (no sentence region)."""
    m: dict[str, Any] = {}
    m["dd"] = _model(
        "DropdownModel", description="rule", _options_labels=["Dempster", "Yager"], index=1
    )
    m["a"] = _model("HTMLModel", value="<p>Dempster state</p>")
    m["b"] = _model("HTMLModel", value="<p>Yager state</p>")
    m["st"] = _model("StackModel", children=["IPY_MODEL_a", "IPY_MODEL_b"], selected_index=1)
    m["root"] = _model("VBoxModel", children=["IPY_MODEL_dd", "IPY_MODEL_st"])
    m["k"] = _model(
        "LinkModel", source=["IPY_MODEL_dd", "index"], target=["IPY_MODEL_st", "selected_index"]
    )
    return m


class _Tree(HTMLParser):
    """Elements of an HTML piece: (tag, attributes, hidden by an ancestor or itself)."""

    def __init__(self) -> None:
        super().__init__()
        self.stack: list[tuple[str, bool]] = []
        self.elements: list[tuple[str, dict[str, str | None], bool]] = []
        self.text: dict[str, str] = {}
        self._open_ids: list[str | None] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        found = dict(attrs)
        hidden = "hidden" in found or any(h for _, h in self.stack)
        self.elements.append((tag, found, hidden))
        if tag not in ("input", "img", "br", "meta", "link"):
            self.stack.append((tag, hidden))
            self._open_ids.append(found.get("id"))

    def handle_endtag(self, tag: str) -> None:
        if self.stack and tag not in ("input", "img"):
            self.stack.pop()
            self._open_ids.pop()

    def handle_data(self, data: str) -> None:
        for key in self._open_ids:
            if key:
                self.text[key] = self.text.get(key, "") + data


def _render(models: dict[str, Any], tmp_path: Path) -> tuple[str, _Tree]:
    body = postbuild.ExplorerHTML(models, tmp_path).view("root")
    tree = _Tree()
    tree.feed(body)
    return body, tree


def test_two_sliders_become_labelled_ranges_that_switch_their_stacks(tmp_path: Path) -> None:
    body, tree = _render(explorer_state(), tmp_path)
    ranges = [a for t, a, _ in tree.elements if t == "input" and a.get("type") == "range"]
    live = [a for a in ranges if "disabled" not in a]
    assert len(live) == 2, body
    level, eps = live
    assert (level["min"], level["max"], level["value"]) == ("0", "1", "1")
    assert level["aria-valuetext"] == "2.6 m"  # the readout and the label's unit
    assert eps["aria-valuetext"] == "0.00"  # "discount ε" names no unit
    assert json.loads(level["data-labels"] or "") == ["1.6", "2.6"]
    assert level["data-switches"] == "out" and (eps["data-switches"] or "").split() == [
        "in0",
        "in1",
    ]
    labels = {
        a["for"]: tree.text.get(a["id"] or "", "")
        for t, a, _ in tree.elements
        if t == "label" and a.get("id")
    }
    assert labels[level["id"]] == "level L (m)" and labels[eps["id"]] == "discount ε"
    readouts = [a for t, a, _ in tree.elements if t == "output"]
    assert {r["for"] for r in readouts} >= {level["id"], eps["id"]}
    assert re.search(
        r'<output class="dstoolkit-readout" for="' + str(level["id"]) + r'"[^>]*>2\.6<', body
    )
    assert "width:320px" in body  # the slider keeps its layout's width


def test_only_the_selected_states_show_and_hidden_pictures_wait(tmp_path: Path) -> None:
    body, tree = _render(explorer_state(), tmp_path)
    images = [(a, hidden) for t, a, hidden in tree.elements if t == "img"]
    assert len(images) == 4, body
    shown = [a for a, hidden in images if not hidden]
    # outer stack at index 1, inner stack at index 0: the state "Level 1 eps 0" only
    assert len(shown) == 1 and shown[0]["src"] == "_states/p10.png", shown
    for attrs, hidden in images:
        if hidden:
            assert "src" not in attrs and (attrs.get("data-src") or "").startswith("_states/")
            assert attrs.get("loading") == "lazy"
        else:  # the shown state's picture comes with the page
            assert "loading" not in attrs and "data-src" not in attrs
    links = [
        str(a["href"])
        for t, a, _ in tree.elements
        if t == "a" and a.get("class") == "dstoolkit-fullsize"
    ]
    assert sorted(links) == [f"_states/p{i}{j}.png" for i in range(2) for j in range(2)]
    stacks = [a for t, a, _ in tree.elements if t == "div" and a.get("data-stack")]
    assert [s["data-stack"] for s in stacks] == ["out", "in0", "in1"]


def test_other_controls_are_disabled_and_described_by_the_note(tmp_path: Path) -> None:
    body, tree = _render(explorer_state(), tmp_path)
    note = next(
        a for t, a, _ in tree.elements if t == "p" and a.get("class") == "dstoolkit-site-note"
    )
    assert note.get("id"), body
    disabled = [
        (t, a)
        for t, a, _ in tree.elements
        if t in ("input", "button", "select") and "disabled" in a
    ]
    kinds = sorted(a.get("type") or t for t, a in disabled)
    assert kinds == ["button", "checkbox", "range"], kinds
    for _, attrs in disabled:
        assert attrs.get("aria-disabled") == "true"
        assert attrs.get("aria-describedby") == note["id"]
        assert "data-switches" not in attrs
    noise = next(a for t, a in disabled if a.get("type") == "range")
    assert noise["aria-valuetext"] == "50 dB SPL" and noise["value"] == "50.0"
    assert "computed 4 states" in body  # the Output's printed line
    region = next(a for t, a, _ in tree.elements if "dstoolkit-announce" in (a.get("class") or ""))
    assert region.get("aria-live") == "polite" and region.get("role") == "status"


def test_a_live_dropdown_is_a_select_and_its_stack_a_live_region(tmp_path: Path) -> None:
    body, tree = _render(dropdown_state(), tmp_path)
    select = next(a for t, a, _ in tree.elements if t == "select")
    assert "disabled" not in select and select["data-switches"] == "st"
    options = [(a.get("value"), "selected" in a) for t, a, _ in tree.elements if t == "option"]
    assert options == [("0", False), ("1", True)]
    stack = next(a for t, a, _ in tree.elements if a.get("data-stack") == "st")
    assert stack.get("aria-live") == "polite"  # no sentence region: the stack itself
    shown = [t for t, a, hidden in tree.elements if t == "p" and not hidden]
    assert len(shown) == 1, body
    assert re.search(r'<div class="dstoolkit-state"><div[^>]*><p>Yager state', body), body
    assert re.search(r'<div class="dstoolkit-state" hidden><div[^>]*><p>Dempster', body), body


@pytest.mark.parametrize(
    ("label", "shown", "said"),
    [
        ("level L (m)", "9.6", "9.6 m"),
        ("background noise (dB SPL)", "50", "50 dB SPL"),
        ("m({low})", "0.3", "0.3"),
        ("copies n", "3", "3"),
    ],
)
def test_the_value_text_carries_the_label_unit(label: str, shown: str, said: str) -> None:
    assert postbuild.value_text(shown, label) == said


def test_a_page_keeps_no_widget_state_nor_widget_script(tmp_path: Path) -> None:
    site = tmp_path / "site"
    (site / "_static").mkdir(parents=True)
    (site / "book").mkdir()
    (site / "index.html").write_text("<html><head></head><body></body></html>")
    state = {"version_major": 2, "version_minor": 0, "state": dropdown_state()}
    page = site / "book" / "x.html"
    page.write_text(
        "<html><head>"
        '<script type="application/vnd.jupyter.widget-state+json">'
        + json.dumps(state)
        + '</script><script defer="defer" src="../_static/jupyter-widgets/embed.js"></script>'
        '</head><body><article class="bd-article"><div class="cell_output">'
        '<script type="application/vnd.jupyter.widget-view+json">'
        '{"model_id": "root", "version_major": 2, "version_minor": 0}</script>'
        "</div></article></body></html>"
    )
    assert postbuild.main([str(site)]) == 0
    text = page.read_text()
    assert "widget-state" not in text and "widget-view" not in text and "embed.js" not in text
    assert '<div class="dstoolkit-explorer' in text
    assert '<script async src="../_static/explorers.js"></script>' in text


# --- the joined stylesheet, purged; its icon fonts cut to the icons it draws --------------

#: Font Awesome's solid font as the theme ships it (TrueType, read by fontTools).
_THEME_FONTS = (
    Path(str(__import__("pydata_sphinx_theme").__file__)).parent
    / "theme/pydata_sphinx_theme/static/vendor/fontawesome/webfonts"
)


def test_css_strings_and_icon_characters_are_read_with_their_escapes() -> None:
    assert postbuild.css_string(r"\f0c9") == "\uf0c9"
    assert postbuild.css_string(r"\f0c9 x") == "\uf0c9x"  # one space ends an escape
    assert postbuild.css_string(r"a\"b") == 'a"b'
    css = (
        '.fa-bars:before{content:"\\f0c9"}:root{--pst-icon-note:"\\f05a";color:"\\41"}'
        ".x::after{content:'\\e2ca'}"
    )
    # color's string is no icon: only content declarations and custom properties count
    assert postbuild.icon_codepoints(css) == {0xF0C9, 0xF05A, 0xE2CA}


def test_an_icon_font_is_cut_to_the_icons_its_stylesheet_draws(tmp_path: Path) -> None:
    from fontTools.ttLib import TTFont  # type: ignore[import-untyped]

    static = tmp_path / "_static"
    fonts = static / "vendor/fontawesome/webfonts"
    fonts.mkdir(parents=True)
    for name in ("fa-solid-900.ttf", "fa-solid-900.woff2"):
        (fonts / name).write_bytes((_THEME_FONTS / name).read_bytes())
    face = (
        "@font-face{font-display:block;font-family:Font Awesome\\ 6 Free;font-weight:900;"
        'src:url(vendor/fontawesome/webfonts/fa-solid-900.woff2) format("woff2"),'
        'url(vendor/fontawesome/webfonts/fa-solid-900.ttf) format("truetype")}'
    )
    other = '@font-face{font-family:Text;src:url(text.ttf) format("truetype")}'
    css = face + other + '.fa-bars:before{content:"\\f0c9"}.fa-xmark:before{content:"\\f00d"}'
    out = postbuild.subset_icon_fonts(css, static)
    found = re.search(
        r"src:url\((vendor/fontawesome/webfonts/fa-solid-900-[0-9a-f]{16}\.woff)\)", out
    )
    assert found, out
    assert other in out  # a text font is left as it is
    subset = static / found.group(1)
    font = TTFont(subset)
    assert set(font.getBestCmap()) == {0xF0C9, 0xF00D}
    # the same bytes on every build: the font keeps its own date, not the build's
    assert font["head"].modified == TTFont(fonts / "fa-solid-900.ttf")["head"].modified
    whole = (fonts / "fa-solid-900.woff2").stat().st_size
    # two icons of ~1400: the subset must be a small fraction of the shipped WOFF 2
    assert subset.stat().st_size < whole / 10


@pytest.fixture(scope="module")
def purged() -> str:
    """Return a stylesheet purged against one page and one script, as slim_styles does."""
    import tempfile

    css = (
        ".used{color:red}.unused{color:blue}"
        "html[data-theme=dark] .used{color:pink}"
        ".bs-tooltip-auto .tooltip-arrow{top:0}"
        ".added-by-script{color:green}"
        ".row{display:flex}"
        "@keyframes spin{to{transform:rotate(1turn)}}"
        ":focus-visible{outline:3px solid purple}"
    )
    page = (
        '<html data-theme="light"><body><p class="used">A row of small words.</p>'
        "<script>document.body.dataset.x = 1;</script></body></html>"
    )
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "s.css").write_text(css)
        (folder / "p.html").write_text(page)
        (folder / "a.js").write_text('el.classList.add("added-by-script");')
        return postbuild.purge_css(folder / "s.css", [folder / "p.html", folder / "a.js"])


def test_purging_keeps_what_a_page_or_script_uses(purged: str) -> None:
    assert ".used{" in purged.replace(" ", "")
    assert "added-by-script" in purged  # named by a script's string
    assert "data-theme=dark" in purged.replace('"', "")  # dark mode, chosen at run time
    assert "bs-tooltip-auto" in purged  # built from pieces by Bootstrap's script
    assert "@keyframes spin" in purged
    assert ":focus-visible{" in purged.replace(" ", "")  # the focus ring of every control


def test_purging_drops_what_nothing_uses(purged: str) -> None:
    assert ".unused" not in purged
    # "row" is a word of the page's prose, not a class of any element
    assert ".row" not in purged


def test_pages_link_the_purged_stylesheet_once_and_the_old_one_goes(tmp_path: Path) -> None:
    site = tmp_path / "site"
    static = site / "_static"
    static.mkdir(parents=True)
    (site / "book").mkdir()
    old = static / "styles-0123456789abcdef.css"
    old.write_text(".used{color:red}.unused{color:blue}")
    pages = []
    for name in ("index.html", "book/x.html"):
        page = site / name
        href = ("" if "/" not in name else "../") + "_static/" + old.name
        page.write_text(
            f'<html><head><link rel="stylesheet" type="text/css" href="{href}" /></head>'
            '<body><p class="used">x</p></body></html>'
        )
        pages.append(page)
    assert postbuild.slim_styles(site, pages) == 1
    assert not old.exists()
    (new,) = static.glob("styles-*.css")
    assert new.read_text().startswith(postbuild.SLIM)
    assert ".unused" not in new.read_text() and ".used" in new.read_text()
    assert f'href="_static/{new.name}"' in pages[0].read_text()
    assert f'href="../_static/{new.name}"' in pages[1].read_text()
    # run again: nothing is purged twice
    assert postbuild.slim_styles(site, pages) == 0
    assert list(static.glob("styles-*.css")) == [new]
