#!/usr/bin/env node
/*
 * Typeset the book's maths at build time: every page of a built site gets its formulas as
 * MathJax SVG (with the MathML that screen readers read), its stylesheet in the page, and
 * no MathJax in the browser.
 *
 *   node scripts/typeset-maths.js _build/html
 *
 * Sphinx writes inline maths as <span class="math notranslate nohighlight">\(...\)</span> and
 * display maths as <div class="math notranslate nohighlight">[eqno]\[...\]</div>; MathJax
 * (mathjax-full, the same version as the mathjax package the site used to load) turns each
 * into an <mjx-container> with the book's settings: the assistive MathML beside it,
 * formulas out of the Tab order. The output is SVG, not CHTML: each glyph is drawn from its
 * outline, defined once a page (MathJax's global font cache, at the start of the body), so
 * the page loads no maths fonts and the browser lays out far fewer boxes (CHTML writes an
 * element and a generated box per character, and lays the page out again when each maths
 * font arrives). The glyphs are those of MathJax's TeX fonts in both outputs. MathJax's
 * SVG stylesheet goes into the page's <head>, and the MathJax configuration and script
 * leave the page. A page is rewritten once (it is marked); the script fails when TeX is
 * left that it could not typeset, or when MathJax reports an error in a formula.
 */
"use strict";

const fs = require("fs");
const path = require("path");
const { mathjax } = require("mathjax-full/js/mathjax.js");
const { TeX } = require("mathjax-full/js/input/tex.js");
const { SVG } = require("mathjax-full/js/output/svg.js");
const { liteAdaptor } = require("mathjax-full/js/adaptors/liteAdaptor.js");
const { RegisterHTMLHandler } = require("mathjax-full/js/handlers/html.js");
const { AllPackages } = require("mathjax-full/js/input/tex/AllPackages.js");
const { SerializedMmlVisitor } = require("mathjax-full/js/core/MmlTree/SerializedMmlVisitor.js");
const { STATE } = require("mathjax-full/js/core/MathItem.js");

const MARK = '<meta name="dstoolkit-maths" content="typeset at build time">';
const INLINE = /<span class="math notranslate nohighlight">\\\(([\s\S]*?)\\\)<\/span>/g;
const DISPLAY = /(<div class="math notranslate nohighlight"[^>]*>\s*(?:<span class="eqno">[\s\S]*?<\/span>)?)\\\[([\s\S]*?)\\\](\s*<\/div>)/g;
const MATHJAX_SCRIPTS = [
  /<script>window\.MathJax = [^<]*<\/script>\s*/g,
  /<script defer="defer" src="[^"]*mathjax\/tex-chtml\.js[^"]*"><\/script>\s*/g,
];
// The assistive MathML is read by screen readers and hidden from sight: MathJax's own rules,
// but one pixel wide (as "visually hidden" text is), so that it never widens a paragraph.
const ASSISTIVE_CSS = `
mjx-container[jax="SVG"] { position: relative; }
mjx-assistive-mml { position: absolute !important; top: 0px; left: 0px;
  clip: rect(1px, 1px, 1px, 1px); clip-path: inset(50%); padding: 1px 0px 0px 0px !important;
  border: 0px !important; display: block !important; width: 1px !important;
  height: 1px !important; overflow: hidden !important; white-space: nowrap;
  -webkit-touch-callout: none; user-select: none; }
mjx-assistive-mml math, mjx-assistive-mml math * { display: inline; }
`;
// That MathML is never seen, only read, so it is laid out as plain inline text, not as
// MathML (where every token is measured, every script placed and every operator looked up
// to be stretched): a fraction of the layout on each load, and the same accessibility tree,
// whose roles come from the elements (math, mfrac, msub, ...) and whose names from their
// text. It is written without the indentation MathJax's serializer adds: laid out inline,
// each run of indentation would be a word of blank text in that tree.
function compactMathML(mml) {
  return mml.replace(/>\s+</g, "><");
}

const adaptor = liteAdaptor();
RegisterHTMLHandler(adaptor);
const visitor = new SerializedMmlVisitor();

