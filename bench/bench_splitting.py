#!/usr/bin/python3
"""Work-normalised variance of P(t) for uniform sampling, mupo sampling alone, and mupo with population
splitting, on a leak with no tail (omega = 100/101 by default: P falls exponentially to 1e-20 by
t = 10000), at the times where the split run's P first falls below 1e-4, 1e-6, 1e-8 and 1e-12, and where it
is smallest (t_max).

The figure of merit is 1 / (relative variance x work): the larger, the less work for a given relative
error. Work is counted in collisions (deterministic: the same on any machine and load; fast-forwarded
bounces included), and the wall seconds of each run are shown beside it. A method "cannot measure" a
time where it has no survivor or under 10 effective survivors, (P / error)^2: its error estimate means
nothing there, and for split runs past the unsplit lines' reach the error is the allowance for lines not
drawn (docs/model.md), which says P is not measured there.

Usage: bench/bench_splitting.py [ROTLEAK] [PARTICLES_PLAIN] [LINES_SPLIT] [OMEGA] [OUT_DIR]
       (defaults: build/rotleak 10000000 1000000 100/101 a temporary directory, removed)
Writes splitting_fom.png into OUT_DIR when given (matplotlib, Debian's python3-matplotlib)."""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(rotleak, out, particles, omega, extra):
    cmd = [rotleak, "simulate", os.path.join(ROOT, "data", "scenes", "stationary_sL_0.toml"), "--particles",
           str(particles), "--set", "leak.omega=" + omega, "--set", "run.t_max=10000", "--out", out, "--force",
           "--no-progress"]
    for kv in extra:
        cmd += ["--set", kv]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    with open(os.path.join(out, "survival.csv"), newline="") as f:
        rows = [(float(r["t"]), int(r["survivors"]), float(r["P"]), float(r["P_err"])) for r in csv.DictReader(f)]
    return s, rows


def main():
    rotleak = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "rotleak")
    plain = int(sys.argv[2]) if len(sys.argv) > 2 else 10000000
    lines = int(sys.argv[3]) if len(sys.argv) > 3 else 1000000
    omega = sys.argv[4] if len(sys.argv) > 4 else "100/101"
    keep = sys.argv[5] if len(sys.argv) > 5 else None
    work = tempfile.mkdtemp()
    try:
        methods = [("uniform", plain, []), ("mupo", plain, ["ensemble.sampling=mupo"]),
                   ("mupo + splitting", lines, ["ensemble.sampling=mupo", "run.splitting=true"])]
        results = {}
        for name, n, extra in methods:
            results[name] = run(rotleak, os.path.join(work, name.replace(" ", "_")), n, omega, extra)
        split_rows = results["mupo + splitting"][1]
        targets = []
        for p in (1e-4, 1e-6, 1e-8, 1e-12):
            i = next((k for k, r in enumerate(split_rows) if 0 < r[2] <= p), None)
            if i is not None:
                targets.append((p, i))
        # the deepest: the smallest P the split run reaches (1.2e-20 at t_max for 100/101)
        i = min((k for k, r in enumerate(split_rows) if r[2] > 0), key=lambda k: split_rows[k][2])
        targets.append((split_rows[i][2], i))
        print("omega = %s, t_max = 10000; work in collisions (wall seconds in brackets, this machine)" % omega)
        for name, (s, _) in results.items():
            print("  %-17s %9d %s  %.3e collisions  [%.1f s]" % (
                name, s["particles"], "lines" if "splitting" in s else "particles", s["collisions"], s["execution"]["wall_seconds"]))
        header = "| P ~ | t | " + " | ".join("%s: rel. error, FOM" % n for n in results) + " | FOM gain of splitting |"
        print()
        print(header)
        print("|" + "---|" * (3 + len(results)))
        fom = {}
        for p, i in targets:
            cells = []
            for name, (s, rows) in results.items():
                t, surv, P, err = rows[i]
                n = s["particles"]
                # effective survivors (P / err)^2: the count for binomial errors, N / R for split lines
                eff = (P / err) ** 2 if err > 0 else (n if P > 0 else 0)
                if P <= 0 or surv == 0 or eff < 10:
                    cells.append("cannot measure")
                    continue
                rel = err / P
                f = 1 / (rel * rel * s["collisions"])
                fom[(name, p)] = f
                cells.append("%.3g, %.3g" % (rel, f))
            best_plain = max((fom.get((m, p), 0) for m in ("uniform", "mupo")), default=0)
            if ("mupo + splitting", p) not in fom:
                gain = "none measures it"
            elif best_plain:
                gain = "%.3g x" % (fom[("mupo + splitting", p)] / best_plain)
            else:
                gain = "only splitting measures it"
            print("| %.2g | %g | %s | %s |" % (p, rows[i][0], " | ".join(cells), gain))
        if keep:  # drawn in rotleak.plot's style (a column wide, 8 pt text), the package beside the binary's build
            sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(rotleak)), "python"))
            from rotleak import plot
            with plot.plt.rc_context(plot.STYLE):
                fig, ax = plot.plt.subplots(figsize=(plot.ONE_COLUMN, 2.8))
                colours = {"uniform": "C0", "mupo": "C4", "mupo + splitting": "C9"}  # as in the sampling picture
                for name, (s, rows) in results.items():
                    pts = [(r[2], 1 / ((r[3] / r[2]) ** 2 * s["collisions"])) for r in rows[::25]
                           if r[2] > 0 and r[3] > 0 and r[1] > 0 and (r[2] / r[3]) ** 2 >= 10]
                    if pts:
                        ax.loglog([x for x, _ in pts], [y for _, y in pts], ".", ms=3, label=name,
                                  color=colours[name])
                ax.invert_xaxis()
                ax.set_xlabel("P(t)")
                ax.set_ylabel("1 / (rel. variance x collisions)")
                ax.set_title("work-normalised precision")
                ax.grid(True, which="major")
                plot.legend_below(fig, (ax,))
            os.makedirs(keep, exist_ok=True)
            plot.save(fig, os.path.join(keep, "splitting_fom.png"))
            print("\nwrote %s: the work-normalised precision 1 / (relative variance x collisions) of P against P, "
                  "omega = %s, for uniform, mupo and mupo with splitting" % (os.path.join(keep, "splitting_fom.png"),
                                                                             omega))
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
