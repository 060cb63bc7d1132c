"""The time a build spends inside the libraries that make its bytes: manifold3d's solids,
ezdxf's documents, OpenCASCADE's solids and checks, LAPACK's least squares and splines.

While camfab keeps these libraries and every output byte for byte, it cannot cut these calls:
the same numbers need the same calls. :func:`tallied` times them within any stretch of
camfab's work, each call once (a library call made inside another is the outer one's).
"""

from __future__ import annotations

import importlib
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

#: (module, a class in it or "" for the module itself, names) per library: the calls timed (a
#: module's class: the making of its instances). A class's methods come before the class.
CALLS: dict[str, tuple[tuple[str, str, tuple[str, ...]], ...]] = {
    "manifold3d": (
        ("manifold3d", "Manifold", ("__sub__", "__add__", "extrude", "cylinder", "revolve",
                                    "translate", "set_tolerance", "batch_boolean", "to_mesh",
                                    "to_mesh64", "status", "volume", "surface_area")),
        ("manifold3d", "", ("Manifold", "Mesh64", "CrossSection")),
    ),
    "ezdxf": (
        ("ezdxf", "", ("new", "read")),
        ("ezdxf.document", "Drawing", ("write",)),
        ("ezdxf.graphicsfactory", "CreatorInterface", ("add_line", "add_arc", "add_circle",
                                                       "add_text", "add_lwpolyline")),
        ("ezdxf.layouts.base", "BaseLayout", ("query",)),
    ),
    "OpenCASCADE": (
        ("OCP.BRepAlgoAPI", "", ("BRepAlgoAPI_Cut", "BRepAlgoAPI_Fuse")),
        ("OCP.BRepGProp", "BRepGProp", ("VolumeProperties_s", "SurfaceProperties_s")),
        ("OCP.STEPControl", "STEPControl_Reader", ("ReadStream", "TransferRoots")),
        ("OCP.STEPControl", "STEPControl_Writer", ("Transfer", "WriteStream")),
        ("OCP.BRepCheck", "", ("BRepCheck_Analyzer",)),
    ),
    "LAPACK": (
        ("scipy.linalg", "", ("lstsq",)),
        ("scipy.interpolate", "", ("make_interp_spline",)),
    ),
}


@contextmanager
def tallied(*libraries: str) -> Iterator[dict[str, float]]:
    """Within the block, the seconds spent in each of *libraries*' calls (:data:`CALLS`), by
    library, as the block runs; the libraries' own functions put back after it."""
    seconds = dict.fromkeys(libraries, 0.0)
    depth = [0]
    undo: list[Callable[[], None]] = []
    try:
        for library in libraries:
            for module, path, names in CALLS[library]:
                owner: Any = importlib.import_module(module)
                if path:
                    owner = getattr(owner, path)
                for name in names:
                    undo.append(_timed(owner, name, library, seconds, depth))
        yield seconds
    finally:
        for put_back in reversed(undo):
            put_back()


def _timed(owner: Any, name: str, library: str, seconds: dict[str, float],
           depth: list[int]) -> Callable[[], None]:
    """*owner*'s *name* replaced by the same call timed into *seconds* (only while no other
    timed call is running): a function or method, or a module's class, whose instances are then
    made by a subclass that times their making. Returns the function that puts it back."""
    static = isinstance(owner, type)
    own = not static or name in owner.__dict__
    original = owner.__dict__[name] if static and own else getattr(owner, name)
    call = original.__func__ if isinstance(original, staticmethod) else original
    if not static and isinstance(original, type):  # the class made anew, its making timed
        call = original.__init__

    def timed(*args: Any, **kwargs: Any) -> Any:
        depth[0] += 1
        start = time.perf_counter()
        try:
            return call(*args, **kwargs)
        finally:
            depth[0] -= 1
            if depth[0] == 0:
                seconds[library] += time.perf_counter() - start

    replacement: Any = timed
    if not static and isinstance(original, type):
        replacement = type(original.__name__, (original,), {"__init__": timed})
    elif static and (isinstance(original, staticmethod)
                     or type(original).__name__ in ("nb_func", "builtin_function_or_method")):
        replacement = staticmethod(timed)
    setattr(owner, name, replacement)
    return (lambda: setattr(owner, name, original)) if own else (lambda: delattr(owner, name))
