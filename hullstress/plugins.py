"""Loading plug-ins: ``--plugin MODULE_OR_FILE`` and the ``hullstress.plugins`` entry points.

A plug-in is any module whose import registers algorithms or generators with
:func:`hullstress.register_algorithm` / :func:`hullstress.register_generator`.
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import sys
from importlib.metadata import entry_points
from pathlib import Path
from types import ModuleType

from .errors import UsageError

__all__ = ["ENTRY_POINT_GROUP", "load_plugin", "load_entry_points", "shadowing_folder", "shadowed_message"]

#: Installed packages register their algorithms through this entry-point group.
ENTRY_POINT_GROUP = "hullstress.plugins"


def shadowing_folder() -> str | None:
    """The folder that shadows the installed hullstress package, or None when it is not shadowed.

    A folder named ``hullstress`` without ``__init__.py`` (a clone of the
    project, say) in the current directory is a namespace package: with an
    editable install, ``import hullstress`` then finds that folder first, and
    ``from hullstress import register_algorithm`` fails with "unknown location".
    The real package has a ``__file__``; a namespace package has none.
    """
    package = sys.modules.get("hullstress")
    if package is None or getattr(package, "__file__", None) is not None:
        return None
    paths = [str(p) for p in getattr(package, "__path__", ())]
    return paths[0] if paths else "."


def shadowed_message(folder: str) -> str:
    """The one line that explains a shadowed package (exit status 2)."""
    return (f"the folder {str(Path(folder).resolve())!r} is named hullstress and shadows the installed hullstress "
            "package (Python imports it as an empty namespace package); run from another folder, or rename it")


def load_plugin(spec: str) -> ModuleType:
    """Import a plug-in given as a dotted module name or a path to a ``.py`` file.

    Parameters
    ----------
    spec : str
        ``package.module`` or ``path/to/file.py``.

    Returns
    -------
    module
        The imported module (its import registered whatever it registers).

    Raises
    ------
    UsageError
        When the module or file cannot be found or raises on import; the
        message names ``spec`` and the underlying error on one line.
    """
    path = Path(spec)
    if spec.endswith(".py") or path.is_file():
        if not path.is_file():
            raise UsageError(f"--plugin {spec!r}: no such file")
        resolved = path.resolve()
        # A stable, unique module name per file so that worker processes that
        # re-import the same file get the same name (and pickling by reference works).
        digest = hashlib.sha256(str(resolved).encode()).hexdigest()[:12]
        name = f"hullstress_plugin_{resolved.stem}_{digest}"
        if name in sys.modules:
            return sys.modules[name]
        module_spec = importlib.util.spec_from_file_location(name, resolved)
        if module_spec is None or module_spec.loader is None:
            raise UsageError(f"--plugin {spec!r}: not an importable Python file")
        module = importlib.util.module_from_spec(module_spec)
        sys.modules[name] = module
        try:
            module_spec.loader.exec_module(module)
        except Exception as exc:
            del sys.modules[name]
            _raise_if_shadowed(spec, exc)
            raise UsageError(
                f"--plugin {spec!r}: import failed: {type(exc).__name__}: {exc}"
            ) from exc
        return module
    try:
        return importlib.import_module(spec)
    except ModuleNotFoundError as exc:
        _raise_if_shadowed(spec, exc)
        raise UsageError(f"--plugin {spec!r}: no module named {exc.name!r}") from exc
    except Exception as exc:
        _raise_if_shadowed(spec, exc)
        raise UsageError(
            f"--plugin {spec!r}: import failed: {type(exc).__name__}: {exc}"
        ) from exc


def _raise_if_shadowed(spec: str, exc: BaseException) -> None:
    """A plug-in's ``from hullstress import ...`` failed because a folder shadows the package: say so."""
    folder = shadowing_folder() if isinstance(exc, ImportError) else None
    if folder is not None:
        raise UsageError(f"--plugin {spec!r}: import failed: {shadowed_message(folder)}") from exc


def load_entry_points() -> list[str]:
    """Import every module registered under the ``hullstress.plugins`` entry-point group.

    Returns
    -------
    list of str
        The names of the entry points loaded.
    """
    loaded = []
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        try:
            ep.load()
        except Exception as exc:
            raise UsageError(
                f"entry point {ep.name!r} ({ep.value}) in group {ENTRY_POINT_GROUP!r} "
                f"failed to load: {type(exc).__name__}: {exc}"
            ) from exc
        loaded.append(ep.name)
    return loaded
