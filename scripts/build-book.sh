#!/usr/bin/env bash
# Build the book into _build/html, a static site that works with no network.
#
# 1. Create/refresh the Python environment (.venv) through scripts/ensure-env.sh.
# 2. Install the browser assets from the npm registry with `npm ci` (package-lock.json):
#    MathJax 3 and reveal.js.
# 3. Copy the files the pages need into _build/_vendor/; _config.yml lists that folder in
#    html_static_path, so Sphinx serves it from _build/html/_static/ and points
#    `mathjax_path` at it.
# 4. jupyter-book build . -W -n --keep-going (every warning is an error; notebooks are
#    executed once and cached in _build/.jupyter_cache). The cache is dropped when the
#    source of dstoolkit changed, and every page is re-read after a failed build.
# 5. scripts/slides.py writes a reveal.js lecture deck per chapter into _build/html/slides/
#    from the chapter's source and its built page (reveal.js is vendored like MathJax).
# 6. Post-build: scripts/typeset-maths.js typesets the maths into the pages (mathjax-full);
#    scripts/site_postbuild.py writes the explorers as plain HTML (no widget manager),
#    links every figure, joins the stylesheets into one and purges the rules no page uses
#    (scripts/purge-styles.js, PurgeCSS), its icon font cut to the icons it draws.
#    Both leave the decks in slides/ as they are (reveal.js typesets its own maths).
#
# Extra arguments are passed to jupyter-book, e.g. `bash scripts/build-book.sh --all`.
set -euo pipefail
book_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$book_root"

source scripts/ensure-env.sh
cd "$book_root"

die() { echo "build-book.sh: error: $*" >&2; exit 2; }

# One build at a time in this checkout: two builds writing into _build/ corrupt each other.
mkdir -p _build
if command -v flock >/dev/null 2>&1; then
  exec 9>_build/.build-book.lock
  if ! flock -n 9; then
    echo "==> another build of this book is running; waiting for it to finish"
    flock 9
  fi
fi

# --- TeX Live for the printable lab handout (installed with apt-get as root when missing) --
source scripts/ensure-tex.sh

# --- Node.js and npm ---------------------------------------------------------------------
if ! command -v npm >/dev/null 2>&1 || ! command -v node >/dev/null 2>&1; then
  die "Node.js and npm are needed to install the book's offline assets (MathJax and
  reveal.js) from the npm registry, but 'node' or 'npm' is not on PATH.
  Install them (Debian/Ubuntu: sudo apt-get install nodejs npm; otherwise
  https://nodejs.org, version 18 or newer) and run this script again."
fi

# `npm ci` wipes and reinstalls node_modules; skip it when node_modules was installed from
# this very package-lock.json (the stamp holds its hash).
stamp="node_modules/.dstoolkit-book-assets"
want="$(sha256sum package-lock.json | cut -d' ' -f1)"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ]; then
  echo "==> npm ci (MathJax 3, reveal.js)"
  npm ci --ignore-scripts --no-audit --no-fund --loglevel=error \
    || die "npm ci failed. Check that the npm registry is reachable (npm config get registry)
  and that package-lock.json matches package.json (npm install --package-lock-only)."
  echo "$want" > "$stamp"
fi

mathjax_src="node_modules/mathjax/es5"
reveal_src="node_modules/reveal.js/dist"
[ -f "$mathjax_src/tex-chtml.js" ] || die "$mathjax_src/tex-chtml.js is missing after npm ci."
[ -f "$reveal_src/reveal.js" ] || die "$reveal_src/reveal.js is missing after npm ci."

# A root _static/ folder makes Jupyter Book add every .js file of every html_static_path
# entry to every page, i.e. all of MathJax's components. Keep page CSS in book/_static/.
[ ! -e _static ] || die "remove the folder _static/ at the book root (Jupyter Book would
  inject every MathJax file into every page); put page CSS into book/_static/ instead."

# --- Offline assets: _build/_vendor -> _build/html/_static -------------------------------
echo "==> copying offline assets into _build/_vendor"
vendor="_build/_vendor"
rm -rf "$vendor"
mkdir -p "$vendor/mathjax" "$vendor/reveal/theme/fonts" "$vendor/reveal/plugin"
# MathJax: the TeX+CHTML bundle, plus what it loads on demand relative to its own URL
# (fonts, autoloaded TeX extensions, menu, accessibility and speech components).
cp "$mathjax_src/tex-chtml.js" "$vendor/mathjax/"
for dir in input output ui a11y sre adaptors; do
  cp -R "$mathjax_src/$dir" "$vendor/mathjax/"
