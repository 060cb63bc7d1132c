"""Design files: YAML with line numbers, units, validated immutable models, the registry of cam
types (:mod:`camfab.design.cam_types`).

A stop (Ctrl-C, SIGTERM) that arrives while this package is imported waits for the import to
end (:func:`camfab.stopping.deferred`): pydantic builds the models' validators then, and an
exception raised inside it is printed as ignored and lost, or wrapped in pydantic's own error.
"""

from camfab.stopping import deferred

with deferred():
    from camfab.design.loader import design_from_mapping, design_from_text, load_design
    from camfab.design.model import Design

__all__ = ["Design", "design_from_mapping", "design_from_text", "load_design"]
