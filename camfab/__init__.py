"""camfab: turn a cam design into the files a workshop needs.

The package root stays import-light on purpose: ``camfab --version`` must not import numpy.
The library is reached through its subpackages (``camfab.design``, ``camfab.motion``, ...)
and ``camfab.pipeline``.
"""

__version__ = "0.1.0"
