"""A drum's scan model: the gauge roller's run over a moved groove is the direct formula's, bit
for bit (each point's radius and polar angle are taken once for the whole window of rows)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from camfab.inspect.models.drum import DrumScan, scan_model
from camfab.inspect.scan_deviation import fitted_surface
from camfab.inspect.surface import windowed_run
from camfab.pipeline import analyse, load_design

from .conftest import DESIGNS

#: The rows' step here (rad): coarser than an inspection's, for quick tests.
STEP = math.radians(0.5)


@pytest.fixture(scope="module")
def model() -> DrumScan:
    return scan_model(analyse(load_design(DESIGNS / "demo-cylindrical.yaml")), STEP)


def _direct(model: DrumScan, points: np.ndarray, theta: np.ndarray, side: int) -> np.ndarray:
    """The lift (mm) at which the gauge roller at *theta* touches the Cartesian *points*: the
    module's formula taken point by point from x, y, z."""
    d = model.drum
    x, y, z = points[..., 0], points[..., 1], points[..., 2]
    r = np.hypot(x, y)
    delta = np.arctan2(-x, y) - d.axis_angle(theta)
    w = r * np.sin(delta)
    rise = np.sqrt(d.roller * d.roller - w * w)
    rise = np.where(r * np.cos(delta) > 0.0, rise, np.nan)
    return z - d.start + (rise if side < 0 else -rise)


def test_the_run_over_a_moved_groove_is_the_direct_formulas_bit_for_bit(
        model: DrumScan) -> None:
    rng = np.random.default_rng(7)
    d = model.drum
    window = math.ceil(math.asin(min(1.0, d.roller / max(d.root, d.roller))) / STEP) + 2
    for flank in model.flanks:
        deviation = rng.normal(0.0, 0.02, flank.points.shape[:2])
        deviation[40:60, 2:7] = np.nan  # a patch unscanned
        deviation[300:300 + 2 * window + 20] = np.nan  # rows no point bounds
        moved = fitted_surface(flank.points, flank.normals, deviation)
        run = model.run(flank, moved)
        direct = windowed_run(moved, model.theta, flank.side, window,
                              lambda p, t, s: _direct(model, p, t, s))
        assert np.isnan(run).any() and np.isfinite(run).sum() > 600
        assert np.array_equal(run, direct, equal_nan=True)

