#!/usr/bin/python3
"""Compare two trees of simulate run directories: survival.csv, fc.csv and scene.toml byte for byte,
summary.json on every field but timing and version. Exit 1 if anything differs.

Usage: /usr/bin/python3 scripts/compare_runs.py BEFORE AFTER   (each holds run directories of the same names)
"""
import filecmp
import json
import os
import sys

# the one field that may differ between two honest runs of the same inputs (docs/output.md)
VOLATILE = {"execution"}


def main(a_root, b_root):
    ok = True
    for d in sorted(os.listdir(a_root)):
        a, b = os.path.join(a_root, d), os.path.join(b_root, d)
        if not os.path.exists(os.path.join(a, "summary.json")):
            continue
        for f in ("survival.csv", "fc.csv", "escapes.csv", "scene.toml"):
            fa, fb = os.path.join(a, f), os.path.join(b, f)
            if os.path.exists(fa) or os.path.exists(fb):
                same = os.path.exists(fa) and os.path.exists(fb) and filecmp.cmp(fa, fb, shallow=False)
                ok &= same
                print(f"{d}/{f}: {'identical' if same else 'DIFFERS'}")
        A = json.load(open(os.path.join(a, "summary.json")))
        B = json.load(open(os.path.join(b, "summary.json")))
        diff = sorted(k for k in set(A) | set(B) if k not in VOLATILE and A.get(k) != B.get(k))
        ok &= not diff
        print(f"{d}/summary.json (all but {', '.join(sorted(VOLATILE))}): {'identical' if not diff else 'DIFFERS in ' + ', '.join(diff)}")
    print("all identical" if ok else "some differ")
    return 0 if ok else 1


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
