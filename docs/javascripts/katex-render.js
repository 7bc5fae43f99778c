// Typesets the formulas pymdownx.arithmatex (generic) leaves in the pages: <span class="arithmatex">\(...\)</span> and
// <div class="arithmatex">\[...\]</div>. KaTeX is vendored (docs/assets/katex), so a local build reads offline.
(function () {
  function typeset(root) {
    root.querySelectorAll(".arithmatex").forEach(function (element) {
      var tex = element.textContent.trim();
      var display = element.tagName === "DIV";
      tex = tex.replace(/^\\[\[(]/, "").replace(/\\[\])]$/, "");
      try {
        katex.render(tex, element, { displayMode: display, throwOnError: false });
      } catch (error) {
        console.error("KaTeX:", error, tex);
      }
    });
  }
  if (window.document$) {
    window.document$.subscribe(function () { typeset(document.body); });   // Material's page (re)loads
  } else {
    document.addEventListener("DOMContentLoaded", function () { typeset(document.body); });
  }
})();
