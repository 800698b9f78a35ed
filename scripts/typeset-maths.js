#!/usr/bin/env node
/*
 * Typeset the book's maths at build time: every page of a built site gets its formulas as
 * MathJax CHTML (with the MathML that screen readers read), its stylesheet in the page, and
 * no MathJax in the browser.
 *
 *   node scripts/typeset-maths.js _build/html
 *
 * Sphinx writes inline maths as <span class="math notranslate nohighlight">\(...\)</span> and
 * display maths as <div class="math notranslate nohighlight">[eqno]\[...\]</div>; MathJax
 * (mathjax-full, the same version as the mathjax package the site used to load) turns each
 * into an <mjx-container>, as it did in the browser with the book's settings: CHTML output,
 * the assistive MathML beside it, formulas out of the Tab order. The page's stylesheet (the
 * characters it uses, its fonts read from _static/mathjax) goes into its <head>, and the
 * MathJax configuration and script leave the page. A page is rewritten once (it is marked);
 * the script fails when TeX is left that it could not typeset.
 */
"use strict";

const fs = require("fs");
const path = require("path");
const { mathjax } = require("mathjax-full/js/mathjax.js");
const { TeX } = require("mathjax-full/js/input/tex.js");
const { CHTML } = require("mathjax-full/js/output/chtml.js");
const { liteAdaptor } = require("mathjax-full/js/adaptors/liteAdaptor.js");
const { RegisterHTMLHandler } = require("mathjax-full/js/handlers/html.js");
const { AllPackages } = require("mathjax-full/js/input/tex/AllPackages.js");
const { SerializedMmlVisitor } = require("mathjax-full/js/core/MmlTree/SerializedMmlVisitor.js");
const { STATE } = require("mathjax-full/js/core/MathItem.js");

const MARK = '<meta name="dstoolkit-maths" content="typeset at build time">';
const FONTS = "_static/mathjax/output/chtml/fonts/woff-v2";
const INLINE = /<span class="math notranslate nohighlight">\\\(([\s\S]*?)\\\)<\/span>/g;
const DISPLAY = /(<div class="math notranslate nohighlight"[^>]*>\s*(?:<span class="eqno">[\s\S]*?<\/span>)?)\\\[([\s\S]*?)\\\](\s*<\/div>)/g;
const MATHJAX_SCRIPTS = [
  /<script>window\.MathJax = [^<]*<\/script>\s*/g,
  /<script defer="defer" src="[^"]*mathjax\/tex-chtml\.js[^"]*"><\/script>\s*/g,
];
// The assistive MathML is read by screen readers and hidden from sight: MathJax's own rules,
// but one pixel wide (as "visually hidden" text is), so that it never widens a paragraph.
const ASSISTIVE_CSS = `
mjx-container[jax="CHTML"] { position: relative; }
mjx-assistive-mml { position: absolute !important; top: 0px; left: 0px;
  clip: rect(1px, 1px, 1px, 1px); clip-path: inset(50%); padding: 1px 0px 0px 0px !important;
  border: 0px !important; display: block !important; width: 1px !important;
  height: 1px !important; overflow: hidden !important; white-space: nowrap;
  -webkit-touch-callout: none; user-select: none; }
`;

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

function typesetPage(file, root) {
  let text = fs.readFileSync(file, "utf8");
  if (text.includes(MARK)) return 0;
  const depth = path.relative(root, path.dirname(file)).split(path.sep).filter(Boolean).length;
  const fontURL = "../".repeat(depth) + FONTS;
  const tex = new TeX({ packages: AllPackages, tags: "none" });
  const chtml = new CHTML({ fontURL, adaptiveCSS: true });
  const doc = mathjax.document("", { InputJax: tex, OutputJax: chtml });
  let count = 0;

  function render(source, display) {
    const math = unescapeHtml(source);
    const options = { display, em: 16, ex: 8, containerWidth: 80 * 16 };
    const node = doc.convert(math, options);
    const mml = visitor.visitTree(doc.convert(math, { ...options, end: STATE.CONVERT }));
    adaptor.setAttribute(node, "role", "presentation");
    const inner = adaptor.firstChild(node);
    adaptor.setAttribute(inner, "aria-hidden", "true");
    count += 1;
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
    const css = adaptor.textContent(chtml.styleSheet(doc)) + ASSISTIVE_CSS;
    head += `\n<style id="dstoolkit-maths-css">${css}</style>`;
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
    const count = typesetPage(file, root);
    total += count;
    if (count) changed += 1;
  }
  console.log(`typeset-maths: ${total} formulas typeset in ${changed} pages`);
}

main();
