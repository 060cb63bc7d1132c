"""Tuning a design's motion laws (``camfab tune``): the free parameters of the laws of chosen
rises and returns set to minimise an objective (the residual vibration over a band of speeds,
the peak acceleration or jerk, the peak contact stress or camshaft torque) under every limit of
the design, and the tuned design written beside the old with only those values changed.

- :mod:`camfab.tune.families` — what a segment's law leaves free, family by family (the choice
  of a standard law, a polynomial's points, a modified law's blend): each reads its parameters
  from a segment and writes them back into the design's data and file;
- :mod:`camfab.tune.objectives` — the objectives, each computed from the motion program where
  it can (the residual vibration straight from the elastic train's model) or the analysis;
- :mod:`camfab.tune.margins` — every limit's margin, from a candidate's findings;
- :mod:`camfab.tune.trials` — one candidate evaluated: its objective, its continuity, and (when
  it could be the best) its full analysis;
- :mod:`camfab.tune.convex` — the least peak acceleration or jerk of polynomial laws as a
  linear programme (the global optimum of that convex sub-problem);
- :mod:`camfab.tune.search` — the search: the standard laws tried, then the continuous
  parameters from several deterministic starts;
- :mod:`camfab.tune.summary` — what was found, in words: the lines printed, the report's rows;
- :mod:`camfab.tune.page` — the comparison report, before against after;
- :mod:`camfab.tune.plan` — the options and the design checked before any search, and the
  tuned design's text;
- :mod:`camfab.tune.run` — the command end to end: the plan, the search, the files.
"""
