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
from dataclasses import dataclass, field
from types import MappingProxyType

from .errors import UsageError

__all__ = ["Defaults", "DEFAULTS", "TriageBudget", "Profile", "PROFILES", "get_profile", "case_memory_bytes",
           "memory_ceiling_bytes"]


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
        What the code under test and its check may allocate in an isolated
        worker, in MiB, beyond the worker's own address space once its
        libraries are loaded (about 0.5 GiB of mappings, most never touched):
        the worker's ``RLIMIT_AS`` is the two together.  4 GiB leaves room for
        large inputs while letting a runaway allocation fail fast.
    min_memory_limit_mb : float
        The smallest ``--memory-limit`` accepted (0, no limit, aside): what a
        worker needs beyond its libraries to judge the profiles' cases (the
        quick profile runs without a memory error at this limit); a smaller
        limit would turn the harness's own work into memory errors.
    max_folders : int
        At most this many failure folders per run (worst groups first).
    shrink_max_calls : int
        Cap on judged calls of one shrink.
    case_bytes_per_coordinate : int
        Peak memory per coordinate of a case while it is generated, hulled and
        checked, in bytes: the worst measured (cospherical 3D points, every one
        extreme, through Qhull and the exact checker: about 1.1 KB; uniform
        points take a fifth of that).  Sizes whose cases would exceed the
        memory limit are refused before anything is generated.
    """

    call_timeout: float = 10.0
    check_timeout_floor: float = 60.0
    memory_limit_mb: float = 4096.0
    min_memory_limit_mb: float = 64.0
    max_folders: int = 2000
    shrink_max_calls: int = 2000
    case_bytes_per_coordinate: int = 1200


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
    simplify_calls : int or None
        Of a group's evaluations, at most this many simplify the coordinates
        of a case whose points are deleted already (None: as many as the
        group's budget leaves).  Deleting points is what makes a case small;
        the first few simplifying evaluations (a power-of-two scale, every
        coordinate rounded to the fewest bits) are what makes it readable,
        and the point-by-point passes after them rarely fit a small budget.
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
    simplify_calls: int | None = None

    def __post_init__(self) -> None:
        for name in ("calls", "group_calls", "hang_calls", "pictures"):
            value = getattr(self, name)
            if not isinstance(value, int) or isinstance(value, bool) or value < 0:
                raise UsageError(f"TriageBudget.{name} must be an integer >= 0, got {value!r}")
        if self.simplify_calls is not None and (not isinstance(self.simplify_calls, int)
                                                or isinstance(self.simplify_calls, bool) or self.simplify_calls < 0):
            raise UsageError(f"TriageBudget.simplify_calls must be an integer >= 0 or None, got {self.simplify_calls!r}")
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
    rotate_sizes : bool
        Give each family variant one of ``sizes``, rotating through them
        (every family meets several sizes at the cost of one); False crosses
        every variant with every size.
    max_points : mapping of str to int
        Algorithms that are not given cases above this many points (slow
        seeds at the profile's largest sizes); the run lists the calls not made.
    """

    name: str
    sizes: Mapping[int, tuple[int, ...]]
    replicates: int
    timeout: float
    triage: TriageBudget
    description: str
    rotate_sizes: bool = False
    max_points: Mapping[str, int] = field(default_factory=lambda: MappingProxyType({}))


PROFILES: Mapping[str, Profile] = MappingProxyType(
    {
        "quick": Profile(
            name="quick",
            # A handful, tens and a hundred points: each variant gets one, rotating.
            sizes=MappingProxyType({2: (8, 24, 100), 3: (8, 24, 100)}),
            rotate_sizes=True,
            replicates=1,
            # The slowest call that ends takes under 0.1 s at these sizes (0.085 s measured, on 2 idle
            # cores); a hang holds a worker this long.  The same limit triage gives a shrink candidate.
            timeout=2.0,
            # Measured on 2 idle cores (2026-11-27): 18.2 s end to end with 2 workers (sweep 7.8 s, triage 8.5 s
            # for 390 groups and 6027 evaluations), about a quarter more when the machine runs slow; 30 per group
            # lets a 24-point case lose its extra points.
            # Simplifying coordinates took 2700 of the 7500 evaluations; 8 keep its scale and global rounding.
            triage=TriageBudget(calls=12_000, group_calls=30, hang_calls=0, pictures=12, safety_seconds=600.0,
                                simplify_calls=8),
            description="every family and variant once, at sizes rotating through 8, 24 and 100 points, every "
            "failure group shrunk",
        ),
        "nightly": Profile(
            name="nightly",
            # Measured on 2 cores: one seed of every family at n=256 is ~100 s of sweep;
            # n=512 roughly quadruples that (naive-2d is O(n^3), Henckel's pivoting O(n h)).
            sizes=MappingProxyType({2: (16, 64, 256, 1024, 4096), 3: (16, 64, 256, 1024, 4096)}),
            replicates=2,
            timeout=30.0,
            triage=TriageBudget(calls=150_000, group_calls=600, hang_calls=12, pictures=100,
                                safety_seconds=3600.0),
            # Measured worst cases (benchmarks/bench_algorithms.py): naive-2d is cubic (21650x
            # scipy at n=4096).  The literal Henckel reaches its step limit on a 4096-point cloud in
            # 0.1 s (its face search is memoised per edge), but outlasts the 30 s timeout on
            # collinear-edges, equal-x-columns and coplanar-grid inputs of that size.
            max_points=MappingProxyType({"naive-2d": 1024, "henckel": 1024}),
            description="every family and variant at five sizes from 16 to 4096 points with two seeds "
            "(naive-2d and the literal henckel up to 1024)",
        ),
    }
)


def case_memory_bytes(n_points: int, dim: int) -> int:
    """Estimated peak memory of one case of ``n_points`` points in ``dim`` dimensions, in bytes.

    Examples
    --------
    >>> case_memory_bytes(10**8, 3) > 300 * 2**30
    True
    """
    return int(n_points) * int(dim) * DEFAULTS.case_bytes_per_coordinate


def memory_ceiling_bytes(memory_limit_mb: float | None) -> tuple[int | None, str]:
    """What one case may take: the per-worker limit, else the machine's memory; with its name for messages."""
    if memory_limit_mb:
        return int(memory_limit_mb * 2**20), f"the --memory-limit of {memory_limit_mb:g} MiB"
    import os

    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None, "no limit"
    return int(total), f"this machine's {total / 2**30:.1f} GiB of memory"


def get_profile(name: str) -> Profile:
    """Return the profile ``name`` or raise UsageError listing the valid ones.

    Examples
    --------
    >>> get_profile("quick").sizes[3]
    (8, 24, 100)
    >>> get_profile("weekly")
    Traceback (most recent call last):
    ...
    hullstress.errors.UsageError: unknown profile 'weekly'; valid profiles: quick, nightly
    """
    try:
        return PROFILES[name]
    except KeyError:
        from .suggest import did_you_mean

        raise UsageError(f"unknown profile {name!r}{did_you_mean(name, PROFILES)}; "
                         f"valid profiles: {', '.join(PROFILES)}") from None
