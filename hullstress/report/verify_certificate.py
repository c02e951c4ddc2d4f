"""Check a hullstress failure certificate, standard library only: ``python verify.py`` inside the folder.

Reads ``certificate.json`` and the files it names (the points, the output as
faces), recomputes every witness in exact rational arithmetic and exits 0
only if every witness holds, 1 if one does not (or a failure has none), 2 if
the files cannot be read.  Faces are counter-clockwise seen from outside (2D:
one counter-clockwise polygon).  Needs nothing but Python 3.8+.
"""
import ast
import json
import struct
import sys
from collections import Counter
from fractions import Fraction as F
from pathlib import Path


def q(text):  # "0x1.8p+1" (a double) or "3/4" (a ratio) -> exact Fraction
    return F(float.fromhex(text)) if "x" in text else F(text)


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def orient(P, ids):  # 2D: sign of (b-a)x(c-a); 3D: of det(b-a, c-a, d-a)
    a = P[ids[0]]
    if len(a) == 2:
        u, v = sub(P[ids[1]], a), sub(P[ids[2]], a)
        d = u[0] * v[1] - u[1] * v[0]
    else:
        d = dot(cross(sub(P[ids[1]], a), sub(P[ids[2]], a)), sub(P[ids[3]], a))
    return (d > 0) - (d < 0)


