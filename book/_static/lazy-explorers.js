/*
 * The explorers' widget code, loaded when an explorer comes near the screen.
 *
 * scripts/site_postbuild.py takes the widget manager (jupyter-widgets/embed.js) and its
 * MathJax shim out of the page's <head> and lists them, in order, in this script's
 * data-scripts; it writes each explorer's first state as plain HTML (div.dstoolkit-preview)
 * before the explorer's widget view. This script loads the listed scripts once, in order,
 * when an explorer comes within a screen of the viewport or takes the keyboard focus (or at
 * once where IntersectionObserver is missing). embed.js draws the widgets on the window's
 * `load` event; its handler is called here as soon as it is loaded. When an explorer is drawn, its
 * preview leaves the page. window.dstoolkitLoadExplorers() loads them at once.
 */
(function () {
  "use strict";

  var me = document.currentScript;
  var scripts = ((me && me.getAttribute("data-scripts")) || "").split(/\s+/).filter(Boolean);
  var VIEW = 'script[type="application/vnd.jupyter.widget-view+json"]';
  var started = false;

  function dropPreviews() {
    document.querySelectorAll(".dstoolkit-preview").forEach(function (preview) {
      var drawn = preview.parentElement && preview.parentElement.querySelector(".widget-subarea");
      if (drawn && drawn.firstElementChild && drawn.offsetHeight > 0) preview.remove();
    });
    if (document.querySelector(".dstoolkit-preview")) window.setTimeout(dropPreviews, 100);
  }

  function runLoadHandlers(handlers) {
    handlers.forEach(function (handler) {
      try {
        handler.call(window, new Event("load"));
      } catch (error) {
        console.error("lazy-explorers.js: the widget manager failed:", error);
      }
    });
    dropPreviews();
  }

  function load() {
    if (started) return;
    started = true;
    // embed.js draws on the window's load event, which may be over when it runs, or come
    // late on a slow network (it waits for every picture): its handler is kept here and
    // called as soon as the scripts have run (the page is parsed by then)
    var handlers = [];
    var add = window.addEventListener;
    window.addEventListener = function (type, handler, options) {
      if (type === "load") handlers.push(handler);
      else add.call(window, type, handler, options);
    };
    var next = 0;
    function one() {
      if (next >= scripts.length) {
        window.addEventListener = add;
        runLoadHandlers(handlers); // the page is parsed: no need to wait for its pictures
        return;
      }
      var script = document.createElement("script");
      script.src = scripts[next];
      next += 1;
      script.onload = one;
      script.onerror = function () {
        console.error("lazy-explorers.js: could not load " + script.src);
        one();
      };
      document.head.appendChild(script);
    }
    one();
  }

  function start() {
    var views = Array.prototype.map.call(document.querySelectorAll(VIEW), function (view) {
      return view.parentElement;
    }).filter(Boolean);
    if (!views.length) return;
    if (!("IntersectionObserver" in window)) {
      load();
      return;
    }
    var observer = new IntersectionObserver(function (entries) {
      if (entries.some(function (entry) { return entry.isIntersecting; })) {
        observer.disconnect();
        load();
      }
    }, {rootMargin: "100% 0px 100% 0px"});
    views.forEach(function (view) {
      observer.observe(view);
      view.addEventListener("focusin", load);
    });
    // a link to an explorer (the skip link, a heading's anchor) brings it into view too
    window.addEventListener("hashchange", function () {
      var target = document.getElementById(decodeURIComponent(location.hash.slice(1)));
      if (target && views.some(function (v) { return target.contains(v) || v.contains(target); })) {
        load();
      }
    });
  }

  // for the browser tests and for pages that want every explorer drawn now
  window.dstoolkitLoadExplorers = load;

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start);
  else start();
})();
