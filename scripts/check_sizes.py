#!/usr/bin/python3
"""Checks the sizes the house keeps: no function over 60 lines and no file over 600 lines in src/,
analysis/ and verify/ (.cpp, .hpp, .ipp).

The functions and files that are over the limits today are listed, with their sizes, in
scripts/long_functions.txt: the list may only shrink. The check fails when a function or file over the
limit is not listed, when a listed one grew, and when a listed one is now within the limit or gone (take
it off the list, so that it cannot grow back). A function's length runs from its first line to its last
(Universal Ctags' C++ parser finds them); lambdas and local classes count toward the function around them.

Prints the longest five functions and every failure; exit 1 on a failure.
Usage: /usr/bin/python3 scripts/check_sizes.py [ROOT] [--list]   (--list: every function over the limit, as the
allowlist's lines)"""
import json
import os
import subprocess
import sys

FUNCTION_LIMIT, FILE_LIMIT = 60, 600
DIRS = ("src", "analysis", "verify")


def functions(paths):
    """{path: [(lines, name, first line)]} of every function body that is not inside another function, as
    Universal Ctags finds them (Debian's universal-ctags: its C++ parser gives each function's first and
    last line; lambdas and local classes are inside their function and count toward it)."""
    res = subprocess.run(["ctags", "--output-format=json", "--fields=+ne", "--kinds-C++=f", "--language-force=C++",
                          "-f", "-"] + paths, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit("check_sizes: ctags failed (Debian: universal-ctags): " + res.stderr.strip())
    out = {p: [] for p in paths}
    for line in res.stdout.splitlines():
        tag = json.loads(line)
        if tag.get("_type") != "tag" or "end" not in tag or tag.get("scopeKind") == "function":
            continue
        out[tag["path"]].append((tag["end"] - tag["line"] + 1, tag["name"], tag["line"]))
    return out


def measure(root):
    """({(path, name): lines} of functions over the limit, {path: lines} of files over it, all functions)"""
    long_functions, long_files, every = {}, {}, []
    paths = []
    for d in DIRS:
        for sub, dirs, names in os.walk(os.path.join(root, d)):
            dirs.sort()
            paths += [os.path.relpath(os.path.join(sub, n), root) for n in sorted(names) if n.endswith((".cpp", ".hpp", ".ipp"))]
    cwd = os.getcwd()
    os.chdir(root)
    try:
        found = functions(paths)
    finally:
        os.chdir(cwd)
    for rel in paths:
        with open(os.path.join(root, rel), encoding="utf-8") as f:
            n = sum(1 for _ in f)
        if n > FILE_LIMIT:
            long_files[rel] = n
        for lines, fname, first in found[rel]:
            every.append((lines, rel, fname, first))
            if lines > FUNCTION_LIMIT:
                key = (rel, fname)
                long_functions[key] = max(lines, long_functions.get(key, 0))
    every.sort(key=lambda x: (-x[0], x[1], x[3]))
    return long_functions, long_files, every


def read_allowlist(root):
    allowed = {}
    with open(os.path.join(root, "scripts", "long_functions.txt"), encoding="utf-8") as f:
        for no, line in enumerate(f, 1):
            line = line.split("#")[0].strip()
            if not line:
                continue
            parts = line.split()
            if len(parts) == 2:  # a file: path lines
                allowed[(parts[0], None)] = int(parts[1])
            elif len(parts) == 3:  # a function: path name lines
                allowed[(parts[0], parts[1])] = int(parts[2])
            else:
                sys.exit("scripts/long_functions.txt:%d: expected 'PATH LINES' or 'PATH FUNCTION LINES'" % no)
    return allowed


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    root = args[0] if args else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    long_functions, long_files, every = measure(root)
    if "--list" in sys.argv:
        for path, n in sorted(long_files.items()):
            print("%s %d" % (path, n))
        for (path, name), n in sorted(long_functions.items(), key=lambda kv: -kv[1]):
            print("%s %s %d" % (path, name, n))
        return 0
    allowed = read_allowlist(root)
    now = {(p, None): n for p, n in long_files.items()}
    now.update(long_functions)
    bad = []
    for key, n in sorted(now.items(), key=lambda kv: -kv[1]):
        what = "%s (%s)" % (key[0], key[1]) if key[1] else key[0]
        limit = FUNCTION_LIMIT if key[1] else FILE_LIMIT
        if key not in allowed:
            bad.append("%s: %d lines, over the %d allowed, and not on scripts/long_functions.txt" % (what, n, limit))
        elif n > allowed[key]:
            bad.append("%s: %d lines, grown from the %d listed (the list may only shrink)" % (what, n, allowed[key]))
    for key, n in sorted(allowed.items(), key=lambda kv: -kv[1]):
        if key not in now:
            what = "%s (%s)" % (key[0], key[1]) if key[1] else key[0]
            bad.append("%s: listed with %d lines, now within the limit or gone: take it off "
                       "scripts/long_functions.txt" % (what, n))
    print("longest functions: " + "; ".join("%s %s %d" % (p, f, n) for n, p, f, _ in every[:5]))
    print("%d functions over %d lines, %d files over %d lines (%d listed to go)"
          % (len(long_functions), FUNCTION_LIMIT, len(long_files), FILE_LIMIT, len(allowed)))
    for b in bad:
        print("FAIL " + b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
