"""The Python driver kit's example: scipy.spatial.ConvexHull (Qhull, "i Qt") as a 3D hull program.

Runs in whatever Python environment has the SciPy to test, e.g.
``--exec 'scipy-old[mode=persistent]=/path/to/old-venv/bin/python drivers/examples/scipy_driver.py'``.
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "kit"))

import numpy as np  # noqa: E402
import scipy  # noqa: E402
from scipy.spatial import ConvexHull, QhullError  # noqa: E402

from hullstress_driver import Reject, run_driver  # noqa: E402


def scipy_hull(points):
    pts = np.array(points, dtype=np.float64)
    try:
        hull = ConvexHull(pts)
    except QhullError as exc:
        raise Reject("QhullError: " + str(exc).splitlines()[0]) from None
    faces = []
    for simplex, normal in zip(hull.simplices, hull.equations[:, :3]):
        a, b, c = pts[simplex]
        if np.dot(np.cross(b - a, c - a), normal) < 0:  # scipy's vertex order is not its orientation
            simplex = simplex[[0, 2, 1]]
        faces.append("%d %d %d" % tuple(simplex))
    return "%d\n%s\n" % (len(faces), "\n".join(faces))


run_driver(scipy_hull, dim=3, output="i", driver="hullstress scipy example driver 1.0",
           library="scipy %s" % scipy.__version__)
