"""Helpers every benchmark script shares: worker-count arguments and the machine's load."""

from __future__ import annotations

import os

__all__ = ["parse_workers", "load_average"]


def parse_workers(text: str) -> list[int]:
    """``"1,2"`` -> ``[1, 2]``; a one-line exit for anything else (argparse ``type=``)."""
    try:
        counts = [int(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise SystemExit(f"--workers must be comma-separated integers, got {text!r}") from None
    if not counts or min(counts) < 1:
        raise SystemExit(f"--workers must list worker counts of at least 1, got {text!r}")
    return counts


def load_average() -> str:
    """The 1, 5 and 15 minute load averages and the CPU count, for a benchmark's header."""
    try:
        return ", ".join(f"{x:.2f}" for x in os.getloadavg()) + f" (1, 5, 15 min) on {os.cpu_count()} CPUs"
    except OSError:
        return "unknown"
