"""The named materials of a design's ``materials:`` section: Young's modulus and Poisson's ratio
for the contact stress (THEORY §I).

The values are the usual handbook ones at room temperature (Shigley's *Mechanical Engineering
Design*, table A-5, for the metals; the makers' data sheets for the plastics); a cam of another
grade gives its own as ``{E: "200 GPa", poisson: 0.29}``. E is in MPa.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Material:
    """A material's elastic constants: Young's modulus (MPa) and Poisson's ratio, and what it
    is in words."""

    youngs_modulus: float
    poisson: float
    what: str


#: The materials a design names, by the name it gives.
MATERIALS: dict[str, Material] = {
    "steel": Material(206_000.0, 0.30, "carbon or alloy steel, hardened or not"),
    "stainless-steel": Material(193_000.0, 0.29, "austenitic stainless steel"),
    "cast-iron": Material(100_000.0, 0.21, "grey cast iron"),
    "ductile-iron": Material(169_000.0, 0.29, "ductile (nodular) cast iron"),
    "bronze": Material(111_000.0, 0.35, "phosphor bronze"),
    "brass": Material(106_000.0, 0.32, "brass"),
    "aluminium": Material(71_700.0, 0.33, "aluminium alloy"),
    "titanium": Material(114_000.0, 0.34, "titanium alloy"),
    "pom": Material(2_900.0, 0.35, "acetal (POM, Delrin), machined or printed"),
    "nylon": Material(2_800.0, 0.39, "nylon (PA 6 or PA 66)"),
    "pla": Material(3_500.0, 0.36, "PLA, 3-D printed"),
    "petg": Material(2_100.0, 0.38, "PETG, 3-D printed"),
}

#: Other names for the same materials.
ALIASES = {"aluminum": "aluminium", "acetal": "pom", "delrin": "pom", "iron": "cast-iron",
           "stainless": "stainless-steel"}

#: The material of the cam and of the follower when the design names none.
DEFAULT_MATERIAL = "steel"


def material(name: str) -> Material | None:
    """The material called *name* (a name or an alias, any case), or None."""
    key = name.strip().lower()
    return MATERIALS.get(ALIASES.get(key, key))
