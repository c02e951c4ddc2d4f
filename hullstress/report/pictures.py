"""Pictures of failures: the point set, the algorithm's output, what the checker blamed.

Matplotlib is driven through its object API on an Agg canvas (no pyplot, no
global backend switch), so drawing is thread-safe and works without a display.
Coordinates are shown relative to the points' centre and scaled to about 1
(the axis labels say so): inputs like 1e300 or 1e-300 then draw without
overflow or empty axes.

Offending indices come from the verdict's ``offending`` mapping: keys that
name faces (containing ``face``) hold face indices, keys that name edges
(``edge``) hold positions in the 2D output polygon (edge ``k`` runs from its
``k``-th vertex to the next), every other key holds point indices.
"""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

__all__ = ["failure_picture", "split_offending", "PNG_SIGNATURE"]

#: The first eight bytes of every PNG file.
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

_OK = "#4C72B0"
_BAD = "#D62728"
_GREY = "#8C8C8C"


def preload_matplotlib() -> None:
    """Import what drawing needs (matplotlib's Agg canvas and 3D axes); a no-op without matplotlib.

    The pipeline runs this in a background thread during the sweep: the
    import takes a second or more, which an interrupted run cannot spend in
    its report.
    """
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: F401
        from matplotlib.figure import Figure  # noqa: F401
        from mpl_toolkits.mplot3d import Axes3D  # noqa: F401
    except ImportError:
        pass


def split_offending(offending: Mapping[str, Sequence[int]] | None) -> tuple[set[int], set[int], set[int]]:
    """Offending point indices, face indices and polygon edge positions from a verdict's ``offending``.

    Examples
    --------
    >>> split_offending({"containment": [3, 5], "degenerate_faces": [0], "flipped_edges": [2]})
    ({3, 5}, {0}, {2})
    """
    points: set[int] = set()
    faces: set[int] = set()
    edges: set[int] = set()
    for key, values in (offending or {}).items():
        target = faces if "face" in key else edges if "edge" in key else points
        target.update(int(v) for v in np.asarray(values, dtype=np.int64).ravel())
    return points, faces, edges


