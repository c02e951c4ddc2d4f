"""The regression corpus: one JSON file per case, exact floats, provenance and expectations.

File format (``format_version`` 1)::

    {
      "format": "hullstress-corpus",
      "format_version": 1,
      "id": "<first 16 hex digits of the content hash>",
      "content_hash": "<sha256 of the exact point bytes, shape and dtype>",
      "dim": 3,
      "shape": [n, 3],
      "points": ["0.1", "-0.0", "nan", "inf", "5e-324", ...],   # row-major, repr(float)
      "provenance": {"family": ..., "params": {...}, "seed": ..., "source": ...,
                     "found_by": "...", "found_at": "...", "original_size": ...},
      "expectations": {"<config label>": "<signature>", ...}
    }

Points are stored as ``repr(float)`` strings: the shortest decimal that reads
back to the same double, so the round trip is bit for bit, and JSON's lack of
NaN and infinities is no obstacle.  Bad-input cases of other shapes keep
their shape.

An expectation is a verdict signature: ``pass``, ``rejected``, ``error``,
``timeout``, ``crash``, ``fail:<first failed check>`` or ``fail:contract``.
Files are named ``<id>.json``; a case whose content hash is already in the
corpus is not added twice.  Writes go through a temporary file and an atomic
rename, so concurrent runs cannot leave a half-written entry.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import DEFAULT_CORPUS
from ..case import Case
from ..errors import CorpusError
from ..files import atomic_write_text
from ..records import Stage, Status
from ..results import ResultRow
from ..triage.signature import failed_check, stage_of

#: Statuses whose corpus signature is the status itself (no failed check to name).
ABNORMAL_STATUSES = frozenset({Status.ERROR, Status.TIMEOUT, Status.CRASH})

__all__ = [
    "FORMAT",
    "FORMAT_VERSION",
    "CorpusEntry",
    "row_signature",
    "is_failure_signature",
    "with_stage",
    "load_entry",
    "save_entry",
    "iter_corpus",
    "DEFAULT_CORPUS",
]

FORMAT = "hullstress-corpus"
FORMAT_VERSION = 1


def row_signature(row: ResultRow | Mapping[str, Any]) -> str:
    """The verdict signature of a result row (what a corpus expectation records).

    ``pass`` / ``rejected`` / ``error`` / ``timeout`` / ``crash``, or for a
    ``fail`` the failed check as triage names it: ``fail:containment``,
    ``fail:contract``, ``fail:invalid-input`` ...; prefixed by the stage when
    that is not the algorithm (``preprocess/fail:containment``, ``check/error``).
    """
    values = row.values if isinstance(row, ResultRow) else row
    status = str(values["status"])
    if status != Status.FAIL:
        signature = status
    else:
        signature = "fail:" + str(failed_check(status, values.get("reason"), values.get("failed_checks")))
    return with_stage(signature, values.get("stage"))


def with_stage(signature: str, stage: Any) -> str:
    """``signature`` prefixed with ``stage/`` unless the stage is the algorithm's (or unknown).

    Examples
    --------
    >>> with_stage("fail:containment", "preprocess"), with_stage("error", None)
    ('preprocess/fail:containment', 'error')
    """
    text = stage_of(stage)
    return signature if text == Stage.ALGORITHM else f"{text}/{signature}"


def is_failure_signature(signature: str) -> bool:
    """True for signatures that count as failures (fail:*, error, timeout, crash, at any stage)."""
    signature = signature.split("/", 1)[-1]
    return signature.startswith(Status.FAIL.value) or signature in ABNORMAL_STATUSES


@dataclass(frozen=True)
class CorpusEntry:
    """One corpus case: the case itself plus the recorded expectation per config label."""

    case: Case
    expectations: Mapping[str, str] = field(default_factory=dict)
    provenance: Mapping[str, Any] = field(default_factory=dict)
    path: Path | None = None

    @property
    def entry_id(self) -> str:
        return self.case.content_hash[:16]

    def with_expectations(self, expectations: Mapping[str, str]) -> "CorpusEntry":
        return CorpusEntry(self.case, dict(sorted(expectations.items())), self.provenance, self.path)

    def to_json(self) -> dict[str, Any]:
        pts = self.case.points
        return {
            "format": FORMAT,
            "format_version": FORMAT_VERSION,
            "id": self.entry_id,
            "content_hash": self.case.content_hash,
            "dim": self.case.dim,
            "shape": list(pts.shape),
            "points": [repr(float(x)) for x in pts.ravel().tolist()],
            "provenance": dict(self.provenance),
            "expectations": dict(sorted(self.expectations.items())),
        }


def _fail(path: Path, problem: str) -> CorpusError:
    return CorpusError(f"corpus file {str(path)!r}: {problem}")


def load_entry(path: str | os.PathLike[str]) -> CorpusEntry:
    """Read one corpus file.

    Raises
    ------
    CorpusError
        One line naming the file: unreadable, not JSON (e.g. truncated), not a
        corpus file, an unknown format version, or points that do not match
        their recorded shape or content hash.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise _fail(path, f"cannot read: {exc.strerror or exc}") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise _fail(path, f"not valid JSON (truncated?): {exc.msg} at line {exc.lineno}") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise _fail(path, f"not a hullstress corpus file (format is {data.get('format') if isinstance(data, dict) else type(data).__name__!r})")
    version = data.get("format_version")
    if version != FORMAT_VERSION:
        raise _fail(path, f"unknown format version {version!r}; this hullstress reads version {FORMAT_VERSION}")
    try:
        shape = tuple(int(s) for s in data["shape"])
        values = [float(s) for s in data["points"]]
        points = np.array(values, dtype=np.float64).reshape(shape)
        dim = int(data["dim"])
        prov = dict(data.get("provenance") or {})
        expectations = {str(k): str(v) for k, v in (data.get("expectations") or {}).items()}
    except (KeyError, TypeError, ValueError) as exc:
        raise _fail(path, f"malformed entry: {type(exc).__name__}: {exc}") from None
    case = Case(
        points=points, dim=dim, family=str(prov.get("family", "corpus")),
        params=prov.get("params") or {}, seed=prov.get("seed"), size=prov.get("size"),
        source=f"corpus:{path.name}",
    )
    if data.get("content_hash") and data["content_hash"] != case.content_hash:
        raise _fail(path, "points do not match the recorded content hash (edited or corrupted)")
    return CorpusEntry(case=case, expectations=expectations, provenance=prov, path=path)


