"""A raster as PNG bytes (8-bit RGB, no interlace), for the few colour maps a report draws
(:meth:`camfab.export.chart.Axes.image`). Written here with ``zlib`` and ``struct`` from
Python's library: the format's writer is a few lines, and no imaging library is otherwise
needed by a build."""

from __future__ import annotations

import struct
import zlib

import numpy as np


def png_bytes(pixels: np.ndarray) -> bytes:
    """The (H, W, 3) uint8 *pixels* (first row at the top) as a PNG file's bytes."""
    height, width, _ = pixels.shape
    rows = np.concatenate((np.zeros((height, 1), dtype=np.uint8),
                           np.ascontiguousarray(pixels, dtype=np.uint8).reshape(height, -1)),
                          axis=1)

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(rows.tobytes(), 9)) + chunk(b"IEND", b""))
