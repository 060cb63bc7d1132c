"""Generators for the fuzz tests: design files made by mutating the example designs and the
starters (every cam type), and whole files that are not designs at all.

A mutation works on the parsed data (wrong types, missing, extra and renamed keys, extreme
numbers, odd units, unicode, motion programs of many or odd segments, sections swapped between
designs, shared nodes that the YAML dumper writes as anchors and aliases) and then, sometimes, on
the YAML text (duplicate keys, tags, noise, line endings, a BOM).
"""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import yaml
from hypothesis import strategies as st

from camfab.motion.laws import ALIASES, LAW_NAMES

ROOT = Path(__file__).resolve().parents[1]
BASE_FILES = [*sorted((ROOT / "designs").glob("*.yaml")),
              *sorted((ROOT / "camfab" / "starters").glob("*.yaml"))]
BASE_TEXTS = {f"{p.parent.name}/{p.name}": p.read_text(encoding="utf-8") for p in BASE_FILES}
BASES = {name: yaml.safe_load(text) for name, text in BASE_TEXTS.items()}
CAM_TYPES = sorted({data["cam"]["type"] for data in BASES.values()})
TABLE_CSV = "table.csv"

# ---- values ------------------------------------------------------------------------------------

ODD_NUMBERS: list[Any] = [
    0, -0.0, -1, 1, 1e-12, -1e-12, 1e-9, 1e-6, 1e12, -1e12, 1e300, -1e300, 1e-300, 5e-324,
    10**30, 2**63, -(2**63), 10**400, math.nan, math.inf, -math.inf, 0.5, 179.999999, 180, 360,
    360.000001, 361, 720, -360, 1e6, 999_999.9, 1_000_001,
]
ODD_STRINGS: list[str] = [
    "nan", "NaN", "-nan", "inf", "-inf", "Infinity", ".nan", ".inf", "1e400", "-1e400", "1e-400",
    "5 parsec", "3 rpm", "3 rpm/s", "20 kg", "1.5 in", "1.5 inch", "2 furlongs", "1e3 km",
    "0 mm", "-5 mm", "5 mm mm", "5 deg", "1 turn", "10 rad", "1e-12 mm", "nan mm", "inf mm",
    "1e400 mm", "1" + "0" * 400 + " mm", "mm", "5", " 5 ", "", " ", "5,5", "5.5.5", "0x10",
    "1_000", "½", "٣", "５", "1e", "e5", "--5", "5 ** 2 mm", "10**10**10 mm", "9**9**9 mm",
    "[1,2] mm", "(5", "5)", "5 / 0 mm", "0/0 mm", "1/0", "5 mm + 3 in", "5 N*m", "3 Hz",
    "1 rev/s", "600 rpm", "1 degC", "100 %", "5 mm²", "5 µm", "5 Å", "1 mm/rad**2",
    "2 mm/rad^3", "0.5 N*s/m", "24 N/mm", "1 lbf", "match", "true", "null", "~", "yes", "no",
    "'5'", "\x00", "\x07", "é", "名前", "🚀", "\u202e", "\ufeff5", "a" * 10_000,
    "5 " + "mm*" * 400 + "mm",
    "5 " + "(" * 300 + "mm" + ")" * 300,
]
UNITS = ["mm", "in", "cm", "m", "km", "um", "deg", "rad", "turn", "rpm", "rev/s", "rad/s", "Hz",
         "kg", "g", "lb", "N", "kN", "lbf", "N/mm", "N/m", "lbf/in", "N*s/m", "s", "K", "parsec",
         "furlong", "ly", "zz", "mm**2", "1/s", ""]

