"""Draw bench_sampling's CSV: P(t) of the uniform and the "mupo" runs of the same scene with their
error bands (one standard error), log-log, each down to the smallest P it resolves (uniform: at least
one survivor; mupo: at least 10 effective survivors).

Usage: /usr/bin/python3 -m rotleak.plot.sampling SAMPLING.csv OUT.png    Needs Debian's python3-matplotlib."""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import matplotlib.pyplot as plt

from . import bench_main


def draw(rows: Sequence[dict[str, str]]) -> Any:
    """The figure of the benchmark's rows."""
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for scheme, ok, color in (
        ("uniform", lambda r: int(r["survivors_uniform"]) >= 1, "C0"),
        ("mupo", lambda r: float(r["effective_mupo"]) >= 10, "C3"),
    ):
        pts = [r for r in rows if float(r["t"]) > 0 and ok(r)]
        t = [float(r["t"]) for r in pts]
        P = [float(r["P_" + scheme]) for r in pts]
        e = [float(r["err_" + scheme]) for r in pts]
        lo = [max(p - s, p * 1e-3) for p, s in zip(P, e)]
        hi = [p + s for p, s in zip(P, e)]
        ax.loglog(t, P, color=color, lw=1, label=f"{scheme} (down to P = {min(P):.2g})")
        ax.fill_between(t, lo, hi, color=color, alpha=0.25, lw=0)
    ax.set_xlabel("t")
    ax.set_ylabel("P(t)")
    ax.set_title("s_L = 0, stationary: uniform vs importance-sampled starts\n(bands: one standard error)",
                 fontsize=10)  # two lines: one was cut at the figure's edge
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    bench_main("sampling", draw)
