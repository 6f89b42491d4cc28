"""Draw the speed-accuracy trade from bench_tiers' CSV: cost per collision (ratio to double) against
the median trust horizon in collisions, one point per tier.

Usage: /usr/bin/python3 -m rotleak.plot.tiers TIERS.csv OUT.png    Needs Debian's python3-matplotlib."""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import matplotlib.pyplot as plt

from . import ONE_COLUMN, bench_main, label_points, styled


@styled
def draw(rows: Sequence[dict[str, str]]) -> Any:
    """The figure of the benchmark's rows: each tier's cost per collision (ratio to double) against its median trust
    horizon (collisions within 1e-6 of the MPFR truth), on the s_L = 0 scene."""
    fig, ax = plt.subplots(figsize=(ONE_COLUMN, 2.6))
    pts = [(float(r["median_horizon_collisions"]), float(r["ratio_to_double"]), r["tier"]) for r in rows]
    ax.loglog([x for x, _, _ in pts], [y for _, y, _ in pts], "o", color="C0")
    ax.set_xlabel("median trust horizon (collisions)")
    ax.set_ylabel("cost per collision / double")
    ax.set_title("what each tier buys")
    ax.grid(True, which="major")
    ax.margins(x=0.15, y=0.15)
    fig.tight_layout(pad=0.3)
    label_points(ax, pts)  # a label near an earlier one steps down (mpfr:128 and float128 once overlapped)
    return fig


if __name__ == "__main__":
    bench_main("tiers", draw)
