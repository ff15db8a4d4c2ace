"""The course as a static web site: ``lpv-explorer site OUT/``.

The same lesson files the window reads (through :mod:`explorer.lessons`) become an index
and one scrolling page per lesson, readable from ``file://`` or any static host with
nothing fetched from a network:

* :mod:`explorer.site.mathml` typesets the lessons' LaTeX as MathML (Chromium, Firefox
  and Safari draw it natively; the shipped Latin Modern Math font draws the symbols);
* :mod:`explorer.site.frames` renders each step headlessly (EGL): its view with the
  step's camera and in-scene overlays, each try-this's "after", iteration sequences, and
  the error measurement a step quotes; the numbers the text quotes are baked from these
  converged frames (:mod:`explorer.site.values`);
* :mod:`explorer.site.figure_shots` draws the imgui figures in a hidden window (a child
  process under a display) as 2× PNG; :mod:`explorer.site.plots` draws the audit plots
  as SVG;
* :mod:`explorer.site.prose` turns the lesson prose into HTML, :mod:`explorer.site.pages`
  writes the pages, :mod:`explorer.site.build` drives it all.
"""
