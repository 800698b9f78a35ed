"""The printable lab handout: parts list, wiring, data sheet and report rubric, as a PDF.

    .venv/bin/python scripts/lab_handout.py [FOLDER]   # writes FOLDER/lab-handout.pdf

Every number on the handout comes from ``dstoolkit``: the tube's diameter from
:class:`dstoolkit.gauge.TubeSetup`, the sweep from :data:`dstoolkit.gauge.PAPER_SWEEP`, the
calibration chirp from :func:`dstoolkit.audio.calibration_chirp`, the speed of sound, the
spacing of the resonances and the plane-wave cutoff from the gauge's acoustics, and the
shortest usable level from the detector's :func:`dstoolkit.gauge.detect_resonances` (the
level from which the band spans as many spacings as the detector needs resonances). The
wiring diagram is drawn in TikZ, and XeLaTeX (through latexmk) typesets it; nothing is
downloaded.

The book builds the handout as a Sphinx extension (listed in ``_config.yml``): when the
builder starts, the PDF is written to ``_build/handout/lab-handout.pdf``, which the lab and
the teaching pages offer with ``{download}``. It is rebuilt only when its LaTeX source
changed.
"""

from __future__ import annotations

import inspect
import math
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
NAME = "lab-handout"
#: The air temperature the handout's reference table assumes, °C (a room).
ROOM_C = 20.0
#: Levels of the reference table, m (the 75 mm tube; the shortest usable one is added, and
#: 0.5 m shows a level too short for the band).
TABLE_LEVELS = (0.5, 1.0, 2.5, 5.0, 9.6)
#: Blank rows of the data sheet.
DATA_ROWS = 10


def handout_numbers() -> dict[str, Any]:
    """Return the numbers the handout prints, each computed by ``dstoolkit``."""
    from dstoolkit.audio import CALIBRATION_GAP_S, calibration_chirp
    from dstoolkit.gauge import (
        PAPER_SWEEP,
        TubeSetup,
        detect_resonances,
        fundamental_frequency,
        plane_wave_cutoff,
        resonance_orders,
        speed_of_sound,
    )
    from dstoolkit.teaching import LabSettings

    chirp = inspect.signature(calibration_chirp).parameters
    need = inspect.signature(detect_resonances).parameters["min_resonances"].default
    tube = TubeSetup(level_m=1.0, temperature_c=ROOM_C)
    c = float(speed_of_sound(ROOM_C))
    band = tuple(float(f) for f in PAPER_SWEEP.band)
    # the shortest level (rounded up to the millimetre) whose spacing f_F = c/(2L) fits
    # `need` times in the band: from there on the sweep holds enough resonances wherever
    # they fall (a shorter level may hold enough by luck, and the next one too few)
    shortest = math.ceil(1000 * need * c / (2 * (band[1] - band[0]))) / 1000
    rows = [
        (level, float(fundamental_frequency(level, c)), int(resonance_orders(level, c, band).size))
        for level in sorted({shortest, *TABLE_LEVELS})
    ]
    return {
        "diameter_mm": tube.diameter_m * 1000,
        "f_lo": band[0],
        "f_hi": band[1],
        "rate": float(PAPER_SWEEP.rate),
        "sweep_s": float(PAPER_SWEEP.duration),
        "chirp_lo": float(chirp["f_start_hz"].default),
        "chirp_hi": float(chirp["f_stop_hz"].default),
        "chirp_s": float(chirp["duration_s"].default),
        "gap_s": float(CALIBRATION_GAP_S),
        "room_c": ROOM_C,
        "c": c,
        "cutoff": plane_wave_cutoff(tube.diameter_m, c),
        "need": int(need),
        "shortest": shortest,
        "rows": rows,
        "volume": float(LabSettings().volume),
    }


PREAMBLE = r"""\documentclass[11pt,a4paper]{article}
\usepackage[margin=18mm]{geometry}
\usepackage{fontspec}
\usepackage{array,booktabs,tabularx,enumitem}
\usepackage{tikz}
\usetikzlibrary{arrows.meta,decorations.pathmorphing,patterns,positioning}
\setlength{\parindent}{0pt}
\setlength{\parskip}{4pt}
\pagestyle{plain}
\newcommand{\blank}[1]{\rule{#1}{0.4pt}}
\begin{document}
"""


