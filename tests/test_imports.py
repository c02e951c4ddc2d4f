"""Import weight: the package, its registry and the generator families stay light.

A worker process, a plug-in and ``python -m hullstress list`` all start by
importing these; pandas and SciPy load only when a stage that needs them runs.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = ("pandas", "scipy", "matplotlib", "pyarrow", "dask", "hypothesis")


def _loaded_after(statement: str) -> set[str]:
    code = f"{statement}\nimport json, sys\nprint(json.dumps(sorted({{m.split('.')[0] for m in sys.modules}})))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120)
    return set(json.loads(out.stdout.strip().splitlines()[-1]))


@pytest.mark.parametrize(
    "statement",
    [
        "import hullstress",
        "from hullstress import register_algorithm, register_generator, UsageError",
        "import hullstress.registry",
        "import generators",
    ],
)
def test_light_imports_load_no_heavy_library(statement: str) -> None:
    heavy = _loaded_after(statement) & set(HEAVY)
    assert not heavy, f"{statement!r} loaded {sorted(heavy)}"


def test_registry_module_needs_not_even_numpy() -> None:
    assert "numpy" not in _loaded_after("import hullstress.registry")


def test_lazy_names_resolve_to_their_homes() -> None:
    import hullstress
    from hullstress.checker import check
    from hullstress.results import to_frame

    assert hullstress.check is check
    assert hullstress.to_frame is to_frame
    with pytest.raises(AttributeError, match="no attribute 'nonsense'"):
        hullstress.nonsense  # noqa: B018
    assert set(hullstress.__all__) <= set(dir(hullstress))
