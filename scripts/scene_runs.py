"""What the literature comparisons share (circle_exact.py, mushroom_exact.py, two_holes.py): one scene run by
`rotleak simulate` in a scratch folder and one of its CSV files read back, and a Markdown table printed.
"""
import csv
import os
import shutil
import subprocess
import sys
import tempfile


class Scratch:
    """A scratch folder for the runs of one comparison, removed on leaving the `with` block."""

    def __init__(self, prefix):
        self.prefix = prefix
        self.path = ""

    def __enter__(self):
        self.path = tempfile.mkdtemp(prefix=self.prefix)
        return self

    def __exit__(self, *exc):
        shutil.rmtree(self.path, ignore_errors=True)

    def simulate(self, build, name, scene, particles, sets=(), read="survival.csv"):
        """Runs the scene text `scene` with `particles` and `--set` for each of `sets`; the rows of its file `read`."""
        path = os.path.join(self.path, name + ".toml")
        with open(path, "w") as f:
            f.write(scene)
        out = os.path.join(self.path, name)
        cmd = [os.path.join(build, "rotleak"), "simulate", path, "--particles", str(particles), "--no-progress",
               "--out", out]
        for s in sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, read), newline="") as f:
            return list(csv.DictReader(f))


def markdown(header, rows):
    """Prints a Markdown table: the header's cells, then each row's (strings)."""
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print("| " + " | ".join(r) + " |")


def arguments(argv, doc, *defaults):
    """BUILD_DIR and the particle counts after it (an integer or a text such as 1e6), each else its default; None,
    with the usage `doc` printed, when BUILD_DIR is missing."""
    if len(argv) < 2:
        print(doc, file=sys.stderr)
        return None
    return argv[1], [int(float(argv[2 + k])) if len(argv) > 2 + k else d for k, d in enumerate(defaults)]
