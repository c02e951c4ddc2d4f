"""Registries of hull algorithms and point-set generators.

Both are filled by decorators (:func:`register_algorithm`,
:func:`register_generator`); programs in any language register with
:func:`register_executable`.  The built-in entries live in
``hullstress.algorithms``, ``hullstress.adapters`` and the top-level
``generators`` package; they are imported lazily, the first time a registry is
read, so that ``import hullstress`` stays cheap and a plug-in can register
before or after the built-ins load.
"""

from __future__ import annotations

import inspect
import threading
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import Any, Generic, TypeVar

from .errors import DuplicateNameError, UnknownNameError, UsageError
from .hull_contract import LENIENT, HullContract, as_contract
from .records import Origin

__all__ = [
    "AlgorithmSpec",
    "GeneratorSpec",
    "Registry",
    "ALGORITHMS",
    "GENERATORS",
    "register_algorithm",
    "register_generator",
    "register_executable",
    "set_clockwise",
    "set_contract",
    "ORIGINS",
    "get_algorithm",
    "get_generator",
    "algorithms",
    "generators",
    "load_builtins",
]


def _summary(func: Callable[..., Any]) -> str:
    doc = inspect.getdoc(func) or ""
    return doc.strip().splitlines()[0] if doc.strip() else ""


#: Where a registered algorithm comes from (the ``origin`` column).
ORIGINS = tuple(o.value for o in Origin)


def _origin(func: Callable[..., Any]) -> str:
    module = getattr(func, "__module__", "") or ""
    if module.startswith("hullstress.algorithms"):
        return "in-house"
    if module.startswith("hullstress.adapters"):
        return "adapter"
    return "plugin"


@dataclass(frozen=True)
class AlgorithmSpec:
    """A registered hull algorithm.

    Attributes
    ----------
    name : str
        The registry name (``--algorithm NAME``).
    func : callable
        ``func(points, /, **kw) -> faces`` under docs/design.md's contract.
    dim : int
        2 or 3.
    takes_eps : bool
        Whether ``func`` accepts an ``eps`` keyword; the eps variants apply only then.
    origin : str
        One of :data:`ORIGINS`: ``in-house``, ``adapter``, ``plugin`` or ``executable``.
    summary : str
        First line of the function's docstring (an executable's command).
    writable : bool
        ``func`` receives a writable copy of the points instead of the
        read-only array (for libraries that write into their input).
    clockwise : bool
        ``func`` returns faces clockwise seen from outside (2D: a clockwise
        polygon); each is reversed before checking.
    contract : HullContract
        What the algorithm promises (:mod:`hullstress.hull_contract`); its
        rows are judged against it.  Its ``orientation`` always agrees with
        ``clockwise``.
    """

    name: str
    func: Callable[..., Any]
    dim: int
    takes_eps: bool
    origin: str
    summary: str
    writable: bool = False
    clockwise: bool = False
    contract: HullContract = LENIENT

    def __post_init__(self) -> None:
        # One truth for the orientation: ``clockwise`` (the mechanism) and the declared contract agree.
        clockwise = self.clockwise or self.contract.orientation == "cw"
        object.__setattr__(self, "clockwise", clockwise)
        object.__setattr__(self, "contract", replace(self.contract, orientation="cw" if clockwise else "ccw"))

    @property
    def module(self) -> str:
        return getattr(self.func, "__module__", "")


@dataclass(frozen=True)
class GeneratorSpec:
    """A registered point-set family.

    Attributes
    ----------
    name : str
        The family name (``--generator NAME``).
    func : callable
        ``func(rng, n, *, dim, **params) -> ndarray of shape (n, dim)``.
    dims : tuple of int
        The dimensions the family supports.
    defaults : mapping
        Keyword parameters and their defaults, read from the signature.
    variants : tuple of mapping
        Parameter sets worth sweeping; the profiles run each of them.
    fixed_size : bool
        True when the family ignores ``n`` (fixed published cases).
    summary : str
        First line of the docstring: what the family stresses.
    """

    name: str
    func: Callable[..., Any]
    dims: tuple[int, ...]
    defaults: Mapping[str, Any]
    variants: tuple[Mapping[str, Any], ...]
    fixed_size: bool
    summary: str


T = TypeVar("T", AlgorithmSpec, GeneratorSpec)


