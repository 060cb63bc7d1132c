"""The command line as given (``InspectOptions``) and everything it resolves to before the
follower is run (``Prepared``)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from camfab.curves.profile import Profile
    from camfab.design import Design
    from camfab.export.outline import Outline
    from camfab.inspect.record import InspectionSetup, Reference


@dataclass(frozen=True)
class InspectOptions:
    """The command line, as given (None: not given). Lengths are text, optionally with a unit."""

    profile: Path
    design: Path | None = None
    follower_file: Path | None = None
    follower: dict[str, str] = field(default_factory=dict)
    rotation: str | None = None
    speed: str | None = None
    units: str | None = None
    layer: str | None = None
    centre: str | None = None
    step: str | None = None
    smooth: str | None = None
    tolerance: str | None = None
    kerf: str | None = None
    align: bool = False
    out_dir: Path | None = None
    scan: bool = False
    fixtured: bool = False
    fit: str | None = None
    gate: str | None = None
    plate_b: Path | None = None


@dataclass(frozen=True)
class Prepared:
    """Everything read and resolved, before the follower is run."""

    options: InspectOptions
    outline: Outline
    profile: Profile
    setup: InspectionSetup
    reference: Reference | None
    units: str
    speed_rpm: float | None
    centre_mm: tuple[float, float]
    kerf_mm: float
    kerf_source: str
    design: Design | None