plain_floats = st.floats(allow_nan=True, allow_infinity=True)
unit_strings = st.builds(
    lambda number, unit, sep: f"{number:g}{sep}{unit}",
    st.one_of(st.sampled_from([0, -1, 1e-12, 1e12, 5, 0.5, 30, 360]), plain_floats),
    st.sampled_from(UNITS), st.sampled_from([" ", "", "  "]),
)
odd_text = st.one_of(
    st.text(max_size=12),
    st.text(alphabet=st.characters(codec="utf-8", exclude_categories=["Cs"]), max_size=40),
    st.builds(lambda c, n: c * n, st.sampled_from(["x", "é", "名", "🚀", " ", "\n"]),
              st.integers(200, 20_000)),
)
scalars = st.one_of(
    st.none(), st.booleans(), st.sampled_from(ODD_NUMBERS), st.sampled_from(ODD_STRINGS),
    st.integers(-(10**20), 10**20), plain_floats, unit_strings, odd_text,
)
odd_values = st.one_of(
    scalars, scalars, scalars,
    st.lists(scalars, max_size=4),
    st.dictionaries(st.one_of(st.text(max_size=6), st.sampled_from(["angle", "lift", "law"])),
                    scalars, max_size=3),
    st.recursive(scalars, lambda inner: st.lists(inner, max_size=2)
                 | st.dictionaries(st.text(max_size=3), inner, max_size=2), max_leaves=6),
)

#: Keys of the design format, to add where they do not belong (and where they do).
KNOWN_KEYS = ["name", "description", "units", "cam", "follower", "motion", "spring", "limits",
              "manufacturing", "outputs", "table_step", "type", "rotation", "speed_rpm",
              "base_radius", "thickness", "bore", "keyway", "radius", "length", "groove_depth",
              "groove_start", "lift", "lift_angle", "nose_radius", "flank_angle", "top_dwell",
              "outer_radius", "stroke", "base_height", "motion", "offset", "roller_radius",
              "face_radius", "face_width", "pivot_distance", "arm_length", "pivot_side",
              "face_offset", "groove_clearance", "roller_spacing", "arm_angle", "mass", "angle",
              "travel", "law", "blend", "start", "end", "points", "csv", "rate", "preload",
              "initial_compression", "gravity", "damping", "external_load", "pressure_angle",
              "min_radius_of_curvature", "tolerance", "kerf", "cutter_radius", "width", "depth",
              "velocity", "acceleration", "jerk", "snap", "order", "controls", "rise",
              "return", "fall", "dwell"]
odd_keys = st.one_of(
    st.sampled_from(KNOWN_KEYS), st.sampled_from(KNOWN_KEYS), st.text(min_size=1, max_size=10),
    st.sampled_from(["名前", "base_radiüs", "ｎａｍｅ", "Name", "NAME", "cam ", " cam", "<<", "?",
                     "-", "true", "null", "1", "0.5", "x" * 500, "🚀"]),
)
CHOICES = {
    "type": [*CAM_TYPES, "knife", "roller", "flat", "mushroom", "spherical", "drum", "grove",
             "Disc", ""],
    "motion": ["translating", "oscillating", "rotating", "Oscillating"],
    "rotation": ["ccw", "cw", "CW", "clockwise", "both"],
    "pivot_side": ["right", "left", "up"],
    "units": ["mm", "in", "inch", "cm", "MM"],
    "law": [*LAW_NAMES, *ALIASES, "cycloid", "polynomial", "table", "POLYNOMIAL-345", "harmonic "],
    "outputs": [["dxf"], ["stl"], ["svg", "svg"], ["report"], ["csv"], [], ["dxf", "pdf"],
                ["dxf", "svg", "stl", "report", "csv"]],
    "gravity": [True, False, "yes", 1],
    "csv": [TABLE_CSV, "missing.csv", "", "/dev/null", ".", "../" * 20 + "etc/passwd"],
}
FACTORS = [0.0, -1.0, 1e-12, 1e-9, 1e-6, 1e-3, 0.01, 0.1, 0.3, 0.5, 0.9, 0.99, 0.999999,
           1.000001, 1.01, 1.1, 1.5, 2.0, 3.0, 10.0, 100.0, 1e3, 1e6, 1e12]
#: Factors that often leave a design camfab builds (for the full builds).
MILD_FACTORS = [1e-3, 0.01, 0.1, 0.3, 0.5, 0.8, 0.99, 1.01, 1.25, 1.5, 2.0, 3.0, 10.0, 100.0]

# ---- walking the data --------------------------------------------------------------------------

Path_ = tuple[Any, ...]


