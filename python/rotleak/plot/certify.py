"""Draw a certified sample (rotleak certify --sample): the sample's survival curve between its proven
bounds, with each point tier's curve of the same particle ids, and below, each tier's distance from the
bracket in standard errors of the difference of two proportions."""
from __future__ import annotations

import math
from typing import Optional, Union

from ..readers import Certification, PathLike, read_certification
from . import ONE_COLUMN, Drawing, legend_below, plain_log_labels, plt, styled
from . import draw as _draw


def draw(certification: Union[Certification, PathLike], formats: object = ("png",)) -> list[str]:
    """Draw a certified sample's certify picture beside its files (``rotleak certify SCENE --sample N --out DIR``),
    in each format; returns the paths."""
    return _draw(certification if isinstance(certification, Certification) else read_certification(certification),
                 formats)  # type: ignore[arg-type]


@styled
def figures(certification: Union[Certification, PathLike]) -> list[Drawing]:
    """certify: the proven bracket with each tier's curve of the same ids, and each tier's distance from it."""
    if not isinstance(certification, Certification):
        certification = read_certification(certification)
    doc, b = certification.document, certification.bracket
    n = float(doc["sample"])
    t = b["t"].astype(float).tolist()
    lower, upper = b["lower"].astype(float).tolist(), b["upper"].astype(float).tolist()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(ONE_COLUMN, 3.9), sharex=True,
                                      gridspec_kw={"height_ratios": [2, 1]})
    floor = 0.5 / n
    label: Optional[str] = "proven bracket"
    top.fill_between(t, [max(x, floor) for x in lower], [max(x, floor) for x in upper], color="k", alpha=0.3,
                     step="post")
    for edge in (lower, upper):  # drawn as lines too: where every escape is proven the two coincide
        top.step(t, [max(x, floor) for x in edge], where="post", color="k", lw=1.6, alpha=0.6, label=label)
        label = None
    worst = []
    for k, tier in enumerate(certification.tiers):
        p = b["p_" + tier].astype(float).tolist()
        top.step(t, [max(x, floor) for x in p], where="post", color="C%d" % k, lw=0.8, label=tier)
        z = []
        for pi, lo, hi in zip(p, lower, upper):
            mid = 0.5 * (lo + hi)
            se = math.sqrt(2 * max(mid * (1 - mid), 1 / n) / n)
            z.append((pi - hi) / se if pi > hi else (pi - lo) / se if pi < lo else 0.0)
        bottom.plot(t, z, color="C%d" % k, lw=0.8)
        worst.append("%s %.2g" % (tier, max((abs(x) for x in z), default=0.0)))
    top.set_yscale("log")
    top.set_ylabel("P(t) of the sample")
    if min(upper) > 0.05:  # less than two decades: 0.6, not 6 x 10^-1
        plain_log_labels(top)
    top.set_title("the sample against its proof")
    bottom.axhspan(-3, 3, color="C2", alpha=0.15, label="within 3 errors")
    bottom.set_ylabel("outside (errors)")
    bottom.set_xlabel("t")
    for ax in (top, bottom):
        ax.grid(True, which="major")
    legend_below(fig, (top, bottom))
    caption = ("P(t) of %d particles certified to t = %g (%.4g%% of their escapes proven): the proven bracket (grey) "
               "and each tier's curve of the same particle ids (top); each tier's distance outside the bracket in "
               "standard errors of the difference of two proportions (bottom; largest: %s)." % (
                   doc["sample"], doc["t_cap"], 100 * doc["proven_fraction"], ", ".join(worst)))
    return [Drawing("certify", fig, caption)]
