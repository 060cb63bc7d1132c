"""``camfab inspect``: a made or scanned cam's outline -> its motion and its deviation from the
design -> files.

From the bottom up: ``record`` (the ``Inspection``), ``checks``, ``measure`` (the follower run
over the outline), ``reference`` (the design's motion); ``options``, ``values``, ``follower`` and
``part`` (the command line, the follower and the outline resolved), ``prepare``; the writers
``lift_csv``, ``report_json``, ``figures`` and ``report_html``; ``run`` (``inspect``).
"""

from camfab.inspect.options import InspectOptions
from camfab.inspect.record import Inspection
from camfab.inspect.run import InspectResult, inspect

__all__ = ["InspectOptions", "InspectResult", "Inspection", "inspect"]