def paths(node: Any, prefix: Path_ = (), inside: frozenset[int] = frozenset()) -> list[Path_]:
    """Every path into *node* (mapping keys and list indices), parents before children; a node
    shared with an ancestor (a cycle made by an alias) is not entered again."""
    out: list[Path_] = []
    if id(node) in inside:
        return out
    inside = inside | {id(node)}
    items = node.items() if isinstance(node, dict) else (
        enumerate(node) if isinstance(node, list) else ())
    for key, value in items:
        out.append((*prefix, key))
        out.extend(paths(value, (*prefix, key), inside))
    return out


def get(node: Any, path: Path_) -> Any:
    for key in path:
        node = node[key]
    return node


def is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def scaled(value: Any, factor: float) -> Any:
    """*value* times *factor*; a string with a unit keeps its unit."""
    if is_number(value):
        try:
            return value * factor
        except OverflowError:
            return math.inf
    if isinstance(value, str):
        number, _, unit = value.strip().partition(" ")
        try:
            return f"{float(number) * factor:g} {unit}".strip()
        except ValueError:
            return value
    return value


# ---- mutations ---------------------------------------------------------------------------------

#: Every mutation, weighted by repetition; BUILDABLE keeps to those that often still give a
#: design camfab builds (absurd numbers, other types and combinations, odd motion programs).
MUTATIONS = ("value", "value", "scale", "scale", "scale", "delete", "add", "rename", "wrap",
             "choice", "choice", "motion", "motion", "motion", "swap", "alias", "conditions",
             "points", "auto", "spline")
BUILDABLE = ("scale", "scale", "scale", "scale", "choice", "motion", "motion", "swap",
             "conditions", "points", "auto", "spline")

#: Where ``auto`` asks camfab to size a design (and some keys it does not size).
AUTO_PATHS = (("cam", "base_radius"), ("cam", "base_radius"), ("cam", "radius"),
              ("follower", "offset"), ("cam", "thickness"), ("follower", "pivot_distance"))


