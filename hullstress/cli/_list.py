"""``python -m hullstress list``: what is registered (algorithms, generators, variants, checks)."""

from __future__ import annotations

import argparse

from ..verdict import CHECKS
from ._common import add_registration_options

__all__ = ["add_parser", "list_command", "render"]

WHAT = ("algorithms", "generators", "variants", "checks")


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser("list", help="list algorithms, variants, generators and checks",
                       description="List what is registered. Plug-ins given with --plugin are included.")
    p.add_argument("what", nargs="?", choices=WHAT, default=None, help="one section only (default: all)")
    add_registration_options(p, clockwise=False)
    p.set_defaults(handler=list_command)


def _algorithms() -> list[str]:
    from .._registry import algorithms
    from ..config import default_variants

    lines = ["algorithms (name, dim, origin, variants):"]
    specs = algorithms()
    width = max((len(s.name) for s in specs), default=4)
    for s in specs:
        defaults = default_variants(s.origin)
        eps = "eps=" + ("|".join(defaults.eps) if s.takes_eps and defaults.eps else "n/a")
        sphere = "sphere=" + "|".join(defaults.sphere)
        lines.append(f"  {s.name:<{width}}  {s.dim}D  {s.origin:<8}  {sphere:<13}  {eps:<16}  {s.summary}")
    lines.append("  (default variants; --sphere and --eps given to `run` apply to every algorithm)")
    try:
        from ..adapters import missing_adapters
    except ImportError:
        missing_adapters = None  # type: ignore[assignment]
    if missing_adapters is not None:
        for name, why in missing_adapters().items():
            lines.append(f"  {name:<{width}}  (not available: {why})")
    return lines


def _generators() -> list[str]:
    from .._registry import generators

    lines = ["generators (name, dims, parameters with defaults; variants swept):"]
    for g in generators():
        dims = ",".join(f"{d}D" for d in g.dims)
        params = ", ".join(f"{k}={v!r}" for k, v in g.defaults.items()) or "-"
        size = " fixed-size" if g.fixed_size else ""
        lines.append(f"  {g.name}  [{dims}]{size}  {g.summary}")
        lines.append(f"      parameters: {params}")
        if len(g.variants) > 1 or g.variants[0]:
            lines.append("      variants: " + "; ".join(
                ", ".join(f"{k}={v!r}" for k, v in var.items()) or "defaults" for var in g.variants))
    return lines


def _variants() -> list[str]:
    return [
        "variants:",
        "  sphere=off   the algorithm sees the input points",
        "  sphere=on    Kenwright's preprocessing first: duplicates removed, support mapping from the "
        "centroid, projection onto a unit sphere (circle in 2D); the algorithm is judged on the projected "
        "points, the method on whether its hull mapped back is the input's hull (stage preprocess)",
        "  eps=scaled   eps = 2**-52 * (max - min distance of the X-Y flattened points from the origin) "
        "(Nathan's gift-wrapping formula, finite at every scale)",
        "  eps=fixed    eps = 2**-52 (the same without the extent factor)",
        "  eps=n/a      no eps is passed: the algorithm takes none, or keeps its own tolerance",
        "defaults: in-house algorithms run sphere=off|on and eps=scaled|fixed; plug-ins, adapters and "
        "executables run sphere=off with their own tolerance (`run --sphere both` opts them in)",
    ]


def _checks() -> list[str]:
    text = {
        "convexity": "non-degenerate (planar, convex) facets; no reflex edge; an interior point below every facet",
        "containment": "no input point strictly outside any facet",
        "manifoldness": "closed, consistently outward-oriented genus-0 surface (2D: simple ccw polygon)",
        "qhull_agreement": "extreme vertex set and volume agree with Qhull (scipy) when Qhull's own hull is "
        "certified; 'qhull-wrong' (never a failure) when it is not",
    }
    return (["checks (all exact):"] + [f"  {c:<16} {text[c]}" for c in CHECKS]
            + ["  lower-dimensional input (a point, a segment, a flat polygon) is judged against its exact hull "
               "instead; see docs/lower-dimensional.md"])


def render(what: str | None) -> str:
    sections = {"algorithms": _algorithms, "generators": _generators, "variants": _variants, "checks": _checks}
    chosen = [what] if what else list(WHAT)
    return "\n\n".join("\n".join(sections[w]()) for w in chosen)


def list_command(args: argparse.Namespace) -> int:
    print(render(args.what))
    return 0
