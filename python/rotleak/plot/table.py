"""Draw tables with their leaks (docs/tables.md): each scene's boundary as rotleak's own geometry computes it
(Table<double>, through the in-process module), where each loop's s starts and which way it runs, and each leak where
it lies at t = 0 (a moving leak dashed).

Usage: /usr/bin/python3 -m rotleak.plot.table OUT.png SCENE.toml...    Needs Debian's python3-matplotlib and the
in-process module (rotleak._rotleak)."""
from __future__ import annotations

import json
import math
import os
import sys
from collections.abc import Sequence
from typing import Any

import matplotlib.pyplot as plt

from .. import _module
from . import TWO_COLUMN, save, styled


def drawing(scene: str, samples: int = 720) -> dict[str, Any]:
    """The table of a scene file as points (analysis/output/table_output.hpp): kind, area, perimeter, loops, leaks."""
    doc: dict[str, Any] = json.loads(_module().table_drawing(os.fspath(scene), [], samples))
    return doc


def panel(ax: Any, d: dict[str, Any], title: str) -> None:
    """One table on one axes: its loops, the origin of each loop's s with an arrow along growing s, its leaks."""
    for loop in d["loops"]:
        ax.plot(loop["x"], loop["y"], color="black", lw=0.8)
        # s = 0 and the way s grows: an arrow a little inside the table (the inward normal is the tangent turned
        # clockwise: the table lies on the right of every loop), from a tick at the origin
        (x0, y0), (tx, ty) = loop["origin"], loop["direction"]
        size = 0.2 * math.sqrt(d["area"])
        nx, ny, gap = ty, -tx, 0.07 * math.sqrt(d["area"])
        ax.plot([x0, x0 + gap * nx], [y0, y0 + gap * ny], color="C0", lw=0.8)
        ax.annotate("", xy=(x0 + gap * nx + size * tx, y0 + gap * ny + size * ty), xytext=(x0 + gap * nx, y0 + gap * ny),
                    arrowprops={"arrowstyle": "->", "color": "C0", "lw": 0.8})
    for j, leak in enumerate(d["leaks"]):
        ax.plot(leak["x"], leak["y"], color="C3", lw=2.6, solid_capstyle="butt", zorder=3,
                linestyle=(0, (1.5, 1)) if leak["moving"] else "-")
        k = len(leak["x"]) // 2
        if len(d["leaks"]) > 1:
            ax.annotate(str(j), (leak["x"][k], leak["y"][k]), textcoords="offset points", xytext=(3, 3),
                        color="C3", fontsize=7)
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title(title, fontsize=8)


@styled
def draw(scenes: Sequence[str], columns: int = 4) -> Any:
    """A page-wide figure of the scenes' tables, one panel each, titled by the scene file's name."""
    rows = (len(scenes) + columns - 1) // columns
    fig, axes = plt.subplots(rows, columns, figsize=(TWO_COLUMN, 1.9 * rows), squeeze=False)
    for ax, scene in zip(axes.flat, scenes):
        panel(ax, drawing(scene), os.path.splitext(os.path.basename(scene))[0].replace("_", " "))
    for ax in list(axes.flat)[len(scenes):]:
        ax.set_axis_off()
    return fig


def main(argv: Sequence[str]) -> int:
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    save(draw(argv[1:]), argv[0])
    print("drew %s: %d tables with their leaks at t = 0 (red; dashed: moving), each loop's s = 0 and direction (blue)"
          % (argv[0], len(argv) - 1))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