class Registry(Generic[T]):
    """A name -> spec mapping that reports unknown names with the valid ones."""

    def __init__(self, kind: str) -> None:
        self.kind = kind
        self._items: dict[str, T] = {}
        self._lock = threading.Lock()

    def add(self, spec: T) -> T:
        with self._lock:
            old = self._items.get(spec.name)
            if old is not None and not _same_function(old.func, spec.func):
                raise DuplicateNameError(
                    f"{self.kind} {spec.name!r} is already registered by "
                    f"{_qualname(old.func)}; cannot register {_qualname(spec.func)}"
                )
            self._items[spec.name] = spec
        return spec

    def replace(self, spec: T) -> T:
        """Register ``spec`` over whatever holds its name (a changed option of the same entry)."""
        with self._lock:
            self._items[spec.name] = spec
        return spec

    def remove(self, name: str) -> None:
        """Forget ``name`` (used by tests and by plug-ins that re-register)."""
        with self._lock:
            self._items.pop(name, None)

    def get(self, name: str) -> T:
        load_builtins()
        try:
            return self._items[name]
        except KeyError:
            from .suggest import unknown_name

            raise UnknownNameError(unknown_name(self.kind, name, self._items)) from None

    def names(self) -> list[str]:
        load_builtins()
        return sorted(self._items)

    def specs(self) -> list[T]:
        load_builtins()
        return [self._items[k] for k in sorted(self._items)]

    def __contains__(self, name: object) -> bool:
        load_builtins()
        return name in self._items

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())

    def __len__(self) -> int:
        load_builtins()
        return len(self._items)


def _qualname(func: Callable[..., Any]) -> str:
    label = getattr(func, "registry_label", None)  # an executable: its command, not its class
    if isinstance(label, str):
        return label
    return f"{getattr(func, '__module__', '?')}.{getattr(func, '__qualname__', func)!s}"


def _same_function(a: Callable[..., Any], b: Callable[..., Any]) -> bool:
    # Re-importing a plug-in file (e.g. twice through --plugin) yields a new
    # function object with the same qualified name; that is not a conflict.
    return a is b or _qualname(a) == _qualname(b)


ALGORITHMS: Registry[AlgorithmSpec] = Registry("algorithm")
GENERATORS: Registry[GeneratorSpec] = Registry("generator")


def _check_name_and_dim(kind: str, name: Any, dim: Any) -> None:
    if not isinstance(name, str) or not name.strip():
        raise UsageError(f"{kind} name must be a non-empty string, got {name!r}")
    if dim not in (2, 3):
        raise UsageError(f"dim must be 2 or 3, got {dim!r}")


