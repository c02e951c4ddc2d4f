"""A 2D hull program built on the Python driver kit, with planted misbehaviour by case size.

Writes Qhull ``Fx`` (the planted_hull monotone chain), in spawn or persistent
mode (drivers/kit/hullstress_driver.py), and on a case of

* 7 points: dies by SIGSEGV;
* 8 points: hangs (its pid in the file PID_FILE first);
* 9 points: in persistent mode only, answers out of step (the hull without
  its ``hull N`` line); in spawn mode, the correct hull;
* 10 points: allocates 3 GB (not touched; an error row under a lower memory limit);
* 11 points: rejects the case ("error N too many points for my taste").

Usage: ``planted_persistent.py [PID_FILE STARTS_FILE]``.  Every start appends
its pid to STARTS_FILE, so that tests can count the programs started.  (Files
given as arguments, not in the environment: workers are forked from a fork
server that may have started before the test set its environment.)
"""

import os
import signal
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent.parent / "drivers" / "kit"))

from hullstress_driver import PROTOCOL_ENV, Reject, run_driver  # noqa: E402
from planted_hull import hull  # noqa: E402

PERSISTENT = PROTOCOL_ENV in os.environ
FILES = [a for a in sys.argv[1:] if a != "--version"]
PID_FILE, STARTS_FILE = (FILES + ["", ""])[:2]


def planted(points):
    n = len(points)
    if n == 7:
        os.kill(os.getpid(), signal.SIGSEGV)
    if n == 8:
        Path(PID_FILE).write_text(str(os.getpid()))
        time.sleep(600)
    if n == 10:
        block = bytearray(3 << 30)  # zero pages, not touched: no real memory without a limit
        del block
    if n == 11:
        raise Reject("too many points for my taste")
    result = hull(points)
    text = "%d\n%s\n" % (len(result), "\n".join(map(str, result)))
    if n == 9 and PERSISTENT:
        sys.stdout.write(text)  # no "hull N" line: out of step
        sys.stdout.flush()
    return text


if STARTS_FILE and sys.argv[-1:] != ["--version"]:
    with open(STARTS_FILE, "a") as fh:
        fh.write("%d\n" % os.getpid())
run_driver(planted, dim=2, output="Fx", driver="planted persistent 1.0", library="planted_hull")