def _mutate(draw: Any, data: dict[str, Any], ops: tuple[str, ...] = MUTATIONS,
            most_segments: int = 100, factors: list[float] = FACTORS, wild: bool = True) -> Any:
    """One mutation of *data* (in place; returns the new root, which may not be a mapping);
    not *wild*: values of the right kind only (for designs that should often build)."""
    odd = scalars if wild else st.sampled_from([0, 1, -1, 0.5, 5, 30])
    every = paths(data)
    op = draw(st.sampled_from(ops))
    if op == "scale":
        numeric = [p for p in every if is_number(get(data, p)) or (
            isinstance(get(data, p), str) and get(data, p)[:1].isdigit())]
        if numeric:
            path = draw(st.sampled_from(numeric))
            parent = get(data, path[:-1])
            parent[path[-1]] = scaled(parent[path[-1]], draw(st.sampled_from(factors)))
        return data
    if op == "value" and every:
        path = draw(st.sampled_from(every))
        get(data, path[:-1])[path[-1]] = draw(odd_values)
        return data
    if op == "delete" and every:
        path = draw(st.sampled_from(every))
        del get(data, path[:-1])[path[-1]]
        return data
    if op == "add":
        maps = [(), *(p for p in every if isinstance(get(data, p), dict))]
        target = get(data, draw(st.sampled_from(maps)))
        key = draw(odd_keys)
        target[key] = draw(st.one_of(
            st.sampled_from([0.5, 1, 3, 5, 10, 30, 60, 100, 360]), odd_values))
        return data
    if op == "rename":
        keyed = [p for p in every if isinstance(p[-1], str)]
        if keyed:
            path = draw(st.sampled_from(keyed))
            parent = get(data, path[:-1])
            new = draw(st.one_of(odd_keys, st.sampled_from([
                path[-1].upper(), path[-1] + "s", path[-1][:-1], path[-1].replace("_", "-"),
                path[-1].replace("_", " "), " " + path[-1], path[-1] + "\u200b"])))
            parent[new] = parent.pop(path[-1])
        return data
    if op == "wrap" and every:
        path = draw(st.sampled_from([(), *every]))
        value = get(data, path)
        how = draw(st.sampled_from(["list", "map", "flip"]))
        if how == "list":
            new: Any = [value]
        elif how == "map":
            new = {"value": value}
        elif isinstance(value, dict):
            new = [{k: v} for k, v in value.items()]
        elif isinstance(value, list):
            new = {str(i): v for i, v in enumerate(value)}
        else:
            new = str(value)
        if path:
            get(data, path[:-1])[path[-1]] = new
            return data
        return new
    if op == "choice":
        keyed = [p for p in every if p[-1] in CHOICES]
        if keyed:
            path = draw(st.sampled_from(keyed))
            get(data, path[:-1])[path[-1]] = draw(st.sampled_from(CHOICES[path[-1]]))
        else:
            data.setdefault("cam", {})
            if isinstance(data["cam"], dict):
                data["cam"]["type"] = draw(st.sampled_from(CHOICES["type"]))
        return data
    if op == "auto":  # a radius or offset left to camfab's sizing, a stock step to round to
        section, key = draw(st.sampled_from(AUTO_PATHS))
        if isinstance(data.get(section), dict):
            data[section][key] = draw(st.sampled_from(["auto", "auto", "AUTO", " auto"]))
        if draw(st.booleans()):
            data["sizing"] = {"round_to": draw(st.sampled_from([0.5, 1, 0.001, 1e-9, 100,
                                                                 -1, "auto", "0.5 in"]))}
        return data
    if op == "swap":  # a section of another design: mismatched but well-formed combinations
        other = BASES[draw(st.sampled_from(sorted(BASES)))]
        key = draw(st.sampled_from(sorted(other)))
        data[key] = copy.deepcopy(other[key])
        return data
    if op == "alias":  # a node shared by two places: the dumper writes &anchor and *alias
        containers = [p for p in every if isinstance(get(data, p), (dict, list))]
        if len(containers) >= 2:
            source = draw(st.sampled_from(containers))
            target = draw(st.sampled_from([p for p in every if p[:len(source)] != source]
                                          or [source]))
            if target[:len(source)] != source and source[:len(target)] != target:
                get(data, target[:-1])[target[-1]] = get(data, source)
        return data
    if op == "conditions":
        segment = _a_segment(draw, data, moving=True)
        if segment is not None:
            segment["law"] = draw(st.sampled_from(["polynomial", "polynomial", "polynomial",
                                                   "table", "spline", "cycloidal"]))
            for end in draw(st.sets(st.sampled_from(["start", "end"]), min_size=1)):
                segment[end] = {k: draw(st.one_of(
                    st.sampled_from([0, 0, "match", "match", 1, -1, 0.5, 10, -10, 1e6, "MATCH",
                                     "1 mm/rad"]), odd))
                    for k in draw(st.sets(st.sampled_from(["velocity", "acceleration", "jerk",
                                                           "snap" if wild else "jerk"]),
                                          min_size=1))}
        return data
    if op == "spline":  # a B-spline law: its order and free control values, odd or not
        segment = _a_segment(draw, data, moving=True)
        if segment is not None:
            segment["law"] = "spline"
            if draw(st.booleans()):
                segment["order"] = draw(st.one_of(st.sampled_from([4, 5, 6, 7, 10]), odd))
            if draw(st.booleans()):
                segment["controls"] = draw(st.one_of(
                    st.integers(0, 12), st.lists(st.one_of(st.floats(0, 1), odd), max_size=8),
                    odd))
        return data
    if op == "points":
        segment = _a_segment(draw, data, moving=True)
        if segment is not None:
            segment["law"] = "table"
            if draw(st.booleans()):
                segment["csv"] = draw(st.sampled_from(CHOICES["csv"]))
            else:
                span = segment.get("angle", 90)
                span = span if is_number(span) else 90
                lift = segment.get("lift", 10)
                lift = lift if is_number(lift) else 10
                count = draw(st.integers(0, 12))
                segment["points"] = [
                    [draw(st.one_of(st.just(span * i / max(count - 1, 1)), odd)),
                     draw(st.one_of(st.just(lift * i / max(count - 1, 1)),
                                    st.just(lift * math.sin(i)), odd))]
                    for i in range(count)]
        return data
    if op == "motion":
        _mutate_motion(draw, data, most_segments)
    return data


def _a_segment(draw: Any, data: dict[str, Any], moving: bool = False) -> dict[str, Any] | None:
    """The body of one motion segment (a rise or return when *moving*), or None."""
    motion = data.get("motion")
    if not isinstance(motion, list):
        return None
    items = [item for item in motion if isinstance(item, dict) and len(item) == 1
             and isinstance(next(iter(item.values())), dict)
             and (not moving or next(iter(item)) != "dwell")]
    if not items:
        return None
    return next(iter(draw(st.sampled_from(items)).values()))


