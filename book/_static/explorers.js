/*
 * The explorers of the static site: native controls that switch precomputed states.
 *
 * scripts/site_postbuild.py writes every explorer (div.dstoolkit-explorer) as plain HTML:
 * a live slider is an <input type="range"> over the indices of its values (data-labels),
 * a live drop-down a <select>; each names in data-switches the stacks it switches
 * (div.dstoolkit-stack[data-stack]), whose states (div.dstoolkit-state) are all written,
 * all but the selected one hidden. Loaded (async: it listens on the document, so a control
 * answers while the rest of a long page is still being read) by myst-nb's nb_ipywidgets_js
 * on the pages with explorers (_config.yml). This script:
 *
 * - shows, in every stack a control switches, the state of the control's position (a
 *   hidden state's pictures wait in data-src: they are fetched when it is first shown);
 * - keeps the slider's readout (<output>, text that cannot be edited) and its
 *   aria-valuetext in step: the value, then the unit of its label that the post-build
 *   wrote in data-unit ("level L (m)" -> "9.6 m");
 * - puts the shown state's one sentence (p.dstoolkit-said: the control's value and the one
 *   or two results that moved) in the explorer's polite live region (.dstoolkit-announce);
 * - adds, at the top of the article, a "Skip to the first explorer" link (shown when it
 *   takes the keyboard focus) that moves the focus to the first explorer's first live
 *   control.
 *
 * The arrow keys move a range natively. Disabled controls are written disabled, with
 * aria-disabled and aria-describedby naming the explorer's note that says where they work.
 */
(function () {
  "use strict";

  function textOf(element) {
    return element ? element.textContent.replace(/\s+/g, " ").trim() : "";
  }

  function labelsOf(control) {
    try {
      return JSON.parse(control.getAttribute("data-labels") || "[]");
    } catch (error) {
      return [];
    }
  }

  // Show the index-th state of a stack.
  function show(stack, index) {
    var states = Array.prototype.filter.call(stack.children, function (child) {
      return child.classList.contains("dstoolkit-state");
    });
    if (index < 0 || index >= states.length) return;
    states.forEach(function (state, i) {
      if (i === index) state.removeAttribute("hidden");
      else if (!state.hasAttribute("hidden")) state.setAttribute("hidden", "");
    });
  }

  // Fetch the pictures of the states an explorer now shows (a nested stack shown again
  // keeps its own position: its shown state's pictures too).
  function fetchShown(explorer) {
    explorer.querySelectorAll(".dstoolkit-state:not([hidden]) img[data-src]").forEach(
      function (img) {
        if (img.closest("[hidden]")) return;  // inside a hidden state of a nested stack
        img.setAttribute("src", img.getAttribute("data-src"));
        img.removeAttribute("data-src");
      });
  }

  // The sentence of the state an explorer shows (each state carries one, hidden).
  function sentenceOf(explorer) {
    var said = Array.prototype.filter.call(
      explorer.querySelectorAll(".dstoolkit-said"),
      function (p) { return p.parentElement && !p.parentElement.closest("[hidden]"); });
    return said.length ? textOf(said[said.length - 1]) : "";
  }

  function update(control) {
    var index = control.tagName === "SELECT" ? control.selectedIndex : Number(control.value);
    var explorer = control.closest(".dstoolkit-explorer") || document;
    (control.getAttribute("data-switches") || "").split(/\s+/).forEach(function (id) {
      if (!id) return;
      explorer.querySelectorAll('[data-stack="' + id + '"]').forEach(function (stack) {
        show(stack, index);
      });
    });
    fetchShown(explorer);
    if (control.type === "range") {
      var labels = labelsOf(control);
      var shown = labels.length ? String(labels[index]) : control.value;
      var unit = control.getAttribute("data-unit") || "";
      control.setAttribute("aria-valuetext", unit ? shown + " " + unit : shown);
      var readout = control.parentElement &&
        control.parentElement.querySelector("output.dstoolkit-readout");
      if (readout) readout.textContent = shown;
    }
    var region = explorer.querySelector(".dstoolkit-announce");
    var sentence = sentenceOf(explorer);
    if (region && sentence && region.textContent !== sentence) region.textContent = sentence;
  }

  function addSkipLink() {
    var article = document.querySelector("article.bd-article, article");
    if (!article || article.querySelector(".dstoolkit-skip")) return;
    var link = document.createElement("a");
    link.className = "dstoolkit-skip";
    link.href = "#";
    link.textContent = "Skip to the first explorer";
    link.addEventListener("click", function (event) {
      event.preventDefault();
      var target = document.querySelector(
        ".dstoolkit-explorer input:not([disabled]), .dstoolkit-explorer select:not([disabled])");
      if (!target) return;
      target.scrollIntoView({block: "center"});
      target.focus();
    });
    article.insertBefore(link, article.firstChild);
  }

  // One listener for the whole page: a control answers as soon as its explorer is parsed,
  // before the rest of a long page is.
  function onChange(event) {
    var control = event.target;
    if (control && control.matches && control.matches(".dstoolkit-explorer [data-switches]")) {
      update(control);
    }
  }
  document.addEventListener("input", onChange);
  document.addEventListener("change", onChange);

  function start() {
    if (!document.querySelector(".dstoolkit-explorer")) return;
    addSkipLink();
    // a position moved before this script ran, or kept by the browser from an earlier
    // visit (back/forward), is shown too
    document.querySelectorAll(".dstoolkit-explorer [data-switches]").forEach(function (control) {
      var selected = control.tagName === "SELECT" ? control.selectedIndex : Number(control.value);
      if (String(selected) !== control.getAttribute("data-index")) update(control);
    });
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start);
  else start();
})();
