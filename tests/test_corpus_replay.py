"""The committed regression corpus, replayed: one test per entry, named after it.

Each entry is a minimised failure found by a sweep (``run --save-corpus``),
with the verdict signature every algorithm config had when it was saved.  A
test fails when its entry regressed: some config now fails differently, or
newly fails.  A fix that makes a recorded failure pass is not a failure here;
``python -m hullstress replay --accept`` then records the new verdicts.
"""

import pytest


@pytest.mark.hullstress_corpus("tests/corpus")
def test_corpus_entry(hullstress_corpus_entry):
    hullstress_corpus_entry.assert_no_regression()
