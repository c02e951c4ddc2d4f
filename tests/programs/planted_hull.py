"""A 2D hull program with planted bugs, for the executable adapter's tests.

Reads Qhull-format points on stdin (dimension, count, one point per line),
writes Qhull ``Fx`` output (the count, then the extreme point indices
counter-clockwise), and misbehaves as its first argument says:

``ok``          the correct hull (Andrew's monotone chain, exact for the small
                integer coordinates the tests use)
``segv``        dies by SIGSEGV
``hang``        sleeps far beyond any test's timeout (writes its pid to $PLANTED_PID_FILE first)
``garbage``     prints a line that is not an index
``drop``        leaves the last hull vertex out (a containment failure)
``range``       names an index one past the last point
``clockwise``   the correct hull, clockwise
``exit``        says "boom: cannot hull this" on stderr and exits with status 3
``chatty``      the correct hull, with a warning on stderr

The bugs show on six points or more: the five-point case hullstress runs
once when it registers a program (its probe, which refuses programs that
cannot hull at all) gets the correct hull.

Pure Python on purpose: it starts fast.
"""

import os
import signal
import sys
import time


def read_points(text):
    tokens = text.split()
    dim, count = int(tokens[0]), int(tokens[1])
    values = [float(t) for t in tokens[2:]]
    return [tuple(values[i * dim:(i + 1) * dim]) for i in range(count)]


def cross(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def hull(points):
    order = sorted(range(len(points)), key=lambda i: points[i])
    lower, upper = [], []
    for i in order:
        while len(lower) >= 2 and cross(points[lower[-2]], points[lower[-1]], points[i]) <= 0:
            lower.pop()
        lower.append(i)
    for i in reversed(order):
        while len(upper) >= 2 and cross(points[upper[-2]], points[upper[-1]], points[i]) <= 0:
            upper.pop()
        upper.append(i)
    return lower[:-1] + upper[:-1]


def main():
    points = read_points(sys.stdin.read())
    mode = sys.argv[1] if len(points) >= 6 else "ok"
    if mode == "segv":
        os.kill(os.getpid(), signal.SIGSEGV)
    if mode == "hang":
        with open(os.environ["PLANTED_PID_FILE"], "w") as fh:
            fh.write(str(os.getpid()))
        time.sleep(600)
    if mode == "garbage":
        print("hello, hull")
        return
    if mode == "exit":
        print("boom: cannot hull this", file=sys.stderr)
        sys.exit(3)
    result = hull(points)
    if mode == "drop":
        result = result[:-1]
    elif mode == "range":
        result = result + [len(points)]
    elif mode == "clockwise":
        result = result[::-1]
    elif mode == "chatty":
        print("warning: chatty hull program at work", file=sys.stderr)
    print(len(result))
    for i in result:
        print(i)


if __name__ == "__main__":
    main()
