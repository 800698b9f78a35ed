"""The chapters as clean notebooks (scripts/chapter_notebook.py, scripts/sphinx_notebooks.py).

First the converter on small pieces of MyST (fast); then what the book build wrote into the
site: one notebook per numbered chapter with no raw MyST, no solution, every exercise,
every glued value and code that runs without myst_nb, linked from its chapter page beside
the chapter's exercise sheet.
"""

from __future__ import annotations

import ast
import json
import re
import sys
from pathlib import Path

import nbformat
import pytest
from conftest import ROOT, BookBuild

sys.path.insert(0, str(ROOT / "scripts"))
from chapter_notebook import (  # noqa: E402
    References,
    clean_markdown,
    clean_notebook,
    split_glue,
    strip_glue,
)

#: MyST that must not survive the conversion: roles, directive fences, options, targets.
RAW_MYST = re.compile(
    r"\{[\w:.+-]+\}`|^\s*[`~:]{3,}\s*\{|^\s*:(label|class|tags):|^\(\S+\)=\s*$", re.MULTILINE
)


def directive_phrases(chapter_source: str, directive: str) -> list[str]:
    """Return plain phrases found only in the bodies of the chapter's ``{directive}`` blocks.

    The phrases have no maths and no markup and at least 25 characters: what must
    (exercise) or must not (solution) be seen of them.
    """
    block = rf"^(`{{3,}})\{{{directive}\}}.*?\n(.*?)^\1\s*$"
    phrases = []
    for _, body in re.findall(block, chapter_source, re.MULTILINE | re.DOTALL):
        text = re.sub(r"\$[^$]*\$|\{[^}]*\}`[^`]*`|^:.*$", "|", body, flags=re.MULTILINE)
        phrases += [p.strip() for p in re.findall(r"[A-Za-z][A-Za-z ,;'-]{24,}", text)]
    elsewhere = re.sub(block, "", chapter_source, flags=re.MULTILINE | re.DOTALL)
    return [p for p in phrases if p not in elsewhere]


def _refs(**glue: str) -> References:
    return References(
        glue_markdown={"table": "| a |\n| - |"},
        equations={"mf-bel": "3.2"},
        numbered={"mf-fig": "Fig. 3.1", "mf-ex": "Exercise 3.1"},
        sections={"intro": "How to use this book"},
        documents={"book/notation": "Notation", "book/mass_functions": "Mass functions"},
        chapter_numbers={"book/notation": "1", "book/mass_functions": "3"},
        citations={"xu2017": ("Xu et al.", "2017"), "shafer1976": ("Shafer", "1976")},
        glue=glue,
        format_glue=lambda text, spec: format(float(text), spec) if spec else text,
    )


# --------------------------------------------------------------------------------------
# The converter
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("myst", "markdown"),
    [
        ("Bel is {glue:text}`bel:.2f` here.", "Bel is 0.80 here."),
        ("as {glue:md}`table`", "as | a |\n| - |"),
        ("by {eq}`mf-bel`", "by (3.2)"),
        ("{numref}`mf-fig` shows", "Fig. 3.1 shows"),
        ("{numref}`Figure %s <mf-fig>`", "Figure 3.1"),
        ("see {doc}`notation`", "see *Notation* (chapter 1)"),
        ("see {doc}`the symbols <notation>`", "see the symbols (chapter 1)"),
        (
            "a {term}`mass function`, {term}`focal elements <focal element>`",
            "a mass function, focal elements",
        ),
        (
            "as {cite:t}`xu2017` do {cite:p}`xu2017,shafer1976`",
            "as Xu et al. (2017) do (Xu et al., 2017; Shafer, 1976)",
        ),
        ("{ref}`intro`", "*How to use this book*"),
        (
            "sheet {download}`notebooks/03_x.ipynb <../notebooks/03_x.ipynb>`",
            "sheet `notebooks/03_x.ipynb`",
        ),
        ("code `{eq}` stays", "code `{eq}` stays"),
    ],
)
def test_roles_read_as_in_the_book(myst: str, markdown: str) -> None:
    assert clean_markdown(myst, _refs(bel="0.8"), "book/mass_functions") == markdown


def test_exercise_is_numbered_and_its_solution_is_dropped() -> None:
    myst = """Before.

```{exercise}
:label: mf-ex

Compute Bel.
```

````{solution} mf-ex
:class: dropdown

The answer is 0.8, shown with
```python
m.belief("low")
```
````

After."""
    out = clean_markdown(myst, _refs(), "book/mass_functions")
    assert out == "Before.\n\n> **Exercise 3.1**\n>\n> Compute Bel.\n\nAfter."