done
cp node_modules/mathjax/LICENSE "$vendor/mathjax/LICENSE"
# reveal.js for the lecture decks (scripts/slides.py): the core, the white theme and the
# one font it imports, the speaker-notes and maths plugins (the decks load the vendored
# MathJax above through the maths plugin).
cp "$reveal_src/reset.css" "$reveal_src/reveal.css" "$reveal_src/reveal.js" "$vendor/reveal/"
cp "$reveal_src/theme/white.css" "$vendor/reveal/theme/"
cp -R "$reveal_src/theme/fonts/source-sans-pro" "$vendor/reveal/theme/fonts/"
cp node_modules/reveal.js/plugin/notes/notes.js node_modules/reveal.js/plugin/math/math.js \
  "$vendor/reveal/plugin/"
cp node_modules/reveal.js/LICENSE "$vendor/reveal/LICENSE"

# --- Execution cache ---------------------------------------------------------------------
# jupyter-cache re-executes a chapter only when one of its code cells changes; it cannot
# see a change in dstoolkit or answer_key/, whose results the chapters print. Drop the cache when the
# package's source changed, so that no number in the book is stale. Set
# DSTOOLKIT_BOOK_KEEP_CACHE=1 to keep it anyway (quick prose edits while the package moves).
cache_dir="_build/.jupyter_cache"
pkg_stamp="_build/.dstoolkit-source-hash"
pkg_hash="$(find dstoolkit answer_key pyproject.toml -type f -not -path '*/__pycache__/*' -print0 \
  | sort -z | xargs -0 sha256sum | sha256sum | cut -d' ' -f1)"
record_hash=1
fresh=()
if [ -d "$cache_dir" ] && [ -f "$pkg_stamp" ] && [ "$(cat "$pkg_stamp")" != "$pkg_hash" ]; then
  if [ "${DSTOOLKIT_BOOK_KEEP_CACHE:-0}" = "1" ]; then
    echo "==> dstoolkit changed; keeping the execution cache (DSTOOLKIT_BOOK_KEEP_CACHE=1)"
    record_hash=0  # the cache still belongs to the old source: clear it next time
  else
    echo "==> dstoolkit changed since the chapters were executed: clearing $cache_dir"
    rm -rf "$cache_dir"
    fresh=(--all)  # Sphinx must re-read (and so re-execute) the unchanged pages too
  fi
fi

# --- Build -------------------------------------------------------------------------------
# Sphinx re-reads only changed pages, so after a build that failed on warnings an unchanged
# rerun would pass without seeing them again. After a failure, re-read every page (--all,
# a fresh Sphinx environment; executed notebooks still come from the cache).
failed_stamp="_build/.book-build-failed"
if [ -f "$failed_stamp" ]; then
  echo "==> the last build failed: re-reading every page (--all)"
  fresh=(--all)
fi
# Explorers executed for the static site precompute the states of their live controls
# (dstoolkit.teaching: Explorer, STATIC_SITE_ENV); in a notebook they recompute instead.
export DSTOOLKIT_STATIC_SITE=1
echo "==> jupyter-book build . -W -n --keep-going ${fresh[*]} $*"
touch "$failed_stamp"
# ipykernel 7 logs "[IPKernelApp] WARNING | Kernel is running over TCP without encryption"
# once per executed chapter. The kernel is started by nbclient on 127.0.0.1 with signed
# messages, as Jupyter always did; the line is noise here, so exactly that line is dropped
# from stderr. Every other message, Sphinx's warnings included, passes through.
jupyter-book build . -W -n --keep-going ${fresh[@]+"${fresh[@]}"} "$@" \
  2> >(grep -v --line-buffered "Kernel is running over TCP without encryption" >&2)
# --- Lecture decks (they read the built pages for numbers, figures and TeX) --------------
echo "==> lecture slides: python scripts/slides.py"
python scripts/slides.py
# After the build: the maths typeset into the pages (no MathJax in the browser), then the
# explorers written as plain HTML with native controls (their widget state leaves the page)
# and every figure linked to its full-size file. Each page is rewritten once.
node scripts/typeset-maths.js _build/html
python scripts/site_postbuild.py _build/html
rm -f "$failed_stamp"
[ "$record_hash" = 0 ] || echo "$pkg_hash" > "$pkg_stamp"
echo "==> book built: $book_root/_build/html/index.html"
