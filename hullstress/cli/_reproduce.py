"""``python -m hullstress reproduce FOLDER``: re-run a failure folder's minimal case and show the evidence.

Reads the folder's ``case.json`` (written by the report stage, ``shrink`` or
``fuzz``), loads the plug-ins it names, runs the minimal case in the same
config in an isolated worker with the recorded timeout, and prints the
verdict, the failed checks and their witness: the offending points with
their exact coordinates, the offending faces with their vertices.

With ``--save-corpus DIR`` the folder's minimal case becomes a regression
corpus entry (every config's current verdict recorded, as ``run
--save-corpus`` records them): the way to keep one particular failure, say
one that only ``search`` found.

Exit status: 1 the config still fails on the case (the output says whether
with the recorded signature or differently); 0 it passes or is rejected now
(fixed); 2 not a failure folder, or its files cannot be read; 4 the corpus
folder cannot be written (read-only, full disk).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import UsageError
from ._common import seconds
from ..records import Status

__all__ = ["add_parser", "reproduce_command", "witness_lines"]


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "reproduce",
        help="re-run a failure folder's minimal case and print the verdict and its witness",
        description="Re-run the minimal case of a failure folder (reports/<run>/failures/<cause>/) in the same "
        "config, isolated, and print the verdict, the failed checks and the witness (offending indices and "
        "coordinates). Exit status: 1 it still fails, 0 it passes now, 2 not a failure folder, 4 --save-corpus "
        "cannot be written.",
    )
    p.add_argument("folder", metavar="FOLDER", help="a failure folder (it holds case.json)")
    p.add_argument("--all", action="store_true",
                   help="also re-run every other config of the cause, each on its own minimal case")
    p.add_argument("--timeout", type=seconds(), default=None, metavar="SECONDS",
                   help="per-call timeout (default: the run's, as recorded in case.json)")
    p.add_argument("--plugin", action="append", default=[], metavar="MODULE_OR_FILE",
                   help="import a plug-in first, besides those case.json names (repeatable)")
    p.add_argument("--save-corpus", default=None, metavar="DIR",
                   help="add the minimal case to the regression corpus in DIR, every config's verdict recorded")
    p.set_defaults(handler=reproduce_command)


def _load_case_json(folder: Path) -> dict[str, Any]:
    from ..report.failures import CASE_FILE

    path = folder / CASE_FILE
    if not folder.is_dir():
        raise UsageError(f"reproduce: {str(folder)!r} is not a folder")
    if not path.is_file():
        raise UsageError(f"reproduce: {str(folder)!r} is not a failure folder (no {CASE_FILE})")
    try:
        meta = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise UsageError(f"reproduce: cannot read {str(path)!r}: {exc}") from None
    for key in ("signature", "dim", "points_file"):
        if key not in meta:
            raise UsageError(f"reproduce: {str(path)!r} has no {key!r}: not written by this version of hullstress")
    return meta


def _load_points(folder: Path, meta: dict[str, Any]) -> np.ndarray:
    from ..io import read_points

    path = folder / str(meta["points_file"])
    if not path.is_file():
        raise UsageError(f"reproduce: the points file {str(path)!r} is missing")
    if path.suffix == ".csv":
        return read_points(path, dim=int(meta["dim"]))
    try:
        return np.load(path, allow_pickle=False)  # as stored: bad-input cases may hold NaN or odd shapes
    except (OSError, ValueError) as exc:
        raise UsageError(f"reproduce: cannot load {str(path)!r}: {exc}") from None


def _coords(points: np.ndarray, index: int) -> str:
    if points.ndim == 2 and 0 <= index < len(points):
        return "(" + ", ".join(repr(float(x)) for x in points[index]) + ")"
    return "(no such point)"


def witness_lines(points: np.ndarray, offending: dict[str, list[int]], faces: Any = None) -> list[str]:
    """The offending indices of a verdict, spelled out: points with coordinates, faces with their vertices.

    Examples
    --------
    >>> witness_lines(np.array([[0.0, 0.0], [1.0, 0.5]]), {"containment": [1]})
    ['containment: point 1 (1.0, 0.5)']
    """
    from ..report.pictures import split_offending

    lines = []
    for kind, indices in offending.items():
        point_kind, face_kind, _ = split_offending({kind: indices})
        for i in indices:
            i = int(i)
            if i in face_kind and isinstance(faces, list) and faces and isinstance(faces[0], list) and i < len(faces):
                vertices = faces[i]
                lines.append(f"{kind}: face {i} = {vertices} " + " ".join(_coords(points, int(v)) for v in vertices))
            elif i in point_kind:
                lines.append(f"{kind}: point {i} {_coords(points, i)}")
            else:
                lines.append(f"{kind}: {'face' if i in face_kind else 'edge'} {i}")
    return lines


def _output_faces(points: np.ndarray, dim: int, config: Any) -> Any:
    """The algorithm's faces on the case, in this process (only called after an isolated run returned)."""
    from ..case import Case
    from ..triage.evidence import faces_to_json
    from ..evaluate import call_algorithm
    import warnings

    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        outcome = call_algorithm(Case(points=points, dim=dim, family="file"), config)
    return faces_to_json(outcome.faces) if outcome.kind == "ok" else None


