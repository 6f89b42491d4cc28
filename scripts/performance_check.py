#!/usr/bin/python3
"""bench_scale's JSON read back with Python's json, and performance_report.py's table made from it in a copy of
docs/performance.md: every scene a row whose shares are its share of the ceiling and its ratio over s_L = 0, the rest of
the document byte for byte as it was, and a second report replacing the first, not adding to it. Small and
untimed: nothing here judges a speed.   Usage: scripts/performance_check.py BUILD_DIR"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import performance_report as pr  # noqa: E402


def fail(why):
    sys.exit("performance_check: " + why)


def main():
    build = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "bench.json")
        lanes = "4"
        subprocess.run([os.path.join(build, "bench", "bench_scale"), "20000", "1", "2", lanes, out], check=True,
                       stdout=subprocess.DEVNULL)
        with open(out) as f:
            doc = json.load(f)
        for key in ("particles", "rounds", "threads", "scenes", "checkpoint_overhead"):
            if key not in doc:
                fail("bench_scale's JSON lacks %s" % key)
        if [s["scene"] for s in doc["scenes"]][0] != "s_L = 0" or len(doc["scenes"]) != 5:
            fail("bench_scale's scenes: %s" % [s["scene"] for s in doc["scenes"]])
        if "lanes" not in doc:
            print("performance_check: this CPU runs no kernel; the JSON read back, no table to make")
            return
        page = os.path.join(tmp, "performance.md")
        shutil.copy(os.path.join(ROOT, "docs", "performance.md"), page)
        with open(page) as f:
            before = f.read()
        for _ in range(2):
            subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "performance_report.py"), "--from", out,
                            "--doc", page], check=True, stdout=subprocess.DEVNULL)
        with open(page) as f:
            after = f.read()
        if after.count(pr.BEGIN) != 1 or after.count(pr.END) != 1:
            fail("the generated part appears %d times" % after.count(pr.BEGIN))
        outside = lambda t: t[:t.index(pr.BEGIN)] + t[t.index(pr.END):] if pr.BEGIN in t else t  # noqa: E731
        if pr.BEGIN in before and outside(before) != outside(after):
            fail("the report changed the document outside its markers")
        section = after[after.index(pr.BEGIN):after.index(pr.END)]
        for s in doc["scenes"]:
            row = re.search(r"^\| %s \| ([0-9.]+) \| ([0-9]+)%% \| ([0-9]+)%% \|" % re.escape(s["scene"]), section, re.M)
            if not row:
                fail("no row for %s" % s["scene"])
            ratio, share, first = float(row.group(1)), int(row.group(2)), int(row.group(3))
            if abs(ratio - s["ratio"]) > 0.005 or share != round(100 * s["ceiling_share"]) or \
                    len(s["ceiling_shares"]) != doc["rounds"] or \
                    first != round(100 * s["ratio"] / doc["scenes"][0]["ratio"]):
                fail("the row of %s does not follow from the JSON: %s" % (s["scene"], row.group(0)))
    print("performance_check: bench_scale's JSON read back; the table made from it, once, rows as the JSON says")


if __name__ == "__main__":
    main()
