"""ezdxf, imported without reading anyone's ezdxf configuration or font cache.

At import, ezdxf reads ``ezdxf.ini`` from the user's config folder (``$XDG_CONFIG_HOME/ezdxf`` or
``~/.config/ezdxf``), from the working directory and from ``$EZDXF_CONFIG_FILE``. A damaged file
there stops the import (a ``configparser`` error, or ezdxf's own ``exit(1)`` on a UTF-16 file),
and a valid one can change what ezdxf writes. It also loads its font cache,
``font_manager_cache.json`` in ``$XDG_CACHE_HOME/ezdxf`` (or ``~/.cache/ezdxf``), or, when there
is none, scans the system's and the user's font folders and writes one there: a cache folder it
may not read (a ``PermissionError``), a path too long, or a damaged cache stops the import, a
folder it cannot write prints a warning, and the scan takes seconds on a machine with many fonts.
camfab measures text with ezdxf's monospaced stand-in font, never with a system font
(:mod:`camfab.export.dxf_page`), and its files must be the same bytes on every machine, so it
imports ezdxf once with none of those files in reach: the config and cache folders, the home
folder and the working directory pointed at a temporary folder for the moment of the import,
holding only an empty font cache (no fonts, nothing scanned).
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path
from types import ModuleType

from camfab.stopping import deferred

#: The environment variables set (or removed) for the moment of the import: where ezdxf looks
#: for its configuration, its font cache and the user's font folders (``~``).
_HIDDEN = ("XDG_CONFIG_HOME", "XDG_CACHE_HOME", "HOME", "USERPROFILE", "EZDXF_CONFIG_FILE")

#: ezdxf's font cache with no fonts in it, in its format (version 2, ezdxf 1.1 and later): with
#: it in place ezdxf scans no font folder. A cache of another version is rebuilt by a scan, of
#: the temporary folder's (empty) home and the system's font folders: then the fonts are the
#: system's, still not the user's, and still unused by camfab.
_EMPTY_FONT_CACHE = '{"version": 2, "font-faces": []}'


def load_ezdxf() -> ModuleType:
    """The ezdxf module, imported (on the first call) without any configuration file or font
    cache of the user's."""
    module = sys.modules.get("ezdxf")
    if module is not None:
        return module
    saved = {name: os.environ.get(name) for name in _HIDDEN}
    try:
        cwd: str | None = os.getcwd()
    except OSError:  # the working directory is gone: ezdxf cannot read one there either
        cwd = None
    with tempfile.TemporaryDirectory(prefix="camfab-ezdxf-") as empty:
        cache = Path(empty, "cache")
        (cache / "ezdxf").mkdir(parents=True)
        (cache / "ezdxf" / "font_manager_cache.json").write_text(_EMPTY_FONT_CACHE,
                                                                 encoding="utf-8")
        os.environ["XDG_CONFIG_HOME"] = str(Path(empty, "config"))
        os.environ["XDG_CACHE_HOME"] = str(cache)
        os.environ["HOME"] = os.environ["USERPROFILE"] = str(Path(empty, "home"))
        os.environ.pop("EZDXF_CONFIG_FILE", None)
        try:
            if cwd is not None:
                os.chdir(empty)
            with deferred():  # a stop raised inside leaves pyparsing's objects half made
                import ezdxf
        finally:
            if cwd is not None:
                os.chdir(cwd)
            for name, value in saved.items():
                if value is None:
                    os.environ.pop(name, None)
                else:
                    os.environ[name] = value
    return ezdxf
