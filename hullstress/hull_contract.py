"""What a hull library promises: the contract a registration declares and its rows are judged by.

Libraries promise different things.  Some return only extreme points as
vertices (CGAL's ``convex_hull_2`` "generates the counterclockwise sequence of
extreme points"), others keep points that lie on an edge or a face; some
return triangles, others polygons; on flat or collinear input some raise and
some return the lower-dimensional hull.  A registration says which with
``register_algorithm(..., contract=...)`` (or ``run --contract NAME=SPEC``),
and every row of that algorithm is judged against it
(:mod:`hullstress.contract_verdict`).

The default, :data:`LENIENT`, is what hullstress has always checked: any
boundary point may be a vertex, faces may be polygons, flat input may raise or
be answered.  :data:`STRICT` demands that every vertex be an extreme point.

This module is about promises; :mod:`hullstress.contract` is the output
*format* every algorithm must meet whatever it promises.

Examples
--------
>>> parse_contract("strict").label
'strict'
>>> parse_contract("strict,faces=triangles,flat=raise").label
'strict,faces=triangles,flat=raise'
>>> parse_contract("lenient") == LENIENT
True
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Any

from .errors import UsageError

__all__ = ["HullContract", "LENIENT", "STRICT", "PRESETS", "CHOICES", "parse_contract", "as_contract",
           "CONTRACT_CHECKS"]

#: Every value each field of a contract can take; the first is the lenient default.
CHOICES: dict[str, tuple[str, ...]] = {
    # boundary: a point on an edge or face may be a vertex; extreme: only extreme points are vertices.
    "vertices": ("boundary", "extreme"),
    # ccw / cw seen from outside (2D: the polygon's turning sense).
    "orientation": ("ccw", "cw"),
    # any: triangles or polygons; triangles: every 3D face has three vertices.
    "faces": ("any", "triangles"),
    # either: raising or answering are both kept; raise: flat input must raise; lower-dim: it must be answered.
    "flat": ("either", "raise", "lower-dim"),
}

#: The failed-check names a contract adds to a row (``failed_checks`` column, failure signatures).
CONTRACT_CHECKS = ("extreme_only", "face_shape", "flat_input")


@dataclass(frozen=True)
class HullContract:
    """A library's declared promises (each field one of :data:`CHOICES`).

    Attributes
    ----------
    vertices : {"boundary", "extreme"}
        ``extreme``: every vertex of the output is an extreme point of the
        input (a strict hull); ``boundary``: points on an edge or face may be
        vertices too.
    orientation : {"ccw", "cw"}
        Faces counter-clockwise (``ccw``) or clockwise (``cw``) seen from
        outside; ``cw`` outputs are reversed before checking.
    faces : {"any", "triangles"}
        ``triangles``: every 3D face has exactly three vertices.
    flat : {"either", "raise", "lower-dim"}
        On affinely degenerate input (collinear in 2D, coplanar in 3D):
        ``raise`` an exception, answer with the ``lower-dim`` hull, or ``either``.
    """

    vertices: str = "boundary"
    orientation: str = "ccw"
    faces: str = "any"
    flat: str = "either"

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if value not in CHOICES[f.name]:
                raise UsageError(f"contract {f.name} must be one of {', '.join(CHOICES[f.name])}, got {value!r}")

    @property
    def label(self) -> str:
        """Its nearest preset and what differs from it (``strict,faces=triangles``): :func:`parse_contract` reads it."""
        base_name = "strict" if self.vertices == "extreme" else "lenient"
        base = PRESETS[base_name]
        return ",".join([base_name] + [f"{f.name}={getattr(self, f.name)}" for f in fields(self)
                                       if getattr(self, f.name) != getattr(base, f.name)])

    def describe(self) -> str:
        """The contract in words, one line (for reports and bug reports)."""
        parts = ["only extreme points as vertices" if self.vertices == "extreme"
                 else "points on edges and faces may be vertices",
                 f"faces {'clockwise' if self.orientation == 'cw' else 'counter-clockwise'} seen from outside",
                 "triangle faces" if self.faces == "triangles" else "triangle or polygon faces",
                 {"either": "flat input may raise or be answered", "raise": "flat input raises",
                  "lower-dim": "flat input gets its lower-dimensional hull"}[self.flat]]
        return f"{self.label}: " + "; ".join(parts)


#: hullstress's long-standing judgement (the default of every registration).
LENIENT = HullContract()
#: A strict hull: only extreme points as vertices.
STRICT = HullContract(vertices="extreme")
#: Named contracts ``--contract`` and ``contract=`` accept.
PRESETS: dict[str, HullContract] = {"lenient": LENIENT, "strict": STRICT}


def parse_contract(text: str) -> HullContract:
    """A contract from its spelling: a preset, ``key=value`` items, or a preset followed by items.

    Raises
    ------
    UsageError
        Naming the item that is not a preset or a valid ``key=value``.
    """
    items = [t.strip() for t in str(text).split(",") if t.strip()]
    contract = LENIENT
    if items and "=" not in items[0]:
        preset = PRESETS.get(items[0])
        if preset is None:
            raise UsageError(f"contract {text!r}: {items[0]!r} is not one of {', '.join(PRESETS)} "
                             f"nor KEY=VALUE (keys: {', '.join(CHOICES)})")
        contract, items = preset, items[1:]
    changes: dict[str, str] = {}
    for item in items:
        key, sep, value = (s.strip() for s in item.partition("="))
        if not sep or key not in CHOICES:
            raise UsageError(f"contract {text!r}: {item!r} is not KEY=VALUE with KEY one of {', '.join(CHOICES)}")
        if value not in CHOICES[key]:
            raise UsageError(f"contract {text!r}: {key} must be one of {', '.join(CHOICES[key])}, got {value!r}")
        changes[key] = value
    return replace(contract, **changes)


def as_contract(value: Any) -> HullContract:
    """``value`` as a :class:`HullContract`: one already, a spelling for :func:`parse_contract`, or None (lenient)."""
    if value is None:
        return LENIENT
    if isinstance(value, HullContract):
        return value
    if isinstance(value, str):
        return parse_contract(value)
    raise UsageError(f"contract must be a HullContract or a string such as 'strict', got {value!r}")
