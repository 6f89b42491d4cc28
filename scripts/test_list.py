#!/usr/bin/python3
"""The list of every test: each CTest test of a build, with the file or script it runs, written into
docs/testing.md between two markers; and the scripts of scripts/ that no test runs.

Usage: test_list.py BUILD_DIR            rewrite docs/testing.md's list from BUILD_DIR's tests
       test_list.py BUILD_DIR --check    fail, naming them, on tests missing from the list (and, with
                                         --complete, on listed tests this build does not have)

Where a test lives: a GoogleTest case lives in the source file of its binary (tests/<binary>.cpp, or
tests/fuzz/...); a test that runs a script lives in that script (the first .sh or .py under the source
tree on its command line); any other command (rotleak verify, rotleak --version) lives in the CMake file
that adds it. The tests come from `ctest --show-only=json-v1`, the names `ctest -N` prints.
"""
import json
import os
import re
import subprocess
import sys
import tempfile
from collections import OrderedDict

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(SOURCE, "docs", "testing.md")
BEGIN = "<!-- test list: written by scripts/test_list.py from `ctest --show-only=json-v1`; do not edit by hand -->"
END = "<!-- end of the test list -->"
# The stages that run tests outside CTest: their scripts are run by the suite too.
STAGES = ["scripts/test.sh", "scripts/test_sanitizers.sh", ".ci/run"]


def rel(path):
    path = os.path.realpath(path)
    root = os.path.realpath(SOURCE)
    return os.path.relpath(path, root) if path.startswith(root + os.sep) else None


def plain_name(name):
    """A test's name without the comment CMake's GoogleTest discovery appends to a parameterised case
    ("  # GetParam() = 24-byte object <F2-6E ...>": bytes of pointers, other in every build)."""
    return name.split("  # ", 1)[0]


def fenced_shell(path):
    """The sh and bash blocks of a Markdown file: what the docs runner runs."""
    text = open(path, encoding="utf-8").read()
    return "\n".join(m.group(1) for m in re.finditer(r"```(?:sh|bash)\n(.*?)```", text, re.S))


def ctest_tests(build):
    # from a scratch directory that includes the build's tests: ctest writes Testing/Temporary/LastTest.log
    # where it runs, and in the build it would overwrite the log of the ctest that runs this check
    with tempfile.TemporaryDirectory(prefix="rotleak-test-list-") as scratch:
        with open(os.path.join(scratch, "CTestTestfile.cmake"), "w", encoding="utf-8") as f:
            f.write('subdirs("%s")\n' % os.path.abspath(build).replace("\\", "/"))
        out = subprocess.run(["ctest", "--show-only=json-v1"], cwd=scratch, check=True, capture_output=True, text=True)
    info = json.loads(out.stdout)
    nodes = info.get("backtraceGraph", {}).get("nodes", [])
    files = info.get("backtraceGraph", {}).get("files", [])
    tests = []
    for t in info["tests"]:
        props = {p["name"]: p["value"] for p in t.get("properties", [])}
        labels = props.get("LABELS", [])
        where = None
        cmd = t.get("command", [])
        if cmd and any(a.startswith("--gtest_filter=") for a in cmd[1:]):
            binary = os.path.basename(cmd[0])
            for cand in (f"tests/{binary}.cpp", f"tests/fuzz/{binary}.cpp"):
                if os.path.exists(os.path.join(SOURCE, cand)):
                    where = cand
                    break
        if where is None:
            for a in cmd[1:]:
                r = rel(a) if os.path.isabs(a) else None
                if r is None and re.match(r"^(tests|scripts)/.*\.(py|sh)$", a):
                    r = a
                if r and re.search(r"\.(sh|py)$", r) and os.path.exists(os.path.join(SOURCE, r)):
                    where = r
                    break
        if where is None:
            bt = t.get("backtrace")
            if bt is not None and bt < len(nodes):
                r = rel(files[nodes[bt]["file"]])
                if r:
                    exe = cmd[0] if cmd else ""
                    in_build = os.path.realpath(exe).startswith(os.path.realpath(build) + os.sep)
                    words = [os.path.basename(exe) if in_build else exe] + cmd[1:] if cmd else []
                    where = f"{r} (`{' '.join(words)}`)"
        tests.append((plain_name(t["name"]), where or "?", ", ".join(labels) if isinstance(labels, list) else labels))
    return tests