def _run(points: np.ndarray, dim: int, recorded: Any, timeout: float) -> tuple[bool, bool, list[str]]:
    """Run the recorded config on ``points``; (still fails, same signature, lines to print)."""
    from ..case import Case
    from ..report.failures import verdict_values
    from ..triage.oracle import run_config
    from ..triage.signature import signature_of

    config = recorded.config
    row = run_config(Case(points=points, dim=dim, family="file"), config, timeout=timeout, isolate=True)
    now = signature_of(row)
    values = verdict_values(row)
    lines = [f"{config.label} on {len(points) if points.ndim else 0} points ({dim}D): {row.status}"
             + (f" in stage {values['stage']}" if values.get("stage") else "")]
    if now is not None and now.checks:
        from ..checker.severity import describe_severity

        shown = describe_severity(now.severity, row.get("max_violation"), manifoldness=row.get("manifoldness"),
                                  detail=str(row.get("reason") or "")) if now.severity else ""
        lines.append(f"  failed checks: {now.checks}" + (f" ({shown})" if shown else ""))
    if row.get("reason"):
        lines.append(f"  reason: {row.get('reason')}")
    if row.get("error_frame"):
        lines.append(f"  raised at: {row.get('error_frame')}")
    offending = values.get("offending") or {}
    if offending:
        faces = _output_faces(points, dim, config) if row.status == Status.FAIL and "face" in " ".join(offending) else None
        lines.append("  witness:")
        lines += [f"    {w}" for w in witness_lines(points, offending, faces)]
    if now == recorded:
        lines.append("  the same failure as recorded: it persists")
    elif now is not None:
        lines.append(f"  fails differently: recorded {recorded.what}, now {now.what}")
    else:
        lines.append(f"  no failure now (recorded: {recorded.what})")
    return now is not None, now == recorded, lines


def _register_recorded(recorded: list[str]) -> None:
    """Register again what the run's ``--exec`` / ``--clockwise`` registered (case.json keeps them)."""
    if not recorded:
        return
    from .._registry import ALGORITHMS
    from ..adapters.executable import parse_exec_spec
    from ._common import add_registration_options, load_registrations

    parser = argparse.ArgumentParser(add_help=False)
    add_registration_options(parser)
    ns = parser.parse_args(recorded)
    ns.exec_specs = [text for text in ns.exec_specs if parse_exec_spec(text)[0] not in ALGORITHMS]
    load_registrations(ns)


def reproduce_command(args: argparse.Namespace) -> int:
    from ..options import DEFAULTS
    from ..plugins import load_plugin
    from ..triage.signature import Signature

    folder = Path(args.folder)
    meta = _load_case_json(folder)
    if args.save_corpus:
        from ..files import writable_folder

        writable_folder(args.save_corpus, "--save-corpus")  # before any work, as `run` checks it
    for spec in list(meta.get("plugins") or []) + list(args.plugin):
        load_plugin(spec)
    _register_recorded(list(meta.get("registration") or []))
    timeout = float(args.timeout or meta.get("timeout") or DEFAULTS.call_timeout)
    dim = int(meta["dim"])
    points = _load_points(folder, meta)
    recorded = Signature.from_dict(meta["signature"])
    print(f"cause: {meta.get('label', recorded.label)}")
    print(f"case: {folder / str(meta['points_file'])}")
    fails, _, lines = _run(points, dim, recorded, timeout)
    print("\n".join(lines))
    if args.all:
        for member in meta.get("members", [])[1:]:
            sig = Signature.from_dict(member["signature"])
            own = points if member.get("points") is None else np.asarray(member["points"], dtype=np.float64)
            more, _, lines = _run(own, dim, sig, timeout)
            fails = fails or more
            print("\n".join(lines))
    if args.save_corpus:
        path, written = _save_to_corpus(args.save_corpus, folder, meta, points, timeout)
        print(f"corpus: {'new entry' if written else 'already there'}: {path}")
    return 1 if fails else 0


def _save_to_corpus(directory: str, folder: Path, meta: dict[str, Any], points: np.ndarray,
                    timeout: float) -> tuple[Path, bool]:
    """The folder's minimal case as a corpus entry; provenance names the folder, its run and its origin."""
    from ..corpus.replay import add_to_corpus
    from ..corpus.save import minimised_entry

    original = meta.get("original_case") or {}
    families = meta.get("families") or {}
    family = str(original.get("family") or (sorted(families)[0] if families else "reproduced"))
    case, provenance = minimised_entry(
        points, int(meta["dim"]), family, signature=meta.get("cause"),
        found_by=f"hullstress reproduce {folder.resolve()}", original_size=meta.get("original_size"),
        original_case_id=original.get("case_id"), params=original.get("params"), seed=original.get("seed"),
        size=original.get("size"))
    from ..corpus.store import held_groups
    from ..triage.signature import Signature

    group = Signature.from_dict(meta["signature"])  # the folder's failure group: the entry holds it
    from ..errors import CorpusError, UsageError

    try:
        held = held_groups(directory)
    except CorpusError as exc:
        raise UsageError(f"--save-corpus: {exc}") from None
    if group in held and held[group].path is not None:
        return held[group].path, False
    [(path, written)] = add_to_corpus(directory, [(case, provenance, group)], workers=1, timeout=timeout,
                                      overwrite=True)
    return path, written
