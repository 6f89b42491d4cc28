"""Draw the speed-accuracy trade from bench_tiers' CSV: cost per collision (ratio to double) against
the median trust horizon in collisions, one point per tier.

Usage: /usr/bin/python3 -m rotleak.plot.tiers TIERS.csv OUT.png    Needs Debian's python3-matplotlib."""
from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import matplotlib.pyplot as plt

from . import Point, annotate_clear, bench_main


def draw(rows: Sequence[dict[str, str]]) -> Any:
    """The figure of the benchmark's rows."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    placed: list[Point] = []  # a label near an earlier one steps down (mpfr:128 and float128 once overlapped)
    for r in sorted(rows, key=lambda q: -float(q["ratio_to_double"])):
        x, y = float(r["median_horizon_collisions"]), float(r["ratio_to_double"])
        ax.loglog([x], [y], "o", color="C0")
        annotate_clear(ax, placed, r["tier"], (x, y), lambda q, p: abs(math.log10(q[0] / p[0])) < 0.25 and
                       abs(math.log10(q[1] / p[1])) < 0.12, offset=(6, -3), step=11, fontsize=9)
    ax.set_xlabel("median trust horizon (collisions within 1e-6 of the truth)")
    ax.set_ylabel("cost per collision / double")
    ax.set_title("what each precision tier buys (s_L = 0 scene)")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    bench_main("tiers", draw)