def save_entry(directory: str | os.PathLike[str], entry: CorpusEntry, *, overwrite: bool = False) -> tuple[Path, bool]:
    """Write ``entry`` atomically as ``<directory>/<id>.json``.

    Returns
    -------
    path : Path
    written : bool
        False when an entry with the same content hash already existed and
        ``overwrite`` is False (de-duplication by content hash).
    """
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f"{entry.entry_id}.json"
    if path.exists() and not overwrite:
        return path, False
    atomic_write_text(path, json.dumps(entry.to_json(), indent=1, sort_keys=False) + "\n", durable=True)
    return path, True


def iter_corpus(directory: str | os.PathLike[str]) -> Iterator[tuple[Path, CorpusEntry | CorpusError]]:
    """Yield ``(path, entry)`` for every ``*.json`` file, or ``(path, CorpusError)`` for a bad one.

    A bad file never stops the others from loading.
    """
    directory = Path(directory)
    if directory.is_file():
        files = [directory]
    elif directory.is_dir():
        files = sorted(p for p in directory.glob("*.json") if not p.name.startswith("."))
    else:
        raise CorpusError(f"corpus {str(directory)!r}: no such file or directory")
    for path in files:
        try:
            yield path, load_entry(path)
        except CorpusError as exc:
            yield path, exc


def provenance_for(case: Case, *, found_by: str, original_size: int | None = None, extra: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Provenance for a new corpus entry made from ``case``."""
    prov: dict[str, Any] = {
        "family": case.family,
        "params": json.loads(case.params_json),
        "seed": case.seed,
        "size": case.size,
        "source": case.source,
        "found_by": found_by,
        "found_at": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "original_size": original_size if original_size is not None else case.n_points,
    }
    if extra:
        prov.update(extra)
    return prov
