"""A plug-in that holds one phase of a run, so a test can interrupt it there.

Environment:

``HOLD_PHASE``
    ``sweep``: calls on cases of more than ``HOLD_SIZE`` points last 10 s
    (smaller cases finish at once, so some rows are done when the signal comes);
    ``triage``: calls on the sweep's cases are quick, calls on fewer than
    ``HOLD_SIZE`` points (only the shrinker makes those) last 10 s;
    ``report``: calls are quick, and drawing each failure's picture takes
    0.5 s (the one step of the report that takes time) when the run draws
    it itself, as with ``--workers 1`` (with more, a helper process draws
    the pictures: :mod:`hullstress.report.picture_helper`).
``HOLD_SIZE``
    See above (default 12).
``HOLD_MARK``
    A file created when the phase starts being held: the test signals then.

Every call returns a monotone chain without its last vertex: a failure, so
that there is something to triage and report.
"""

import os
import time
from pathlib import Path

import numpy as np

from hullstress import register_algorithm

PHASE = os.environ.get("HOLD_PHASE", "sweep")
SIZE = int(os.environ.get("HOLD_SIZE", "12"))


def _hold(seconds):
    mark = os.environ.get("HOLD_MARK")
    if mark:
        Path(mark).touch()
    time.sleep(seconds)


@register_algorithm("phase-holder", dim=2)
def phase_holder(points):
    """Monotone chain without its last vertex, slow in the phase under test."""
    if (PHASE == "sweep" and len(points) > SIZE) or (PHASE == "triage" and len(points) < SIZE):
        _hold(10.0)
    order = np.lexsort((points[:, 1], points[:, 0]))
    hull = []
    for chain in (order, order[::-1]):
        start = len(hull)
        for i in chain:
            while len(hull) >= start + 2:
                a, b = points[hull[-2]], points[hull[-1]]
                if (b[0] - a[0]) * (points[i][1] - a[1]) - (b[1] - a[1]) * (points[i][0] - a[0]) > 0:
                    break
                hull.pop()
            hull.append(int(i))
        hull.pop()
    return hull[:-1]


if PHASE == "report":
    import hullstress.report.stage as _stage

    _draw = _stage.draw_picture

    def _slow_draw(record):
        _hold(0.5)
        return _draw(record)

    _stage.draw_picture = _slow_draw
