#!/usr/bin/python3
"""The stadium with two holes, transmission and reflection of entering particles and per-hole escapes, against rotleak.

The bouncing-ball model: docs/model.md, "Two holes: transmission and reflection"; Dettmann & Georgiou,
arXiv:1006.1316.

The scene: the stadium d = 4, r = 1 (perimeter L = 8 + 2 pi, area 8 + pi), hole A on the top edge over
x in [-1.5, -0.7], hole B on the bottom edge over x in [0.1, 0.9] (each w = 0.8 long). Seen from a bouncing-ball
orbit (p near 0, drifting along the edges) the straight edges are cut into three free gaps: cap-A (h1 = 0.5),
A-B (h2 = 0.8) and B-cap (h3 = 1.1). Started uniformly on the boundary (Birkhoff), the particles that escape
through hole X after t go as c_X / t with c_A = ((1 + G) h1^2 + h2^2 / 2) / L, c_B = ((1 + G) h3^2 + h2^2 / 2) / L,
G = (3/4) ln 3 (a cap passage's mean <1/g>). Entering through hole A (ensemble.enter_through), the share still
inside at t that leaves through A (reflection) goes as K_AA / t^2 with K_AA = 2 r (1 + G) h1^2 / w, the share that
leaves through B (transmission) as K_AB / t^2 with K_AB = r h2^2 / w, and entering through B, K_BB = 2 r (1 + G)
h3^2 / w and K_BA = K_AB (time reversal). Each constant is estimated from the escapes through that hole within a
window [t1, t2) of the run: E[count] = N K (1/t1^2 - 1/t2^2) (entries) or N c (1/t1 - 1/t2) (uniform starts), the
count Poisson, so K = count / (N (1/t1^2 - 1/t2^2)) +- sqrt(count) / (...). All particles are created at t = 0.

Usage: scripts/two_holes.py BUILD_DIR [ENTERING_PARTICLES (default 400000000)] [UNIFORM_PARTICLES (default
100000000)]. Prints a Markdown table; exits 1 if a constant lies more than 5 standard errors from its prediction.
"""
import math
import sys

from scene_runs import Scratch, arguments, markdown

D, R = 4.0, 1.0
L = 2 * D + 2 * math.pi * R
W = 0.8
A_X, B_X = (-1.5, -0.7), (0.1, 0.9)  # A on the top edge, B on the bottom edge, as x ranges
G = 0.75 * math.log(3)
H1, H2, H3 = A_X[0] + D / 2, B_X[0] - A_X[1], D / 2 - B_X[1]

SCENE = """[stadium]
d = "4"
r = "1"

[[leaks]]
width = "0.8/(8+2*pi)"
start = "-1.1/(8+2*pi)"

[[leaks]]
width = "0.8/(8+2*pi)"
start = "1/2-0.5/(8+2*pi)"

[ensemble]
creation_window = 0.0

[run]
t_max = %r
"""

ENTRY_WINDOWS = ((500.0, 1000.0), (1000.0, 3000.0))
UNIFORM_WINDOWS = ((1000.0, 4000.0), (4000.0, 20000.0))


def count(rows, leak, t1, t2):
    return sum(int(r["escaped_%d" % leak]) for r in rows if float(r["t_from"]) >= t1 and float(r["t_to"]) <= t2)


def main(argv):
    args = arguments(argv, __doc__, 400000000, 100000000)
    if args is None:
        return 2
    build, (n_entry, n_uniform) = args
    with Scratch("rotleak_two_holes_") as work:
        # a seed each: independent samples (with the same draws, entries at A's and B's inner edges are images
        # under the half turn that maps the A-B gap onto itself)
        entry = {h: work.simulate(build, "enter_" + h, SCENE % 3000.0, n_entry,
                                  ["ensemble.enter_through=%d" % k, "ensemble.seed=%d" % (k + 1)], read="leaks.csv")
                 for k, h in enumerate("AB")}
        uniform = work.simulate(build, "uniform", SCENE % 20000.0, n_uniform, ["ensemble.seed=3"], read="leaks.csv")
    rows = []  # (start, exit, window, predicted, count, estimate, error)
    predicted = {("A", "A"): 2 * R * (1 + G) * H1 ** 2 / W, ("A", "B"): R * H2 ** 2 / W,
                 ("B", "A"): R * H2 ** 2 / W, ("B", "B"): 2 * R * (1 + G) * H3 ** 2 / W}
    for (start, leave), k in sorted(predicted.items()):
        for t1, t2 in ENTRY_WINDOWS:
            n = count(entry[start], "AB".index(leave), t1, t2)
            scale = n_entry * (1 / t1 ** 2 - 1 / t2 ** 2)
            rows.append(("enters " + start, leave, (t1, t2), k, n, n / scale, math.sqrt(max(n, 1)) / scale, "t^2"))
    c_uniform = {"A": ((1 + G) * H1 ** 2 + H2 ** 2 / 2) / L, "B": ((1 + G) * H3 ** 2 + H2 ** 2 / 2) / L}
    for leave, c in sorted(c_uniform.items()):
        for t1, t2 in UNIFORM_WINDOWS:
            n = count(uniform, "AB".index(leave), t1, t2)
            scale = n_uniform * (1 / t1 - 1 / t2)
            rows.append(("uniform", leave, (t1, t2), c, n, n / scale, math.sqrt(max(n, 1)) / scale, "t"))
    worst, lines = 0.0, []
    for start, leave, (t1, t2), k, n, est, err, law in rows:
        z = (est - k) / err
        worst = max(worst, abs(z))
        lines.append(["%s (%.0e)" % (start, n_entry if start != "uniform" else n_uniform), leave,
                      "[%g, %g)" % (t1, t2), "%.4f / %s" % (k, law), "%d" % n, "%.4f +- %.4f" % (est, err), "%+.2f" % z])
    markdown(["particles", "leave through", "window", "model", "escapes", "measured", "(measured - model) / error"],
             lines)
    t_ab, t_ba = count(entry["A"], 1, 0, 3000), count(entry["B"], 0, 0, 3000)
    p_ab, p_ba = t_ab / n_entry, t_ba / n_entry
    z = (p_ab - p_ba) / math.sqrt((p_ab * (1 - p_ab) + p_ba * (1 - p_ba)) / n_entry)
    print("\nTransmitted in all: A -> B %.6f, B -> A %.6f (%+.2f standard errors apart; time reversal: equal)"
          % (p_ab, p_ba, z))
    return 0 if worst < 5 and abs(z) < 5 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
