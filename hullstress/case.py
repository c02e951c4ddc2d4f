"""Cases: a point set plus where it came from, with a stable id."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

__all__ = ["Case", "canonical_params", "points_digest"]


def canonical_params(params: Mapping[str, Any] | None) -> str:
    """Return ``params`` as canonical JSON (sorted keys, no spaces), the form used in ids and tables."""
    return json.dumps(dict(params or {}), sort_keys=True, separators=(",", ":"), default=repr)


def points_digest(points: np.ndarray) -> str:
    """Hex SHA-256 of the exact bytes, shape and dtype of ``points`` (the content hash)."""
    arr = np.ascontiguousarray(points)
    h = hashlib.sha256()
    h.update(f"{arr.dtype.str}:{arr.shape}".encode())
    h.update(arr.tobytes())
    return h.hexdigest()


def _frozen(points: Any) -> np.ndarray:
    arr = np.array(points, dtype=np.float64, copy=True, order="C")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class Case:
    """One point set to hull, with its provenance.

    Parameters
    ----------
    points : ndarray of shape (n, dim), float64
        Copied, C-contiguous and read-only.  Bad-input families may give other
        shapes on purpose; ``dim`` still says which algorithms the case is for.
    dim : int
        2 or 3.
    family : str
        Generator family, or ``file`` / ``corpus`` for cases from elsewhere.
    params : mapping
        Generator parameters (canonicalised to JSON in ``params_json``).
    seed : int or None
        The seed the generator was called with.
    size : int or None
        The requested number of points (``n_points`` may differ for fixed cases).
    source : str
        Free-form origin: ``generator``, a file path, a corpus entry.

    Examples
    --------
    >>> c = Case.from_points([[0, 0], [1, 0], [0, 1], [0, 1]], family="file")
    >>> c.n_points, c.dim, len(c.case_id)
    (4, 2, 16)
    """

    points: np.ndarray
    dim: int
    family: str
    params: Mapping[str, Any] = field(default_factory=dict)
    seed: int | None = None
    size: int | None = None
    source: str = "generator"

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", _frozen(self.points))
        object.__setattr__(self, "params", dict(self.params))

    @classmethod
    def from_points(cls, points: Any, *, family: str = "file", dim: int | None = None, **kw: Any) -> "Case":
        """Build a case from array-like points; ``dim`` defaults to the number of columns."""
        arr = _frozen(points)
        if dim is None:
            dim = int(arr.shape[1]) if arr.ndim == 2 else 0
        return cls(points=arr, dim=dim, family=family, **kw)

    @property
    def n_points(self) -> int:
        return int(self.points.shape[0]) if self.points.ndim >= 1 else 0

    @cached_property
    def params_json(self) -> str:
        """The parameters as canonical JSON (computed once: every row of the case carries it)."""
        return canonical_params(self.params)

    @cached_property
    def content_hash(self) -> str:
        """SHA-256 of the exact point bytes (used to de-duplicate corpus entries)."""
        return points_digest(self.points)

    @cached_property
    def case_id(self) -> str:
        """16 hex digits from the exact point bytes and the provenance; stable across runs and machines."""
        h = hashlib.sha256()
        h.update(self.content_hash.encode())
        h.update(
            json.dumps(
                [self.family, self.params_json, self.seed, self.dim], separators=(",", ":")
            ).encode()
        )
        return h.hexdigest()[:16]

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Case) and self.case_id == other.case_id

    def __hash__(self) -> int:
        return hash(self.case_id)

    def __repr__(self) -> str:
        return (
            f"Case(id={self.case_id}, family={self.family!r}, params={self.params_json}, "
            f"seed={self.seed}, dim={self.dim}, n_points={self.n_points})"
        )
