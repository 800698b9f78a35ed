/*
 * Boxes that scroll sideways can be scrolled with the keyboard.
 *
 * On a narrow screen a line of code, a wide table, a cell's output or a long formula
 * scrolls inside its own box instead of widening the page (dstoolkit.css). A box that
 * does scroll gets the keyboard focus (tabindex="0", so the arrow keys scroll it), the role
 * of a region and a name that says what it holds ("Code, scrolls sideways"); a box that
 * fits again gives them back, so on a wide screen the Tab order holds only links and
 * controls. Checked again when the window is resized and when the page changes (MathJax
 * typesets, the explorers draw).
 *
 * Loaded on every page by book/_ext/dstoolkit_a11y.py.
 */
(function () {
  "use strict";

  // What may scroll, and the name of what it holds.
  var BOXES = [
    [".bd-article div.highlight pre", "Code"],
    [".bd-article div.highlight", "Code"],
    [".bd-article div.cell_output div.output.text_html", "Output"],
    [".bd-article div.cell_output div.output.text_markdown", "Output"],
    [".bd-article .pst-scrollable-table-container", "Table"],
    [".bd-article div.table-wrapper", "Table"],
    [".bd-article mjx-container", "Formula"]
  ];
  var MARK = "data-scroll-box";

  // Content that passes its box by a few pixels (the overhang of an italic glyph in a
  // formula) is not a reason to scroll: the same 13 px margin as axe-core's rule
  // scrollable-region-focusable.
  var OVERHANG_PX = 13;

  function scrolls(box) {
    if (box.scrollWidth <= box.clientWidth + OVERHANG_PX) return false;
    var overflow = window.getComputedStyle(box).overflowX;
    return overflow === "auto" || overflow === "scroll";
  }

  function nameOf(box, kind) {
    var caption = box.querySelector("caption");
    var text = caption ? caption.textContent.replace(/\s+/g, " ").trim() : "";
    return (text ? kind + " " + text : kind) + ", scrolls sideways";
  }

  // A marked box keeps, in MARK, the tabindex it had before (MathJax gives formulas -1).
  function update() {
    BOXES.forEach(function (entry) {
      document.querySelectorAll(entry[0]).forEach(function (box) {
        var marked = box.hasAttribute(MARK);
        if (scrolls(box)) {
          if (marked || box.getAttribute("tabindex") === "0") return; // done, or focusable
          box.setAttribute(MARK, box.getAttribute("tabindex") || "");
          box.setAttribute("tabindex", "0");
          box.setAttribute("role", "region");
          box.setAttribute("aria-label", nameOf(box, entry[1]));
        } else if (marked) {
          var before = box.getAttribute(MARK);
          if (before) box.setAttribute("tabindex", before); else box.removeAttribute("tabindex");
          ["role", "aria-label", MARK].forEach(function (name) {
            box.removeAttribute(name);
          });
        }
      });
    });
  }

  var pending = null;
  function schedule() {
    if (pending !== null) return;
    pending = window.setTimeout(function () {
      pending = null;
      update();
    }, 150);
  }

  function start() {
    update();
    window.addEventListener("resize", schedule);
    window.addEventListener("load", schedule);
    var article = document.querySelector("article.bd-article") || document.body;
    new MutationObserver(schedule).observe(article, {childList: true, subtree: true});
  }

  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", start);
  } else {
    start();
  }
})();
