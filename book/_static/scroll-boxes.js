/*
 * Boxes that scroll can be scrolled with the keyboard.
 *
 * On a narrow screen a line of code, a wide table, a cell's output, an explorer's row of
 * controls or a long formula scrolls inside its own box instead of widening the page
 * (dstoolkit.css). Any box of the article that does scroll gets the keyboard focus
 * (tabindex="0", so the arrow keys scroll it), the role of a region and a name that says
 * what it holds and which one it is ("Code: positions(slider(…, scrolls sideways"; the
 * same name twice gets its number, "(2)"); a box inside a box that already scrolls (a
 * code block's pre in its highlight box) takes no Tab stop of its own; a box that
 * fits again gives them back, so on a wide screen the Tab order holds only links and
 * controls. Only the boxes a stylesheet (or their own style) lets scroll are measured.
 * Checked again when the window is resized and when the page changes (an explorer shows
 * another state, the theme changes a Tab stop).
 *
 * Loaded on every page by book/_ext/dstoolkit_a11y.py.
 */
(function () {
  "use strict";

  var MARK = "data-scroll-box";
  var SIDEWAYS = ", scrolls sideways";
  // Content that passes its box by a few pixels (the overhang of an italic glyph in a
  // formula) is not a reason to scroll: the same 13 px margin as axe-core's rule
  // scrollable-region-focusable.
  var OVERHANG_PX = 13;

  function scrollable(value) {
    return value === "auto" || value === "scroll";
  }

  // "x" when a box scrolls sideways, "y" when it scrolls only up and down, "" when not.
  function scrolls(box) {
    var wide = box.scrollWidth > box.clientWidth + OVERHANG_PX;
    var tall = box.scrollHeight > box.clientHeight + OVERHANG_PX;
    if (!wide && !tall) return "";
    var style = window.getComputedStyle(box);
    if (wide && scrollable(style.overflowX)) return "x";
    if (tall && scrollable(style.overflowY)) return "y";
    return "";
  }

  // What a box holds, for its name.
  function kindOf(box) {
    if (box.tagName === "MJX-CONTAINER") return "Formula";
    if (box.matches("pre, div.highlight")) return "Code";
    if (box.matches("table, .pst-scrollable-table-container, div.table-wrapper")) {
      return "Table";
    }
    if (box.closest(".widget-subarea, .jupyter-widgets")) return "Controls";
    if (box.closest("div.cell_output")) return "Output";
    return "Content";
  }

  // The words that tell this box from the others of its kind: a table's caption or first
  // header, a code block's first line of code, a formula's text.
  var WHICH_CHARS = 40;
  function whichOf(box, kind) {
    var text = "";
    if (kind === "Table") {
      var head = box.querySelector("caption") || box.querySelector("th");
      text = head ? head.textContent : "";
    } else {
      text = (box.textContent || "").split("\n").map(function (line) {
        return line.trim();
      }).filter(Boolean)[0] || "";
    }
    text = text.replace(/\s+/g, " ").trim();
    return text.length > WHICH_CHARS ? text.slice(0, WHICH_CHARS - 1) + "…" : text;
  }

  function nameOf(box, direction) {
    var kind = kindOf(box);
    var which = whichOf(box, kind);
    return (which ? kind + ": " + which : kind) + (direction === "x" ? SIDEWAYS : ", scrolls");
  }

  // The same name on two boxes: the second and later ones get their number.
  function distinctNames() {
    var seen = {};
    document.querySelectorAll(".bd-article [role='region'][aria-label]").forEach(function (box) {
      if (!/, scrolls( sideways)?$/.test(box.getAttribute("aria-label"))) return;
      var name = box.getAttribute("aria-label").replace(/ \(\d+\)(, scrolls( sideways)?)$/, "$1");
      seen[name] = (seen[name] || 0) + 1;
      var wanted = seen[name] === 1 ? name
        : name.replace(/(, scrolls( sideways)?)$/, " (" + seen[name] + ")$1");
      if (box.getAttribute("aria-label") !== wanted) box.setAttribute("aria-label", wanted);
    });
  }

  // The boxes that can scroll: those a stylesheet or their own style gives an overflow of
  // auto or scroll, those the theme made Tab stops, and those marked before. Only these are
  // measured, not every element of the article: a chapter holds some ten thousand elements,
  // most of them inside formulas, and reading each one's size costs more than the page's
  // own layout.
  var SCROLLING = /(^|\s)(auto|scroll)(\s|$)/;
  var candidates = null;

  // A rule's selector list, split at its top-level commas (not those inside :is(...)).
  function selectorParts(list) {
    var parts = [];
    var depth = 0;
    var start = 0;
    for (var i = 0; i < list.length; i++) {
      var c = list.charAt(i);
      if (c === "(" || c === "[") depth += 1;
      else if (c === ")" || c === "]") depth -= 1;
      else if (c === "," && depth === 0) {
        parts.push(list.slice(start, i).trim());
        start = i + 1;
      }
    }
    parts.push(list.slice(start).trim());
    return parts;
  }

  var probe = document.createElement("div"); // a detached element: matching it is instant
  function usable(selector) {
    if (!selector || selector.indexOf("::") >= 0) return false; // a pseudo-element is no box
    try {
      probe.matches(selector);
      return true;
    } catch (error) {
      return false; // a nested rule's relative selector, or one this browser cannot parse
    }
  }

  function candidateSelector() {
    var found = {};
    found["[tabindex='0']"] = true;
    found["[style*='overflow']"] = true;
    found["[" + MARK + "]"] = true;
    function visit(rules) {
      for (var i = 0; i < rules.length; i++) {
        var rule = rules[i];
        var style = rule.style;
        if (rule.selectorText && style && (SCROLLING.test(style.overflow) ||
            SCROLLING.test(style.overflowX) || SCROLLING.test(style.overflowY))) {
          selectorParts(rule.selectorText).forEach(function (part) {
            if (usable(part)) found[part] = true;
          });
        }
        if (rule.cssRules) visit(rule.cssRules); // @media, @supports, @layer, nesting
      }
    }
    Array.prototype.forEach.call(document.styleSheets, function (sheet) {
      try {
        visit(sheet.cssRules);
      } catch (error) {
        // a stylesheet from another origin cannot be read (the site serves its own)
      }
    });
    return Object.keys(found).join(", ");
  }

  // The boxes of the article that may scroll (not those inside a formula).
  function findBoxes() {
    var article = document.querySelector(".bd-article");
    if (!article) return [];
    return Array.prototype.filter.call(article.querySelectorAll(candidates), function (box) {
      if (box.tagName.indexOf("MJX-") === 0 && box.tagName !== "MJX-CONTAINER") return false;
      return !box.closest("mjx-assistive-mml, svg"); // not inside a formula
    });
  }

  // Every box of the article that scrolls sideways takes the focus and is named; a marked
  // box keeps, in MARK, the tabindex it had before (the theme gives some code blocks 0
  // without a name).
  function mark(boxes) {
    // Every size first, then every change: a change (a tabindex, a name) makes the next
    // size read lay the page out again, so reads and writes in turn would lay it out once
    // per box.
    var looks = boxes.map(function (box) {
      return {direction: scrolls(box), overhang: box.scrollWidth > box.clientWidth + 1};
    });
    boxes.forEach(function (box, i) {
      var marked = box.hasAttribute(MARK);
      var direction = looks[i].direction;
      var named = box.hasAttribute("aria-label") || box.hasAttribute("aria-labelledby");
      if (!direction && !named && box.getAttribute("tabindex") === "0" && looks[i].overhang
          && !box.matches("a, button, input, select, textarea, summary, [role]")) {
        // a box the theme made a Tab stop because it scrolls by a few pixels: named too
        box.setAttribute("aria-label", nameOf(box, "x"));
        box.setAttribute("role", "region");
        return;
      }
      // one Tab stop per region: a box inside one that scrolls already is reached by it
      if (direction && !marked && box.parentElement &&
          box.parentElement.closest("[" + MARK + "]")) {
        if (box.getAttribute("tabindex") === "0" && !named) box.setAttribute("tabindex", "-1");
        return;
      }
      if (direction) {
        if (marked) return;
        if (box.getAttribute("tabindex") === "0" && named) return; // done by its maker
        box.setAttribute(MARK, box.getAttribute("tabindex") || "");
        box.setAttribute("tabindex", "0");
        if (!named) {
          box.setAttribute("role", "region");
          box.setAttribute("aria-label", nameOf(box, direction));
        }
      } else if (marked) {
        var before = box.getAttribute(MARK);
        if (before) box.setAttribute("tabindex", before); else box.removeAttribute("tabindex");
        if (box.getAttribute("role") === "region") box.removeAttribute("role");
        if (/, scrolls( sideways)?$/.test(box.getAttribute("aria-label") || "")) {
          box.removeAttribute("aria-label");
        }
        box.removeAttribute(MARK);
      }
    });
    distinctNames();
  }

  // The check runs as separate tasks (reading the stylesheets once, finding the boxes,
  // measuring and marking them), each short enough that a tap on a slow phone never waits
  // for the whole of it. A check asked for while one runs starts when it has finished.
  var running = false;
  var again = false;
  function finish() {
    running = false;
    if (again) {
      again = false;
      schedule();
    }
  }
  function update() {
    running = true;
    var boxes = [];
    var steps = [
      function () {
        if (candidates === null) candidates = candidateSelector();
      },
      function () {
        boxes = findBoxes();
      },
      function () {
        mark(boxes);
      },
    ];
    function run(step) {
      window.setTimeout(function () {
        var last = step === steps.length - 1;
        try {
          steps[step]();
        } catch (error) {
          last = true; // a check that failed does not stop the next one
          throw error;
        } finally {
          if (last) finish();
          else run(step + 1);
        }
      }, 0);
    }
    run(0);
  }

  var pending = null;
  function schedule() {
    if (running) {
      again = true;
      return;
    }
    if (pending !== null) return;
    pending = window.setTimeout(function () {
      pending = null;
      update();
    }, 150);
  }

  function start() {
    schedule(); // after the first paint: the page is laid out once, by the browser
    window.addEventListener("resize", schedule);
    window.addEventListener("load", schedule);
    var article = document.querySelector("article.bd-article") || document.body;
    // the theme makes scrolling code blocks Tab stops on its own, after a resize: a new
    // tabindex is a change to look at too
    new MutationObserver(schedule).observe(article, {childList: true, subtree: true,
                                                     attributes: true,
                                                     attributeFilter: ["tabindex"]});
  }

  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", start);
  } else {
    start();
  }
})();
