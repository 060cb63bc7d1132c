"""ezdxf, imported without reading anyone's ezdxf configuration.

At import, ezdxf reads ``ezdxf.ini`` from the user's config folder (``$XDG_CONFIG_HOME/ezdxf`` or
``~/.config/ezdxf``), from the working directory and from ``$EZDXF_CONFIG_FILE``. A damaged file
there stops the import (a ``configparser`` error, or ezdxf's own ``exit(1)`` on a UTF-16 file),
and a valid one can change what ezdxf writes. camfab's files must be the same bytes on every
machine, so it imports ezdxf once with none of those files in reach: the config folder and the
working directory pointed at an empty temporary folder for the moment of the import.
"""

from __future__ import annotations

import os
import sys
import tempfile
from types import ModuleType

from camfab.stopping import deferred

_HIDDEN = ("XDG_CONFIG_HOME", "EZDXF_CONFIG_FILE")


def load_ezdxf() -> ModuleType:
    """The ezdxf module, imported (on the first call) without any configuration file."""
    module = sys.modules.get("ezdxf")
    if module is not None:
        return module
    saved = {name: os.environ.get(name) for name in _HIDDEN}
    try:
        cwd: str | None = os.getcwd()
    except OSError:  # the working directory is gone: ezdxf cannot read one there either
        cwd = None
    with tempfile.TemporaryDirectory(prefix="camfab-ezdxf-") as empty:
        os.environ["XDG_CONFIG_HOME"] = empty
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
