/*
 * The explorers for screen readers and keyboards.
 *
 * Loaded (by myst-nb's nb_ipywidgets_js, see _config.yml) on the pages with widgets, before
 * embed.js draws them. Each control is fixed up as soon as embed.js puts it in the page
 * (a MutationObserver), and again whenever it changes:
 *
 * - a slider's handle is named by the slider's label (aria-labelledby), and its
 *   aria-valuetext is the value its readout shows, followed by the unit its label ends with
 *   ("level L (m)" -> "9.6 m"), not noUiSlider's position index; the readout is plain
 *   text, not editable (the handle is the only way to change the value);
 * - a disabled control (a slider, a dropdown, a check box or a button) is exposed as
 *   disabled (aria-disabled), leaves the Tab order and is described (aria-describedby) by
 *   the explorer's note that says where it works;
 * - when an explorer's live controls switch its precomputed states, the state's one
 *   sentence (the control's value and the one or two results that moved) is put in the
 *   explorer's polite live region (.dstoolkit-announce); the last part of a widget whose
 *   slider switches a stack of its own is a polite live region itself.
 *
 * On a page with an explorer, a "Skip to the first explorer" link opens the article; it is
 * shown when it takes the keyboard focus.
 *
 * Every slider gets data-a11y="1" once it is done (the browser tests wait for it).
 */
