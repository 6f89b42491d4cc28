"""The table scripts' CSV (docs/output.md, "Table scripts' CSV"), run small and read back with csv and pandas.

scripts/table_engines.py must find every example table's files byte-identical between the scalar engine and the
vectorised kernel (it exits 1 otherwise); scripts/table_rates.py must write one row per table and hole width with a
positive small-hole rate; scripts/small_hole_limit.py one row per table and width; scripts/gpu_lanes.py (the GPU
threads' busy shares from a run's lives) one row per bench_gpu scene, its two measures checked on lives whose answer is
known. ROTLEAK_BINARY names the rotleak binary of the build (its folder is the scripts' BUILD).
"""
import csv
import os
import subprocess
import sys
import tempfile
import unittest

import pandas

SOURCE = os.environ.get("ROTLEAK_SOURCE", os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD = os.path.dirname(os.environ["ROTLEAK_BINARY"])
ENGINES = ["table", "lanes", "scalar_collisions_per_s", "simd_collisions_per_s", "ratio", "identical"]
RATES = ["table", "width", "kappa0", "kappa", "kappa_err", "kappa_syst", "ratio", "ratio_err", "P_3T", "P_3T_err",
         "particles", "collisions"]
LANES = ["scene", "particles", "mean_collisions", "max_collisions", "plain_busy", "lanes_busy", "lives_a_thread",
         "predicted_ratio"]
LIMIT = ["table", "width", "kappa0", "kappa", "kappa_err", "kappa_syst", "ratio", "ratio_err", "particles",
         "collisions"]


def script(name, *args):
    return subprocess.run([sys.executable, os.path.join(SOURCE, "scripts", name), BUILD, *args], check=True,
                          capture_output=True, text=True)


def written(name, *args, dtype=None):
    """The script run into a temporary CSV: its rows read back with csv, its frame with pandas, and what it printed."""
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out.csv")
        printed = script(name, out, *args).stdout
        with open(out, newline="") as f:
            rows = list(csv.DictReader(f))
        frame = pandas.read_csv(out, dtype=dtype)
    return rows, frame, printed


class TableScripts(unittest.TestCase):
    def test_engines_write_identical_files_on_every_table(self):
        version = subprocess.run([os.path.join(BUILD, "rotleak"), "--version"], check=True, capture_output=True,
                                 text=True).stdout
        if "lanes" not in version:
            self.skipTest("this CPU runs no vectorised kernel: " + version.strip())
        rows, frame, _ = written("table_engines.py", "3000", "1")
        tables = sorted(n[:-5] for n in os.listdir(os.path.join(SOURCE, "data", "scenes", "tables")))
        self.assertEqual(list(frame.columns), ENGINES)
        self.assertEqual(sorted(set(r["table"] for r in rows)), tables)
        self.assertTrue(all(r["identical"] == "yes" for r in rows), rows)
        self.assertTrue((frame["scalar_collisions_per_s"] > 0).all() and (frame["simd_collisions_per_s"] > 0).all())

    def test_rates_write_a_row_per_table_and_width(self):
        rows, frame, _ = written("table_rates.py", "3000", dtype={"width": str})
        self.assertEqual(list(frame.columns), RATES)
        self.assertEqual(len(rows), 18)  # 9 tables, 2 widths
        self.assertEqual(sorted(set(frame["width"])), ["0.01", "0.02"])
        self.assertTrue((frame["kappa0"] > 0).all() and (frame["particles"] == 3000).all())

    def test_small_hole_limit_writes_a_row_per_table_and_width(self):
        rows, frame, printed = written("small_hole_limit.py", "3000", dtype={"width": str})
        self.assertEqual(list(frame.columns), LIMIT)
        self.assertEqual(sorted(set(r["table"] for r in rows)), ["lorentz", "sinai"])
        self.assertEqual(sorted(set(frame["width"])), ["0.0025", "0.005", "0.01", "0.02"])
        self.assertTrue((frame["kappa0"] > 0).all() and (frame["ratio_err"] > 0).all())
        # kappa0 is proportional to the hole: halving lambda halves it, to rounding
        for t in ("lorentz", "sinai"):
            k0 = frame[frame["table"] == t].set_index("width")["kappa0"]
            self.assertAlmostEqual(k0["0.02"] / k0["0.01"], 2.0, places=12)
        self.assertEqual(printed.count("| lorentz |"), 1 + 2)  # its ratios, then its two fits


class GpuLanes(unittest.TestCase):
    def test_busy_shares_of_known_lives(self):
        sys.path.insert(0, os.path.join(SOURCE, "scripts"))
        import gpu_lanes
        # a warp of equal lives is always busy; one life 32 times the others' keeps 31 threads waiting
        self.assertEqual(gpu_lanes.plain_busy([7] * 64), 1.0)
        self.assertEqual(gpu_lanes.plain_busy([1] * 31 + [32]), 63 / 1024)
        # threads that take the next particle: 4 threads, lives 3, 1, 1, 1, 2 -> the second thread takes the fifth
        # life at time 1 and ends at 3, as the first: makespan 3, busy 8 / 12
        self.assertEqual(gpu_lanes.lanes_busy([3, 1, 1, 1, 2], 4), 8 / 12)

    def test_writes_a_row_per_scene(self):
        rows, frame, _ = written("gpu_lanes.py", "20000")
        self.assertEqual(list(frame.columns), LANES)
        self.assertEqual([r["scene"] for r in rows], ["s_L = 0", "omega = 2/3", "quick-start"])
        self.assertTrue(((frame["plain_busy"] > 0) & (frame["plain_busy"] <= frame["lanes_busy"])).all())


if __name__ == "__main__":
    unittest.main()