def test_admonition_and_labelled_equation() -> None:
    myst = """```{admonition} What you will learn
:class: tip

- belief, with {eq}`mf-bel`
```

(mf-target)=
$$
\\mathrm{Bel}(A) = \\sum_{B \\subseteq A} m(B)
$$ (mf-bel)"""
    out = clean_markdown(myst, _refs(), "book/mass_functions")
    assert out == (
        "> **What you will learn**\n>\n> - belief, with (3.2)\n\n$$\n"
        "\\mathrm{Bel}(A) = \\sum_{B \\subseteq A} m(B)\n\\tag{3.2}\n$$"
    )


def test_unknown_syntax_is_reported() -> None:
    said: list[str] = []
    out = clean_markdown(
        "{mystery}`x` and {eq}`nowhere`\n\n```{tabs}\nInside.\n```",
        _refs(),
        "book/mass_functions",
        warn=said.append,
    )
    assert "x and (nowhere)" in out and "> Inside." in out
    assert len(said) == 3 and any("tabs" in s for s in said) and any("mystery" in s for s in said)


def test_glue_is_removed_from_the_code() -> None:
    setup = '''import numpy as np
from myst_nb import glue


def g(name, value):
    """Glue a number."""
    glue(name, float(value), display=False)


def twice(x):
    return 2 * x'''
    numbers = """total = np.sum([1, 2])
g("total", total)
for k in range(2):
    g(f"k{k}", k)
if total > 2:
    g("big", 1)
else:
    print("small")
glue("word", "does", display=False)"""
    only_glue = 'g("a", 1)\ng("b", 2)'
    out = strip_glue([setup, numbers, only_glue])
    assert out[0] == "import numpy as np\n\ndef twice(x):\n    return 2 * x"
    assert out[1] == 'total = np.sum([1, 2])\nif total > 2:\n    pass\nelse:\n    print("small")'
    assert out[2] == ""
    for source in out:
        assert "glue" not in source and "g(" not in source
        ast.parse(source)


def test_code_without_glue_is_untouched() -> None:
    sources = ["x = 1\n# a comment\nprint(x)", "def g(a):\n    return a"]
    assert strip_glue(sources) == sources
    magics = [
        "%matplotlib inline\nfrom myst_nb import glue\nglue('a', 1)",
        "%%bash\nls",
        "# only a comment",
    ]
    assert strip_glue(magics) == ["%matplotlib inline", "%%bash\nls", "# only a comment"]


def test_notebook_folds_hidden_code_and_captions_figures() -> None:
    cells = [
        nbformat.v4.new_markdown_cell("(mf)=\n# Mass functions\n\nSee {eq}`mf-bel`."),
        nbformat.v4.new_code_cell(
            "from myst_nb import glue\nx = 1\nglue('x', x)", metadata={"tags": ["remove-cell"]}
        ),
        nbformat.v4.new_code_cell(
            "plot(x)",
            metadata={
                "mystnb": {"figure": {"name": "mf-fig", "caption": "The masses, {eq}`mf-bel`."}}
            },
        ),
        nbformat.v4.new_markdown_cell("```{solution} mf-ex\nSecret.\n```"),
    ]
    nb = clean_notebook(cells, _refs(), "book/mass_functions", preface="From the book.")
    nbformat.validate(nbformat.from_dict(nb))
    assert [(c["cell_type"], c["source"]) for c in nb["cells"]] == [
        ("markdown", "From the book."),
        ("markdown", "# Mass functions\n\nSee (3.2)."),
        ("code", "x = 1"),
        ("code", "plot(x)"),
        ("markdown", "**Fig. 3.1.** The masses, (3.2)."),
    ]
    assert nb["cells"][2]["metadata"] == {"jupyter": {"source_hidden": True}}
    assert nb["metadata"]["kernelspec"]["name"] == "python3"


# --------------------------------------------------------------------------------------
# The built site
# --------------------------------------------------------------------------------------


def _numbered_chapters() -> list[str]:
    """Stems of the chapters in the numbered parts of _toc.yml, in order."""
    import yaml

    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    return [
        Path(ch["file"]).stem
        for part in toc["parts"]
        if part.get("numbered")
        for ch in part["chapters"]
    ]


CHAPTERS = _numbered_chapters()


def _site_notebook(built_book: BookBuild, stem: str) -> tuple[Path, dict]:
    found = sorted((built_book.html_dir / "notebooks").glob(f"chapter_*_{stem}.ipynb"))
    assert len(found) == 1, f"expected one notebooks/chapter_NN_{stem}.ipynb, found {found}"
    return found[0], json.loads(found[0].read_text(encoding="utf-8"))


