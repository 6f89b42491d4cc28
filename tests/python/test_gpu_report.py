"""scripts/gpu_report.py: bench_gpu's JSON line (docs/output.md, "bench_gpu JSON") into docs/performance.md's GPU
table, between its markers and nowhere else. The bench output here is made up in the test (no device runs in the
suite): its numbers test the report's arithmetic and its verdicts on the targets, not the engine.
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

SOURCE = os.environ.get("ROTLEAK_SOURCE", os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(SOURCE, "scripts"))
import gpu_report  # noqa: E402


def scene(name, engine, plain, seconds):
    return {"scene": name, "engine_rate": engine, "plain_rate": plain, "ratio": engine / plain,
            "engine_seconds": seconds, "plain_seconds": seconds * engine / plain, "engine_collisions": 1,
            "plain_collisions": 1, "cpu_rate": 2e9, "engine_registers": 80, "engine_blocks": 6,
            "plain_registers": 62, "plain_blocks": 8,
            "kernel_caps": [{"min_blocks": m, "rate": engine, "registers": r, "blocks": m}
                            for m, r in ((1, 108), (6, 80), (8, 64))]}


BENCH = {"device": "a made-up card", "particles": 10 ** 8, "rounds": 3,
         "scenes": [scene("s_L = 0", 1e11, 4e10, 0.1), scene("omega = 2/3", 6e10, 4e10, 0.17),
                    scene("quick-start with f_c", 9e10, 4e10, 0.12)],
         "fp64_peak": 3.4e13, "limit_at_100_flops": 3.4e11}


class GpuReport(unittest.TestCase):
    def test_writes_the_table_between_the_markers_only(self):
        with tempfile.TemporaryDirectory() as d:
            bench, doc = os.path.join(d, "bench_gpu.txt"), os.path.join(d, "performance.md")
            with open(bench, "w") as f:
                f.write("| a table bench_gpu printed |\n" + json.dumps(BENCH) + "\n")
            with open(doc, "w") as f:
                f.write(f"before\n{gpu_report.BEGIN}\nold\n{gpu_report.END}\nafter\n")
            subprocess.run([sys.executable, os.path.join(SOURCE, "scripts", "gpu_report.py"), bench, "--doc", doc,
                            "--date", "2026-12-01"], check=True, capture_output=True)
            with open(doc) as f:
                text = f.read()
        self.assertTrue(text.startswith("before\n") and text.endswith("after\n"))
        self.assertNotIn("old", text)
        self.assertIn("a made-up card (2026-12-01)", text)
        self.assertEqual(text.count("| s_L = 0 |"), 1 + 3)  # the main table and one row a cap
        self.assertIn("engine / plain on s_L = 0: 2.50 (met", text)
        self.assertIn("engine / plain on omega = 2/3: 1.50 (NOT met", text)
        self.assertIn("s_L = 0: 1e+11 collisions/s (met", text)
        # 0.12 s for 10^8 particles: 12 s for 10^10
        self.assertIn("10^10 quick-start particles with f_c at this rate: 12.0 s (met", text)

    def test_refuses_a_file_without_json(self):
        with tempfile.TemporaryDirectory() as d:
            bench = os.path.join(d, "bench_gpu.txt")
            with open(bench, "w") as f:
                f.write("bench_gpu: no CUDA device is visible\n")
            r = subprocess.run([sys.executable, os.path.join(SOURCE, "scripts", "gpu_report.py"), bench],
                               capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("holds no JSON line", r.stderr)


if __name__ == "__main__":
    unittest.main()
