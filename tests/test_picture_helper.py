"""The report's pictures drawn by a helper process (:mod:`hullstress.report.picture_helper`).

With two or more workers a helper draws the top causes' pictures while the
report writes its folders.  What it draws must be exactly what the report
would draw itself; whatever happens to it (a picture that raises, a helper
that dies, an interrupt while waiting for it) the report must go on as it
would have without it.
"""

from __future__ import annotations

import json
import signal
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from hullstress.report.failures import CASE_FILE, picture_png, picture_request
from hullstress.report.picture_helper import PictureDrawer
from hullstress.report.pictures import PNG_SIGNATURE
from hullstress.runner import start_method


@dataclass(frozen=True)
class _Label:
    label: str


@dataclass(frozen=True)
class _Record:
    """What :func:`picture_request` reads of a :class:`~hullstress.report.failures.FailureRecord`."""

    folder: Path
    points: np.ndarray
    offending: dict
    signature: _Label
    minimal_size: int


def _folder(root: Path, name: str, points: np.ndarray, faces, offending=None) -> _Record:
    folder = root / name
    folder.mkdir()
    (folder / "faces.json").write_text(json.dumps({"faces": faces}))
    (folder / CASE_FILE).write_text(json.dumps({"dim": points.shape[1]}))
    return _Record(folder, points, offending or {}, _Label(name), len(points))


def _records(root: Path) -> list[_Record]:
    rng = np.random.default_rng(3)
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]])
    tetra = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.2, 0.2, 0.2]])
    return [
        _folder(root, "square", square, [0, 1, 2], {"containment": [3]}),
        _folder(root, "tetra", tetra, [[0, 2, 1], [0, 1, 3], [0, 3, 2]], {"manifoldness_faces": [1]}),
        _folder(root, "cloud", rng.normal(size=(40, 2)) * 1e300, None),
        _folder(root, "single", np.array([[0.0, 0.0, 0.0]]), []),
    ]


@pytest.fixture(scope="module", autouse=True)
def _fork_server():
    start_method()  # the run's fork server, with its imports, as in a run


def test_the_helper_draws_the_bytes_this_process_draws_in_any_order_of_asking(tmp_path):
    records = _records(tmp_path)
    here = [picture_png(*picture_request(r)) for r in records]
    with PictureDrawer.start(pictures=True, workers=2) as drawer:
        assert drawer.helped
        for record in records:
            drawer.request(record)
        # Asked in order, collected out of it: answers read on the way wait for their turn.
        got = {k: drawer.drawn(records[k]) for k in (2, 0, 3, 1)}
    assert [got[k] for k in range(len(records))] == here
    assert all(png.startswith(PNG_SIGNATURE) for png in here)


def test_a_picture_not_asked_for_or_after_close_is_drawn_here(tmp_path):
    records = _records(tmp_path)
    drawer = PictureDrawer.start(pictures=True, workers=2)
    drawer.request(records[0])
    assert drawer.drawn(records[1]) is None  # never asked: the report draws it itself
    drawer.close()
    assert drawer.drawn(records[0]) is None
    assert not drawer.helped
    drawer.close()  # twice is harmless


def test_what_drawing_raises_in_the_helper_is_raised_here(tmp_path):
    records = _records(tmp_path)
    (records[1].folder / "faces.json").unlink()
    with pytest.raises(FileNotFoundError) as here:
        picture_png(*picture_request(records[1]))
    with PictureDrawer.start(pictures=True, workers=2) as drawer:
        for record in records[:3]:
            drawer.request(record)
        with pytest.raises(FileNotFoundError) as there:
            drawer.drawn(records[1])
        assert str(there.value) == str(here.value)
        # The helper lives on: the next picture is its.
        assert drawer.drawn(records[2]) == picture_png(*picture_request(records[2]))


def test_a_helper_that_dies_leaves_its_pictures_to_this_process(tmp_path):
    records = _records(tmp_path)
    with PictureDrawer.start(pictures=True, workers=2) as drawer:
        drawer.request(records[0])
        assert drawer.drawn(records[0]) == picture_png(*picture_request(records[0]))
        drawer._helper.process.kill()
        drawer._helper.process.join()
        drawer.request(records[1])
        assert drawer.drawn(records[1]) is None


def test_an_interrupt_while_waiting_raises_here_and_close_ends_the_helper_at_once(tmp_path):
    # A picture of 150 000 triangles takes seconds: an interrupt comes while this process waits.
    rng = np.random.default_rng(0)
    big = _folder(tmp_path, "big", rng.normal(size=(3000, 3)), rng.integers(0, 3000, size=(150_000, 3)).tolist())
    small = _records(tmp_path)[0]

    def interrupt(signum, frame):
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGALRM, interrupt)
    drawer = PictureDrawer.start(pictures=True, workers=2)
    try:
        process = drawer._helper.process
        drawer.request(big)
        drawer.request(small)
        signal.setitimer(signal.ITIMER_REAL, 0.5)
        started = time.monotonic()
        with pytest.raises(KeyboardInterrupt):
            drawer.drawn(big)
        assert time.monotonic() - started < 1.0
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
        started = time.monotonic()
        drawer.close()
    assert time.monotonic() - started < 1.0
    assert not process.is_alive() and process.exitcode == -signal.SIGKILL


@pytest.mark.parametrize("pictures, workers", [(True, 1), (False, 2), (False, 1)])
def test_one_worker_or_no_pictures_starts_no_helper(pictures, workers):
    with PictureDrawer.start(pictures=pictures, workers=workers) as drawer:
        assert not drawer.helped


def test_a_drawer_starts_its_helper_when_begun_or_first_asked(tmp_path):
    # The pipeline makes the drawer before the sweep and begins it when the sweep ends, so that the
    # helper's warm-up does not take CPU from the sweep's workers.
    record = _records(tmp_path)[0]
    with PictureDrawer(pictures=True, workers=2) as drawer:
        assert not drawer.helped
        drawer.begin()
        assert drawer.helped
    with PictureDrawer(pictures=True, workers=2) as drawer:
        drawer.request(record)
        assert drawer.helped and drawer.drawn(record) == picture_png(*picture_request(record))
