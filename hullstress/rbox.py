"""Cases from Qhull's own test-point generator: ``--generator rbox:'100 D3 s'``.

``rbox`` (installed with Qhull; ``pip install cmeel-qhull``) prints points
for Qhull's distributions (cospherical ``s``, lattices ``M3,4``, narrow lenses
``L``, fuzzy cube faces ``W1e-13``, ...; see ``/work/shared/data/qhull_reference.md``
and ``rbox``'s own help).  A spec ``rbox:ARGS`` runs ``rbox ARGS t<seed>``
where the seed is derived from ``--seed``, the arguments and the replicate,
so the same run gives the same points.  The dimension comes from rbox's
output (``D2`` or ``D3``; the default is 3).

Examples
--------
>>> parse_rbox_spec("rbox:100 D2 s")
'100 D2 s'
>>> parse_rbox_spec("rbox:100 t5")
Traceback (most recent call last):
...
hullstress.errors.UsageError: --generator 'rbox:100 t5': leave out rbox's seed option 't5': hullstress passes t<seed> derived from --seed
"""

from __future__ import annotations

import re
import shlex
import subprocess

import numpy as np

from .errors import UsageError

__all__ = ["RBOX_PREFIX", "is_rbox_spec", "parse_rbox_spec", "rbox_count", "rbox_points", "RBOX_SEED_MODULUS"]

#: ``--generator`` values starting with this run rbox.
RBOX_PREFIX = "rbox:"
#: rbox reads its seed as a C int.
RBOX_SEED_MODULUS = 2**31 - 1


def is_rbox_spec(name: str) -> bool:
    """True for a ``--generator`` value that asks for rbox."""
    return name.startswith(RBOX_PREFIX)


def parse_rbox_spec(spec: str) -> str:
    """The rbox arguments of ``rbox:ARGS``, checked (no seed option, parseable, a count if any)."""
    args = spec[len(RBOX_PREFIX):].strip()
    try:
        tokens = shlex.split(args)
    except ValueError as exc:
        raise UsageError(f"--generator {spec!r}: {exc}") from None
    for token in tokens:
        if re.fullmatch(r"t\d*", token):
            raise UsageError(f"--generator {spec!r}: leave out rbox's seed option {token!r}: "
                             "hullstress passes t<seed> derived from --seed")
    return " ".join(tokens)


def rbox_count(args: str) -> int | None:
    """The number of random points rbox is asked for (its first bare integer), or None.

    Examples
    --------
    >>> rbox_count("1000 s W1e-13 D3"), rbox_count("c D2")
    (1000, None)
    """
    for token in args.split():
        if token.isdigit():
            return int(token)
    return None


def rbox_points(args: str, seed: int) -> np.ndarray:
    """Run ``rbox ARGS t<seed>`` and return its points.

    Parameters
    ----------
    args : str
        rbox's arguments (from :func:`parse_rbox_spec`).
    seed : int
        Any non-negative integer (reduced modulo :data:`RBOX_SEED_MODULUS`).

    Returns
    -------
    ndarray of shape (n, d), float64

    Raises
    ------
    UsageError
        rbox is not installed, fails, or prints something other than 2D or 3D points.
    """
    from .adapters.executable import locate_program
    from .errors import InputFileError
    from .io import read_points_text

    program = locate_program("rbox")
    label = f"rbox {args}"
    if program is None:
        raise UsageError(f"--generator 'rbox:{args}': rbox not found (pip install cmeel-qhull, or install Qhull)")
    argv = [program, *shlex.split(args), f"t{seed % RBOX_SEED_MODULUS}"]
    try:
        proc = subprocess.run(argv, capture_output=True, timeout=120, check=False)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise UsageError(f"--generator 'rbox:{args}': rbox did not run: {exc}") from None
    if proc.returncode != 0:
        said = " ".join(proc.stderr.decode("utf-8", "replace").split())[:200]
        raise UsageError(f"--generator 'rbox:{args}': rbox exited with code {proc.returncode}: {said}")
    try:
        return read_points_text(proc.stdout.decode("utf-8", "replace"), label=label)
    except InputFileError as exc:
        raise UsageError(f"--generator 'rbox:{args}': {exc}") from None
