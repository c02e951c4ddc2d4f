"""Write the checker's negative corpus, ``tests/data/negative/<kind>.json``.

Each entry is one hull with exactly one defect (a point one ulp outside, a
face one ulp out of plane, a repeated face, ...) or its minimally right twin
(the same construction one ulp on the allowed side, or exactly on the
boundary).  Every expectation is the intent declared here *and* what the
exact integer verdict of ``tests/_exact_verdict.py`` computes (Fractions, no
checker code); an entry whose two disagree is a mistake in this file and
stops the build.  Coordinates are small integers, mapped by an integer
matrix (``oblique``: no face in a coordinate plane) and scaled by a power of
two (``tiny`` 2**-997 ~ 7e-301, ``huge`` 2**994 ~ 2e299), so every
coplanarity and collinearity is exact; the ulp steps come after, with
``np.nextafter``.

Run ``python tools/make_negative_corpus.py`` from the repository root; the
output is deterministic.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from _exact_verdict import exact_verdict  # noqa: E402

OUT = ROOT / "tests" / "data" / "negative"
OBLIQUE3 = np.array([[2, 1, 0], [-1, 2, 1], [1, -1, 2]])  # det 13
OBLIQUE2 = np.array([[2, 1], [-1, 2]])  # det 5
SCALES = {"unit": 1.0, "tiny": 2.0**-997, "huge": 2.0**994}
OFFSET = 5  # 1 mod 4 after the (multiple-of-4) coordinates: never 0, so an ulp is a relative step
COUNT_KEYS = (
    "n_outside", "n_degenerate_faces", "n_nonconvex_edges", "n_extreme", "n_missing_extreme",
    "n_boundary_nonextreme", "n_hull_vertices", "n_faces", "affine_rank",
)

POLYGONS = {  # convex, counter-clockwise, coordinates multiples of 4 (midpoints stay integer)
    4: [(0, 0), (16, 0), (16, 16), (0, 16)],
    5: [(0, 0), (16, 0), (24, 16), (8, 32), (-8, 16)],
    6: [(0, 0), (16, 0), (24, 16), (16, 32), (0, 32), (-8, 16)],
    8: [(8, 0), (24, 0), (32, 8), (32, 24), (24, 32), (8, 32), (0, 24), (0, 8)],
}

CORPUS: dict[str, list[dict]] = {}


# --------------------------------------------------------------------------- building blocks


def place(ints, orient: str, scale: str) -> np.ndarray:
    """Integer points -> floats: optional oblique map, offset, power-of-two scale (all exact)."""
    p = np.asarray(ints, dtype=np.int64)
    if orient == "oblique":
        p = p @ (OBLIQUE3 if p.shape[1] == 3 else OBLIQUE2).T
    out = (p + OFFSET).astype(np.float64) * SCALES[scale]
    assert np.all(np.abs(out) < 1e305) and np.all(out[out != 0] != 0)
    return out


def nudge(points: np.ndarray, i: int, axis: int, toward: float) -> np.ndarray:
    out = points.copy()
    out[i, axis] = np.nextafter(out[i, axis], toward)
    return out


def prism(k: int):
    """A prism over the k-gon: bottom z = 0 (face 0, seen from below), top z = 16 (face 1)."""
    base = POLYGONS[k]
    pts = [(x, y, 0) for x, y in base] + [(x, y, 16) for x, y in base]
    faces = [list(range(k))[::-1], list(range(k, 2 * k))]
    faces += [[i, (i + 1) % k, k + (i + 1) % k, k + i] for i in range(k)]
    return pts, faces


def pyramid(k: int):
    """A pyramid over the k-gon (face 0, seen from below) with its apex above the middle."""
    base = POLYGONS[k]
    cx = sum(x for x, _ in base) // k
    cy = sum(y for _, y in base) // k
    pts = [(x, y, 0) for x, y in base] + [(cx, cy, 24)]
    faces = [list(range(k))[::-1]] + [[i, (i + 1) % k, k] for i in range(k)]
    return pts, faces


def tetra():
    return [(0, 0, 0), (16, 0, 0), (0, 16, 0), (0, 0, 16)], [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]


def triangulated(faces):
    """Fan triangles of polygon faces."""
    return [[f[0], f[i], f[i + 1]] for f in faces for i in range(1, len(f) - 1)]


def add(kind: str, id: str, points, faces, failed, about: str, reason=(), *, severity=None,
        keys=COUNT_KEYS, xfail: str | None = None, qhull: bool = True) -> dict:
    """Record one entry after checking the declared intent against the exact verdict.

    ``qhull=False`` for flat inputs: Qhull's reference there is a joggled (QJ) hull,
    not modelled by the exact verdict, and the entry is checked without it.
    """
    pts = np.asarray(points, dtype=np.float64).tolist()
    faces = [int(i) for i in faces] if np.ndim(faces[0]) == 0 else [[int(i) for i in f] for f in faces]
    e = exact_verdict(pts, faces, qhull=qhull)
    keys = list(keys)
    if len(pts[0]) == 3 and not e.ok and e.qhull_ok is not True:
        # Neither hull certified: the checker documents the 3D extreme set as unknown
        # (n_extreme None) unless its Qhull repair happens to certify, which the exact
        # verdict does not model.
        keys = [k for k in keys if k not in ("n_extreme", "n_missing_extreme", "n_boundary_nonextreme")]
    if e.counts.get("n_degenerate_faces"):
        # Next to a bent or non-convex polygon the checker tests only the polygon's plane
        # triple for reflex edges; the count is defined for planar convex faces only.
        keys = [k for k in keys if k != "n_nonconvex_edges"]
    assert e.failed == list(failed), f"{id}: intent {list(failed)}, exact verdict {e.failed} ({e.notes})"
    if severity is not None:
        assert e.severity == severity, f"{id}: intent {severity}, exact verdict {e.severity} ({e.magnitudes})"
    close = [n for n in e.notes if "factor 2" in n]
    assert not close, f"{id}: too close to a threshold to be a stable expectation: {close}"
    assert e.severity != "unknown", f"{id}: the severity depends on the checker's interior point"
    expect = {
        "failed": e.failed,
        "severity": e.severity,
        "reason": list(reason) if e.failed else ["ok:"],
        "qhull_ok": e.qhull_ok,
        "counts": {k: e.counts[k] for k in keys if k in e.counts},
    }
    entry = {"id": id, "about": about, "dim": len(pts[0]), "points": pts, "faces": faces, "expect": expect}
    if not qhull:
        entry["qhull"] = False
    if e.convexity is None:
        # A face plane cuts the surface's vertices: docs/design.md's "one interior point below
        # every facet" holds for some interior points and not others, so convexity is
        # the checker's choice here and not part of the expectation.
        expect["undecided"] = ["convexity"]
    if xfail:
        entry["xfail"] = xfail
    ids = {x["id"] for entries in CORPUS.values() for x in entries}
    assert id not in ids, f"duplicate id {id}"
    CORPUS.setdefault(kind, []).append(entry)
    return entry


def variants():
    for orient in ("axis", "oblique"):
        for scale in SCALES:
            yield orient, scale, f"{orient}-{scale}"


def outward_ulp(points, i, probe_faces, want_failed, dims=(0, 1, 2)):
    """The one-ulp move of point i (axis, direction) whose exact verdict is ``want_failed``."""
    for axis in dims:
        for toward in (np.inf, -np.inf):
            moved = nudge(points, i, axis, toward)
            if exact_verdict(moved.tolist(), probe_faces, qhull=False).failed == want_failed:
                return moved
    raise AssertionError(f"no one-ulp move of point {i} gives {want_failed}")


# --------------------------------------------------------------------------- containment


def containment():
    """A point one ulp outside a face (triangle, quad, 5-, 6-, 8-gon), and its twins."""
    shapes = {"tri": tetra(), "quad": prism(4), "pent": prism(5), "hex": prism(6), "oct": prism(8)}
    for name, (ints, faces) in shapes.items():
        face = faces[-1] if name == "tri" else faces[1]
        v = [np.array(ints[i]) for i in face]
        inner = (v[0] + v[1] + 2 * v[2]) // 4 if len(face) == 3 else (v[0] + v[2]) // 2
        for orient, scale, tag in variants():
            if name in ("pent", "hex") and scale != "unit":
                continue  # the scales are covered by the triangle, quad and octagon
            base = place(list(ints) + [tuple(inner)], orient, scale)
            q = len(ints)
            add("containment", f"on-face-{name}-{tag}", base, faces, [],
                f"an input point exactly on a {len(face)}-gon face, not a vertex: allowed")
            out = outward_ulp(base, q, faces, ["containment"])
            add("containment", f"ulp-outside-{name}-{tag}", out, faces,
                exact_verdict(out.tolist(), faces).failed,
                f"an input point one ulp outside a {len(face)}-gon face: the hull misses it",
                ["points outside"], severity="roundoff")
            inside = outward_ulp(base, q, faces, [])
            inside_moves = [m for m in (nudge(base, q, a, t) for a in range(3) for t in (np.inf, -np.inf))
                            if not np.array_equal(m, base) and exact_verdict(m.tolist(), faces, qhull=False).failed == []
                            and not np.array_equal(m, inside)]
            if inside_moves:
                add("containment", f"ulp-inside-{name}-{tag}", inside_moves[0], faces, [],
                    f"an input point one ulp inside a {len(face)}-gon face: allowed")
    # An extreme point left out of the hull: gross.
    for orient, scale, tag in variants():
        ints, faces = prism(4)
        pts = place(list(ints) + [(8, 8, 40)], orient, scale)
        add("containment", f"apex-left-out-{tag}", pts, faces, ["containment", "qhull_agreement"],
            "a far extreme point left out: outside, missing, and Qhull's volume disagrees",
            ["points outside", "extreme points: 1 missing"], severity="gross")
    # 2D: a point one ulp outside an edge of each polygon, on it, and inside it.
    for k in (4, 5, 6, 8):
        for orient, scale, tag in variants():
            if k in (5, 6) and scale != "unit":
                continue
            ring = POLYGONS[k]
            mid = ((ring[0][0] + ring[1][0]) // 2, (ring[0][1] + ring[1][1]) // 2)
            base = place(ring + [mid], orient, scale)
            poly = list(range(k))
            add("containment", f"2d-on-edge-{k}gon-{tag}", base, poly, [],
                f"an input point exactly on an edge of a {k}-gon, not a vertex: allowed")
            out = outward_ulp(base, k, poly, ["containment"], dims=(0, 1))
            add("containment", f"2d-ulp-outside-{k}gon-{tag}", out, poly,
                exact_verdict(out.tolist(), poly).failed,
                f"an input point one ulp outside an edge of a {k}-gon", ["points outside"], severity="roundoff")
            inside = outward_ulp(base, k, poly, [], dims=(0, 1))
            if not np.array_equal(inside, base):
                add("containment", f"2d-ulp-inside-{k}gon-{tag}", inside, poly, [],
                    f"an input point one ulp inside an edge of a {k}-gon: allowed")


# --------------------------------------------------------------------------- convexity


def convexity():
    # Polygon faces one ulp out of plane, per face size: the raised vertex is not in the
    # face's plane triple, and in the axis-aligned prism it moves along its vertical
    # edge, so the side quads stay planar and only the k-gon is bent.
    for k in (4, 5, 6, 8):
        ints, faces = prism(k)
        for orient, scale, tag in variants():
            pts = place(ints, orient, scale)
            top = faces[1]
            corner = top[3]
            add("convexity", f"prism{k}-{tag}", pts, faces, [], f"a prism over a {k}-gon: polygon faces, valid")
            if orient == "axis":
                inward = nudge(pts, corner, 2, -np.inf)
                add("convexity", f"bent-{k}gon-inward-{tag}", inward, faces, ["convexity"],
                    f"one corner of the top {k}-gon one ulp down its vertical edge: that face is not planar",
                    ["degenerate faces"], severity="roundoff")
                outward = nudge(pts, corner, 2, np.inf)
                add("convexity", f"bent-{k}gon-outward-{tag}", outward, faces,
                    exact_verdict(outward.tolist(), faces).failed,
                    f"one corner of the top {k}-gon one ulp up: not planar, and the corner is above its plane",
                    ["degenerate faces", "points outside"], severity="roundoff")
            else:
                for axis in range(3):
                    moved = nudge(pts, corner, axis, -np.inf)
                    e = exact_verdict(moved.tolist(), faces)
                    if "convexity" in e.failed:
                        add("convexity", f"bent-{k}gon-{tag}", moved, faces, e.failed,
                            f"one corner of the top {k}-gon one ulp off along axis {axis}: polygon faces out of plane",
                            ["degenerate faces"], severity="roundoff")
                        break
        # The same k-gon as a triangulated top: triangles cannot bend, the edge turns reflex.
    # Polygon faces one ulp non-convex inside their plane: a pyramid whose base has a
    # vertex on the middle of an edge (allowed: boundary, not extreme), moved one ulp in
    # or out within the base plane.
    for k in (4, 5, 6, 8):
        for orient, scale, tag in variants():
            if k in (5, 6) and scale != "unit":
                continue
            ints, faces = pyramid(k)
            ring = POLYGONS[k]
            mid = ((ring[0][0] + ring[1][0]) // 2, (ring[0][1] + ring[1][1]) // 2, 0)
            pts_int = list(ints) + [mid]
            m = len(pts_int) - 1
            base_face = [m if False else i for i in faces[0]]
            # insert the midpoint between vertex 0 and 1 in the base (seen from below: 1 then 0)
            b = faces[0]
            j = b.index(0)
            base_face = b[:j] + [m] + b[j:]
            side = [[0, m, k], [m, 1, k]] + [f for f in faces[1:] if f[:2] != [0, 1]]
            fs = [base_face] + side
            pts = place(pts_int, orient, scale)
            add("convexity", f"base-{k + 1}gon-collinear-{tag}", pts, fs, [],
                f"a pyramid whose base ({k + 1}-gon) has a vertex exactly on an edge: allowed, counted",
                severity="none")
            axes = (1,) if orient == "axis" else (0, 1, 2)
            for axis in axes:
                moved_in = nudge(pts, m, axis, np.inf)
                e = exact_verdict(moved_in.tolist(), fs)
                if "convexity" in e.failed:
                    add("convexity", f"base-{k + 1}gon-ulp-reflex-{tag}", moved_in, fs, e.failed,
                        f"the base's edge vertex one ulp inward: a non-convex {k + 1}-gon face and a reflex edge",
                        ["degenerate faces", "reflex edges"], severity="roundoff")
                    break
            for axis in axes:
                moved_out = nudge(pts, m, axis, -np.inf)
                e = exact_verdict(moved_out.tolist(), fs)
                if not e.failed:
                    add("convexity", f"base-{k + 1}gon-ulp-extreme-{tag}", moved_out, fs, [],
                        f"the base's edge vertex one ulp outward: a convex {k + 1}-gon, the vertex now extreme")
                    break
    # A dent: the top of a cube as four triangles to its centre, which sits on the face
    # (allowed), one ulp below it (reflex edges), or one ulp above (a flat pyramid: valid).
    for orient, scale, tag in variants():
        ints, faces = prism(4)
        top = faces[1]
        c = len(ints)
        centre = tuple((np.array(ints[top[0]]) + np.array(ints[top[2]])) // 2)
        fs = [faces[0]] + faces[2:] + [[top[i], top[(i + 1) % 4], c] for i in range(4)]
        pts = place(list(ints) + [centre], orient, scale)
        add("convexity", f"dent-on-face-{tag}", pts, fs, [],
            "the top face split at its centre: a coplanar vertex, allowed and counted")
        down = outward_ulp(pts, c, fs, ["convexity", "containment"])
        add("convexity", f"dent-ulp-{tag}", down, fs, ["convexity", "containment"],
            "the top face's centre vertex one ulp inside: reflex edges, the far corners above the dented faces",
            ["reflex edges", "points outside"], severity="roundoff")
        up = outward_ulp(pts, c, fs, [])
        if not np.array_equal(up, pts):
            add("convexity", f"dent-ulp-up-{tag}", up, fs, [],
                "the top face's centre vertex one ulp outside: a flat pyramid, convex and valid")
    # A collinear (zero-area) triangle glued into a tetrahedron's edge.
    for orient, scale, tag in variants():
        ints, _ = tetra()
        m = 4
        pts = place(list(ints) + [(8, 0, 0)], orient, scale)  # on the edge 0-1
        split = [[0, 2, m], [m, 2, 1], [0, m, 3], [m, 1, 3], [0, 3, 2], [1, 2, 3]]
        add("convexity", f"edge-point-{tag}", pts, split, [],
            "both faces along a tetrahedron edge split at a point on it: a collinear vertex, allowed")
        flat = [[0, 2, 1], [0, m, 3], [m, 1, 3], [0, 3, 2], [1, 2, 3], [0, 1, m]]
        add("convexity", f"collinear-triangle-{tag}", pts, flat, ["convexity"],
            "one face along the edge split at the edge point, the gap closed by the flat triangle (0, 1, m)",
            ["degenerate faces"], severity="roundoff")
        for axis in range(3):
            for toward in (np.inf, -np.inf):
                moved = nudge(pts, m, axis, toward)
                if exact_verdict(moved.tolist(), flat, qhull=False).failed == []:
                    add("convexity", f"sliver-triangle-{tag}", moved, flat, [],
                        "the edge point one ulp off the edge, outward: the flat triangle becomes a real sliver face")
                    break
            else:
                continue
            break
    # A locally convex surface that wraps twice: a double cover of a bipyramid over a
    # 7-gon (the equator taken with step 2): closed, genus 0, every face has the interior
    # point below it, every edge convex; only the degree test (and the skipped equator
    # vertices) can tell.
    ring7 = [(16, 0), (28, 6), (32, 18), (24, 30), (8, 30), (0, 18), (4, 6)]
    for orient, scale, tag in variants():
        if scale == "tiny" and orient == "axis":
            continue
        ints = [(x, y, 16) for x, y in ring7] + [(16, 16, 40), (16, 16, -8)]
        top, bottom = 7, 8
        order = [(2 * i) % 7 for i in range(7)]
        fs = []
        for i in range(7):
            u, w = order[i], order[(i + 1) % 7]
            fs += [[u, w, top], [w, u, bottom]]
        pts = place(ints, orient, scale)
        add("convexity", f"double-cover-7-{tag}", pts, fs, ["convexity", "containment", "qhull_agreement"],
            "a bipyramid over a 7-gon taken with step 2: locally convex, closed, genus 0, wraps twice",
            ["wraps 2 times", "points outside"], severity="gross")
    # One face turned over.
    for orient, scale, tag in variants():
        ints, faces = prism(5)
        fs = [list(f) for f in faces]
        fs[3] = fs[3][::-1]
        pts = place(ints, orient, scale)
        add("convexity", f"flipped-quad-{tag}", pts, fs, exact_verdict(pts.tolist(), fs).failed,
            "one side quad of a pentagonal prism listed clockwise", ["not strictly below", "same direction"],
            severity="gross")


# --------------------------------------------------------------------------- manifoldness


def manifoldness():
    for orient, scale, tag in variants():
        if scale == "huge" and orient == "axis":
            pass
        for name, (ints, faces) in {"tri": tetra(), "quad": prism(4), "pent": prism(5)}.items():
            pts = place(ints, orient, scale)
            if scale != "unit" and name == "pent":
                continue
            dup = [list(f) for f in faces] + [list(faces[-1])]
            add("manifoldness", f"repeated-face-{name}-{tag}", pts, dup, exact_verdict(pts.tolist(), dup).failed,
                f"a {len(faces[-1])}-vertex face listed twice", ["repeated faces"], severity="gross")
            hole = [list(f) for f in faces][:-1]
            add("manifoldness", f"missing-face-{name}-{tag}", pts, hole, exact_verdict(pts.tolist(), hole).failed,
                f"a {len(faces[-1])}-vertex face left out: a hole", ["without an opposite half-edge"], severity="gross")
            inward = [list(f)[::-1] for f in faces]
            add("manifoldness", f"inward-{name}-{tag}", pts, inward, exact_verdict(pts.tolist(), inward).failed,
                "every face clockwise: a closed surface oriented inward", ["inward orientation"], severity="gross")
        # A face repeating a vertex.
        ints, faces = prism(4)
        pts = place(ints, orient, scale)
        rep = [list(f) for f in faces]
        rep[1] = rep[1][:2] + [rep[1][1]] + rep[1][2:]
        add("manifoldness", f"face-repeats-vertex-{tag}", pts, rep, exact_verdict(pts.tolist(), rep).failed,
            "a quad listed with one vertex twice (a 5-cycle)", ["repeat a vertex"], severity="gross")
        # A zero-volume closed surface: a quad covered twice with different diagonals, under
        # an apex left out (the input is full-dimensional, the surface flat).
        quad = [(0, 0, 0), (16, 0, 0), (16, 16, 0), (0, 16, 0), (8, 8, 16)]
        flat = [[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]]
        flat = [[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]]
        pts = place(quad, orient, scale)
        e = exact_verdict(pts.tolist(), flat)
        add("manifoldness", f"flat-double-cover-{tag}", pts, flat, e.failed,
            "a quad covered on both sides with different diagonals: closed, genus 0, zero volume",
            ["zero signed volume", "no interior point"], severity="gross")
    # Two tetrahedra sharing one vertex: every edge paired, yet the vertex's link is two cycles.
    for orient, scale, tag in variants():
        if scale != "unit":
            continue
        ints = [(0, 0, 0), (16, 0, 0), (0, 16, 0), (0, 0, 16), (-16, 0, 0), (0, -16, 0), (0, 0, -16)]
        fs = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 4, 5], [0, 6, 4], [0, 5, 6], [4, 6, 5]]
        pts = place(ints, orient, scale)
        add("manifoldness", f"pinched-vertex-{tag}", pts, fs, exact_verdict(pts.tolist(), fs).failed,
            "two tetrahedra sharing one vertex: its link is two cycles", ["link is not a single cycle", "connected pieces"],
            severity="gross")
    # Genus one: a square frame (a polyhedral torus).
    for orient, scale, tag in variants():
        if scale == "tiny":
            continue
        outer = [(0, 0), (48, 0), (48, 48), (0, 48)]
        inner = [(16, 16), (32, 16), (32, 32), (16, 32)]
        ints = [(x, y, z) for z in (0, 16) for x, y in outer + inner]
        ob, ib, ot, it = 0, 4, 8, 12
        fs = []
        for i in range(4):
            j = (i + 1) % 4
            fs.append([ob + i, ob + j, ot + j, ot + i])  # outer wall
            fs.append([ib + j, ib + i, it + i, it + j])  # inner wall, facing the hole
            fs.append([ot + i, ot + j, it + j, it + i])  # top ring
            fs.append([ob + j, ob + i, ib + i, ib + j])  # bottom ring
        pts = place(ints, orient, scale)
        add("manifoldness", f"torus-{tag}", pts, fs, exact_verdict(pts.tolist(), fs).failed,
            "a square frame: closed and oriented, genus one", ["Euler characteristic 0", "reflex edges"],
            severity="gross")


# --------------------------------------------------------------------------- 2D polygons


def polygon2d():
    for k in (4, 5, 6, 8):
        ring = POLYGONS[k]
        for orient, scale, tag in variants():
            if k in (5, 6) and scale != "unit":
                continue
            pts = place(ring, orient, scale)
            poly = list(range(k))
            add("polygon2d", f"{k}gon-{tag}", pts, poly, [], f"a convex {k}-gon, counter-clockwise")
            add("polygon2d", f"{k}gon-clockwise-{tag}", pts, poly[::-1],
                ["convexity", "containment", "manifoldness", "qhull_agreement"],
                f"a {k}-gon listed clockwise", ["clockwise"], severity="gross")
            rep = poly[:2] + [poly[1]] + poly[2:]
            add("polygon2d", f"{k}gon-repeated-index-{tag}", pts, rep, exact_verdict(pts.tolist(), rep).failed,
                f"a {k}-gon with one index listed twice in a row", ["repeated vertex indices"], severity="gross")
            # Two indices with the same coordinates, next to each other.
            twin = np.vstack([pts, pts[2:3]])
            dup = poly[:3] + [k] + poly[3:]
            add("polygon2d", f"{k}gon-same-coordinates-{tag}", twin, dup, exact_verdict(twin.tolist(), dup).failed,
                f"a {k}-gon whose vertex 2 is followed by index {k}, a copy of the same point",
                ["repeated coordinates", "zero-length edges"], severity="gross")
            missing = [i for i in poly if i != 2]
            add("polygon2d", f"{k}gon-missing-corner-{tag}", pts, missing, ["containment", "qhull_agreement"],
                f"a {k}-gon with one corner left out", ["points outside", "extreme points: 1 missing"], severity="gross")
            add("polygon2d", f"{k}gon-two-vertices-{tag}", pts, poly[:2], exact_verdict(pts.tolist(), poly[:2]).failed,
                "two vertices of a full-dimensional input", ["needs at least 3"], severity="gross")
            if k >= 5:
                bow = [poly[0], poly[2], poly[1], poly[3]] + poly[4:]
                add("polygon2d", f"{k}gon-crossing-{tag}", pts, bow, exact_verdict(pts.tolist(), bow).failed,
                    f"a {k}-gon with two vertices swapped: edges cross", ["touching or crossing"], severity="gross")
            # A vertex on the middle of an edge (allowed), one ulp inward (reflex), one ulp out.
            mid = ((ring[0][0] + ring[1][0]) // 2, (ring[0][1] + ring[1][1]) // 2)
            base = place(ring + [mid], orient, scale)
            with_mid = [0, k] + poly[1:]
            add("polygon2d", f"{k}gon-collinear-vertex-{tag}", base, with_mid, [],
                f"a {k}-gon with a vertex exactly on an edge: boundary, not extreme")
            reflex = outward_ulp(base, k, with_mid, ["convexity", "containment"], dims=(0, 1))
            add("polygon2d", f"{k}gon-ulp-reflex-{tag}", reflex, with_mid, ["convexity", "containment"],
                "that edge vertex one ulp inward: a reflex vertex, the next corner right of the dented edge",
                ["reflex vertices", "points outside"], severity="roundoff")
            out = outward_ulp(base, k, with_mid, [], dims=(0, 1))
            if not np.array_equal(out, base):
                add("polygon2d", f"{k}gon-ulp-extreme-{tag}", out, with_mid, [],
                    f"that edge vertex one ulp outward: a convex {k + 1}-gon")
    # Simple but not convex (an arrowhead: boxes of opposite edges touch, the edges do not),
    # and a polygon whose vertex lands exactly on a non-adjacent edge (touching, not simple).
    for orient, scale, tag in variants():
        if scale == "tiny" and orient == "axis":
            continue
        dart = place([(0, 0), (16, 8), (0, 16), (4, 8)], orient, scale)
        add("polygon2d", f"arrowhead-{tag}", dart, [0, 1, 2, 3], exact_verdict(dart.tolist(), [0, 1, 2, 3]).failed,
            "a simple arrowhead: one reflex vertex, no edges meeting", ["reflex vertices"], severity="gross")
        square = place([(0, 0), (16, 0), (16, 16), (0, 16), (8, 0)], orient, scale)
        touch = [0, 1, 2, 4, 3]
        add("polygon2d", f"vertex-on-edge-{tag}", square, touch, exact_verdict(square.tolist(), touch).failed,
            "a pentagon whose vertex (8, 0) lies on its own bottom edge: it touches itself",
            ["touching or crossing"], severity="gross")
        # An edge whose end lies on the extension of a non-adjacent edge, boxes overlapping:
        # they do not meet (simple, not convex).
        near = place([(0, 0), (8, 0), (8, -8), (16, -8), (10, 0), (6, 4), (0, 8)], orient, scale)
        add("polygon2d", f"end-on-extension-{tag}", near, list(range(7)), exact_verdict(near.tolist(), list(range(7))).failed,
            "edge (10, 0)-(6, 4) starts on the line of edge (0, 0)-(8, 0), beyond its end: no contact",
            ["reflex vertices"], severity="gross")
        mirror = place([(-x, y) for x, y in [(0, 0), (8, 0), (8, -8), (16, -8), (10, 0), (6, 4), (0, 8)]], orient, scale)
        ring = [1, 0, 6, 5, 4, 3, 2]  # mirrored, listed so the edge now *ends* on that line
        add("polygon2d", f"end-on-extension-mirrored-{tag}", mirror, ring, exact_verdict(mirror.tolist(), ring).failed,
            "the same, mirrored: an edge ends on the line of an earlier edge, beyond its end",
            ["reflex vertices"], severity="gross")
        # Two non-adjacent edges on one line but apart: they do not meet (a simple U).
        u = place([(0, 0), (4, 0), (4, 8), (12, 8), (12, 0), (16, 0), (16, 16), (0, 16)], orient, scale)
        add("polygon2d", f"u-shape-{tag}", u, list(range(8)), exact_verdict(u.tolist(), list(range(8))).failed,
            "a U: its two bottom edges are collinear and apart (simple, not convex)", ["reflex vertices"],
            severity="gross")
        rotated = touch[2:] + touch[:2]  # both edges at the touching vertex now come before the edge it touches
        add("polygon2d", f"vertex-on-edge-rotated-{tag}", square, rotated, exact_verdict(square.tolist(), rotated).failed,
            "the same pentagon listed from the touching vertex", ["touching or crossing"], severity="gross")
    # A star polygon: every turn left, the centre left of every edge, winding twice.
    ring7 = [(16, 0), (28, 6), (32, 18), (24, 30), (8, 30), (0, 18), (4, 6)]
    for orient, scale, tag in variants():
        pts = place(ring7, orient, scale)
        star = [(2 * i) % 7 for i in range(7)]
        add("polygon2d", f"star-7-2-{tag}", pts, star, ["convexity", "containment", "manifoldness", "qhull_agreement"],
            "a 7-gon taken with step 2: locally convex, winds twice", ["winds 2 times", "touching or crossing"],
            severity="gross")


# --------------------------------------------------------------------------- Qhull agreement


def qhull_agreement():
    # The volume tolerance (10 DISTround times Qhull's area, compared exactly: checker/qhull.py,
    # volume_tolerance): a cube's top centre dented by 2**-36 of the edge disagrees (about 44
    # tolerances), by 2**-44 agrees (about 0.17), though both are still reflex and leave the
    # far corners outside.  (2**-40, about 2.7 tolerances, agreed only under an earlier
    # tolerance with 2**-40 relative slack for float volume sums.)
    for orient, scale, tag in variants():
        ints, faces = prism(4)
        top = faces[1]
        c = len(ints)
        centre = np.array(ints[top[0]] + np.array(ints[top[2]])) // 2
        fs = [faces[0]] + faces[2:] + [[top[i], top[(i + 1) % 4], c] for i in range(4)]
        # 2**-40 and 2**-43 pin the tolerance to within a factor of about 3 each way (the
        # generator refuses a depth within a factor 2 of it: not a stable expectation).
        for depth, failed, what in ((2.0**-36, ["convexity", "containment", "qhull_agreement"], "outside"),
                                    (2.0**-40, ["convexity", "containment", "qhull_agreement"], "just-outside"),
                                    (2.0**-43, ["convexity", "containment"], "just-within"),
                                    (2.0**-44, ["convexity", "containment"], "within")):
            pts = place(list(ints) + [tuple(centre)], orient, scale)
            normal = place([(0, 0, 0), (0, 0, 16)], orient, scale)
            step = (normal[1] - normal[0]) * depth
            pts[c] = pts[c] - step
            e = exact_verdict(pts.tolist(), fs)
            add("qhull_agreement", f"dent-volume-{what}-tolerance-{tag}", pts, fs, failed,
                f"the cube's top centre dented by {depth:g} of the edge: Qhull's volume {what.replace('-', ' ')} the tolerance",
                ["reflex edges"] + (["volume differs"] if "qhull_agreement" in failed else []),
                severity="gross")
    # Vertices compared by coordinates: duplicates of the corners, the hull using the copies.
    for orient, scale, tag in variants():
        ints, faces = prism(4)
        pts = place(list(ints) + list(ints), orient, scale)
        copies = [[i + 8 for i in f] for f in faces]
        add("qhull_agreement", f"duplicate-corners-{tag}", pts, copies, [],
            "every point twice; the hull uses the second copies: the same vertices by coordinates")
    # A hull with an interior point in place of an extreme one (2D and 3D).
    for orient, scale, tag in variants():
        ring = POLYGONS[5]
        pts = place(ring + [(8, 16)], orient, scale)
        poly = [0, 1, 2, 5, 4]
        add("qhull_agreement", f"2d-interior-for-corner-{tag}", pts, poly,
            exact_verdict(pts.tolist(), poly).failed,
            "a pentagon with one corner replaced by an interior point", ["extreme vertices against"], severity="gross")
    # Extra vertices on the boundary: on an edge and on a face of a cube (allowed, counted,
    # not extreme).
    for orient, scale, tag in variants():
        ints, faces = prism(4)
        edge_mid = (8, 0, 0)  # on the edge between corners 0 and 1
        face_mid = (8, 8, 16)  # the top face's centre
        pts = place(list(ints) + [edge_mid, face_mid], orient, scale)
        e, f = 8, 9
        fs = [list(x) for x in faces]
        fs[0] = [3, 2, 1, e, 0]  # bottom (seen from below) with the edge point
        fs[2] = [0, e, 1, 5, 4]  # front side with the edge point
        top = fs[1]
        fs = fs[:1] + fs[2:] + [[top[i], top[(i + 1) % 4], f] for i in range(4)]
        add("qhull_agreement", f"boundary-points-{tag}", pts, fs, [],
            "a cube with a vertex on an edge (in two faces) and one on a face: both allowed, counted, not extreme")


def crashes():
    """Inputs on which the checker itself dies: run in a subprocess by the test."""
    ints = [[-2, -1, 3], [-2, 3, -1], [-2, -4, 3], [4, -3, 1], [1, -2, 3], [4, 0, 0], [-3, 3, 1],
            [-2, 3, -4], [4, -4, 4], [1, -4, 1]]
    from scipy.spatial import ConvexHull

    small = np.array(ints, dtype=np.float64)
    pts = small * 2.0**990
    ints_exact = [tuple(int(x) for x in p) for p in ints]
    centre = tuple(sum(p[i] for p in ints_exact) for i in range(3))
    faces = []
    for a, b, c in ConvexHull(small).simplices.tolist():
        pa, pb, pc = (np.array(ints_exact[i]) for i in (a, b, c))
        up = np.dot(np.cross(pb - pa, pc - pa), np.array(centre) - len(ints) * pa) > 0
        faces.append([a, c, b] if up else [a, b, c])
    pts[5, 1] = np.nextafter(0.0, -np.inf)  # (4, 0, 0) * 2**990 with y one ulp below 0: -5e-324
    e = exact_verdict(pts.tolist(), faces)
    entry = add("qhull_agreement", "huge-with-subnormal-coordinate", pts, faces, e.failed,
                "Qhull's hull of ten points at ~1e298, one zero coordinate moved one ulp to -5e-324: "
                "the input cannot be rescaled exactly, so Qhull runs on a rounded rescaled copy")
    # Qhull on the raw ~1e298 coordinates died with SIGSEGV (the checker once did that):
    # the test runs the checker in a subprocess, so a regression is a failure, not a dead run.
    entry["isolate"] = True


# --------------------------------------------------------------------------- affine rank


def affine_rank():
    """Flat inputs (docs/lower-dimensional.md), in oblique planes and along oblique lines.

    The right answers (a flat polygon on one side or both, a triangulation or a closed
    pillow, a segment walked out and back, a face and its reverse) pass; each wrong one
    has one defect: a corner or an endpoint missing, faces overlapping or leaving a
    hole, a face of zero area, a point twice, points out of order along the segment.
    The full-rank twin is one ulp off the plane.
    """
    # A square in the plane z = 0 (mapped obliquely), its centre, an edge midpoint, and an
    # inner triangle (a ring of faces around it leaves a hole).
    plane = [(0, 0, 0), (16, 0, 0), (16, 16, 0), (0, 16, 0), (8, 8, 0), (8, 0, 0),
             (4, 4, 0), (12, 4, 0), (8, 12, 0)]
    answers = {
        # id: (faces, failed checks, severity, reason words, about)
        "pillow": ([[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]], [], None, [],
                   "a closed pillow: both sides of the square, each triangulated (a flat 'tetrahedron')"),
        "polygon": ([[0, 1, 2, 3]], [], None, [], "the square as one face"),
        "polygon-both-sides": ([[0, 1, 2, 3], [3, 2, 1, 0]], [], None, [], "the square and its reverse"),
        "fan-from-centre": ([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]], [], None, [],
                            "four triangles to the centre: an inner vertex is a boundary point, allowed"),
        "edge-vertex": ([[0, 5, 1, 2, 3]], [], None, [], "the square with its edge midpoint as a vertex: allowed"),
        "corner-missing": ([[0, 1, 2]], ["containment"], "gross", ["extreme point 3 missing"],
                           "one triangle: the corner 3 is missing"),
        "faces-overlap": ([[0, 1, 2], [0, 2, 3], [0, 1, 3]], ["manifoldness"], "gross", ["overlap"],
                          "a triangulation and one more triangle over it, on the same side"),
        "hole": ([[0, 1, 7], [0, 7, 6], [1, 2, 8], [1, 8, 7], [2, 3, 8], [3, 6, 8], [3, 0, 6]],
                 ["manifoldness"], "gross", ["do not tile"],
                 "triangles around an inner triangle that none covers: a hole"),
        "zero-area-face": ([[0, 1, 2, 3], [0, 5, 1]], ["convexity"], "roundoff", ["no area"],
                           "the square and a face along its edge through the midpoint: zero area"),
        "notch": ([[0, 1, 2], [0, 2, 8], [0, 8, 3]], ["manifoldness"], "gross", ["do not tile", "not on the hull edge"],
                  "convex faces whose boundary cuts in to the inner point 8 between corners 2 and 3: a hole"),
        "reflex-face": ([[0, 1, 2, 7], [0, 7, 2, 3]], ["convexity"], "roundoff", ["is not a convex polygon"],
                        "an exact cover of the square by two faces, one with a reflex corner at the inner "
                        "point 7: only the face test can reject it"),
    }
    for scale in SCALES:
        pts = place(plane, "oblique", scale)
        for name, (fs, failed, severity, reason, about) in answers.items():
            add("affine_rank", f"coplanar-{name}-oblique-{scale}", pts, fs, failed,
                f"nine coplanar points in an oblique plane (rank 2); {about}", reason or ["coplanar input"],
                severity=severity, qhull=False)
        for axis in range(3):
            for toward in (np.inf, -np.inf):
                off = nudge(place(plane[:4], "oblique", scale), 2, axis, toward)
                flat = answers["pillow"][0]
                e = exact_verdict(off.tolist(), flat)
                if not e.failed:
                    add("affine_rank", f"coplanar-oblique-ulp-off-{scale}", off, flat, [],
                        "the pillow's corner one ulp off the oblique plane: rank 3, a valid thin tetrahedron")
                    break
            else:
                continue
            break
    # A line that stays oblique under the 2D map ((16, 4) -> (36, -8)); point 4 repeats point 0.
    line2 = [(0, 0), (16, 4), (32, 8), (8, 2), (0, 0)]
    walks2 = {
        "ends": ([0, 2], [], None, "the two endpoints"),
        "ends-reversed": ([2, 0], [], None, "the two endpoints, the other way"),
        "out-and-back": ([0, 3, 1, 2], [], None, "out along the line through the inner points, back directly"),
        "endpoint-missing": ([0, 1], ["containment"], "gross", "an endpoint missing"),
        "misordered": ([0, 1, 3, 2], ["convexity"], "roundoff", "inner points out of order along the line"),
        "point-twice": ([0, 2, 4], ["manifoldness"], "gross", "point 0 and its copy, point 4"),
    }
    reasons = {"containment": "extreme point 2 missing", "convexity": "do not run in order",
               "manifoldness": "more than once"}
    for scale in SCALES:
        pts = place(line2, "oblique", scale)
        for name, (poly, failed, severity, about) in walks2.items():
            add("affine_rank", f"2d-collinear-{name}-oblique-{scale}", pts, poly, failed,
                f"five points on an oblique line (rank 1): {about}",
                [reasons[c] for c in failed] or ["collinear input"], severity=severity, qhull=False)
    line3 = [(0, 0, 0), (16, 8, 4), (32, 16, 8), (8, 4, 2)]
    walks3 = {
        "segment-face": ([[0, 2]], [], None, "one face of the two endpoints"),
        "face-and-reverse": ([[0, 1, 2], [0, 2, 1]], [], None, "a walk out and back and its reverse (two-sided)"),
        "endpoint-missing": ([[0, 1]], ["containment"], "gross", "an endpoint missing"),
        "two-faces": ([[0, 2], [0, 1, 2]], ["manifoldness"], "gross", "two faces that are not one face and its reverse"),
        "misordered": ([[0, 1, 3, 2]], ["convexity"], "roundoff", "inner points out of order"),
    }
    reasons3 = dict(reasons, manifoldness="2 faces")
    for scale in SCALES:
        pts = place(line3, "oblique", scale)
        for name, (fs, failed, severity, about) in walks3.items():
            add("affine_rank", f"3d-collinear-{name}-oblique-{scale}", pts, fs, failed,
                f"four points on an oblique line in 3D (rank 1): {about}",
                [reasons3[c] for c in failed] or ["collinear input"], severity=severity, qhull=False)


def main() -> None:
    for build in (containment, convexity, manifoldness, polygon2d, qhull_agreement, crashes, affine_rank):
        build()
    OUT.mkdir(parents=True, exist_ok=True)
    for kind, entries in CORPUS.items():
        path = OUT / f"{kind}.json"
        # One entry per line: floats as repr (exact round trip), diffs stay readable.
        path.write_text("[\n" + ",\n".join(json.dumps(e) for e in entries) + "\n]\n")
        print(f"{path.relative_to(ROOT)}: {len(entries)} entries")


if __name__ == "__main__":
    main()