def register_algorithm(
    name: str, *, dim: int, writable: bool = False, clockwise: bool = False,
    contract: HullContract | str | None = None,
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Register a hull algorithm under ``name`` (a decorator).

    Parameters
    ----------
    name : str
        Registry name, e.g. ``"my-quickhull"``.
    dim : {2, 3}
        Dimension of the points the function accepts.
    writable : bool
        Pass a writable copy of the points (default: the read-only array
        itself, so a function that writes into its input fails loudly
        instead of corrupting the case).
    clockwise : bool
        The function returns faces clockwise seen from outside (a clockwise
        polygon in 2D); hullstress reverses each before checking.
    contract : HullContract or str, optional
        What the function promises, judged on every row: ``"lenient"`` (the
        default: points on edges and faces may be vertices), ``"strict"``
        (only extreme points as vertices), or ``KEY=VALUE`` items such as
        ``"strict,faces=triangles,flat=raise"`` (:mod:`hullstress.hull_contract`).

    Returns
    -------
    callable
        A decorator that registers the function and returns it unchanged.

    Notes
    -----
    The function receives an ``(n, dim)`` float64, C-contiguous, read-only
    array (a writable copy with ``writable=True``) and returns, in 3D, an
    ``(m, 3)`` integer array of counter-clockwise triangles or a list of
    polygons; in 2D, a counter-clockwise sequence of vertex indices.  If it
    accepts a keyword ``eps``, the eps variants apply.

    Examples
    --------
    >>> from hullstress import register_algorithm
    >>> @register_algorithm("doc-example-triangle", dim=2)
    ... def triangle_only(points):
    ...     '''Accepts exactly three points (declines a degenerate pair).'''
    ...     if len(points) != 3:
    ...         raise ValueError("need exactly 3 points")
    ...     return [0, 1, 2]
    >>> ALGORITHMS.remove("doc-example-triangle")  # keep the registry as it was
    """
    _check_name_and_dim("algorithm", name, dim)
    declared = as_contract(contract)

    def decorate(func: Callable[..., Any]) -> Callable[..., Any]:
        if not callable(func):
            raise UsageError(f"register_algorithm needs a callable, got {func!r}")
        try:
            params = inspect.signature(func).parameters
        except (TypeError, ValueError):
            params = {}
        takes_eps = "eps" in params or any(
            p.kind is inspect.Parameter.VAR_KEYWORD for p in params.values()
        )
        ALGORITHMS.add(
            AlgorithmSpec(
                name=name,
                func=func,
                dim=int(dim),
                takes_eps=takes_eps,
                origin=_origin(func),
                summary=_summary(func),
                writable=bool(writable),
                clockwise=bool(clockwise),
                contract=declared,
            )
        )
        return func

    return decorate


def register_executable(
    name: str,
    command: str | Sequence[str],
    *,
    dim: int,
    output: str = "i",
    clockwise: bool = False,
    contract: HullContract | str | None = None,
    mode: str = "spawn",
    probe: bool = True,
) -> AlgorithmSpec:
    """Register a program in any language as a hull algorithm.

    The program reads the points on stdin in Qhull's input format (the
    dimension, the count, one point per line at full precision, as ``rbox``
    writes them) and writes its hull on stdout.  It runs under the same
    isolation as Python algorithms (per-call timeout, memory limit); a
    non-zero exit is an ``error`` (``rejected`` on degenerate input) and
    death by a signal a ``crash``, each with the tail of its stderr in the
    row's reason; output that cannot be parsed is a ``fail`` naming the line.

    Parameters
    ----------
    name : str
        Registry name (``--algorithm NAME``).
    command : str or sequence of str
        The command line, split like a shell would (``"qconvex Qt i"``); it
        is not run through a shell (use ``["sh", "-c", "..."]`` for pipes).
    dim : {2, 3}
        Dimension of the points the program hulls.
    output : {"i", "Fx", "off"}
        What it writes: Qhull's ``i`` (a count line, then one facet per line
        as vertex indices; in 2D, Qhull's ``i`` lists edges ``a b``),
        Qhull's ``Fx`` (2D only: the count, then the extreme point indices in
        counter-clockwise order) or OFF (vertex coordinates, matched exactly to
        input points, then faces).
    clockwise : bool
        The program writes 3D faces clockwise seen from outside, as Qhull's
        ``i`` does (2D: a clockwise polygon); they are reversed before checking.
    contract : HullContract or str, optional
        What the program promises (as for :func:`register_algorithm`; lenient by default).
    mode : {"spawn", "persistent"}
        ``spawn``: one process per case.  ``persistent``: the program starts
        once per worker and answers case after case over the protocol of
        :mod:`hullstress.adapters.exec_protocol` (a handshake, then framed cases).
    probe : bool
        Run the program once now on five points in general position
        (:func:`hullstress.adapters.executable.probe`): a program that cannot
        start, prints nothing, never answers its handshake or speaks another
        dimension is refused here; what it says it is (its handshake or
        ``--version``) is kept for ``run.json`` and the report.

    Returns
    -------
    AlgorithmSpec

    Raises
    ------
    UsageError
        A bad option, a program not found, a name already registered, a
        failed probe: one line naming the program and the problem.

    Examples
    --------
    >>> from hullstress.registry import register_executable, ALGORITHMS
    >>> spec = register_executable("doc-qconvex", "qconvex Qt i", dim=3, clockwise=True)
    >>> spec.origin, spec.summary
    ('executable', 'qconvex Qt i (Qhull i output, clockwise)')
    >>> ALGORITHMS.remove("doc-qconvex")
    """
    _check_name_and_dim("executable", name, dim)
    # Imported here: the adapter module is light, but the registry stays lighter.
    from .adapters.executable import ExecutableHull

    load_builtins()  # a clash with a built-in name is reported here, naming this program
    declared = as_contract(contract)
    func = ExecutableHull.from_command(command, dim=int(dim), output=output, mode=mode)
    clockwise = bool(clockwise) or declared.orientation == "cw"
    spec = ALGORITHMS.add(  # before running anything: a clash names both entries
        AlgorithmSpec(name=name, func=func, dim=int(dim), takes_eps=False, origin=Origin.EXECUTABLE.value,
                      summary=func.describe(clockwise=clockwise), clockwise=clockwise, contract=declared)
    )
    if probe:
        try:
            spec = probe_executable(name)
        except UsageError:
            ALGORITHMS.remove(name)
            raise
    return spec


def probe_executable(name: str) -> AlgorithmSpec:
    """Run the registered program ``name`` once on a small case and keep what it says it is.

    See :func:`hullstress.adapters.executable.probe`; ``--exec`` registers
    every program first and probes them afterwards, so that a malformed
    option or a duplicate name is reported before any program runs.

    Raises
    ------
    UsageError
        The program is refused (one line naming it and the problem).
    """
    from .adapters.executable import probe

    spec = ALGORITHMS.get(name)
    func = probe(spec.func)
    return ALGORITHMS.replace(replace(spec, func=func, summary=func.describe(clockwise=spec.clockwise)))


def set_clockwise(name: str, clockwise: bool = True) -> AlgorithmSpec:
    """Mark the registered algorithm ``name`` as returning clockwise faces (``run --clockwise NAME``).

    Raises
    ------
    UnknownNameError
        When ``name`` is not registered (the message lists the valid names).
    """
    spec = ALGORITHMS.get(name)
    if spec.clockwise == clockwise:
        return spec
    orientation = "cw" if clockwise else "ccw"
    return ALGORITHMS.replace(replace(spec, clockwise=bool(clockwise),
                                      contract=replace(spec.contract, orientation=orientation)))


def set_contract(name: str, contract: HullContract | str) -> AlgorithmSpec:
    """Declare the contract of the registered algorithm ``name`` (``run --contract NAME=SPEC``).

    The orientation stays what the registration (or ``--clockwise``) said
    unless ``contract`` names one.

    Raises
    ------
    UnknownNameError
        When ``name`` is not registered.
    UsageError
        When ``contract`` is not a valid contract spelling.
    """
    spec = ALGORITHMS.get(name)
    declared = as_contract(contract)
    said_orientation = isinstance(contract, str) and "orientation=" in contract
    if not said_orientation:
        declared = replace(declared, orientation=spec.contract.orientation)
    return ALGORITHMS.replace(replace(spec, contract=declared, clockwise=declared.orientation == "cw"))


def register_generator(
    name: str,
    *,
    dims: tuple[int, ...] | list[int] = (2, 3),
    variants: tuple[Mapping[str, Any], ...] | list[Mapping[str, Any]] = ({},),
    fixed_size: bool = False,
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Register a point-set family under ``name`` (a decorator).

    Parameters
    ----------
    name : str
        Family name, e.g. ``"coplanar-grid"``.
    dims : tuple of int
        Dimensions the family supports.
    variants : sequence of mapping
        Parameter sets the sweep profiles run (each merged over the defaults).
    fixed_size : bool
        True when the family ignores ``n`` (fixed published cases).

    Returns
    -------
    callable
        A decorator that registers the function and returns it unchanged.

    Notes
    -----
    The function is called as ``func(rng, n, *, dim, **params)`` with a
    ``numpy.random.Generator`` and must return an ``(n, dim)`` float64 array;
    the same (family, params, seed) must always give the same bytes.
    """
    if not isinstance(name, str) or not name.strip():
        raise UsageError(f"generator name must be a non-empty string, got {name!r}")
    dims_t = tuple(int(d) for d in dims)
    if not dims_t or any(d not in (2, 3) for d in dims_t):
        raise UsageError(f"dims must be a non-empty subset of (2, 3), got {dims!r}")

    def decorate(func: Callable[..., Any]) -> Callable[..., Any]:
        sig = inspect.signature(func)
        defaults = {
            p.name: p.default
            for p in sig.parameters.values()
            if p.kind is inspect.Parameter.KEYWORD_ONLY
            and p.name != "dim"
            and p.default is not inspect.Parameter.empty
        }
        for v in variants:
            unknown = set(v) - set(defaults)
            if unknown:
                raise UsageError(
                    f"generator {name!r}: variant {dict(v)!r} names unknown "
                    f"parameters {sorted(unknown)}; known: {sorted(defaults)}"
                )
        GENERATORS.add(
            GeneratorSpec(
                name=name,
                func=func,
                dims=dims_t,
                defaults=MappingProxyType(defaults),
                variants=tuple(MappingProxyType(dict(v)) for v in variants),
                fixed_size=bool(fixed_size),
                summary=_summary(func),
            )
        )
        return func

    return decorate