def read_points(folder, name):
    path = folder / name
    if name.endswith(".json"):
        return [[q(x) for x in row] for row in json.loads(path.read_text())["points"]]
    if name.endswith(".csv"):
        rows = [ln.split(",") for ln in path.read_text().splitlines() if ln.strip() and not ln.startswith("#")]
        return [[F(float(x)) for x in r] for r in rows if not r[0].strip().isalpha()]  # skip a header line
    raw = path.read_bytes()  # .npy, little-endian float64, C order
    hlen = struct.unpack("<H", raw[8:10])[0]
    header = raw[10:10 + hlen].decode("latin1")
    shape = ast.literal_eval(header)["shape"]
    vals = struct.unpack("<%dd" % (len(raw[10 + hlen:]) // 8), raw[10 + hlen:])
    cols = shape[1] if len(shape) == 2 else 1
    return [[F(v) for v in vals[i:i + cols]] for i in range(0, len(vals), cols)]


def cyc(face, a, b):  # b follows a in the cyclic face
    return any(face[i] == a and face[(i + 1) % len(face)] == b for i in range(len(face)))


def closed(faces):  # every directed edge once, and its reverse once
    count = Counter((f[i], f[(i + 1) % len(f)]) for f in faces for i in range(len(f)))
    return all(n == 1 and count.get((b, a)) == 1 for (a, b), n in count.items())


def check(w, P, faces, dim):
    k = w["kind"]
    if k == "outside":
        f = faces[w["face"]]
        t = w["triangle"]
        if dim == 2:
            ok_face = cyc(f, t[0], t[1])
        else:
            ok_face = t[0] == f[0] and any(f[i] == t[1] and f[i + 1] == t[2] for i in range(1, len(f) - 1))
        s = orient(P, t + [w["point"]])
        want = -1 if dim == 2 else 1
        return ok_face and s == w["orient"] == want, "point %d outside face %d" % (w["point"], w["face"])
    if k == "reflex":
        f, g = faces[w["faces"][0]], faces[w["faces"][1]]
        u, v, x = w["triangle"]
        s = orient(P, [u, v, x, w["apex"]])
        ok = cyc(f, u, v) and cyc(f, v, x) and cyc(g, v, u) and w["apex"] in g and s == w["orient"] == 1
        return ok, "edge %d-%d reflex between faces %s" % (u, v, w["faces"])
    if k == "reflex-vertex":
        a, b, c = w["vertices"]
        f = faces[0]
        s = orient(P, [a, b, c])
        return cyc(f, a, b) and cyc(f, b, c) and s == w["orient"] == -1, "reflex turn at vertex %d" % b
    if k == "edge-count":
        u, v = w["edge"]
        n = sum(1 for f in faces if cyc(f, u, v) or cyc(f, v, u))
        return n == w["count"] != 2, "edge %d-%d in %d faces" % (u, v, n)
    if k == "edge-direction":
        u, v = w["edge"]
        both = [i for i, f in enumerate(faces) if cyc(f, u, v)]
        return len(both) >= 2 and sorted(w["faces"]) == both[:2], "edge %d->%d in faces %s" % (u, v, both)
    if k == "repeated-vertex":
        f = faces[w["face"]] if dim == 3 else faces[0]
        return f.count(w["vertex"]) >= 2, "vertex %d repeated in a face" % w["vertex"]
    if k in ("signed-area", "signed-volume"):
        ring = faces if dim == 3 else [faces[0]]
        o = P[min(v for f in ring for v in f)]
        total = F(0)
        for f in ring:
            for i in range(1, len(f) - 1) if dim == 3 else range(len(f)):
                if dim == 3:
                    total += dot(cross(sub(P[f[0]], o), sub(P[f[i]], o)), sub(P[f[i + 1]], o)) / 6
                else:
                    b, c = sub(P[f[i]], o), sub(P[f[(i + 1) % len(f)]], o)
                    total += (b[0] * c[1] - b[1] * c[0]) / 2
        full = "spanning" in w and orient(P, w["spanning"]) != 0  # a zero measure is wrong only for full-dim input
        ok = total == q(w["value"]) and (total < 0 or total == 0 and full) and (dim == 2 or closed(faces))
        return ok, "signed %s %s" % ("volume" if dim == 3 else "area", total)
    if k == "non-planar":
        ids = w["vertices"]
        f = faces[w["face"]]
        return all(i in f for i in ids) and orient(P, ids) == w["orient"] != 0, "face %d not planar" % w["face"]
    if k == "non-convex":
        f = faces[w["face"]]
        (a, b, c), (d, e, g) = w["turns"]
        t1 = cross(sub(P[b], P[a]), sub(P[c], P[b]))
        t2 = cross(sub(P[e], P[d]), sub(P[g], P[e]))
        ok = all(cyc(f, x, y) for x, y in ((a, b), (b, c), (d, e), (e, g))) and dot(t1, t2) < 0
        return ok, "face %d turns both ways" % w["face"]
    if k == "missing-extreme":
        p, c = w["point"], [q(x) for x in w["direction"]]
        used = {tuple(P[v]) for f in faces for v in f}
        top = dot(c, P[p])
        ok = tuple(P[p]) not in used and all(dot(c, r) < top for r in P if r != P[p])
        return ok, "extreme point %d missing from the output" % p
    if k == "backtrack":  # a collinear walk turning back at a vertex that is not an end of the segment
        a, b, c = w["vertices"]
        ok = cyc(faces[0], a, b) and cyc(faces[0], b, c) and orient(P, [a, b, c]) == 0
        ok = ok and dot(sub(P[b], P[a]), sub(P[c], P[b])) < 0
        return ok and check(dict(w, kind="not-extreme", vertex=b), P, faces, dim)[0], "walk turns back at %d" % b
    if k == "not-extreme":
        v, combo = w["vertex"], [(i, q(lam)) for i, lam in w["combination"]]
        sums = [sum(lam * P[i][j] for i, lam in combo) for j in range(dim)]
        ok = (any(v in f for f in faces) and sum(lam for _, lam in combo) == 1
              and all(0 <= lam < 1 for _, lam in combo) and sums == P[v])
        return ok, "vertex %d is a convex combination of other points" % v
    if k == "zero-area":  # distinct vertices, all on one line: the face encloses nothing
        f = faces[w["face"]]
        d = sub(P[f[1]], P[f[0]])
        ok = len(f) >= 3 and len({tuple(P[v]) for v in f}) == len(f)
        return ok and all(not any(cross(d, sub(P[v], P[f[0]]))) for v in f[2:]), "face %d has no area" % w["face"]
    if k == "coincident":
        u, v = w["vertices"]
        f = faces[w["face"]]
        return u != v and u in f and v in f and P[u] == P[v], "vertices %d and %d of one face coincide" % (u, v)
    if k == "face-size":
        return len(faces[w["face"]]) == w["size"] != 3, "face %d has %d vertices" % (w["face"], w["size"])
    if k == "flat":
        n, o = [q(x) for x in w["normal"]], P[w["through"]]
        return any(n) and all(dot(n, sub(r, o)) == 0 for r in P), "every point lies on one %s" % (
            "line" if dim == 2 else "plane")
    return False, "unknown witness kind %r" % k


def main(folder="."):
    folder = Path(folder)
    try:
        cert = json.loads((folder / "certificate.json").read_text())
        if not cert.get("geometric", True):
            print("no geometric certificate: " + cert.get("note", ""))
            return 0
        P = [[q(x) for x in row] for row in cert["points"]]
        on_disk = read_points(folder, cert["points_file"])
        faces_doc = json.loads((folder / cert["faces_file"]).read_text())
    except (OSError, ValueError, KeyError) as exc:
        print("cannot read the certificate: %s" % exc)
        return 2
    faces = faces_doc["faces"]
    dim = cert["dim"]
    faces = [faces] if dim == 2 else faces
    if on_disk != P:
        print("REJECTED: the certificate's points are not the points in " + cert["points_file"])
        return 1
    if faces != ([cert["faces"]] if dim == 2 else cert["faces"]):
        print("REJECTED: the certificate's faces are not the output in " + cert["faces_file"])
        return 1
    bad = 0
    for n, w in enumerate(cert["witnesses"]):
        try:
            ok, what = check(w, P, faces, dim)
        except (IndexError, KeyError, TypeError, ValueError, ZeroDivisionError) as exc:
            ok, what = False, "malformed witness (%s)" % exc
        print("%s witness %d: %s" % ("holds" if ok else "FAILS", n, what))
        bad += not ok
    if not cert["witnesses"]:
        print("REJECTED: a failure certificate with no witness")
        return 1
    print("certificate %s: %d of %d witnesses hold" % ("VERIFIED" if not bad else "REJECTED",
                                                       len(cert["witnesses"]) - bad, len(cert["witnesses"])))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:2]))