def _mutate_motion(draw: Any, data: dict[str, Any], most_segments: int) -> None:
    motion = data.get("motion")
    if not isinstance(motion, list):
        motion = data["motion"] = [{"dwell": {"angle": 360}}]
    span = "travel" if isinstance(data.get("cam"), dict) and data["cam"].get(
        "type") == "linear" else "angle"
    how = draw(st.sampled_from(["split", "many", "tiny", "drop", "duplicate", "reverse", "lift",
                                "span", "append"]))
    if how == "split" and motion:  # one segment cut into equal pieces of the same kind
        i = draw(st.integers(0, len(motion) - 1))
        item = motion[i]
        if isinstance(item, dict) and len(item) == 1:
            (kind, body), = item.items()
            if isinstance(body, dict) and is_number(body.get(span)):
                pieces = draw(st.integers(2, 40))
                new = {span: body[span] / pieces}
                if kind == "dwell":
                    motion[i:i + 1] = [{kind: dict(new)} for _ in range(pieces)]
                elif is_number(body.get("lift")) and body.get("law"):
                    new.update(lift=body["lift"] / pieces, law=body["law"])
                    motion[i:i + 1] = [{kind: dict(new)} for _ in range(pieces)]
    elif how == "many":  # a long program of small rises and returns
        # programs camfab builds (up to *most_segments*) and ones it refuses for their length
        count = draw(st.sampled_from([*(c for c in (5, 10, 25, 50, 90, 180)
                                        if 2 * c <= most_segments), 501, 2000]))
        total = 300.0 if span == "travel" else 360.0
        if span == "travel" and isinstance(data.get("cam"), dict):
            data["cam"]["stroke"] = total
        step = total / (2 * count)
        law = draw(st.sampled_from(["cycloidal", "harmonic", "polynomial-345", "linear"]))
        data["motion"] = [seg for _ in range(count) for seg in (
            {"rise": {span: step, "lift": 0.01, "law": law}}, {"return": {span: step, "law": law}})]
    elif how == "tiny" and motion:
        i = draw(st.integers(0, len(motion) - 1))
        body = next(iter(motion[i].values())) if isinstance(motion[i], dict) and motion[i] else None
        if isinstance(body, dict):
            tiny = draw(st.sampled_from([1e-9, 1e-7, 1e-6, 1.0000001e-6, 1e-4, 1e-3]))
            body[span] = tiny
            if draw(st.booleans()):  # keep the total
                other = draw(st.integers(0, len(motion) - 1))
                body2 = next(iter(motion[other].values())) if motion[other] else None
                if isinstance(body2, dict) and is_number(body2.get(span)) and other != i:
                    body2[span] = body2[span] - tiny
    elif how == "drop" and motion:
        del motion[draw(st.integers(0, len(motion) - 1))]
    elif how == "duplicate" and motion:
        i = draw(st.integers(0, len(motion) - 1))
        motion.insert(i, copy.deepcopy(motion[i]))
    elif how == "reverse":
        motion.reverse()
    elif how == "lift":  # lifts larger than the cam, or vanishing
        body = _a_segment(draw, data, moving=True)
        if body is not None:
            body["lift"] = draw(st.sampled_from([1e-12, 1e-6, 0.001, 50, 99, 200, 1000, 1e5, 1e6,
                                                 179, 180, 360, -5]))
    elif how == "span":
        body = _a_segment(draw, data)
        if body is not None:
            body[span] = draw(st.sampled_from([0, -30, 1e-9, 359.999, 360, 400, 1e5, "360 deg",
                                               "1 turn", "0.5 turn", "3.14 rad", "1 mm"]))
    else:
        kind = draw(st.sampled_from(["rise", "return", "fall", "dwell", "jump", "Rise"]))
        body = {span: draw(st.sampled_from([1, 10, 90, 1e-6]))}
        if kind != "dwell":
            body.update(lift=draw(st.sampled_from([1, 5, 20])),
                        law=draw(st.sampled_from(CHOICES["law"])))
        motion.append({kind: body})


