# Sourced by scripts/build-book.sh (the printable lab handout) and scripts/build-pdf.sh (the
# PDF edition): make sure XeLaTeX, latexmk, TikZ and the GNU FreeFont fonts are there.
# When they are missing, install them from Debian with apt-get (as root, about two minutes),
# or stop with the command that installs them.
TEX_PACKAGES="texlive-xetex texlive-latex-extra texlive-pictures texlive-fonts-recommended"
TEX_PACKAGES="$TEX_PACKAGES fonts-freefont-otf latexmk"
have_tex() {
  command -v xelatex >/dev/null 2>&1 && command -v latexmk >/dev/null 2>&1 \
    && fc-list : family 2>/dev/null | grep "FreeSerif" >/dev/null  # no -q: pipefail, SIGPIPE
}
if ! have_tex; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "==> apt-get install $TEX_PACKAGES"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    # shellcheck disable=SC2086
    apt-get install -y -qq --no-install-recommends $TEX_PACKAGES >/dev/null
  else
    echo "error: the book's printable parts need XeLaTeX, latexmk, TikZ and the GNU FreeFont
  fonts. On Debian/Ubuntu:
  sudo apt-get install --no-install-recommends $TEX_PACKAGES" >&2
    exit 2
  fi
fi
have_tex || { echo "error: xelatex, latexmk or FreeSerif still missing after apt-get" >&2; exit 2; }
