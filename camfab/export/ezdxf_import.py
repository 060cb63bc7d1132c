"""ezdxf, imported without reading anyone's ezdxf configuration or font cache, and without
touching the process's working directory or environment.

At import, ezdxf reads ``ezdxf.ini`` from the user's config folder (``$XDG_CONFIG_HOME/ezdxf`` or
``~/.config/ezdxf``), from the working directory and from ``$EZDXF_CONFIG_FILE``: its module of
options (``ezdxf._options``) ends by making ``options = Options()``, which reads the files that
module's ``config_files()`` lists. A damaged file there stops the import (a ``configparser``
error, or ezdxf's own ``exit(1)`` on a UTF-16 file), and a valid one can change what ezdxf
writes. It also loads its font cache, ``font_manager_cache.json`` in the folder that module's
``xdg_path("XDG_CACHE_HOME", ".cache")`` answers (``$XDG_CACHE_HOME/ezdxf`` or
``~/.cache/ezdxf``), or, when there is none, scans the system's and the user's font folders and
writes one there: a cache folder it may not read (a ``PermissionError``), a path too long, or a
damaged cache stops the import, a folder it cannot write prints a warning, and the scan takes
seconds on a machine with many fonts. camfab measures text with ezdxf's monospaced stand-in font,
never with a system font (:mod:`camfab.export.dxf_page`), and its files must be the same bytes on
every machine.

So camfab runs ezdxf's module of options itself, as it is but for those two functions while the
import lasts: ``config_files()`` lists no file (ezdxf's defaults, and its ``EZDXF_*`` variables,
are what it reads) and ``xdg_path()`` answers a temporary folder holding only an empty font cache
(no fonts, nothing scanned). Both are ezdxf's own again once it is imported. Nothing else is
changed: the working directory and the environment are the process's, which the studio's other
threads use meanwhile (moving them for the moment of the import made those threads read the
wrong files).
"""

from __future__ import annotations

import ast
import importlib.abc
import importlib.machinery
import sys
import tempfile
import threading
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

from camfab.stopping import deferred

#: ezdxf's module of options, run by :class:`_QuietLoader`.
_OPTIONS = "ezdxf._options"

#: ezdxf's font cache with no fonts in it, in its format (version 2, ezdxf 1.1 and later), for
#: an ezdxf whose font manager cannot say its own: with it in place ezdxf scans no font folder.
_EMPTY_FONT_CACHE = '{"version": 2, "font-faces": []}'

#: One import at a time: a second thread waits for the first instead of taking its module half
#: made from ``sys.modules``.
_IMPORTING = threading.Lock()


def load_ezdxf() -> ModuleType:
    """The ezdxf module, imported (on the first call) without any configuration file or font
    cache of the user's."""
    with _IMPORTING:
        module = sys.modules.get("ezdxf")
        if module is not None:
            return module
        with tempfile.TemporaryDirectory(prefix="camfab-ezdxf-") as empty:
            finder = _QuietOptions(Path(empty))
            sys.meta_path.insert(0, finder)
            try:
                with deferred():  # a stop raised inside leaves pyparsing's objects half made
                    import ezdxf
            finally:
                sys.meta_path.remove(finder)
                finder.restore()
        return ezdxf


class _QuietOptions(importlib.abc.MetaPathFinder):
    """Finds ezdxf's module of options where Python would, to be run by :class:`_QuietLoader`
    with *folder* (a temporary folder) for every folder ezdxf asks ``xdg_path`` for."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.module: ModuleType | None = None
        self.xdg_path: Any = None

    def find_spec(self, fullname: str, path: Sequence[str] | None,
                  target: ModuleType | None = None) -> importlib.machinery.ModuleSpec | None:
        if fullname != _OPTIONS:
            return None
        spec = importlib.machinery.PathFinder.find_spec(fullname, path)
        if spec is not None and isinstance(spec.loader, importlib.machinery.SourceFileLoader):
            spec.loader = _QuietLoader(spec.loader, self)
        return spec  # (an ezdxf without its sources: imported as it is)

    def quiet_xdg_path(self, xdg_var: str, directory: str) -> Path:
        """ezdxf's ``xdg_path`` while it is imported: the temporary folder's ``ezdxf`` folder,
        holding an empty font cache."""
        found = self.folder / "ezdxf"
        cache = found / "font_manager_cache.json"
        if not cache.exists():
            found.mkdir(exist_ok=True)
            cache.write_text(_empty_font_cache(), encoding="utf-8")
        return found

    def restore(self) -> None:
        """ezdxf's own ``xdg_path`` again, once the import is over."""
        if self.module is None:
            return
        if self.xdg_path is None:
            self.module.__dict__.pop("xdg_path", None)
        else:
            self.module.xdg_path = self.xdg_path


class _QuietLoader(importlib.abc.Loader):
    """Runs ``ezdxf/_options.py`` as it is, but for its last statement (``options =
    Options()``, which reads the configuration files), run with ``config_files`` listing none
    and ``xdg_path`` answering the finder's folder. A module of another shape is run as it is."""

    def __init__(self, loader: importlib.machinery.SourceFileLoader,
                 finder: _QuietOptions) -> None:
        self.loader = loader
        self.finder = finder

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType | None:
        return None

    def exec_module(self, module: ModuleType) -> None:
        origin = self.loader.get_filename(module.__name__)
        source = self.loader.get_source(module.__name__)
        tree = ast.parse(source or "", origin)
        if not tree.body or not _makes_options(tree.body[-1]):
            self.loader.exec_module(module)
            return
        names = module.__dict__
        exec(_compiled(tree.body[:-1], origin), names)
        found = names.get("config_files")
        self.finder.module, self.finder.xdg_path = module, names.get("xdg_path")
        names["config_files"] = _no_files
        names["xdg_path"] = self.finder.quiet_xdg_path
        try:
            exec(_compiled(tree.body[-1:], origin), names)
        finally:
            names["config_files"] = found


def _makes_options(statement: ast.stmt) -> bool:
    """True for ``options = Options()``."""
    return (isinstance(statement, ast.Assign) and len(statement.targets) == 1
            and isinstance(statement.targets[0], ast.Name)
            and statement.targets[0].id == "options"
            and isinstance(statement.value, ast.Call)
            and isinstance(statement.value.func, ast.Name)
            and statement.value.func.id == "Options")


def _compiled(statements: list[ast.stmt], origin: str) -> Any:
    return compile(ast.Module(body=statements, type_ignores=[]), origin, "exec",
                   dont_inherit=True)


def _no_files() -> list[Path]:
    """ezdxf's ``config_files`` while it is imported: no configuration file."""
    return []


def _empty_font_cache() -> str:
    """An empty font cache in the format of the ezdxf being imported (its font manager is
    loaded by the time it asks where the cache is)."""
    manager = sys.modules.get("ezdxf.fonts.font_manager")
    try:
        return str(manager.FontManager().dumps())  # type: ignore[union-attr]
    except Exception:  # no font manager loaded, or one of another make: ezdxf 1.1's format
        return _EMPTY_FONT_CACHE
