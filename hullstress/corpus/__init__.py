"""The regression corpus: one JSON file per minimised case, replayed against every config.

One entry per failure group: the group is a
:class:`~hullstress.triage.signature.Signature`, the one identity of "the
same failure" that triage, the report, ``--baseline`` and ``replay`` share.

* :mod:`.store` -- the file format, loading, atomic saving, the groups a corpus holds.
* :mod:`.save` -- ``run --save-corpus``: each failure group the corpus does not
  hold yet becomes an entry (its minimal case).
* :mod:`.replay` -- ``replay``: every entry against every config, classified
  against the recorded verdicts.
* :mod:`.baseline` -- ``run --baseline``: which failure groups are new, still
  failing, fixed or not reached against an earlier run or a corpus.

The submodules are imported on first use: ``store`` needs NumPy and pandas,
the others the runner too.
"""

from __future__ import annotations

from importlib import import_module
from pathlib import Path
from typing import Any

__all__ = [
    "DEFAULT_CORPUS",
    "CorpusEntry",
    "iter_corpus",
    "load_entry",
    "save_entry",
    "replay_corpus",
    "add_to_corpus",
    "save_new_groups",
    "load_baseline",
    "compare_with_baseline",
]

#: Where the project's own regression corpus lives (relative to the repository root).  Here, not in
#: :mod:`.store`: the command line's help shows it, and building the parser must not import NumPy.
DEFAULT_CORPUS = Path("tests") / "corpus"

_HOMES = {
    "CorpusEntry": "store", "iter_corpus": "store", "load_entry": "store",
    "save_entry": "store", "replay_corpus": "replay", "add_to_corpus": "replay",
    "save_new_groups": "save", "load_baseline": "baseline", "compare_with_baseline": "baseline",
}


def __getattr__(name: str) -> Any:
    if name in _HOMES:
        return getattr(import_module(f"{__name__}.{_HOMES[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
