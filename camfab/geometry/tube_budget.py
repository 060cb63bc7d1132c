"""How large a groove's tube camfab builds: a drum's and a globoid's groove is a mesh whose
facets grow as the tolerance shrinks (some 1/tolerance: stations and rows each as its square
root) and as the motion bends more tightly, and every stage after it (the boolean with the
blank, the mesh's repair, the STL, the roller run through it) takes time and memory in
proportion. A design whose tube would take more than :data:`MAX_TUBE_FACETS` is refused as it
is loaded, with the size it would take and the finest tolerance the cam can be built to.

Tolerances are millimetres.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from camfab.design.rules import fail, mm

#: Most facets of a groove's tube camfab builds. A build takes up to some 25 µs of CPU and
#: 2 kB of memory per facet (a concave globoid: the boolean, the repair of its slivers, the roller
#: run through the STL read back; a convex one or a drum a third to a half of that), so that
#: 500,000 keep a build within some 13 s and 1 GB. A globoid's rows double up to 257 where its
#: flanks twist, which at a degree between stations makes some 460,000 facets (a convex globoid
#: grazing its blank, at the default 0.01 mm: 407,000); the starters' tubes have 31,000 (drum)
#: and 135,000 (globoid) at their default tolerances.
MAX_TUBE_FACETS = 500_000

#: Memory a build takes per facet of the tube at the most (bytes), for the size a refusal states.
BYTES_PER_FACET = 2000

#: How far past the most a refused tube's facets are counted, as a multiple of it: so that a
#: refusal states the size the tube would take, not only that it passes the most.
COUNTED = 4

#: The coarsest tolerance the design file allows (mm; see camfab.design.rules).
COARSEST_MM = 1.0

#: Bisections :func:`finest_within` makes once it has a tolerance the tube fits at: the last
#: step's ratio (at least 2) narrowed to its 32nd root, some 2 %.
_BISECTIONS = 5


def check_tube(facets_at: Callable[[float, int], int], tolerance: float, what: str,
               segments: int) -> None:
    """Refuse a groove whose tube at *tolerance* (mm) takes more than :data:`MAX_TUBE_FACETS`.

    Parameters
    ----------
    facets_at
        The tube's facets (count) at a tolerance (mm), counted up to a most (count): exact up
        to it, and past it at least the most and one (counted no further).
    tolerance
        The design's ``manufacturing.tolerance`` (mm).
    what
        The groove in words for the message ("a drum's groove").
    segments
        The motion's segment count, for the message when no tolerance is coarse enough.

    Raises :class:`~camfab.design.rules.RuleViolation` on ``manufacturing.tolerance`` with the
    finest tolerance within the limit, or on ``motion`` when even the coarsest (1 mm) is not.
    """
    counted = COUNTED * MAX_TUBE_FACETS
    facets = facets_at(tolerance, counted)
    if facets <= MAX_TUBE_FACETS:
        return
    finest = finest_within(lambda tol: facets_at(tol, MAX_TUBE_FACETS), tolerance, facets)
    size = (f"{'at least ' if facets > counted else ''}{_count(facets)} facets, "
            f"{_memory(facets)}")
    if finest is None:
        fail(("motion",), f"makes {what} too fine to build: its {segments:,} segments bend it "
             f"so tightly that even at the coarsest tolerance ({mm(COARSEST_MM)}) its mesh "
             f"would take more than the {MAX_TUBE_FACETS:,} facets camfab builds (at "
             f"{mm(tolerance)}, {size}); give fewer or gentler segments", show_got=False)
    fail(("manufacturing", "tolerance"), f"is too fine for {what}: its mesh at "
         f"{mm(tolerance)} would take {size}, and camfab builds at most "
         f"{MAX_TUBE_FACETS:,} facets; this cam can be built to {mm(finest)} or coarser",
         show_got=False)


def finest_within(facets_at: Callable[[float], int], tolerance: float,
                  facets: int) -> float | None:
    """About the finest tolerance (mm, coarser than *tolerance*, at which the tube takes
    *facets*) at which the tube takes at most :data:`MAX_TUBE_FACETS`, to two significant
    digits; None when even :data:`COARSEST_MM` is too fine.

    The facets fall about as the tolerance grows (not quite: a globoid's rows double in
    steps), so the tolerance is scaled up by the facets over the most, at least doubling,
    until the tube fits, and the finest that fits is then bisected for between the last two."""
    fine, coarse = tolerance, tolerance
    while True:
        if coarse >= COARSEST_MM:
            return None
        fine = coarse
        coarse = min(COARSEST_MM, coarse * max(2.0, 1.05 * facets / MAX_TUBE_FACETS))
        facets = facets_at(coarse)
        if facets <= MAX_TUBE_FACETS:
            break
    for _ in range(_BISECTIONS):
        middle = math.sqrt(fine * coarse)
        if facets_at(middle) <= MAX_TUBE_FACETS:
            coarse = middle
        else:
            fine = middle
    rounded = _round_up(coarse)
    return rounded if facets_at(rounded) <= MAX_TUBE_FACETS else coarse


def _round_up(value: float) -> float:
    """*value* rounded up to two significant digits."""
    step = 10.0 ** (math.floor(math.log10(value)) - 1)
    return math.ceil(value / step - 1e-9) * step


def _count(facets: int) -> str:
    """A facet count in words: ``450,000``, ``1.5 million``, ``23 million`` or ``4.1e+12``."""
    if facets < 10**6:
        return f"{facets:,}"
    if facets < 10**9:
        return f"{facets / 1e6:.2g} million" if facets < 10**7 else f"{facets / 1e6:.0f} million"
    return f"{facets:.2g}"


def _memory(facets: int) -> str:
    """The memory a build of a tube of *facets* would take, in words."""
    gigabytes = facets * BYTES_PER_FACET / 1e9
    return f"some {gigabytes:.2g} GB to build" if gigabytes >= 1.0 else \
        f"some {gigabytes * 1000:.0f} MB to build"