def _wiring() -> str:
    """Draw the wiring diagram in TikZ.

    It shows the tube, the speaker on top, the microphone in the wall below it, the
    thermometer probe, the liquid surface, and the cables to the laptop.
    """
    return r"""\begin{center}
\begin{tikzpicture}[scale=1.15, font=\small, >={Stealth}, line width=0.6pt,
                    box/.style={draw, rounded corners, align=center, inner sep=4pt}]
  % the tube: two walls, the liquid at the bottom
  \draw (0,0) -- (0,6.5); \draw (1.2,0) -- (1.2,6.5);
  \fill[pattern=north east lines] (0,0) rectangle (1.2,0.8);
  \draw[decorate, decoration={snake, amplitude=0.6pt, segment length=6pt}] (0,0.8) -- (1.2,0.8);
  % the speaker on its platform, facing down
  \draw[fill=black!15] (-0.2,6.5) rectangle (1.4,6.75);
  \draw[fill=black!35] (0.3,6.3) -- (0.9,6.3) -- (1.05,6.5) -- (0.15,6.5) -- cycle;
  % the microphone through the wall, just below the speaker
  \draw[fill=black!60] (-0.3,5.95) rectangle (0.05,6.15);
  % the thermometer probe in the air column, its lead out through the wall
  \draw (1.6,4.2) -- (0.8,4.2) -- (0.8,3.7); \fill (0.8,3.6) circle (0.09);
  % the level L
  \draw[<->] (1.75,6.45) -- (1.75,0.85);
  \node[anchor=west] at (1.85,2.4) {level $L$};
  % labels on the right, with leaders
  \draw (1.4,6.62) -- (2.6,6.62) node[anchor=west] {speaker on a foam ring, facing down};
  \draw (1.6,4.2) -- (2.6,4.2) node[anchor=west] {thermometer probe in the air};
  \draw (1.2,0.4) -- (2.6,0.4) node[anchor=west] {liquid (water), surface at depth $L$};
  % the laptop and the sound path on the left
  \node[box] (amp) at (-4.6,7.4) {amplifier (if the\\speaker is passive)};
  \node[box] (card) at (-1.9,4.6) {USB sound\\card};
  \node[box] (laptop) at (-4.6,2.6) {laptop\\(Python, dstoolkit)};
  \draw[->] (-0.3,6.05) -- node[above] {microphone} (-1.9,6.05) -- (card.north);
  \draw[->] (card.south) |- node[pos=0.75, above] {USB} (laptop.east);
  \draw[->] (laptop.north) -- node[left, align=right] {headphone\\out} (amp.south);
  \draw[->] (amp.east) -- (0.6,7.4) -- (0.6,6.75);
\end{tikzpicture}
\end{center}
Cables are tied to a post and led away from the tube's mouth; mains plugs and the laptop
stay out of splash range. The level $L$ is measured with the tape from the speaker's
platform to the surface.
"""


def handout_tex(n: dict[str, Any]) -> str:
    """Return the handout's LaTeX source, with the numbers ``n`` of :func:`handout_numbers`."""
    reference = "\n".join(
        rf"{level:.3f} & {f_f:.1f} & {count} \\" for level, f_f, count in n["rows"]
    )
    blank_rows = "\n".join(r" & & & & & & & \\[7mm] \hline" for _ in range(DATA_ROWS))
    return (
        PREAMBLE
        + rf"""
{{\LARGE\bfseries The lab: an acoustic level gauge}}\par
\vspace{{2pt}}
Handout for the lab of the book \emph{{Evidence under bounded noise}}. A sweep of sound
travels down a tube and back from the liquid's surface; the resonances of the air column
sit $f_F = c/(2L)$ apart, and their spacing gives the level $L$. Work in groups of four
(operator, safety and sound, level keeper, analyst; rotate the roles after every level);
hand in the data sheet with your report.

\section*{{1. Parts list}}
\begin{{tabularx}}{{\linewidth}}{{@{{}}>{{\bfseries}}l X@{{}}}}
\toprule
part & what to look for \\
\midrule
tube & PVC drain pipe, inner diameter {n["diameter_mm"]:.0f} mm; the level must be at
least {n["shortest"]:.3f} m, so that the sweep spans {n["need"]} spacings and holds the
{n["need"]} resonances the detector needs wherever they fall (table below) \\
speaker & small full-range driver or powered USB speaker covering
{n["f_lo"]:.0f}--{n["f_hi"]:.0f} Hz (the sweep) and {n["chirp_lo"]:.0f}--{n["chirp_hi"]:.0f}
Hz (the calibration chirp) \\
microphone & electret capsule on a USB sound card, or a USB microphone \\
laptop & Python with \texttt{{dstoolkit[audio]}}; every microphone ``enhancement'' off \\
thermometer & digital, 0.1\,°C resolution, probe on a lead \\
surface & a bucket of water the tube stands in, or a sliding plug in a horizontal tube \\
also & tape measure, cable ties, tape, foam or putty, ear muffs, towels \\
\bottomrule
\end{{tabularx}}

The sweep rises from {n["f_lo"]:.0f} Hz to {n["f_hi"]:.0f} Hz in {n["sweep_s"]:.0f} s
($\kappa$ = {n["rate"]:.0f} Hz/s), between two chirps of {n["chirp_s"]:.2f} s separated
from it by {n["gap_s"]:.2f} s gaps. At {n["room_c"]:.0f}\,°C the speed of sound is
$c$ = {n["c"]:.1f} m/s, and the {n["diameter_mm"]:.0f} mm tube carries plane waves only
below {n["cutoff"]:.0f} Hz. What to expect:

\begin{{center}}
\begin{{tabular}}{{rrr}}
\toprule
level $L$ (m) & spacing $f_F$ (Hz) & resonances in the sweep \\
\midrule
{reference}
\bottomrule
\end{{tabular}}
\end{{center}}

\newpage
\section*{{2. Wiring}}
{_wiring()}
\begin{{enumerate}}[nosep]
\item Cut the tube's end square; stand it in the bucket and strap it to a wall at two
heights, or lay it down with a sliding plug.
\item Seat the speaker on top, facing down, on foam or putty: no leak, no rattle.
\item Put the microphone through a small hole just below the speaker, flush with the
inside wall; hang the thermometer probe in the air column.
\item Speaker cable from the headphone output (through the amplifier), microphone cable to
the sound card; tie both away from the tube's mouth.
\item Safety: start at volume {n["volume"]:g} and raise step by step; ear muffs for
everyone near the tube's mouth; say ``sweep!'' before recording; water only,
electrics out of splash range.
\end{{enumerate}}

\newpage
\section*{{3. Data sheet}}
Group: \blank{{70mm}} \quad Date: \blank{{40mm}}\par
Tube inner diameter (mm): \blank{{25mm}} \quad Tube length (m): \blank{{25mm}}

\smallskip
\renewcommand{{\arraystretch}}{{1.3}}
\begin{{tabularx}}{{\linewidth}}{{|c|*{{7}}{{>{{\raggedright\arraybackslash}}X|}}}}
\hline
run & tape level (m) & air temp. (°C) & latency, first chirp (ms) & latency, last chirp
(ms) & resonances found & measured level (m) & uncertainty (mm) \\ \hline
{blank_rows}
\end{{tabularx}}

\smallskip
The two latencies of one run must agree (the analysis says so when they do not); if they
do not, the stream lost samples: repeat the run. Notes (what you changed between runs,
anything odd):

\vspace{{28mm}}

\newpage
\section*{{4. Report rubric}}
\begin{{tabularx}}{{\linewidth}}{{@{{}}X r@{{}}}}
\toprule
criterion & points \\
\midrule
Set-up: a photo or sketch of your gauge, the parts used, what you did about safety & 10 \\
Data sheet complete, with units, every run and every repeated run & 15 \\
Latency: first and last chirp compared for every run; runs that disagree repeated & 10 \\
Levels: measured against the tape, with the uncertainty split into fit, offsets and
temperature & 25 \\
Noise of your own gauge: its bounds and mode, compared with the paper's & 15 \\
Filters: the paper's filter and one rival on your recordings, with their level errors &
15 \\
Discussion: what limited your accuracy, and what you would change next time & 10 \\
\midrule
total & 100 \\
\bottomrule
\end{{tabularx}}

A report earns a criterion's points when another group could repeat the step from it
alone; half when a number or a unit is missing; none when the step is absent.
\end{{document}}
"""
    )


