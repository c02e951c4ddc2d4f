"""Adapters that register real hull libraries as hullstress algorithms.

Each adapter module registers its algorithms when it is imported, and it is
imported only when its library imports: the libraries are optional extras.
Importing this package loads none of them; :func:`register_all` (called when
the registry first loads its built-ins) does, so that the light
:mod:`.executable` adapter can be imported by a plug-in without SciPy.
A library that is not installed means "not registered"; that is not an error,
but it is recorded, and :func:`missing_adapters` says why, so that
``hullstress list`` can show what is absent and how to install it.

=============  =========================  ===========================================
family         module                     algorithms
=============  =========================  ===========================================
scipy-qhull    :mod:`.scipy_qhull`        Qhull through ``scipy.spatial.ConvexHull``
                                          under several option sets, 2D and 3D
shapely-geos   :mod:`.shapely_geos`       GEOS ``convex_hull`` through shapely, 2D
cgal           :mod:`.cgal_hull`          CGAL's 2D and 3D hulls through the ``cgal``
                                          SWIG bindings
executable     :mod:`.executable`         any program reading Qhull-format points on
                                          stdin (``--exec``, ``register_executable``)
=============  =========================  ===========================================
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass

from ..errors import one_line

__all__ = ["available_adapters", "missing_adapters", "register_all"]


@dataclass(frozen=True)
class _Adapter:
    """One adapter module and the library it needs."""

    family: str
    module: str
    library: str  # top-level import name of the library
    install: str  # what to run when it is missing


_ADAPTERS = (
    _Adapter("scipy-qhull", "scipy_qhull", "scipy", "pip install scipy"),
    _Adapter("shapely-geos", "shapely_geos", "shapely", "pip install 'shapely>=2.0'"),
    _Adapter("cgal", "cgal_hull", "CGAL", "pip install cgal"),
)


def _probe(adapter: _Adapter) -> tuple[tuple[str, ...], str | None]:
    """Import one adapter module; return (registered names, None) or ((), reason)."""
    try:
        module = importlib.import_module(f"{__name__}.{adapter.module}")
    except ImportError as exc:
        name = exc.name or ""
        if name == "hullstress" or name.startswith("hullstress."):
            raise  # a bug in hullstress itself must not pass for a missing extra
        if isinstance(exc, ModuleNotFoundError) and name == adapter.library:
            return (), f"{adapter.library} not installed ({adapter.install})"
        # Installed but unusable (a broken build, a missing shared library, an
        # incompatible version): still optional, but say exactly what failed.
        return (), f"{adapter.library} failed to import: {one_line(exc)}"
    return tuple(module.ALGORITHM_NAMES), None


_AVAILABLE: dict[str, tuple[str, ...]] = {}
_MISSING: dict[str, str] = {}
_probed = False


def register_all() -> None:
    """Import every library adapter whose library imports (once); record why the others are absent."""
    global _probed
    if _probed:
        return
    _probed = True
    for adapter in _ADAPTERS:
        names, reason = _probe(adapter)
        if reason is None:
            _AVAILABLE[adapter.family] = names
        else:
            _MISSING[adapter.family] = reason


def available_adapters() -> dict[str, tuple[str, ...]]:
    """Adapter families whose library imported, with the algorithm names each registered.

    Returns
    -------
    dict of str to tuple of str
        E.g. ``{"scipy-qhull": ("scipy-qhull-2d", ...), "shapely-geos": ("shapely-convex-hull",)}``.

    Examples
    --------
    >>> "scipy-qhull" in available_adapters()
    True
    """
    register_all()
    return dict(_AVAILABLE)


def missing_adapters() -> dict[str, str]:
    """Adapter families that are not registered, with the reason.

    Returns
    -------
    dict of str to str
        E.g. ``{"cgal": "CGAL not installed (pip install cgal)"}``; empty when
        every adapter's library imported.

    Examples
    --------
    >>> isinstance(missing_adapters(), dict)
    True
    """
    register_all()
    return dict(_MISSING)