@st.composite
def mutated_data(draw: Any, max_mutations: int = 4, ops: tuple[str, ...] = MUTATIONS,
                 most_segments: int = 100, factors: list[float] = FACTORS,
                 wild: bool = True) -> tuple[str, Any]:
    """(base name, data): an example design or starter after 1..*max_mutations* mutations."""
    name = draw(st.sampled_from(sorted(BASES)))
    data: Any = copy.deepcopy(BASES[name])
    for _ in range(draw(st.integers(1, max_mutations))):
        if not isinstance(data, dict):
            break
        data = _mutate(draw, data, ops, most_segments, factors, wild)
    return name, data


def buildable_data(max_mutations: int = 2, most_segments: int = 50) -> Any:
    """Milder mutations, which often leave a design camfab builds (absurd numbers within
    reason, other types and combinations, odd motion programs, polynomials and tables)."""
    return mutated_data(max_mutations, BUILDABLE, most_segments, MILD_FACTORS, wild=False)


csv_texts = st.one_of(
    st.just("angle, lift\n0, 0\n30, 2\n60, 8\n90, 10\n"),
    st.lists(st.tuples(st.one_of(st.integers(-10, 400), plain_floats, st.text(max_size=4)),
                       st.one_of(st.integers(-10, 100), plain_floats, st.text(max_size=4))),
             max_size=8).map(lambda rows: "\n".join(f"{a}, {b}" for a, b in rows)),
    st.text(max_size=60),
)


def dump(data: Any, flow: bool | None = False) -> str:
    """*data* as YAML (floats such as nan and inf as ``.nan`` and ``.inf``)."""
    try:
        return yaml.safe_dump(data, allow_unicode=True, sort_keys=False,
                              default_flow_style=flow, width=100)
    except yaml.representer.RepresenterError:
        return repr(data)


NOISE = [*":{}[],-#'\"\n\t &*!|>%@`0123456789.e+ abcxyz", "\x00", "é", "\ufeff", "\r", "\x85",
         "\u2028", "名"]
TAGS = ["!!str", "!!int", "!!float", "!!bool", "!!null", "!!binary", "!!timestamp", "!!set",
        "!!omap", "!!seq", "!!map", "!custom", "!!python/object:os.system",
        "!<tag:yaml.org,2002:float>"]


@st.composite
def text_mutations(draw: Any) -> str:
    """YAML text of a mutated design, then changed as text."""
    _, data = draw(mutated_data(max_mutations=2))
    text = dump(data, draw(st.sampled_from([False, False, True, None])))
    lines = text.split("\n")
    for _ in range(draw(st.integers(1, 3))):
        how = draw(st.sampled_from(["duplicate-line", "tag", "noise", "crlf", "bom", "tabs",
                                    "comment", "documents", "anchor", "merge", "indent"]))
        i = draw(st.integers(0, max(len(lines) - 1, 0)))
        line = lines[i] if lines else ""
        if how == "duplicate-line":  # duplicate keys
            lines.insert(i, line)
        elif how == "tag" and ": " in line:
            key, _, value = line.partition(": ")
            lines[i] = f"{key}: {draw(st.sampled_from(TAGS))} {value}"
        elif how == "noise" and line:
            j = draw(st.integers(0, len(line)))
            lines[i] = line[:j] + draw(st.sampled_from(NOISE)) + line[j + 1:]
        elif how == "crlf":
            lines = [x + "\r" for x in lines]
        elif how == "bom":
            lines[0] = "\ufeff" + lines[0]
        elif how == "tabs":
            lines[i] = line.replace("  ", "\t", 1)
        elif how == "comment":
            lines.insert(i, "# " + draw(odd_text).replace("\n", " "))
        elif how == "documents":
            lines = draw(st.sampled_from([["%YAML 1.1", "---", *lines], [*lines, "---", *lines],
                                          [*lines, "...", "junk: 1"], ["---", *lines, "..."]]))
        elif how == "anchor" and ": " in line and not line.rstrip().endswith(":"):
            key, _, value = line.partition(": ")
            lines[i] = f"{key}: &a {value}"
            lines.insert(draw(st.integers(0, len(lines))), f"{key}: *a")
        elif how == "merge":
            lines += ["extra: &m {angle: 10}", draw(st.sampled_from(
                ["motion2: {<<: *m}", "cam: {<<: *m}", "<<: *m"]))]
        elif how == "indent":
            lines[i] = " " * draw(st.integers(1, 3)) + line
    return "\n".join(lines)