_loaded = False
_loading = threading.RLock()


def load_builtins() -> None:
    """Import the built-in algorithms, adapters, generators and entry-point plug-ins once."""
    global _loaded
    if _loaded:
        return
    with _loading:
        if _loaded:
            return
        _loaded = True  # set first: the imports below call back into the registries
        import importlib

        for module in ("hullstress.algorithms", "hullstress.adapters", "generators"):
            try:
                imported = importlib.import_module(module)
            except ModuleNotFoundError as exc:
                # Only tolerate the package itself being absent (a partial
                # install); a missing dependency inside it is a real error.
                if exc.name != module:
                    raise
                continue
            # A package whose import is kept light registers on request (the adapters).
            register_all = getattr(imported, "register_all", None)
            if callable(register_all):
                register_all()
        from . import plugins

        plugins.load_entry_points()


def get_algorithm(name: str) -> AlgorithmSpec:
    """Return the registered algorithm ``name`` or raise :class:`UnknownNameError`."""
    return ALGORITHMS.get(name)


def get_generator(name: str) -> GeneratorSpec:
    """Return the registered generator ``name`` or raise :class:`UnknownNameError`."""
    return GENERATORS.get(name)


def algorithms(dim: int | None = None) -> list[AlgorithmSpec]:
    """All registered algorithms (optionally only those of dimension ``dim``), by name."""
    return [s for s in ALGORITHMS.specs() if dim is None or s.dim == dim]


def generators(dim: int | None = None) -> list[GeneratorSpec]:
    """All registered generators (optionally only those supporting ``dim``), by name."""
    return [s for s in GENERATORS.specs() if dim is None or dim in s.dims]
