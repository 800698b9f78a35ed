"""Sphinx extension: the PDF edition carries each figure's written description.

On the web every figure has a written ``alt`` (a chapter's ``mystnb.image.alt``). LaTeX
drops it; here, for the LaTeX builder, each image that has one is wrapped in
``\\BeginAccSupp{method=hex,unicode,Alt=...}`` ... ``\\EndAccSupp{}`` (package ``accsupp``,
loaded by ``scripts/build-pdf.sh``). XeLaTeX then writes a marked-content span
``/Span<</Alt<FEFF...>>>BDC ... EMC`` around the picture, which a PDF reader's screen
reader reads instead of the image. The description is passed as UTF-16BE hex digits, so no
character of it needs LaTeX escaping.

The outline (PDF bookmarks) of every chapter and section comes from ``hyperref``, which
Sphinx loads; the build script opens it on the chapters.
"""

from __future__ import annotations

from typing import Any

from docutils import nodes
from sphinx.application import Sphinx

#: Commands of Sphinx's LaTeX writer that draw an image (``visit_image``).
_IMAGE_COMMANDS = (r"\sphinxincludegraphics", r"\lowercase{\sphinxincludegraphics",
                   r"{\catcode`\#=12\sphinxincludegraphics")


def alt_hex(text: str) -> str:
    """``text`` as the hex digits of its UTF-16BE encoding (accsupp adds the FEFF mark)."""
    return " ".join(text.split()).encode("utf-16-be").hex().upper()


def with_alt(command: str, alt: str) -> str:
    """The LaTeX ``command`` that draws an image, wrapped in an accsupp span with ``alt``."""
    return (rf"\BeginAccSupp{{method=hex,unicode,Alt={alt_hex(alt)}}}"
            rf"{command}\EndAccSupp{{}}")


class AltTextMixin:
    """A LaTeX translator whose images keep their ``alt`` as the PDF's alternate text."""

    body: list[str]

    def visit_image(self, node: nodes.Element) -> None:
        start = len(self.body)
        super().visit_image(node)  # type: ignore[misc]
        alt = (node.get("alt") or "").strip()
        if not alt:
            return
        for index in range(start, len(self.body)):
            if self.body[index].startswith(_IMAGE_COMMANDS):
                self.body[index] = with_alt(self.body[index], alt)
                return


def builder_inited(app: Sphinx) -> None:
    """For the LaTeX builder: its translator with :class:`AltTextMixin` mixed in."""
    if app.builder.format != "latex":
        return
    base: Any = app.builder.get_translator_class()
    if issubclass(base, AltTextMixin):
        return
    translator = type(f"AltText{base.__name__}", (AltTextMixin, base), {})
    app.set_translator(app.builder.name, translator, override=True)


def setup(app: Sphinx) -> dict[str, object]:
    """Register the LaTeX translator's alternate texts."""
    app.connect("builder-inited", builder_inited)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
