"""The phase search's occupancy grid: the cells holding a sample of the part and the 26 about
each, the same cells as every one of the 27 shifts taken at once; the points in them counted as
one by one."""

from __future__ import annotations

import numpy as np

from camfab.inspect.scan_align import Occupancy, _distinct


def test_the_occupied_cells_are_those_next_to_a_sample() -> None:
    rng = np.random.default_rng(3)
    points = rng.normal(size=(4000, 3))
    points = 30.0 * points / np.linalg.norm(points, axis=1, keepdims=True)  # a sphere's surface
    points[:500, 2] += rng.uniform(0.0, 40.0, 500)  # and a stalk
    grid = Occupancy(points)
    cells = grid._cells(points)
    shifts = np.stack(np.meshgrid(*[np.arange(-1, 2)] * 3, indexing="ij"), -1).reshape(-1, 3)
    every = np.unique(grid._keys((cells[:, None, :] + shifts[None]).reshape(-1, 3)))
    assert every.min() >= 0  # (the grid leaves room about the samples)
    assert np.array_equal(grid.occupied, every)
    assert grid.hits(points) == len(points)
    # and points anywhere (in any order, off the grid too) counted one by one
    others = rng.uniform(-45.0, 75.0, (3000, 3))
    inside = np.isin(grid._keys(grid._cells(others)), every)
    assert grid.hits(others) == np.count_nonzero(inside) > 0


def test_distinct_keys_are_numpys_unique() -> None:
    rng = np.random.default_rng(5)
    for keys in (rng.integers(-50, 50, 1000), rng.integers(0, 10**12, 300), np.array([7]),
                 np.zeros(0, dtype=np.int64), np.full(5, 3)):
        assert np.array_equal(_distinct(keys), np.unique(keys))