(function () {
  "use strict";

  // A unit is written at the end of a label, after a space, in parentheses: "level L (m)",
  // "background noise (dB SPL)"; "m({low})" or "m1([0.30, 1.90])" name a set, not a unit.
  var UNIT = /\s\(([^()]+)\)\s*$/;
  var counter = 0;

  function idOf(element, prefix) {
    if (!element.id) {
      counter += 1;
      element.id = prefix + "-" + counter;
    }
    return element.id;
  }

  function textOf(element) {
    return element ? element.textContent.replace(/\s+/g, " ").trim() : "";
  }

  function unitOf(label) {
    var found = UNIT.exec(textOf(label));
    return found ? found[1] : "";
  }

  function setAttr(element, name, value) {
    if (value === null) {
      if (element.hasAttribute(name)) element.removeAttribute(name);
    } else if (element.getAttribute(name) !== value) {
      element.setAttribute(name, value);
    }
  }

  // The note under an explorer's controls ("On this page ... answers; the disabled ones
  // work when this chapter runs as a notebook ...").
  function noteFor(element) {
    var area = element.closest(".widget-subarea") || document;
    return area.querySelector(".dstoolkit-site-note");
  }

  function describeDisabled(control, disabled) {
    var note = noteFor(control);
    setAttr(control, "aria-disabled", disabled ? "true" : null);
    setAttr(control, "aria-describedby",
            disabled && note ? idOf(note, "dstoolkit-note") : null);
  }

  function fixSlider(box) {
    var handle = box.querySelector('[role="slider"]');
    var label = box.querySelector(".widget-label");
    var readout = box.querySelector(".widget-readout");
    var track = box.querySelector(".noUi-target");
    if (!handle || !label || !readout || !track) return;
    var unit = unitOf(label);

    function sync() {
      var shown = textOf(readout);
      setAttr(handle, "aria-labelledby", idOf(label, "dstoolkit-label"));
      setAttr(handle, "aria-valuetext", unit ? shown + " " + unit : shown);
      var disabled = track.hasAttribute("disabled");
      setAttr(handle, "tabindex", disabled ? "-1" : "0");
      describeDisabled(handle, disabled);
      // On this page the slider is the control and its readout is text that follows it:
      // a value typed into the readout would have no precomputed state, so the readout
      // cannot be edited (the widget makes it editable again on every update: undone here).
      setAttr(readout, "aria-labelledby", idOf(label, "dstoolkit-label"));
      setAttr(readout, "contenteditable", "false");
      setAttr(readout, "role", null);
    }

    var observer = new MutationObserver(sync);
    observer.observe(handle, {attributes: true,
                              attributeFilter: ["aria-valuetext", "tabindex"]});
    observer.observe(readout, {childList: true, characterData: true, subtree: true,
                               attributes: true, attributeFilter: ["contenteditable"]});
    observer.observe(track, {attributes: true, attributeFilter: ["disabled"]});
    sync();
    box.setAttribute("data-a11y", "1");
  }

  function fixFormControl(control) {
    function sync() {
      describeDisabled(control, control.disabled);
    }
    new MutationObserver(sync).observe(control, {attributes: true,
                                                 attributeFilter: ["disabled"]});
    sync();
  }

  // The sentence of the state an explorer shows (each state carries one, hidden).
  function sentenceOf(stack) {
    var said = Array.from(stack.querySelectorAll(".dstoolkit-said"));
    var shown = said.filter(function (p) {
      return p.parentElement && p.parentElement.offsetParent !== null;
    });
    var one = shown.length ? shown[shown.length - 1] : said[said.length - 1];
    return one ? textOf(one) : "";
  }

  function fixStates(stack) {
    // Only the outermost stack of an explorer (two live controls nest stacks).
    if (stack.parentElement && stack.parentElement.closest(".dstoolkit-states")) return;
    if (stack.hasAttribute("data-a11y")) return;
    var area = stack.closest(".widget-subarea") || stack.parentElement;
    var region = area && area.querySelector(".dstoolkit-announce");
    if (!region) return;  // drawn a moment later: fixed then
    stack.setAttribute("data-a11y", "1");
    // One short sentence per change ("Level L 5.1 m: series-fit L 5.101 m, resonances 41."),
    // not the readout's headers and numbers and the figure's text alternative.
    setAttr(region, "aria-live", "polite");
    setAttr(region, "aria-atomic", "true");
    setAttr(region, "role", "status");
    var last = sentenceOf(stack);
    var waiting = false;
    new MutationObserver(function () {
      if (waiting) return;
      waiting = true;
      window.setTimeout(function () {
        waiting = false;
        var now = sentenceOf(stack);
        if (now && now !== last) {
          last = now;
          region.textContent = now;
        }
      }, 50);
    }).observe(stack, {childList: true, subtree: true, attributes: true,
                       attributeFilter: ["class", "style", "hidden"]});
  }

  function fix(root) {
    root.querySelectorAll(".widget-slider:not([data-a11y])").forEach(fixSlider);
    root.querySelectorAll(
      ".widget-subarea select:not([data-a11y]), .widget-subarea button:not([data-a11y])," +
      " .widget-subarea input:not([data-a11y])"
    ).forEach(function (control) {
      control.setAttribute("data-a11y", "1");
      fixFormControl(control);
    });
    root.querySelectorAll(".dstoolkit-states").forEach(fixStates);
    // A widget that links a slider to precomputed states itself (a VBox of controls and a
    // Stack): its last part is what the slider switches.
    root.querySelectorAll(".widget-subarea").forEach(function (area) {
      var box = area.querySelector(":scope > .jupyter-widgets");
      if (!box || !area.querySelector(".widget-slider") ||
          area.querySelector(".dstoolkit-states")) return;
      var last = box.lastElementChild;
      if (last && last.classList.contains("widget-box")) setAttr(last, "aria-live", "polite");
    });
  }

  var pending = false;
  function schedule() {
    if (pending) return;
    pending = true;
    window.setTimeout(function () {
      pending = false;
      fix(document);
    }, 0);
  }

  // A link at the top of the article, shown when it has the keyboard focus, that takes
  // the focus to the first explorer's first live control (past the text, its links and
  // its code cells).
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
        '.widget-subarea [role="slider"][tabindex="0"], .widget-subarea select:not([disabled])');
      if (!target) return;
      target.scrollIntoView({block: "center"});
      target.focus();
    });
    article.insertBefore(link, article.firstChild);
  }

  function start() {
    if (document.querySelector('script[type="application/vnd.jupyter.widget-view+json"]')) {
      addSkipLink();
    }
    fix(document);
    new MutationObserver(schedule).observe(document.body, {childList: true, subtree: true});
  }

  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", start);
  } else {
    start();
  }
})();
