"""The report's pictures, drawn by processes of their own when the run has workers to spare.

Drawing the top causes' pictures is the report's longest step: about 50 ms a
picture on matplotlib's Agg canvas, most of it ticks and text, after about
0.3 s of importing matplotlib and drawing a first picture (fonts, 3D axes).
A run with two or more workers has the cores for it.  When its sweep's tail
first leaves a core idle, or at the latest when the sweep ends
(:meth:`PictureDrawer.begin`), a helper process forked from the run's fork
server imports matplotlib, draws a throw-away picture and forks
:data:`DRAWERS` - 1 copies of itself, warm as it is, on that idle core
(while the last calls run, or this process writes the tables); this process
never imports matplotlib.  In the report the drawers take the requested
pictures in turn while this process writes the cause folders and the
tables (and the findings come from another helper that computed them
during triage: :class:`hullstress.report.stage.FindingsBeside`).

With one worker, or when the helper cannot start or a drawer dies, the
pictures it has not delivered are drawn here instead, by the same function:
the PNG bytes depend only on the folder's files, the points, the offending
indices and the title (:func:`hullstress.report.failures.picture_png`),
whichever process draws them, so a run's folders are byte-identical on any
number of workers.

Each drawer has a pipe of its own; the requests go to them in turn, from a
thread of this process (a large case's points never hold up the report on a
full pipe), and the PNG bytes come back on the same pipes, each tagged with
its folder, where another thread reads them as they come (a drawer never
waits for the report to ask).  A drawer leaves at the end of file of its
pipe, so none outlives a run that is killed.  The drawers ignore SIGINT like
the sweep's workers: an interrupt raises here, in the wait for a picture, as
it would in the drawing of one, and :meth:`PictureDrawer.close` kills the
helper (its copies die with it), so a picture under way never delays the
run's exit.
"""

from __future__ import annotations

import multiprocessing
import os
import queue
import threading
from multiprocessing.connection import Connection, wait
from pathlib import Path
from typing import Any

from .failures import FailureRecord, picture_png, picture_request
from ..forkserver import current_niceness, die_with_parent, helper_start
from .pictures import preload_matplotlib

__all__ = ["PictureDrawer", "DRAWERS"]

#: Processes that draw the pictures when the run has workers to spare: a dozen pictures then take
#: about as long as the rest of the report (writing 135 folders, the tables and report.html).
DRAWERS = 2


def _serve(ends: list[Connection], niceness: int) -> None:
    """The helper's life: load and warm up matplotlib, fork the other drawers from itself, then draw
    the pictures asked on its own pipe until the run closes it (or dies)."""
    helper_start(niceness)  # it leaves at the end of file of its pipe
    preload_matplotlib()
    _warm_up()
    mine = ends[0]
    for other in ends[1:]:
        # A fork of this warm process draws as fast at once, for no second import; it dies with it.
        if os.fork() == 0:
            die_with_parent()
            mine = other
            break
    for end in ends:
        if end is not mine:
            end.close()  # each pipe has one drawer: the run's end of file reaches it
    _draw_until_closed(mine)


def _draw_until_closed(conn: Connection) -> None:
    """Draw each picture asked on ``conn`` and send its PNG bytes back; leave at end of file."""
    while True:
        try:
            request = conn.recv()
        except Exception:  # end of file: the run closed the pipe, or is gone
            os._exit(0)
        folder = request[0]
        try:
            answer: tuple[Path, bool, Any] = (folder, True, picture_png(*request))
        except Exception as exc:  # drawing failed: the report records it as for a picture drawn there
            answer = (folder, False, exc)
        try:
            conn.send(answer)
        except (BrokenPipeError, ConnectionResetError, EOFError):
            os._exit(0)  # the run's process is gone
        except Exception as exc:  # an exception that does not pickle: its text instead
            conn.send((folder, False, RuntimeError(f"{type(exc).__name__}: {exc}")))


def _warm_up() -> None:
    """Draw a 2D and a 3D picture and throw them away: the first drawing in a process loads the fonts
    and builds the 3D axes' machinery (about 0.1 s after the 0.25 s import), which the helper does at
    the sweep's tail, not in the report."""
    import numpy as np

    from .pictures import failure_picture

    try:
        failure_picture(np.eye(3)[:, :2], [0, 1, 2], dim=2, offending={"containment": [0]}, title="warm-up")
        failure_picture(np.eye(3), [[0, 1, 2]], dim=3, offending={"containment": [0]}, title="warm-up")
    except Exception:  # no matplotlib, or a drawing problem the real pictures will report
        pass


def _preload_here() -> None:
    """Import matplotlib in a background thread of this process, which draws the pictures itself."""
    threading.Thread(target=preload_matplotlib, name="hullstress-preload", daemon=True).start()