def scripts_run_by_hand(tests):
    """Scripts under scripts/ that no CTest test and no stage runs, directly or through another script."""
    run = set()
    todo = [w.split(":")[0] for _, w, _ in tests if w.startswith(("scripts/", "tests/python/"))]
    todo += [s for s in STAGES if os.path.exists(os.path.join(SOURCE, s))]
    todo += [f"tests/{f}" for f in os.listdir(os.path.join(SOURCE, "tests")) if f.endswith((".cpp", ".hpp"))]
    all_scripts = sorted(f for f in os.listdir(os.path.join(SOURCE, "scripts")) if f.endswith((".sh", ".py")))
    docs = [os.path.join(d, f) for d, _, fs in os.walk(os.path.join(SOURCE, "docs")) for f in fs if f.endswith(".md")]
    docs.append(os.path.join(SOURCE, "README.md"))
    while todo:
        path = todo.pop()
        if path in run:
            continue
        run.add(path)
        try:
            text = open(os.path.join(SOURCE, path), encoding="utf-8").read()
        except OSError:
            continue
        if path == "scripts/run_docs.py":  # it runs the docs' shell blocks
            text += "\n".join(fenced_shell(d) for d in docs)
        for s in all_scripts:
            if re.search(r"(?<![\w.-])" + re.escape(s) + r"\b", text) and f"scripts/{s}" not in run:
                todo.append(f"scripts/{s}")
    by_hand = []
    for s in all_scripts:
        if f"scripts/{s}" in run:
            continue
        by_hand.append((f"scripts/{s}", first_comment(os.path.join(SOURCE, "scripts", s))))
    return by_hand


def first_comment(path):
    lines = open(path, encoding="utf-8").read().splitlines()
    if path.endswith(".py"):
        m = re.search(r'"""(.*?)(\n\n|""")', "\n".join(lines), re.S)
        text = m.group(1) if m else ""
    else:
        text = []
        for line in lines[1:]:
            if not line.startswith("#"):
                break
            text.append(line[1:].strip())
        text = " ".join(text)
    text = " ".join(text.split())
    m = re.match(r"(.+?[.:])(\s|$)", text)
    first = (m.group(1) if m else text).rstrip(":")
    return first or "(no description)"


def render(tests, by_hand):
    groups = OrderedDict()
    for name, where, labels in sorted(tests, key=lambda t: (t[1], t[0])):
        groups.setdefault((where, labels), []).append(name)
    out = [BEGIN, "", f"{len(tests)} tests, by the file that holds them (label in brackets):", ""]
    out += ["| where | label | tests |", "|---|---|---|"]
    for (where, labels), names in groups.items():
        w = where if where.startswith("`") or "(`" in where else f"`{where}`"
        out.append(f"| {w} | {labels} | {', '.join(f'`{n}`' for n in names)} |")
    out += ["", "Scripts that no test and no stage of the suite runs (run by hand):", ""]
    out += ["| script | what it does |", "|---|---|"]
    for s, what in by_hand:
        out.append(f"| `{s}` | {what.replace('|', '/')} |")
    out += ["", END]
    return "\n".join(out)


def listed_names(block):
    names = set()
    for line in block.splitlines():
        if line.startswith("| `") or line.startswith("| "):
            cells = line.split(" | ")
            if len(cells) >= 3 and not cells[0].startswith("| script"):
                names.update(re.findall(r"`([^`]+)`", cells[-1]))
    return names


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    if len(args) != 1:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    build = args[0]
    tests = ctest_tests(build)
    block = render(tests, scripts_run_by_hand(tests))
    doc = open(DOC, encoding="utf-8").read()
    if BEGIN not in doc or END not in doc:
        print(f"test_list.py: {DOC} lacks the list's markers", file=sys.stderr)
        return 1
    head, rest = doc.split(BEGIN, 1)
    old, tail = rest.split(END, 1)
    if "--check" not in argv:
        new = head + block + tail
        tmp = DOC + ".tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(new)
        os.replace(tmp, DOC)
        print(f"test_list.py: {len(tests)} tests written to docs/testing.md")
        return 0
    listed = listed_names(old)
    have = {t[0] for t in tests}
    missing = sorted(have - listed)
    stale = sorted(listed - have) if "--complete" in argv else []
    for n in missing:
        print(f"docs/testing.md does not list the test {n} (run: /usr/bin/python3 scripts/test_list.py {build})")
    for n in stale:
        print(f"docs/testing.md lists {n}, which this build does not have (run: /usr/bin/python3 scripts/test_list.py {build})")
    if not missing and not stale and BEGIN + old + END != block:
        where = [t for t in tests if t[1] == "?"]
        if where:
            print(f"test_list.py: no file found for {', '.join(t[0] for t in where)}")
            return 1
        if "--complete" in argv:
            print(f"docs/testing.md's list is out of date (a file or label changed): run /usr/bin/python3 scripts/test_list.py {build}")
            return 1
    if missing or stale:
        return 1
    print(f"docs/testing.md lists all {len(have)} tests of {build}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
