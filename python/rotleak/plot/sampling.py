"""Draw bench_sampling's CSV: P(t) of the uniform and the "mupo" runs of the same scene with their
error bands (one standard error), log-log, each down to the smallest P it resolves (uniform: at least
one survivor; mupo: at least 10 effective survivors).

Usage: /usr/bin/python3 -m rotleak.plot.sampling SAMPLING.csv OUT.png    Needs Debian's python3-matplotlib."""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import matplotlib.pyplot as plt

from . import ONE_COLUMN, bench_main, legend_below, styled


@styled
def draw(rows: Sequence[dict[str, str]]) -> Any:
    """The figure of the benchmark's rows: P(t) of the uniform and the mupo runs of the s_L = 0 stationary scene with
    one standard error either side, each to the smallest P it resolves."""
    fig, ax = plt.subplots(figsize=(ONE_COLUMN, 2.8))
    for scheme, ok, color in (
        ("uniform", lambda r: int(r["survivors_uniform"]) >= 1, "C0"),
        ("mupo", lambda r: float(r["effective_mupo"]) >= 10, "C4"),
    ):
        pts = [r for r in rows if float(r["t"]) > 0 and ok(r)]
        t = [float(r["t"]) for r in pts]
        P = [float(r["P_" + scheme]) for r in pts]
        e = [float(r["err_" + scheme]) for r in pts]
        lo = [max(p - s, p * 1e-3) for p, s in zip(P, e)]
        hi = [p + s for p, s in zip(P, e)]
        ax.loglog(t, P, color=color, label=f"{scheme} (to {min(P):.2g})")
        ax.fill_between(t, lo, hi, color=color, alpha=0.25, lw=0)
    ax.set_xlabel("t")
    ax.set_ylabel("P(t)")
    ax.set_title("uniform and mupo starts")
    ax.grid(True, which="major")
    legend_below(fig, (ax,))
    return fig


if __name__ == "__main__":
    bench_main("sampling", draw)
