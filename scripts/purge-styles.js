#!/usr/bin/env node
/*
 * Drop from the site's stylesheet the rules that nothing on the site can match.
 *
 *   node scripts/purge-styles.js STYLESHEET CONTENT...   (the purged stylesheet on stdout)
 *
 * Run by scripts/site_postbuild.py on the one stylesheet it joins for every page: most of its
 * rules are Bootstrap's, the theme's and Font Awesome's for elements no page has. PurgeCSS
 * (npm devDependency) keeps every rule whose class, id, element or attribute occurs in a
 * CONTENT file: the built pages (their tags: names, attributes and the values that select,
 * and their inline scripts; not their prose, where "row" or "small" is just a word) and the
 * site's own scripts, whose strings name the classes they add at run time. Kept whatever
 * the content says: the classes Bootstrap's script builds from pieces ("bs-tooltip-" +
 * placement, tooltips, popovers and their states), the dark-mode rules ([data-theme],
 * [data-mode], set by the theme's script from the reader's choice), the theme's focus ring
 * (":focus-visible"), keyframes, font faces and CSS variables.
 */
"use strict";

const fs = require("fs");
const { PurgeCSS } = require("purgecss");

// Classes the theme's and extensions' scripts put together at run time.
const SAFELIST = {
  standard: [/^bs-/, /tooltip/, /popover/, /^show$/, /^showing$/, /^hiding$/, /^fade$/],
  // the theme's focus ring for everything that takes the keyboard (a selector of a
  // pseudo-class alone names nothing PurgeCSS could find in a page)
  greedy: [/data-theme/, /data-mode/, /^:focus-visible$/],
};

const WORD = /[A-Za-z0-9_-]+/g;
const TAG = /<([A-Za-z][\w-]*)((?:[^>"']|"[^"]*"|'[^']*')*)>/g;
const ATTRIBUTE = /([^\s=/>]+)(?:\s*=\s*("[^"]*"|'[^']*'|[^\s>]+))?/g;
const SCRIPT = /<script\b[^>]*>([\s\S]*?)<\/script>/gi;
// Attributes whose values are text or addresses, never what a stylesheet selects on.
const TEXT_VALUED = new Set([
  "alt", "title", "href", "src", "srcset", "data-src", "content", "aria-label",
  "aria-valuetext", "data-labels", "placeholder", "value", "action", "download",
]);

// The words a page's markup offers to a selector: tag and attribute names, the values of
// attributes a selector can test, and the words of its inline scripts.
function pageWords(html) {
  const words = [];
  for (const script of html.matchAll(SCRIPT)) words.push(...(script[1].match(WORD) || []));
  for (const tag of html.matchAll(TAG)) {
    words.push(tag[1].toLowerCase());
    for (const attribute of tag[2].matchAll(ATTRIBUTE)) {
      const name = attribute[1].toLowerCase();
      words.push(name);
      if (attribute[2] && !TEXT_VALUED.has(name)) words.push(...(attribute[2].match(WORD) || []));
    }
  }
  return words;
}

async function main(argv) {
  if (argv.length < 2) {
    process.stderr.write("usage: node scripts/purge-styles.js STYLESHEET CONTENT...\n");
    return 2;
  }
  const [stylesheet, ...content] = argv;
  const [result] = await new PurgeCSS().purge({
    css: [stylesheet],
    content: content.map((file) => ({
      raw: fs.readFileSync(file, "utf8"),
      extension: file.split(".").pop(),
    })),
    extractors: [{ extractor: pageWords, extensions: ["html"] }],
    safelist: SAFELIST,
    keyframes: false,
    fontFace: false,
    variables: false,
  });
  process.stdout.write(result.css);
  return 0;
}

main(process.argv.slice(2)).then(
  (code) => { process.exitCode = code; },
  (error) => { process.stderr.write(`purge-styles.js: ${error.stack || error}\n`); process.exitCode = 1; },
);