def _normalised(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Finite rows centred and scaled to about unit size; the row mask; the scale."""
    finite = np.isfinite(points).all(axis=1) if points.ndim == 2 else np.zeros(0, bool)
    pts = points[finite].astype(np.float64)
    if len(pts) == 0:
        return np.zeros((0, points.shape[1] if points.ndim == 2 else 2)), finite, 1.0
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    # Halves throughout: near the float maximum, hi - lo and pts - centre overflow.
    centre = lo / 2 + hi / 2
    half = float(np.max(hi / 2 - lo / 2))
    if not (np.isfinite(half) and half > 0):
        return pts - centre, finite, 1.0
    with np.errstate(under="ignore"):
        return (pts / 2 - centre / 2) / half, finite, 2 * half


def _limits(values: np.ndarray) -> tuple[float, float]:
    if values.size == 0:
        return -1.0, 1.0
    lo, hi = float(values.min()), float(values.max())
    pad = max((hi - lo) * 0.08, 0.05)
    return lo - pad, hi + pad


def failure_picture(
    points: np.ndarray,
    faces: Any,
    *,
    dim: int,
    offending: Mapping[str, Sequence[int]] | None = None,
    title: str = "",
    label_points: bool | None = None,
    dpi: int = 80,
) -> bytes:
    """Draw a failure as PNG bytes.

    Parameters
    ----------
    points : ndarray of shape (n, dim), float64
    faces : sequence
        2D: vertex indices of the output polygon; 3D: a list of polygons
        (index sequences).  ``None`` or empty when the call produced no hull.
    dim : {2, 3}
    offending : mapping of str to sequence of int, optional
        The verdict's offending indices (see :func:`split_offending`).
    title : str
    label_points : bool, optional
        Write point indices next to the points (default: when n <= 16; text is
        the slowest thing to draw).
    dpi : int

    Returns
    -------
    bytes
        A PNG image.

    Examples
    --------
    A degenerate input (three collinear points) and a "hull" that misses one:

    >>> png = failure_picture(np.array([[0., 0.], [1., 0.], [2., 0.]]), [0, 1], dim=2,
    ...                       offending={"containment": [2]})
    >>> png[:8] == PNG_SIGNATURE
    True
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2:
        pts = pts.reshape(-1, dim) if pts.size % max(dim, 1) == 0 else np.zeros((0, dim))
    bad_points, bad_faces, bad_edges = split_offending(offending)
    norm, finite, scale = _normalised(pts)
    # Map original row indices to rows of ``norm`` (non-finite rows are not drawn).
    rows = np.full(len(pts), -1, dtype=np.int64)
    rows[np.flatnonzero(finite)] = np.arange(int(finite.sum()))
    if label_points is None:
        label_points = len(norm) <= 16

    fig = Figure(figsize=(6.4, 5.6), dpi=dpi)
    FigureCanvasAgg(fig)
    if dim == 3 and norm.shape[1] >= 3:
        ax = fig.add_subplot(projection="3d")
        _draw_3d(ax, norm, rows, faces, bad_points, bad_faces, label_points)
    else:
        ax = fig.add_subplot()
        _draw_2d(ax, norm[:, :2], rows, faces, bad_points, bad_edges, label_points)
    note = f"centred, scaled by 1/{scale:.3g}" if np.isfinite(scale) else "centred, scaled by 2**-1024"
    if not finite.all():
        note += f"; {int((~finite).sum())} non-finite rows not drawn"
    ax.set_title(f"{title}\n({note})" if title else f"({note})", fontsize=9)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return buf.getvalue()


def _mapped(indices: Sequence[int], rows: np.ndarray) -> np.ndarray:
    idx = np.asarray(indices, dtype=np.int64).ravel()
    idx = idx[(idx >= 0) & (idx < len(rows))]
    mapped = rows[idx]
    return mapped[mapped >= 0]


def _draw_2d(ax: Any, pts: np.ndarray, rows: np.ndarray, faces: Any, bad: set[int], bad_edges: set[int],
             label: bool) -> None:
    bad_rows = _mapped(sorted(bad), rows)
    if faces is not None and len(faces):
        polygon = np.asarray(faces, dtype=np.int64).ravel()
        ring = _mapped(list(polygon), rows)
        if len(ring):
            closed = np.append(ring, ring[0])
            ax.plot(pts[closed, 0], pts[closed, 1], "-", color=_OK, lw=1.5, label="output polygon", zorder=2)
            drawn = False
            for k in sorted(bad_edges):
                if 0 <= k < len(polygon):
                    ends = _mapped([polygon[k], polygon[(k + 1) % len(polygon)]], rows)
                    if len(ends) == 2:
                        ax.plot(pts[ends, 0], pts[ends, 1], "-", color=_BAD, lw=3, zorder=3,
                                label=None if drawn else "offending edges")
                        drawn = True
            ax.plot(pts[ring, 0], pts[ring, 1], "o", color=_OK, ms=6, zorder=3)
            ax.annotate("", xy=pts[ring[1 % len(ring)]], xytext=pts[ring[0]],
                        arrowprops={"arrowstyle": "->", "color": _OK, "lw": 2})
    ax.plot(pts[:, 0], pts[:, 1], ".", color=_GREY, ms=5, label="input points", zorder=1)
    if len(bad_rows):
        ax.plot(pts[bad_rows, 0], pts[bad_rows, 1], "x", color=_BAD, ms=10, mew=2,
                label="offending points", zorder=4)
    if label:
        _labels(ax, pts, rows)
    # One span for both axes: equal aspect in a square box, whatever the shape of the data.
    (x0, x1), (y0, y1) = _limits(pts[:, 0]), _limits(pts[:, 1])
    half = max(x1 - x0, y1 - y0) / 2
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    ax.set_xlim(cx - half, cx + half)
    ax.set_ylim(cy - half, cy + half)
    ax.set_aspect("equal", adjustable="box")
    ax.locator_params(nbins=5)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.07), ncol=4, fontsize=7, frameon=False)


def _draw_3d(ax: Any, pts: np.ndarray, rows: np.ndarray, faces: Any, bad_points: set[int],
             bad_faces: set[int], label: bool) -> None:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    polys, colours = [], []
    for k, face in enumerate(faces or []):
        ring = _mapped(list(face), rows)
        if len(ring) >= 3:
            polys.append(pts[ring, :3])
            colours.append(_BAD if k in bad_faces else _OK)
    if polys:
        ax.add_collection3d(Poly3DCollection(polys, facecolors=colours, edgecolors="k",
                                             linewidths=0.5, alpha=0.35))
    ax.scatter(pts[:, 0], pts[:, 1], pts[:, 2], color=_GREY, s=8, depthshade=False)
    bad_rows = _mapped(sorted(bad_points), rows)
    if len(bad_rows):
        ax.scatter(pts[bad_rows, 0], pts[bad_rows, 1], pts[bad_rows, 2], color=_BAD, marker="x",
                   s=60, depthshade=False)
    if label:
        for i, r in enumerate(rows):
            if r >= 0:
                ax.text(*pts[r, :3], f" {i}", fontsize=7, color="k")
    ax.set_xlim(*_limits(pts[:, 0]))
    ax.set_ylim(*_limits(pts[:, 1]))
    ax.set_zlim(*_limits(pts[:, 2]))
    ax.locator_params(nbins=4)
    n_bad = len(bad_faces)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.text2D(0.0, 0.0, f"{len(polys)} faces ({n_bad} offending, red); offending points: x",
              transform=ax.transAxes, fontsize=7)


def _labels(ax: Any, pts: np.ndarray, rows: np.ndarray) -> None:
    for i, r in enumerate(rows):
        if r >= 0:
            ax.annotate(str(i), pts[r], textcoords="offset points", xytext=(3, 3), fontsize=7)