@pytest.mark.slow
@pytest.mark.parametrize("stem", CHAPTERS)
def test_chapter_notebook_is_clean(built_book: BookBuild, stem: str) -> None:
    path, nb = _site_notebook(built_book, stem)
    number = CHAPTERS.index(stem) + 1
    assert path.name == f"chapter_{number:02d}_{stem}.ipynb"
    nbformat.validate(nbformat.from_dict(nb))
    source = (ROOT / "book" / f"{stem}.md").read_text(encoding="utf-8")
    markdown = "\n".join(c["source"] for c in nb["cells"] if c["cell_type"] == "markdown")
    flat = " ".join(markdown.split())

    raw = RAW_MYST.findall(markdown)
    assert not raw, f"raw MyST left in {path.name}"
    shown = [p for p in directive_phrases(source, "solution") if " ".join(p.split()) in flat]
    assert not shown, f"{path.name} shows solutions: {shown[:3]}"
    exercises = len(re.findall(r"^`{3,}\{exercise\}", source, re.MULTILINE))
    headings = re.findall(rf"\*\*Exercise {number}\.(\d+)\*\*", markdown)
    assert headings == [str(i) for i in range(1, exercises + 1)]
    missing = [p for p in directive_phrases(source, "exercise") if " ".join(p.split()) not in flat]
    assert not missing, f"exercise text missing from {path.name}: {missing[:3]}"

    from IPython.core.inputtransformer2 import TransformerManager

    for cell in (c for c in nb["cells"] if c["cell_type"] == "code"):
        assert cell["outputs"] == [] and "myst_nb" not in cell["source"]
        ast.parse(TransformerManager().transform_cell(cell["source"]))  # IPython's magics


def _outside_solutions(source: str) -> str:
    return re.sub(r"^(`{3,})\{solution\}.*?^\1\s*$", "", source, flags=re.MULTILINE | re.DOTALL)


#: Chapters that glue values into their text (outside the solutions).
GLUING = [
    stem
    for stem in CHAPTERS
    if "{glue:text}"
    in _outside_solutions((ROOT / "book" / f"{stem}.md").read_text(encoding="utf-8"))
]


@pytest.mark.slow
@pytest.mark.parametrize("stem", GLUING)
def test_chapter_notebook_shows_glued_values(built_book: BookBuild, stem: str) -> None:
    from myst_nb.core.variables import format_plain_text

    _, nb = _site_notebook(built_book, stem)
    source = (ROOT / "book" / f"{stem}.md").read_text(encoding="utf-8")
    glue_file = built_book.html_dir.parent / "jupyter_execute" / "book" / f"{stem}.glue.json"
    glued = json.loads(glue_file.read_text(encoding="utf-8"))
    markdown = "\n".join(c["source"] for c in nb["cells"] if c["cell_type"] == "markdown")
    for role in re.findall(r"\{glue:text\}`([^`]+)`", _outside_solutions(source)):
        key, spec = split_glue(role)
        value = format_plain_text(glued[key]["data"]["text/plain"], spec)
        assert value in markdown, f"{key} = {value} is not in the notebook of {stem}"


def _download_link(name: str) -> re.Pattern[str]:
    """Match a link on a chapter page that downloads notebooks/<name>."""
    return re.compile(rf'<a [^>]*\bdownload\b[^>]*href="\.\./notebooks/{re.escape(name)}"')


@pytest.mark.slow
@pytest.mark.parametrize("stem", CHAPTERS)
def test_chapter_page_offers_notebook_and_sheet(built_book: BookBuild, stem: str) -> None:
    path, _ = _site_notebook(built_book, stem)
    page = (built_book.html_dir / "book" / f"{stem}.html").read_text(encoding="utf-8")
    assert _download_link(path.name).search(page), "no link under the title"
    assert f'href="../notebooks/{path.name}"' in page.split('class="run-this-chapter"')[0], (
        "no entry in the download menu"
    )
    sheets = sorted((ROOT / "notebooks").glob(f"*_{stem}.ipynb"))
    for sheet in sheets:
        copy = built_book.html_dir / "notebooks" / sheet.name
        assert copy.read_bytes() == sheet.read_bytes()
        assert _download_link(sheet.name).search(page), "no link to the sheet"
    assert 'href="run.html"' in page, "no link to Run this book"


@pytest.mark.slow
def test_run_page_lists_every_chapter(built_book: BookBuild) -> None:
    page = (built_book.html_dir / "book" / "run.html").read_text(encoding="utf-8")
    for stem in CHAPTERS:
        path, _ = _site_notebook(built_book, stem)
        assert f'href="../notebooks/{path.name}"' in page
    intro = (built_book.html_dir / "book" / "intro.html").read_text(encoding="utf-8")
    assert 'href="run.html"' in intro
