"""Algorithm configurations: a registered algorithm plus its sphere and eps variant.

Which variants run when ``--sphere`` / ``--eps`` are not given depends on
where the algorithm comes from (:func:`default_variants`): the in-house
algorithms implement the seed documents, whose claims the sphere and eps
variants test, so both run; a plug-in, adapter or executable is someone's
finished hull code, so by default it sees the input points as they are and
keeps its own tolerance (no ``eps`` is passed).  A ``--sphere`` or ``--eps``
given explicitly applies to every algorithm (``--sphere both`` opts a
library in).
"""

from __future__ import annotations

import re

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from ._registry import AlgorithmSpec, get_algorithm
from .errors import UsageError
from .records import NO_EPS, EpsPolicy, Origin, Sphere

__all__ = [
    "AlgorithmConfig",
    "VariantDefaults",
    "SEED_VARIANTS",
    "LIBRARY_VARIANTS",
    "default_variants",
    "single_config",
    "expand_configs",
    "SPHERE_CHOICES",
    "EPS_CHOICES",
    "NO_EPS",
    "sphere_duplicate_policy",
]

#: The word of ``--sphere`` / ``--eps`` that asks for every variant.
BOTH = "both"
SPHERE_CHOICES = (Sphere.OFF.value, Sphere.ON.value, BOTH)
EPS_CHOICES = (EpsPolicy.SCALED.value, EpsPolicy.FIXED.value, BOTH)
# NO_EPS (records): the eps column's value when no ``eps`` is passed: the algorithm takes none,
# or keeps its own tolerance (a library's default).


def sphere_duplicate_policy(eps: str) -> str:
    """The eps policy of the sphere method's duplicate tolerance for a config's ``eps``: its own, else scaled.

    Examples
    --------
    >>> sphere_duplicate_policy("fixed"), sphere_duplicate_policy(NO_EPS)
    ('fixed', 'scaled')
    """
    return EpsPolicy.SCALED.value if eps == NO_EPS else eps


@dataclass(frozen=True)
class VariantDefaults:
    """The variants an algorithm runs in when ``--sphere`` / ``--eps`` are not given.

    Attributes
    ----------
    sphere : tuple of {"off", "on"}
    eps : tuple of {"scaled", "fixed"}
        Empty: no ``eps`` is passed, the algorithm keeps its own tolerance.
    """

    sphere: tuple[str, ...]
    eps: tuple[str, ...]


#: In-house algorithms: every variant the seeds' claims are about.
SEED_VARIANTS = VariantDefaults(sphere=(Sphere.OFF.value, Sphere.ON.value),
                                eps=(EpsPolicy.SCALED.value, EpsPolicy.FIXED.value))
#: Plug-ins, adapters and executables: the input as it is, the library's own tolerance.
LIBRARY_VARIANTS = VariantDefaults(sphere=(Sphere.OFF.value,), eps=())


def default_variants(origin: str) -> VariantDefaults:
    """The default variants for an algorithm of this origin.

    Examples
    --------
    >>> default_variants("in-house").sphere, default_variants("plugin").eps
    (('off', 'on'), ())
    """
    return SEED_VARIANTS if origin == Origin.IN_HOUSE else LIBRARY_VARIANTS


_SPHERES = frozenset(Sphere)
_EPS_VALUES = frozenset(EpsPolicy) | {NO_EPS}


