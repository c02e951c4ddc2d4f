"""Search, not only sweep: grow inputs toward failures nobody has seen yet (``python -m hullstress search``).

A sweep runs the cases its catalogue anticipates.  A search keeps a
population of inputs and mutates them (:mod:`.mutate`), keeping a candidate
when it shows a failure signature not seen before, raises the exact
degeneracy score of its dimension (:mod:`.score`) or makes two algorithms
disagree on the extreme points (:mod:`.guidance`).  It runs as the execute
stage of the ordinary pipeline (:mod:`.engine`), so its failures are triaged,
shrunk, reported and saved to the corpus exactly as a sweep's.
"""

from .engine import SEARCH_FAMILY, Search, SearchOptions
from .guidance import Guidance, extreme_answer
from .mutate import MUTATIONS, mutations_for
from .score import SCORE_PARTS, DegeneracyScore, degeneracy_score

__all__ = ["Search", "SearchOptions", "SEARCH_FAMILY", "Guidance", "extreme_answer", "MUTATIONS", "mutations_for",
           "DegeneracyScore", "degeneracy_score", "SCORE_PARTS"]