def alias_bomb(levels: int, width: int, key: str = "description") -> str:
    """A billion-laughs file: each anchor lists *width* aliases of the one before."""
    out = [f"name: bomb\n{key}: &l0 [lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
    for i in range(1, levels + 1):
        out.append(f"x{i}: &l{i} [" + ", ".join([f"*l{i - 1}"] * width) + "]")
    return "\n".join(out) + "\n"


def nested(depth: int, flow: bool) -> str:
    if flow:
        return "name: deep\ncam: " + "[" * depth + "1" + "]" * depth + "\n"
    return "name: deep\n" + "".join("  " * i + f"k{i}:\n" for i in range(depth)) + \
        "  " * depth + "v: 1\n"


@st.composite
def whole_files(draw: Any) -> bytes:
    """Files that are not designs, or barely: empty, whitespace, scalars, lists, binary, broken
    UTF-8, deep nesting, alias bombs, duplicate keys, large files."""
    how = draw(st.sampled_from(["empty", "blank", "scalar", "list", "binary", "bad-utf8",
                                "nested", "bomb", "duplicate", "large", "unicode", "nul"]))
    if how == "empty":
        return b""
    if how == "blank":
        return draw(st.text(alphabet=" \t\r\n\u00a0\u2028\u3000\ufeff", max_size=50)).encode()
    if how == "scalar":
        return dump(draw(scalars)).encode("utf-8", "surrogatepass")
    if how == "list":
        return dump(draw(st.lists(odd_values, max_size=4))).encode("utf-8", "surrogatepass")
    if how == "binary":
        return draw(st.binary(min_size=1, max_size=2000))
    if how == "bad-utf8":
        text = BASE_TEXTS[draw(st.sampled_from(sorted(BASE_TEXTS)))].encode()
        i = draw(st.integers(0, len(text)))
        junk = draw(st.sampled_from([b"\xff", b"\xc3", b"\xed\xa0\x80", b"\xfe\xff", b"\x80\x80",
                                     b"\xf4\x90\x80\x80"]))
        return text[:i] + junk + text[i:]
    if how == "nested":
        return nested(draw(st.sampled_from([49, 50, 51, 100, 1000, 20_000])),
                      draw(st.booleans())).encode()
    if how == "bomb":
        return alias_bomb(draw(st.integers(3, 9)), draw(st.integers(2, 10)),
                          draw(st.sampled_from(["description", "cam", "motion", "zz"]))).encode()
    if how == "duplicate":
        text = BASE_TEXTS[draw(st.sampled_from(sorted(BASE_TEXTS)))]
        lines = text.split("\n")
        i = draw(st.integers(0, len(lines) - 1))
        return "\n".join([*lines[:i + 1], lines[i], *lines[i + 1:]]).encode()
    if how == "large":  # a large but not huge file (the huge ones run as real processes)
        text = BASE_TEXTS[draw(st.sampled_from(sorted(BASE_TEXTS)))]
        filler = draw(st.sampled_from(["# " + "x" * 78 + "\n", "\n", "   \n"]))
        return (text + filler * draw(st.integers(100, 3000))).encode()
    if how == "unicode":
        return draw(st.text(alphabet=st.characters(codec="utf-8", exclude_categories=["Cs"]),
                            max_size=200)).encode()
    text = BASE_TEXTS[draw(st.sampled_from(sorted(BASE_TEXTS)))].encode()
    i = draw(st.integers(0, len(text)))
    return text[:i] + b"\x00" + text[i:]


def variant(base: str, **changes: Any) -> str:
    """The YAML of design *base* with values changed: ``cam__radius=5`` sets ``cam.radius``,
    ``motion__0__rise__lift=1`` the first segment's lift."""
    data = copy.deepcopy(BASES[base])
    for key, value in changes.items():
        node = data
        steps = [int(k) if k.isdigit() else k for k in key.split("__")]
        for step in steps[:-1]:
            node = node.setdefault(step, {}) if isinstance(node, dict) else node[step]
        node[steps[-1]] = value
    return dump(data)
