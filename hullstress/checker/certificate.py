"""The certificate: the exact findings on one surface, from which a verdict is assembled.

Filled by :func:`.certify.certify` (the general checks) or
:func:`.closed_mesh.certify_closed_mesh` (the batched path for closed convex
triangle meshes), never by anything else.

Soundness of :func:`corners3`: collinearity is exact (:func:`.predicates.collinear3d`)
and "v between its two neighbours" is read from signs of comparisons per axis,
never from a product of differences, which underflows to -0.0 for spacings
below about 1.5e-162 and overflows near the top of the range (issue 33, F4).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .measure import Measure
from .predicates import collinear3d

__all__ = ["Certificate", "corners3"]


@dataclass
class Certificate:
    """The exact findings on one surface.

    Attributes
    ----------
    dim : int
    containment, convexity, manifoldness : bool
    n_faces : int
        Faces (3D) or edges (2D).
    hull_vertices : ndarray of int64
        Distinct vertex indices used by the surface.
    extreme : ndarray of int64 or None
        The surface's corners (strictly convex vertices) when it is certified
        (all three checks pass), which are then exactly the extreme points of
        the input; None otherwise.
    boundary_nonextreme : ndarray of int64 or None
        Certified surfaces only: vertices on an edge or face but not corners.
    outside : ndarray of int64
    n_nonconvex_edges, n_degenerate_faces : int
    offending : dict of str to ndarray
        Full (untruncated) offending indices per kind.
    magnitudes : dict of str to float
        Largest violation distance per kind, in scaled units.
    measure : Measure or None
        Signed volume (area in 2D) in scaled units: order-independent estimate,
        exact value on demand (:mod:`.measure`).
    reasons : dict of str to list of str
        Per check, what failed.
    wraps : int or None
        How many times the surface wraps around its interior point, when that
        was tested (a closed, locally convex surface).
    witness : ndarray of int64 or None
        ``dim + 1`` affinely independent vertices of the surface, when the
        check met them on the way (a certified surface always has some).
    """

    dim: int
    containment: bool
    convexity: bool
    manifoldness: bool
    n_faces: int
    hull_vertices: np.ndarray
    extreme: np.ndarray | None
    boundary_nonextreme: np.ndarray | None
    outside: np.ndarray
    n_nonconvex_edges: int
    n_degenerate_faces: int
    offending: dict[str, np.ndarray] = field(default_factory=dict)
    magnitudes: dict[str, float] = field(default_factory=dict)
    measure: Measure | None = None
    reasons: dict[str, list[str]] = field(default_factory=dict)
    wraps: int | None = None
    witness: np.ndarray | None = None

    @property
    def certified(self) -> bool:
        return self.containment and self.convexity and self.manifoldness

    @property
    def volume(self) -> float:
        """Volume (area in 2D) in scaled units, a function of the face set only."""
        return self.measure.value() if self.measure is not None else 0.0

    @property
    def structural(self) -> bool:
        """A failure no rounding explains: not a closed manifold, or wrapping more than once."""
        return not self.manifoldness or (self.wraps is not None and self.wraps != 1)


def corners3(points: np.ndarray, vertices: np.ndarray, sharp: np.ndarray) -> np.ndarray:
    """Corners of a certified convex surface, from its sharp (non-flat) edges.

    On the boundary of a convex polytope a vertex with no sharp edge lies
    inside a flat region, one with exactly two collinear sharp edges on either
    side lies inside an edge of the polytope, and a corner has at least three.
    """
    n = len(points)
    count = np.bincount(sharp.ravel(), minlength=n) if sharp.size else np.zeros(n, np.int64)
    is_corner = count[vertices] >= 3
    two = vertices[count[vertices] == 2]
    if two.size:
        # The two sharp neighbours of each such vertex.
        ends = np.concatenate([sharp, sharp[:, ::-1]])
        ends = ends[np.isin(ends[:, 0], two)]
        ends = ends[np.lexsort((ends[:, 1], ends[:, 0]))]
        v = ends[0::2, 0]
        x, y = ends[0::2, 1], ends[1::2, 1]
        px, pv, py = points[x], points[v], points[y]
        # Opposite sides of v on some axis.  Signs of comparisons, never a product of
        # differences: that product underflows to -0.0 below spacings of about 1e-162
        # (issue 33, F4) and overflows near the top of the float range.
        side_x = (px > pv).astype(np.int8) - (px < pv).astype(np.int8)
        side_y = (py > pv).astype(np.int8) - (py < pv).astype(np.int8)
        between = collinear3d(px, pv, py) & np.any(side_x * side_y < 0, axis=1)
        corner_two = v[~between]
        is_corner |= np.isin(vertices, corner_two)
    is_corner |= count[vertices] == 1  # impossible on a convex surface; kept as a corner, not dropped
    return vertices[is_corner]
