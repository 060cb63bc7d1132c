"""Reading a DXF layer's closed contours back as a reader would: ezdxf's edge miner chains the
LINE and ARC entities into loops, and ezdxf's own arcs flatten them (independent of camfab's arc
code)."""

from __future__ import annotations

import numpy as np
import shapely
from ezdxf import edgeminer, edgesmith

#: Ends closer than this (file units) meet: CAD programs join far wider gaps (1e-4 and more).
GAP = 1e-6


def loops(doc, layer: str, sagitta: float = 1e-5) -> list[np.ndarray]:  # type: ignore[no-untyped-def]
    """The closed contours on *layer* as (N, 2) points in the file's units, largest first.

    Arcs are cut into chords within *sagitta* by ezdxf (true circles; its Bézier paths are
    only within 2.7e-4 of the radius, too coarse here); circles count as contours too.
    """
    msp = doc.modelspace()
    out = [np.array([(v.x, v.y) for v in c.flattening(sagitta)])[:-1]
           for c in msp.query(f'CIRCLE[layer=="{layer}"]')]
    edges = list(edgesmith.edges_from_entities_2d(msp.query(f'LINE ARC[layer=="{layer}"]'),
                                                  gap_tol=GAP))
    for loop in edgeminer.find_all_loops(edgeminer.Deposit(edges, gap_tol=GAP)):
        points: list[tuple[float, float]] = []
        for edge in loop:
            entity = edge.payload
            if entity.dxftype() == "ARC":
                pts = [(v.x, v.y) for v in entity.flattening(sagitta)]
            else:
                pts = [(entity.dxf.start.x, entity.dxf.start.y), (entity.dxf.end.x,
                                                                  entity.dxf.end.y)]
            start = np.array([edge.start.x, edge.start.y])
            if np.hypot(*(np.array(pts[-1]) - start)) < np.hypot(*(np.array(pts[0]) - start)):
                pts.reverse()  # this edge runs against the entity's own direction
            points.extend(pts[:-1])
        out.append(np.array(points))
    return sorted(out, key=lambda c: -shapely.Polygon(c).area)


def loop_sizes(doc, layer: str) -> tuple[int, list[int]]:  # type: ignore[no-untyped-def]
    """(LINE and ARC entities on *layer*, the entities of each closed loop, largest loop
    first)."""
    entities = doc.modelspace().query(f'LINE ARC[layer=="{layer}"]')
    edges = list(edgesmith.edges_from_entities_2d(entities, gap_tol=GAP))
    found = edgeminer.find_all_loops(edgeminer.Deposit(edges, gap_tol=GAP))
    area = [abs(edgesmith.loop_area(loop)) for loop in found]
    return len(entities), [len(loop) for _, loop in sorted(zip(area, found, strict=True),
                                                           key=lambda x: -x[0])]
