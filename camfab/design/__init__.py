"""Design files: YAML with line numbers, units, validated immutable models, the registry of cam
types (:mod:`camfab.design.cam_types`)."""

from camfab.design.loader import design_from_mapping, design_from_text, load_design
from camfab.design.model import Design

__all__ = ["Design", "design_from_mapping", "design_from_text", "load_design"]
