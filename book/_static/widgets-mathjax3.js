/*
 * MathJax 2 compatibility for the Jupyter widget embedder (embed.js).
 *
 * @jupyter-widgets/base typesets widget labels with the MathJax 2 call
 * `MathJax.Hub.Queue(["Typeset", MathJax.Hub, element])` whenever `window.MathJax` exists.
 * The book serves MathJax 3, which has no `Hub`, so every labelled widget would throw
 * "Cannot read properties of undefined (reading 'Queue')". This file is loaded (by
 * myst-nb's nb_ipywidgets_js, see _config.yml) just before embed.js, only on pages with
 * widgets. It runs before the deferred MathJax 3 script, so it adds a `startup.ready`
 * hook to the MathJax configuration object that Sphinx wrote into the page; the hook
 * gives MathJax 3 a `Hub.Queue` that forwards "Typeset" to `MathJax.typesetPromise`.
 */
(function () {
  "use strict";

  function typeset(element) {
    var mathjax = window.MathJax;
    if (!mathjax || typeof mathjax.typesetPromise !== "function") return;
    mathjax.typesetPromise(element ? [element] : undefined).catch(function (error) {
      console.warn("MathJax could not typeset a widget label:", error);
    });
  }

  function addHub(mathjax) {
    if (mathjax.Hub) return;
    mathjax.Hub = {
      Queue: function () {
        Array.prototype.forEach.call(arguments, function (command) {
          if (Array.isArray(command) && command[0] === "Typeset") typeset(command[2]);
        });
      },
    };
  }

  var config = window.MathJax;
  if (!config) return; // no maths on this page: embed.js skips typesetting
  if (config.version) {
    addHub(config); // MathJax 3 is already running
    return;
  }
  config.startup = config.startup || {};
  var ready = config.startup.ready;
  config.startup.ready = function () {
    if (ready) ready();
    else window.MathJax.startup.defaultReady();
    addHub(window.MathJax);
  };
})();
