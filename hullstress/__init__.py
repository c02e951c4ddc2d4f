"""hullstress: a robustness test harness and degeneracy fuzzer for convex hull algorithms."""
from ._registry import register_algorithm, register_generator