@dataclass(frozen=True, order=True)
class AlgorithmConfig:
    """One way of running one algorithm.

    Attributes
    ----------
    algorithm : str
        Registered algorithm name.
    sphere : {"off", "on"}
        Whether Kenwright's support mapping and sphere projection run first.
    eps : {"scaled", "fixed", "n/a"}
        The tolerance policy passed as ``eps``; ``n/a`` when none is passed
        (the algorithm takes none, or keeps its own).
    """

    algorithm: str
    sphere: str = Sphere.OFF.value
    eps: str = NO_EPS

    def __post_init__(self) -> None:
        if self.sphere not in _SPHERES:
            raise UsageError(f"sphere must be 'off' or 'on', got {self.sphere!r}")
        if self.eps not in _EPS_VALUES:
            raise UsageError(f"eps must be 'scaled', 'fixed' or {NO_EPS!r}, got {self.eps!r}")
        # Stored as plain strings: a config is a key of tables, JSON and pickles.
        object.__setattr__(self, "sphere", str(self.sphere))
        object.__setattr__(self, "eps", str(self.eps))

    @property
    def variant(self) -> str:
        """``sphere=off,eps=scaled``: the variant without the algorithm's name."""
        return f"sphere={self.sphere},eps={self.eps}"

    @property
    def label(self) -> str:
        """``name[sphere=off,eps=scaled]``: unique per config, used in reports and JUnit."""
        return f"{self.algorithm}[{self.variant}]"

    @property
    def spec(self) -> AlgorithmSpec:
        return get_algorithm(self.algorithm)

    @classmethod
    def from_label(cls, label: str) -> "AlgorithmConfig":
        """The config whose :attr:`label` is ``label``.

        Examples
        --------
        >>> AlgorithmConfig.from_label("gift-wrap-3d[sphere=on,eps=fixed]")
        AlgorithmConfig(algorithm='gift-wrap-3d', sphere='on', eps='fixed')
        >>> AlgorithmConfig.from_label("gift-wrap-3d")
        Traceback (most recent call last):
        ...
        hullstress.errors.UsageError: not a config label (name[sphere=...,eps=...]): 'gift-wrap-3d'
        """
        match = _LABEL.match(label)
        if match is None:
            raise UsageError(f"not a config label (name[sphere=...,eps=...]): {label!r}")
        return cls(match["algorithm"], match["sphere"], match["eps"])


#: How :attr:`AlgorithmConfig.label` spells a config.
_LABEL = re.compile(r"^(?P<algorithm>.+)\[sphere=(?P<sphere>[^,\]]+),eps=(?P<eps>[^\]]+)\]$")


def _choices(value: str, allowed: Sequence[str], option: str) -> tuple[str, ...]:
    if value not in allowed:
        from .suggest import did_you_mean

        raise UsageError(f"{option} must be one of {', '.join(allowed)}, got {value!r}{did_you_mean(value, allowed)}")
    if value == BOTH:
        return tuple(a for a in allowed if a != BOTH)
    return (value,)


def single_config(spec: AlgorithmSpec, sphere: str = Sphere.OFF.value, eps: str | None = None) -> AlgorithmConfig:
    """One config of ``spec`` (for shrink and fuzz): ``eps=None`` means its origin's first default.

    Examples
    --------
    >>> from hullstress import get_algorithm
    >>> single_config(get_algorithm("monotone-chain")).label
    'monotone-chain[sphere=off,eps=scaled]'
    """
    if not spec.takes_eps:
        return AlgorithmConfig(spec.name, sphere, NO_EPS)
    if eps is None:
        eps = next(iter(default_variants(spec.origin).eps), NO_EPS)
    return AlgorithmConfig(spec.name, sphere, eps)


def expand_configs(
    specs: Iterable[AlgorithmSpec], *, sphere: str | None = None, eps: str | None = None
) -> list[AlgorithmConfig]:
    """Cross algorithms with the requested variants.

    Parameters
    ----------
    specs : iterable of AlgorithmSpec
    sphere : {"off", "on", "both"} or None
        None: each algorithm's default (:func:`default_variants`); given, it
        applies to every algorithm.
    eps : {"scaled", "fixed", "both"} or None
        The same; applies only to algorithms that accept ``eps``, the others get ``n/a``.

    Returns
    -------
    list of AlgorithmConfig
        Sorted, without duplicates.
    """
    spheres = _choices(sphere, SPHERE_CHOICES, "--sphere") if sphere is not None else None
    epses = _choices(eps, EPS_CHOICES, "--eps") if eps is not None else None
    out = set()
    for spec in specs:
        defaults = default_variants(spec.origin)
        spec_eps = (epses if epses is not None else defaults.eps) if spec.takes_eps else ()
        for s in spheres if spheres is not None else defaults.sphere:
            for e in spec_eps or (NO_EPS,):
                out.add(AlgorithmConfig(spec.name, s, e))
    return sorted(out)