def typeset(folder: Path, name: str, source: str, what: str) -> Path:
    """Write ``folder/<name>.tex`` and typeset it with XeLaTeX to ``folder/<name>.pdf``.

    The PDF is kept when it is newer than an unchanged source. ``what`` names the document
    in the messages.

    Raises
    ------
    RuntimeError
        When latexmk or xelatex is missing, or LaTeX fails (the message points at the log).
    """
    folder.mkdir(parents=True, exist_ok=True)
    tex, pdf = folder / f"{name}.tex", folder / f"{name}.pdf"
    if (
        pdf.exists()
        and tex.exists()
        and tex.read_text(encoding="utf-8") == source
        and pdf.stat().st_mtime >= tex.stat().st_mtime
    ):
        return pdf
    missing = [tool for tool in ("latexmk", "xelatex") if shutil.which(tool) is None]
    if missing:
        raise RuntimeError(
            f"{what} needs {' and '.join(missing)} (TeX Live). On Debian/Ubuntu: "
            "sudo apt-get install --no-install-recommends texlive-xetex "
            "texlive-latex-extra texlive-pictures fonts-freefont-otf latexmk"
        )
    tex.write_text(source, encoding="utf-8")
    done = subprocess.run(
        [
            "latexmk",
            "-xelatex",
            "-interaction=nonstopmode",
            "-halt-on-error",
            "-quiet",
            f"{name}.tex",
        ],
        cwd=folder,
        capture_output=True,
        text=True,
    )
    if done.returncode != 0 or not pdf.exists():
        raise RuntimeError(
            f"LaTeX failed on {what}; see {folder / (name + '.log')}:\n{done.stdout[-2000:]}"
        )
    return pdf


def build(folder: Path) -> Path:
    """Write ``folder/lab-handout.tex`` and typeset it to ``folder/lab-handout.pdf``.

    Raises
    ------
    RuntimeError
        When latexmk or xelatex is missing, or LaTeX fails (the message points at the log).
    """
    return typeset(folder, NAME, handout_tex(handout_numbers()), "the lab handout")


def _on_builder_inited(app: Any) -> None:
    from sphinx.errors import ExtensionError

    try:
        build(Path(app.srcdir) / "_build" / "handout")
    except RuntimeError as err:
        raise ExtensionError(str(err)) from err


def setup(app: Any) -> dict[str, Any]:
    """Sphinx: build the handout when the book's builder starts."""
    app.connect("builder-inited", _on_builder_inited)
    return {"parallel_read_safe": True, "parallel_write_safe": True}


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    print(build(Path(args[0]) if args else ROOT / "_build" / "handout"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
