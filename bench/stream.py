"""Sustainable memory bandwidth of one core (STREAM-like copy and triad with numpy), for the
roofline estimates of docs/performance.md.

Usage:  python -m bench.stream [--mib 256] [--repeat 10]

Copy b = a (16 bytes per element: read a, write b) and triad a = b + s c (24 bytes per element),
on arrays of --mib MiB each (far beyond the caches), best of --repeat; numpy runs these loops on
one thread. Prints GB/s (1e9 bytes per second).
"""
from __future__ import annotations

import argparse
import time

import numpy as np


def best_time(fn, repeat: int) -> float:
    """Shortest wall time [s] of `repeat` calls of fn."""
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mib", type=int, default=256)
    parser.add_argument("--repeat", type=int, default=10)
    args = parser.parse_args(argv)
    n = args.mib * 2**20 // 8
    a = np.full(n, 1.0)
    b = np.full(n, 2.0)
    c = np.full(n, 3.0)

    def copy():
        np.copyto(b, a)

    def triad():
        np.multiply(c, 3.0, out=a)
        np.add(a, b, out=a)

    t_copy = best_time(copy, args.repeat)
    t_triad = best_time(triad, args.repeat)
    # the numpy triad is two passes: c*3 -> a (16 B), a + b -> a (24 B)
    print(f"copy : {16 * n / t_copy / 1e9:6.2f} GB/s ({args.mib} MiB arrays)")
    print(f"triad: {40 * n / t_triad / 1e9:6.2f} GB/s (two numpy passes, 40 bytes per element)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
