#!/usr/bin/env bash
# Build the whole book as one PDF through LaTeX (XeLaTeX): _build/latex/book.pdf
#
# 1. TeX Live from Debian: when xelatex, latexmk or the FreeFont fonts are missing, install
#    them with apt-get (as root), or say which packages to install.
# 2. The web edition first (scripts/build-book.sh): it executes every chapter once, checks
#    it (-W) and leaves the outputs in the execution cache, which the PDF build reuses.
# 3. jupyter-book build --builder pdflatex with _config.yml plus the print settings below
#    (solutions left out: the exercises close each chapter, their solutions are on the web
#    and in the sheets), then latexmk/xelatex.
#
# Extra arguments are passed to the second jupyter-book call.
set -euo pipefail
book_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$book_root"

die() { echo "build-pdf.sh: error: $*" >&2; exit 2; }

# --- TeX Live (Debian packages, installed with apt-get as root when missing) -------------
source scripts/ensure-tex.sh

# --- the web edition: executes and checks every chapter, fills the execution cache -------
bash scripts/build-book.sh
source scripts/ensure-env.sh
cd "$book_root"

# --- the print settings: _config.yml with a few keys changed ------------------------------
pdf_config="_build/pdf-config.yml"
python - "$pdf_config" <<'PY'
import os
import sys
import yaml

config = yaml.safe_load(open("_config.yml", encoding="utf-8"))
latex = config.setdefault("latex", {})
latex["latex_documents"] = {"targetname": "book.tex"}
# local extensions are found relative to the config file, which moves into _build/
extensions = config["sphinx"].get("local_extensions") or {}
config["sphinx"]["local_extensions"] = {name: os.path.abspath(path)
                                        for name, path in extensions.items()}
sphinx = config.setdefault("sphinx", {}).setdefault("config", {})
sphinx["hide_solutions"] = True  # sphinx-exercise: the exercises stay, the solutions go
sphinx["latex_show_urls"] = "no"
sphinx["latex_use_xindy"] = False  # makeindex comes with TeX Live; xindy is one more package
# Jupyter Book's document class loads bbm (texlive-fonts-extra): a stand-in (see the file)
sphinx["latex_additional_files"] = ["scripts/latex/bbm.sty"]
sphinx["latex_elements"] = {
    "papersize": "a4paper",
    "pointsize": "11pt",
    # wide tables and long lines of code outputs break instead of running off the page
    "sphinxsetup": "verbatimwrapslines=true, verbatimforcewraps=true",
    # the part "Back matter" and every chapter after it are not numbered, as on the web
    # the outline (bookmarks): every chapter and section (Sphinx asks hyperref for depth
    # 5), numbered as in the text, open on the chapters
    "passoptionstopackages": r"\PassOptionsToPackage{bookmarksnumbered,bookmarksopen,"
                             r"bookmarksopenlevel=0}{hyperref}",
    # accsupp: each figure's description as its alternate text (book/_ext/dstoolkit_pdf.py)
    "preamble": r"""\usepackage{amssymb}
\usepackage{accsupp}
\makeatletter
\let\dstk@part\part
\renewcommand{\part}[1]{\def\dstk@title{#1}\def\dstk@back{Back matter}%
  \ifx\dstk@title\dstk@back\setcounter{secnumdepth}{-1}\fi\dstk@part{#1}}
\makeatother""",
    "extraclassoptions": "openany",  # no blank pages before chapters
}
yaml.safe_dump(config, open(sys.argv[1], "w", encoding="utf-8"), allow_unicode=True,
               sort_keys=False)
PY

echo "==> jupyter-book build . --builder pdflatex --config $pdf_config $*"
jupyter-book build . --builder pdflatex --config "$pdf_config" -n --keep-going "$@" \
  2> >(grep -v --line-buffered "Kernel is running over TCP without encryption" >&2)
pdf="$(ls -t _build/latex/*.pdf 2>/dev/null | head -n 1 || true)"
[ -n "$pdf" ] || die "no PDF in _build/latex (see _build/latex/*.log)"
echo "==> book built: $book_root/$pdf"
