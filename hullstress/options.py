"""One home for the defaults: profiles, limits and budgets, read by the CLI, the runner and the pipeline.

* :data:`DEFAULTS` -- limits that do not depend on the sweep's size: the
  per-call timeout when nothing else says, the floor of the checker's time
  limit, the memory limit of a worker, caps on failure folders and shrink calls.
* :class:`Profile` and :data:`PROFILES` -- how big a sweep is: sizes per
  dimension, seeds, the per-call timeout, and the triage and report budgets.
  ``quick`` is the default of ``python -m hullstress run``; ``nightly`` is
  sized for about 30 minutes on 2 cores.

Nothing here imports more than the standard library and hullstress's errors,
so the CLI can build its ``--help`` without loading NumPy.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from .errors import UsageError

__all__ = ["Defaults", "DEFAULTS", "TriageBudget", "Profile", "PROFILES", "get_profile"]


@dataclass(frozen=True)
class Defaults:
    """Limits shared by every command.

    Attributes
    ----------
    call_timeout : float
        Per-call timeout in seconds when neither a profile nor ``--timeout`` gives one
        (``shrink``, ``fuzz``, ``replay``, ``check``).
    check_timeout_floor : float
        The checker's limit per step in a worker is ``max(this, 10 * call timeout)``.
    memory_limit_mb : float
        Address-space limit per isolated worker in MiB.  A worker holding
        Python, NumPy and SciPy maps well under 1 GiB; 4 GiB leaves room for
        large inputs while letting a runaway allocation fail fast (two workers
        on a 24 GiB machine can never take it down).
    max_folders : int
        At most this many failure folders per run (worst groups first).
    shrink_max_calls : int
        Cap on judged calls of one shrink.
    """

    call_timeout: float = 10.0
    check_timeout_floor: float = 60.0
    memory_limit_mb: float = 4096.0
    max_folders: int = 2000
    shrink_max_calls: int = 2000


#: The one defaults object.
DEFAULTS = Defaults()


@dataclass(frozen=True)
class TriageBudget:
    """How much work triage and the report's pictures may do.

    Shrinking is budgeted in **evaluations** (judged calls of the code under
    test), never in seconds, so the same seed gives the same minimal cases
    and failure folders on any machine, under any load and with any number
    of workers.  The wall-clock cap is only a safety net: when it fires,
    triage stops early and the report says that its folders may differ
    between runs.

    Attributes
    ----------
    calls : int
        Evaluations for the whole of triage: shrinking and the cross-checks
        that let a group start from another group's minimal case (verifying
        each minimal case adds one call per group).  Groups reached after it
        is spent keep their smallest failing case, unshrunk.
    group_calls : int
        Evaluations for one group's shrink.
    hang_calls : int
        Evaluations for shrinking a ``timeout`` group, where every failing
        call lasts the whole per-call timeout (0: such groups are not shrunk).
    pictures : int
        Causes that get a picture, worst first.
    safety_seconds : float
        Wall-clock safety net on triage.
    call_timeout : float
        Per-call limit for shrink candidates, in seconds (the sweep's own
        timeout when that is shorter; hangs are shrunk with the sweep's).  A
        candidate of a few points takes milliseconds, so this is generous,
        and a candidate that hangs costs a round this long, not a whole
        sweep timeout.
    """

    calls: int
    group_calls: int
    hang_calls: int
    pictures: int
    safety_seconds: float
    call_timeout: float = 2.0

    def __post_init__(self) -> None:
        for name in ("calls", "group_calls", "hang_calls", "pictures"):
            value = getattr(self, name)
            if not isinstance(value, int) or isinstance(value, bool) or value < 0:
                raise UsageError(f"TriageBudget.{name} must be an integer >= 0, got {value!r}")
        for name in ("safety_seconds", "call_timeout"):
            if not getattr(self, name) > 0:
                raise UsageError(f"TriageBudget.{name} must be positive, got {getattr(self, name)!r}")


@dataclass(frozen=True)
class Profile:
    """A named sweep size.

    Attributes
    ----------
    name : str
    sizes : mapping of int to tuple of int
        Point counts per dimension (fixed-size families ignore them).
    replicates : int
        Seeds per (family, variant, dim, size).
    timeout : float
        Default per-call timeout in seconds.
    triage : TriageBudget
    description : str
    """

    name: str
    sizes: Mapping[int, tuple[int, ...]]
    replicates: int
    timeout: float
    triage: TriageBudget
    description: str


PROFILES: Mapping[str, Profile] = MappingProxyType(
    {
        "quick": Profile(
            name="quick",
            sizes=MappingProxyType({2: (24,), 3: (24,)}),
            replicates=1,
            timeout=10.0,
            # Measured on 2 shared cores: ~80 s end to end with 2 workers (sweep ~25 s, triage ~50 s for
            # 418 groups and ~8500 evaluations); 30 per group lets a 24-point case lose its extra points.
            triage=TriageBudget(calls=12_000, group_calls=30, hang_calls=0, pictures=12, safety_seconds=600.0),
            description="every family and variant once at a small size, every failure group shrunk; "
            "about a minute and a half on 2 cores",
        ),
        "nightly": Profile(
            name="nightly",
            # Measured on 2 cores: one seed of every family at n=256 is ~100 s of sweep;
            # n=512 roughly quadruples that (naive-2d is O(n^3), Henckel's pivoting O(n h)).
            sizes=MappingProxyType({2: (16, 64, 256, 512), 3: (16, 64, 256, 512)}),
            replicates=2,
            timeout=30.0,
            triage=TriageBudget(calls=150_000, group_calls=600, hang_calls=12, pictures=100,
                                safety_seconds=3600.0),
            description="every family and variant at four sizes up to 512 points with two seeds; "
            "about 30 minutes on 2 cores",
        ),
    }
)


def get_profile(name: str) -> Profile:
    """Return the profile ``name`` or raise UsageError listing the valid ones.

    Examples
    --------
    >>> get_profile("quick").sizes[3]
    (24,)
    >>> get_profile("weekly")
    Traceback (most recent call last):
    ...
    hullstress.errors.UsageError: unknown profile 'weekly'; valid profiles: quick, nightly
    """
    try:
        return PROFILES[name]
    except KeyError:
        raise UsageError(f"unknown profile {name!r}; valid profiles: {', '.join(PROFILES)}") from None
