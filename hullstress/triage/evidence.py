"""The evidence a failure folder shows, gathered by triage so that the report runs nothing.

* :func:`storage_kind` -- how the minimal case's points survive a file: as a
  ``points.csv`` that ``run --points-file`` reads back bit for bit, as a
  ``.npy`` that it reads, or only as a raw ``.npy`` (non-finite values, odd
  shapes) that ``shrink --raw`` loads.
* :func:`output_faces` -- the algorithm's output on the minimal case, for the
  folder's ``faces.json`` and picture.
* :func:`verify_from_storage` -- the failure reproduces from the points as
  they will be stored (the reproduce command's promise).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ..case import Case
from ..config import AlgorithmConfig
from ..contract import FaceSet
from ..records import Status
from .oracle import IsolationUnavailable, fails_same_way
from .signature import Signature

__all__ = ["STORAGE_KINDS", "storage_kind", "faces_to_json", "output_faces", "verify_from_storage"]

#: ``csv``: points.csv round-trips exactly; ``npy``: points.npy is a valid points file;
#: ``raw``: only the raw array can be stored (replayed with ``shrink --raw``).
STORAGE_KINDS = ("csv", "npy", "raw")


def _reread(points: np.ndarray, kind: str) -> np.ndarray | None:
    """``points`` written as a ``kind`` points file and read back (the same writer and reader, in memory), or None."""
    from ..errors import InputFileError
    from ..io import points_file_bytes, read_points_bytes

    try:
        return read_points_bytes(points_file_bytes(points, kind), name=f"points.{kind}")
    except (ValueError, InputFileError):
        return None


def storage_kind(points: np.ndarray) -> str:
    """The first of :data:`STORAGE_KINDS` that stores ``points`` exactly as a readable points file.

    Examples
    --------
    >>> storage_kind(np.array([[0.1, 0.2], [1.0, 3.0], [5e-324, -0.0]]))
    'csv'
    >>> storage_kind(np.array([[0.0, np.nan], [1.0, 2.0], [3.0, 4.0]]))
    'raw'
    """
    arr = np.asarray(points, dtype=np.float64)
    for kind in ("csv", "npy"):
        back = _reread(arr, kind)
        if back is not None and back.shape == arr.shape and np.array_equal(back, arr):
            return kind
    return "raw"


def faces_to_json(faces: np.ndarray | FaceSet | None) -> Any:
    """Normalised output faces as JSON-ready lists (2D: one index list; 3D: a list of polygons)."""
    if faces is None:
        return None
    if isinstance(faces, FaceSet):
        return faces.to_python()
    return [int(i) for i in np.asarray(faces).ravel()]


def output_faces(case: Case, config: AlgorithmConfig, signature: Signature) -> tuple[Any, str]:
    """The algorithm's output on ``case`` as JSON-ready faces, and a note when there is none.

    Only ``fail`` signatures have an output: the shrinker has just seen this
    exact call return, so running it once more in this process is safe;
    errors, timeouts and crashes produce no faces.
    """
    if signature.status != Status.FAIL:
        return None, f"no output: the call ends in {signature.status}"
    from ..evaluate import call_algorithm

    # The code under test may be noisy (overflow warnings on extreme inputs): the
    # row already records what matters, so keep this run quiet.
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        outcome = call_algorithm(case, config)
    if outcome.kind == "ok":
        return faces_to_json(outcome.faces), ""
    return None, outcome.error


def verify_from_storage(case: Case, kind: str, config: AlgorithmConfig, signature: Signature,
                        timeout: float | None, qhull_options: str | None = None) -> bool | None:
    """Whether ``config`` fails with ``signature`` on ``case``'s points as stored in form ``kind``.

    Returns None when the failure cannot be re-run safely here (a crash or
    hang with no isolated runner).
    """
    if kind == "raw":
        replay = Case(points=np.array(case.points), dim=case.dim, family=case.family)
    else:
        back = _reread(np.asarray(case.points), kind)
        if back is None:
            return False
        replay = Case.from_points(back, family="file")
    try:
        return fails_same_way(replay, config, signature, timeout=timeout, qhull_options=qhull_options)
    except IsolationUnavailable:
        return None
