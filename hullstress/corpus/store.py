"""The regression corpus: one JSON file per failure group, its minimal case with exact floats.

File format (``format_version`` 2)::

    {
      "format": "hullstress-corpus",
      "format_version": 2,
      "id": "<the group's Signature.group_id; or the content hash's first 16 hex digits>",
      "group": {"algorithm": ..., "sphere": ..., "eps": ..., "stage": ..., "status": ...,
                "checks": ..., "severity": ..., "error": ..., "frame": ...},   # or null
      "label": "<the group's Signature.label>",
      "state": "failing" | "fixed",
      "content_hash": "<sha256 of the exact point bytes, shape and dtype>",
      "dim": 3,
      "shape": [n, 3],
      "points": ["0.1", "-0.0", "nan", "inf", "5e-324", ...],   # row-major, repr(float)
      "provenance": {"family": ..., "params": {...}, "seed": ..., "source": ...,
                     "found_by": "...", "found_at": "...", "original_size": ...},
      "expectations": {"<config label>": "<verdict>", ...}
    }

The corpus holds **one entry per failure group**: ``group`` is the
:class:`~hullstress.triage.signature.Signature` the entry was saved for (the
one identity of "the same failure", see that module) and the file is named
``<group_id>.json``, so a group cannot be saved twice.  ``state`` is
``failing`` until ``replay --accept`` records that the group's config no
longer fails that way on the entry (``fixed``); a fixed entry stays as a
passing regression case.  An entry without a group (``null``) is a plain
regression case named after its content hash.

Points are stored as ``repr(float)`` strings: the shortest decimal that reads
back to the same double, so the round trip is bit for bit, and JSON's lack of
NaN and infinities is no obstacle.  Bad-input cases of other shapes keep
their shape.

An expectation is a call's verdict (:func:`~hullstress.triage.signature.verdict_of`):
``pass``, ``rejected``, or the failure's signature without its config
(``fail containment (gross)``, ``error ZeroDivisionError at m:3 in f``).
Writes go through a temporary file and an atomic rename, so concurrent runs
cannot leave a half-written entry.
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
from ..triage.signature import Signature

__all__ = [
    "FORMAT",
    "FORMAT_VERSION",
    "FAILING",
    "FIXED",
    "CorpusEntry",
    "load_entry",
    "save_entry",
    "iter_corpus",
    "held_groups",
    "DEFAULT_CORPUS",
]

FORMAT = "hullstress-corpus"
FORMAT_VERSION = 2
#: An entry's ``state``: its group's config still fails that way on it (as far as the corpus knows) ...
FAILING = "failing"
#: ... or ``replay --accept`` recorded that it no longer does.
FIXED = "fixed"
_STATES = (FAILING, FIXED)


@dataclass(frozen=True)
class CorpusEntry:
    """One corpus entry: a failure group's minimal case plus the recorded verdict per config label.

    Attributes
    ----------
    case : Case
    expectations : mapping of str to str
        Config label -> verdict (:func:`~hullstress.triage.signature.verdict_of`).
    provenance : mapping
    path : Path or None
        The file it was read from.
    group : Signature or None
        The failure group the entry holds (None: a plain regression case).
    state : {"failing", "fixed"}
    """

    case: Case
    expectations: Mapping[str, str] = field(default_factory=dict)
    provenance: Mapping[str, Any] = field(default_factory=dict)
    path: Path | None = None
    group: Signature | None = None
    state: str = FAILING

    @property
    def entry_id(self) -> str:
        """The group's id, or for a plain case the first 16 hex digits of its content hash."""
        return self.group.group_id if self.group is not None else self.case.content_hash[:16]

    @property
    def holds(self) -> Signature | None:
        """The group this entry holds as still failing (None when it is fixed or has no group)."""
        return self.group if self.state == FAILING else None

    def with_expectations(self, expectations: Mapping[str, str], state: str | None = None) -> "CorpusEntry":
        return CorpusEntry(self.case, dict(sorted(expectations.items())), self.provenance, self.path, self.group,
                           state or self.state)

    def to_json(self) -> dict[str, Any]:
        pts = self.case.points
        return {
            "format": FORMAT,
            "format_version": FORMAT_VERSION,
            "id": self.entry_id,
            "group": self.group.as_dict() if self.group is not None else None,
            "label": self.group.label if self.group is not None else None,
            "state": self.state,
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
    if version == 1:
        raise _fail(path, "format version 1 (one entry per algorithm x family) predates failure groups; rebuild "
                    "the corpus with `python -m hullstress run ... --save-corpus DIR` into an empty folder")
    if version != FORMAT_VERSION:
        raise _fail(path, f"unknown format version {version!r}; this hullstress reads version {FORMAT_VERSION}")
    try:
        shape = tuple(int(s) for s in data["shape"])
        values = [float(s) for s in data["points"]]
        points = np.array(values, dtype=np.float64).reshape(shape)
        dim = int(data["dim"])
        prov = dict(data.get("provenance") or {})
        expectations = {str(k): str(v) for k, v in (data.get("expectations") or {}).items()}
        group = Signature.from_dict(data["group"]) if data.get("group") else None
        state = str(data.get("state") or FAILING)
        if state not in _STATES:
            raise ValueError(f"state must be one of {', '.join(_STATES)}, got {state!r}")
    except (KeyError, TypeError, ValueError) as exc:
        raise _fail(path, f"malformed entry: {type(exc).__name__}: {exc}") from None
    case = Case(
        points=points, dim=dim, family=str(prov.get("family", "corpus")),
        params=prov.get("params") or {}, seed=prov.get("seed"), size=prov.get("size"),
        source=f"corpus:{path.name}",
    )
    if data.get("content_hash") and data["content_hash"] != case.content_hash:
        raise _fail(path, "points do not match the recorded content hash (edited or corrupted)")
    entry = CorpusEntry(case=case, expectations=expectations, provenance=prov, path=path, group=group, state=state)
    if data.get("id") and data["id"] != entry.entry_id:
        raise _fail(path, f"id {data['id']!r} does not match its group (or points): edited by hand?")
    return entry


def save_entry(directory: str | os.PathLike[str], entry: CorpusEntry, *, overwrite: bool = False) -> tuple[Path, bool]:
    """Write ``entry`` atomically as ``<directory>/<id>.json``.

    Returns
    -------
    path : Path
    written : bool
        False when an entry with the same id (the same failure group, or for a
        plain case the same points) already existed and ``overwrite`` is False.
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


def held_groups(directory: str | os.PathLike[str]) -> dict[Signature, CorpusEntry]:
    """The failure groups a corpus holds as failing, each with its entry; ``{}`` for a missing folder.

    Raises
    ------
    CorpusError
        The first unreadable file, naming it: a group it may hold must not
        silently count as new.
    """
    if not Path(directory).exists():
        return {}
    held: dict[Signature, CorpusEntry] = {}
    for _, item in iter_corpus(directory):
        if isinstance(item, CorpusError):
            raise item
        if item.holds is not None:
            held[item.holds] = item
    return held


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