class _Helper:
    """The drawing processes, their pipes, and the threads here that send them requests and read their answers.

    The answers are PNG bytes, larger together than a pipe holds: read only
    when the report asks for them, a drawer would stop after a few
    pictures, blocked on a full pipe, while this process writes the folders.
    """

    def __init__(self) -> None:
        context = multiprocessing.get_context("forkserver")
        pipes = [context.Pipe() for _ in range(DRAWERS)]
        self.conns = [ours for ours, _ in pipes]
        theirs = [end for _, end in pipes]
        self.process = context.Process(target=_serve, args=(theirs, current_niceness()), daemon=True,
                                       name="hullstress-pictures")
        try:
            self.process.start()
        finally:
            for end in theirs:
                end.close()  # this process's copies: a drawer's death then reads as end of file here
        self.waiting: set[Path] = set()
        self.asked = 0
        self._arrived: dict[Path, tuple[bool, Any]] = {}
        self._ended = False
        self._news = threading.Condition()
        # Requests go out from a thread: a large case's points never hold up the report on a full pipe.
        self._outbox: queue.SimpleQueue[tuple[Connection, tuple] | None] = queue.SimpleQueue()
        self._sender = threading.Thread(target=self._send, name="hullstress-pictures-sender", daemon=True)
        self._reader = threading.Thread(target=self._read, name="hullstress-pictures-reader", daemon=True)
        self._sender.start()
        self._reader.start()

    def ask(self, request: tuple) -> None:
        """Send ``request`` to the drawers, in turn."""
        self._outbox.put((self.conns[self.asked % len(self.conns)], request))
        self.asked += 1

    def _send(self) -> None:
        while (item := self._outbox.get()) is not None:
            conn, request = item
            try:
                conn.send(request)
            except Exception:  # the drawer is gone: the reader sees its end of file
                pass

    def _read(self) -> None:
        try:
            while True:
                for conn in wait(self.conns):
                    got, ok, payload = conn.recv()
                    with self._news:
                        self._arrived[got] = (ok, payload)
                        self._news.notify_all()
        except Exception:  # end of file (a drawer died or was killed), or a garbled message
            pass
        with self._news:
            # A drawer is gone (or both are): whatever is not in is drawn by the report itself.
            self._ended = True
            self._news.notify_all()

    def answer_for(self, folder: Path) -> tuple[bool, Any] | None:
        """The helper's answer for ``folder`` (waiting for it), or None when it has none (it died, or was never asked)."""
        with self._news:
            if folder not in self.waiting:
                return None
            while folder not in self._arrived and not self._ended:
                self._news.wait()  # an interrupt raises here, and the answer stays to be read
            self.waiting.discard(folder)
            return self._arrived.pop(folder, None)

    def close(self) -> None:
        # Every answer this run wanted is in (or it was interrupted): nothing the helper still does
        # is needed, so it is killed rather than asked to leave (it may be loading matplotlib); the
        # drawers forked from it die with it.
        self.process.kill()
        self.process.join()
        self._outbox.put(None)
        self._sender.join()
        self._reader.join()  # it reads the end of file the drawers' deaths leave
        for conn in self.conns:
            conn.close()


class PictureDrawer:
    """Where the report's pictures are drawn: by a helper process, or here.

    Make one when the run begins (with one worker it starts importing
    matplotlib here, in a thread), :meth:`begin` it when a core frees at
    the sweep's tail (with more, that starts the drawers), :meth:`request`
    each picture once its cause's folder is written, then take each with
    :meth:`drawn` (in any order; the drawers take the requests in turn),
    and :meth:`close` it (or use a ``with`` block) at the end.

    Examples
    --------
    >>> drawer = PictureDrawer.start(pictures=False, workers=2)
    >>> drawer.helped
    False
    >>> drawer.close()
    """

    def __init__(self, *, pictures: bool = False, workers: int = 1) -> None:
        self._helper: _Helper | None = None
        self._lock = threading.Lock()
        self._wanted = pictures and workers >= 2 and "forkserver" in multiprocessing.get_all_start_methods()
        self._begun = False
        if pictures and not self._wanted:
            _preload_here()

    @classmethod
    def start(cls, *, pictures: bool, workers: int) -> PictureDrawer:
        """A drawer for a run of ``workers`` processes, begun (see :meth:`begin`).

        Parameters
        ----------
        pictures : bool
            The run draws pictures; False loads nothing and starts nothing.
        workers : int
            Processes the run may keep busy (its ``--workers``): with two or
            more, helper processes draw the pictures (where the platform has
            a fork server); otherwise a background thread imports matplotlib
            for this process, which draws them itself.
        """
        drawer = cls(pictures=pictures, workers=workers)
        drawer.begin()
        return drawer

    def begin(self) -> None:
        """Start the helper now (with two workers or more), which loads matplotlib and warms up.

        The pipeline calls this when the sweep's tail first leaves a core
        idle (a worker has nothing left to run), and again when the sweep
        ends: the helper then warms up on a core the workers do not need,
        instead of taking CPU from them.  Without it, the first
        :meth:`request` starts the helper.
        """
        with self._lock:
            if self._begun:
                return
            self._begun = True
            if not self._wanted:
                return
            try:
                self._helper = _Helper()
            except (OSError, RuntimeError, ValueError):  # no process for it: drawn here
                _preload_here()

    @property
    def helped(self) -> bool:
        """Whether a helper process draws the pictures."""
        return self._helper is not None

    def request(self, record: FailureRecord) -> None:
        """Ask for ``record``'s picture (its folder is written); a no-op when pictures are drawn here."""
        self.begin()
        if self._helper is None:
            return
        self._helper.ask(picture_request(record))
        self._helper.waiting.add(record.folder)

    def drawn(self, record: FailureRecord) -> bytes | None:
        """The PNG bytes the helper drew for ``record``, or None: draw it here.

        Raises
        ------
        Exception
            What drawing the picture raised in the helper.
        """
        if self._helper is None:
            return None
        answer = self._helper.answer_for(record.folder)
        if answer is None:
            return None
        ok, payload = answer
        if not ok:
            raise payload
        return payload

    def close(self) -> None:
        """End the helper (killed if it is still drawing), once."""
        with self._lock:
            helper, self._helper = self._helper, None
            self._begun = True  # a request after this draws here
        if helper is not None:
            helper.close()

    def __enter__(self) -> PictureDrawer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