function unescapeHtml(text) {
  return text
    .replace(/&lt;/g, "<")
    .replace(/&gt;/g, ">")
    .replace(/&quot;/g, '"')
    .replace(/&#39;/g, "'")
    .replace(/&#x27;/g, "'")
    .replace(/&amp;/g, "&");
}

// The text of the first error MathJax's TeX input put into a formula (an merror node), if any.
function findError(node) {
  if (node.isKind && node.isKind("merror")) {
    return node.attributes.get("data-mjx-error") || "merror";
  }
  for (const child of node.childNodes || []) {
    const found = findError(child);
    if (found) return found;
  }
  return null;
}

// Groups whose element MathJax's SVG stylesheet selects (an error's box, a table's lines and
// frame, a toggle): they and their children stay as written.
const STYLED = new Set(["merror", "mtable", "mtr", "mtd", "mlabeledtr", "maction"]);
// What a plain group of MathJax's SVG may carry besides its transform: nothing drawn.
const PLAIN = new Set(["data-mml-node", "data-mjx-texclass", "transform"]);

// Elements a transform attribute moves (an inner <svg> ignores one in some browsers).
const MOVABLE = new Set(["g", "use", "path", "rect", "line", "polygon", "ellipse", "text"]);

function isPlainGroup(node) {
  if (node.kind !== "g" || STYLED.has(node.attributes["data-mml-node"])) return false;
  if (!Object.keys(node.attributes).every((name) => PLAIN.has(name))) return false;
  if (node.styles && node.styles.cssText) return false;
  return !node.attributes.transform || node.children.every((child) => MOVABLE.has(child.kind));
}

// Fewer elements, the same picture: a plain group (one per MathML node, most holding one
// glyph) is dissolved into its children, its transform put in front of each child's own
// (an SVG transform list applies left to right, as nested groups do). A chapter's formulas
// hold thousands of such groups, and every element is styled and laid out on each load.
function dissolveGroups(node) {
  if (!node.children) return;
  for (const child of node.children) dissolveGroups(child);
  if (node.kind !== "g" || STYLED.has(node.attributes["data-mml-node"])) return;
  const children = [];
  for (const child of node.children) {
    if (!isPlainGroup(child)) {
      children.push(child);
      continue;
    }
    const shift = child.attributes.transform;
    for (const grandchild of child.children) {
      if (shift) {
        const own = grandchild.attributes.transform;
        grandchild.attributes.transform = own ? `${shift} ${own}` : shift;
      }
      grandchild.parent = node;
      children.push(grandchild);
    }
  }
  node.children = children;
}

function typesetPage(file) {
  let text = fs.readFileSync(file, "utf8");
  if (text.includes(MARK)) return 0;
  const tex = new TeX({ packages: AllPackages, tags: "none" });
  const svg = new SVG({ fontCache: "global" });
  const doc = mathjax.document("", { InputJax: tex, OutputJax: svg });
  let count = 0;

  function render(source, display) {
    const math = unescapeHtml(source);
    const options = { display, em: 16, ex: 8, containerWidth: 80 * 16 };
    const tree = doc.convert(math, { ...options, end: STATE.CONVERT });
    const error = findError(tree);
    if (error) throw new Error(`${file}: TeX error "${error}" in ${math.slice(0, 120)}`);
    const mml = compactMathML(visitor.visitTree(tree));
    const node = doc.convert(math, options);
    adaptor.setAttribute(node, "role", "presentation");
    const inner = adaptor.firstChild(node);
    adaptor.setAttribute(inner, "aria-hidden", "true");
    adaptor.removeAttribute(inner, "role"); // a picture of the formula, hidden: the MathML is read
    count += 1;
    dissolveGroups(inner);
    const html = adaptor.outerHTML(node);
    const assistive =
      `<mjx-assistive-mml unselectable="on" display="${display ? "block" : "inline"}">` +
      `${mml}</mjx-assistive-mml>`;
    return html.replace(/<\/mjx-container>$/, assistive + "</mjx-container>");
  }

  text = text.replace(INLINE, (_, source) => render(source, false));
  text = text.replace(DISPLAY, (_, head, source, tail) => head + render(source, true) + tail);
  for (const script of MATHJAX_SCRIPTS) text = text.replace(script, "");
  const left = /class="math notranslate nohighlight"[^>]*>[^<]*\\[([]/.exec(text);
  if (left) {
    throw new Error(`${file}: maths left untypeset near ${text.slice(left.index, left.index + 120)}`);
  }
  let head = MARK;
  if (count) {
    const css = adaptor.textContent(svg.styleSheet(doc)) + ASSISTIVE_CSS;
    head += `\n<style id="dstoolkit-maths-css">${css}</style>`;
    // the glyph outlines every formula of the page draws with <use>, once
    const cache = adaptor.outerHTML(svg.pageElements(doc));
    text = text.replace(/<body[^>]*>/, (body) => body + cache);
  }
  text = text.replace("</head>", head + "\n</head>");
  fs.writeFileSync(file + ".tmp", text);
  fs.renameSync(file + ".tmp", file); // atomic: a reader sees the old page or the new one
  return count;
}

function pages(dir) {
  const found = [];
  for (const entry of fs.readdirSync(dir, { withFileTypes: true })) {
    const full = path.join(dir, entry.name);
    if (entry.isDirectory()) {
      // _static and the like hold no pages; the lecture decks typeset their own maths
      if (!entry.name.startsWith("_") && entry.name !== "slides") found.push(...pages(full));
    } else if (entry.name.endsWith(".html")) {
      found.push(full);
    }
  }
  return found;
}

function main() {
  const root = process.argv[2];
  if (!root || !fs.existsSync(path.join(root, "index.html"))) {
    console.error("usage: node scripts/typeset-maths.js BUILT_SITE (the folder with index.html)");
    process.exit(2);
  }
  let total = 0;
  let changed = 0;
  for (const file of pages(root)) {
    const count = typesetPage(file);
    total += count;
    if (count) changed += 1;
  }
  console.log(`typeset-maths: ${total} formulas typeset in ${changed} pages`);
}

main();
