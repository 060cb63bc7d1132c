"""The report's colour maps as PNG: what camfab writes is read back by Pillow, an independent
decoder, pixel for pixel."""

from __future__ import annotations

import io

import numpy as np

from camfab.export.png import png_bytes


def test_pixels_come_back_from_an_independent_decoder() -> None:
    from PIL import Image

    pixels = np.random.default_rng(0).integers(0, 256, size=(37, 53, 3), dtype=np.uint8)
    image = Image.open(io.BytesIO(png_bytes(pixels)))
    assert image.size == (53, 37) and image.mode == "RGB"
    assert np.array_equal(np.asarray(image), pixels)
