"""Draw a certified sample (rotleak certify --sample): the sample's survival curve between its proven
bounds, with each point tier's curve of the same particle ids, and below, each tier's distance from the
bracket in standard errors of the difference of two proportions."""
from __future__ import annotations

import math
import os
from typing import Optional, Union

from ..readers import Certification, PathLike, read_certification
from . import plt, save


def draw(certification: Union[Certification, PathLike]) -> list[str]:
    """Draw a certified sample's certify.png beside its files.

    Parameters
    ----------
    certification : Certification or a directory
        ``rotleak certify SCENE --sample N --out DIR`` (a damaged one is refused: RotleakError).

    Returns
    -------
    list of str
        The path drawn.
    """
    if not isinstance(certification, Certification):
        certification = read_certification(certification)
    doc, b = certification.document, certification.bracket
    n = float(doc["sample"])
    t = b["t"].astype(float).tolist()
    lower, upper = b["lower"].astype(float).tolist(), b["upper"].astype(float).tolist()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    floor = 0.5 / n
    label: Optional[str] = "proven bracket (%.4f%% of %d proven)" % (100 * doc["proven_fraction"], doc["sample"])
    top.fill_between(t, [max(x, floor) for x in lower], [max(x, floor) for x in upper], color="k", alpha=0.3,
                     step="post")
    for edge in (lower, upper):  # drawn as lines too: where every escape is proven the two coincide
        top.step(t, [max(x, floor) for x in edge], where="post", color="k", lw=2.2, alpha=0.6, label=label)
        label = None
    for k, tier in enumerate(certification.tiers):
        p = b["p_" + tier].astype(float).tolist()
        top.step(t, [max(x, floor) for x in p], where="post", color="C%d" % k, lw=0.9, label="%s, same ids" % tier)
        z = []
        for pi, lo, hi in zip(p, lower, upper):
            mid = 0.5 * (lo + hi)
            se = math.sqrt(2 * max(mid * (1 - mid), 1 / n) / n)
            z.append((pi - hi) / se if pi > hi else (pi - lo) / se if pi < lo else 0.0)
        bottom.plot(t, z, color="C%d" % k, lw=0.8, label=tier)
    top.set_yscale("log")
    top.set_ylabel("P(t) of the sample")
    top.set_title("%d particles certified to t = %g: the double curve against the proven bracket"
                  % (doc["sample"], doc["t_cap"]), fontsize=10)
    top.legend(loc="upper right", fontsize=8)
    bottom.axhspan(-3, 3, color="C2", alpha=0.15, label="within 3 errors")
    bottom.set_ylabel("outside, in errors")
    bottom.set_xlabel("t")
    bottom.legend(loc="lower left", fontsize=8, ncol=4)
    for ax in (top, bottom):
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    path = os.path.join(certification.path, "certify.png")
    save(fig, path)
    return [path]
