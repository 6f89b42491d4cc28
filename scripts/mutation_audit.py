#!/usr/bin/python3
"""Mutation audit: deliberate errors, kept as small patches under tests/mutants/, applied one at a time; each is
built incrementally and run against the tests named to catch it (or the whole suite), then reverted. It reports
which tests fail -- "caught" -- or that none does -- "survived". A tool, not a CI stage (docs/testing.md holds its
last report); the test MutationAudit.PatchesStillApply keeps every patch applicable to the code as it is.

Usage: /usr/bin/python3 scripts/mutation_audit.py [NAME ...]       targeted: the mutant's own `catch` tests
       /usr/bin/python3 scripts/mutation_audit.py --whole [NAME ...] the whole suite (ctest) against each
       /usr/bin/python3 scripts/mutation_audit.py --list | --check
Needs a configured build/ (bash scripts/build.sh). Targeted, a mutant takes 20 s to 2 minutes on 2 cores (a
header everything includes: longer); --whole about 8 minutes each. Each mutant's test output is kept in
build/mutation_audit/NAME.log. Every mutant is reverted, also on Ctrl-C or an error, and the build rebuilt.

A mutant file, tests/mutants/NAME.patch: header lines, then a unified diff (`git diff` of one small change):
  # what: one line saying what the error is
  # catch: TEST_BINARY GTEST_FILTER      (one line per test binary that should catch it)
  # catch: tests/python/test_X.py PATTERN (a Python test file: unittest -k PATTERN, the package built first)
  # note: why it survives, where it is known to (optional, shown in the report)
"""
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.path.join(ROOT, "build")
MUTANTS = os.path.join(ROOT, "tests", "mutants")
LOGS = os.path.join(BUILD, "mutation_audit")

RSS_WRAPPER = ("import resource, subprocess, sys\n"
               "r = subprocess.run(sys.argv[1:])\n"
               "print('MAXRSS_KB', resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, file=sys.stderr)\n"
               "sys.exit(r.returncode)\n")


class Mutant:
    def __init__(self, path):
        self.name = os.path.basename(path)[:-len(".patch")]
        self.what, self.note, self.catch = "", "", []
        diff = []
        with open(path) as f:
            for line in f:
                if not diff and line.startswith("# "):
                    key, _, value = line[2:].partition(":")
                    value = value.strip()
                    if key == "what":
                        self.what = value
                    elif key == "note":
                        self.note = value
                    elif key == "catch":
                        parts = value.split()
                        if len(parts) != 2:
                            raise SystemExit(f"{path}: '# catch:' needs a test binary and a gtest filter: {value!r}")
                        self.catch.append((parts[0], parts[1]))
                    else:
                        raise SystemExit(f"{path}: unknown header key {key!r} (what, catch, note)")
                else:
                    diff.append(line)
        self.diff = "".join(diff)
        if not self.what or not self.catch or "\n+++ " not in "\n" + self.diff:
            raise SystemExit(f"{path}: needs '# what:', at least one '# catch:' and a unified diff")
        self.files = re.findall(r"^\+\+\+ b/(\S+)", self.diff, re.M)

    def git_apply(self, *flags):
        return subprocess.run(["git", "apply", *flags, "-"], cwd=ROOT, input=self.diff, text=True,
                              capture_output=True)


def missing_tests(m):
    """What in the mutant's catch lines names no test: a binary without its tests/NAME.cpp, or a filter pattern
    whose suite no TEST/TEST_F/TEST_P/INSTANTIATE in that file defines."""
    out = []
    for binary, filt in m.catch:
        if binary.endswith(".py"):
            src = os.path.join(ROOT, binary)
            if not os.path.isfile(src):
                out.append(f"catch names {binary}, which is not there")
            elif not re.search(r"^\s*def " + re.escape(filt) + r"\w*\(", open(src).read(), re.M):
                out.append(f"catch pattern {filt!r}: no test method def {filt}... in {binary}")
            continue
        src = os.path.join(ROOT, "tests", binary + ".cpp")
        if not os.path.isfile(src):
            out.append(f"catch names {binary}, but there is no tests/{binary}.cpp")
            continue
        with open(src) as f:
            text = f.read()
        for pattern in filt.split(":"):
            suite, _, test = pattern.partition(".")
            suite = suite.split("/")[-1].lstrip("*")  # "Leaks/FastForward", "*FastForward": a parameterised suite
            if not suite or not re.search(r"\b(TEST|TEST_F|TEST_P)\(\s*" + re.escape(suite.rstrip("*")) +
                                          (r"\w*" if suite.endswith("*") else "") + r"\s*,", text):
                out.append(f"catch filter {pattern!r}: no suite {suite} in tests/{binary}.cpp")
            elif test and test != "*" and not test.endswith("*") and not re.search(
                    r"\(\s*" + re.escape(suite) + r"\s*,\s*" + re.escape(test) + r"\s*\)", text):
                out.append(f"catch filter {pattern!r}: no test {test} in suite {suite}")
    return out


def load(names):
    paths = sorted(p for p in os.listdir(MUTANTS) if p.endswith(".patch"))
    mutants = [Mutant(os.path.join(MUTANTS, p)) for p in paths]
    unknown = set(names) - {m.name for m in mutants}
    if unknown:
        raise SystemExit("unknown mutant(s): " + ", ".join(sorted(unknown)) + "; --list names them")
    return [m for m in mutants if not names or m.name in names]


def build(targets=None):
    cmd = ["cmake", "--build", BUILD, "-j", str(os.cpu_count() or 2)]
    if targets:
        cmd += ["--target", *targets]
    r = subprocess.run(cmd, capture_output=True, text=True)
    return r.returncode == 0, (r.stdout + r.stderr)[-3000:]


def test_binary(name):
    for d in ("tests", "."):
        p = os.path.join(BUILD, d, name)
        if os.path.isfile(p):
            return p
    raise SystemExit(f"no test binary {name} in {BUILD}/tests")


# what a Python test file needs from the build (tests/CMakeLists.txt's Python.* tests): the package copied to
# build/python with its module, and the command
PYTHON_TARGETS = ["rotleak_python_files", "rotleak_python", "rotleak"]


def build_targets(m):
    return sorted({t for b, _ in m.catch for t in (PYTHON_TARGETS if b.endswith(".py") else [b])})


def run_python(binary, filt, log):
    env = dict(os.environ, PYTHONPATH=os.path.join(BUILD, "python"), ROTLEAK_BINARY=os.path.join(BUILD, "rotleak"),
               ROTLEAK_SOURCE=ROOT)
    r = subprocess.run(["/usr/bin/python3", "-m", "unittest", "-v", "-k", filt, binary],
                       cwd=ROOT, env=env, capture_output=True, text=True, timeout=1200)
    log.write(f"$ /usr/bin/python3 -m unittest -k {filt} {binary}\n{r.stdout}{r.stderr}\n")
    names = list(dict.fromkeys(re.findall(r"^(?:FAIL|ERROR): (\w+)", r.stderr, re.M)))
    if r.returncode != 0 and not names:
        names = [f"{binary} (exit {r.returncode})"]
    if re.search(r"^Ran 0 tests", r.stderr, re.M):  # a catch line that runs nothing is a broken catch, not a catch
        raise SystemExit(f"{binary}: no test matches {filt}")
    return names


def run_targeted(m, log):
    failed = []
    for binary, filt in m.catch:
        if binary.endswith(".py"):
            failed += run_python(binary, filt, log)
            continue
        r = subprocess.run([test_binary(binary), f"--gtest_filter={filt}"], cwd=BUILD, capture_output=True,
                           text=True, timeout=1200)
        log.write(f"$ {binary} --gtest_filter={filt}\n{r.stdout}{r.stderr}\n")
        # "[  FAILED  ] Suite.Name (12 ms)", or "Prefix/Suite.Name/0, where GetParam() = ..." (parameterised);
        # each failing test is listed again in the summary: once each
        names = list(dict.fromkeys(re.findall(r"^\[  FAILED  \] ([A-Za-z_][\w/.]*)(?:, where| \(|$)", r.stdout, re.M)))
        if r.returncode != 0 and not names:
            names = [f"{binary} (exit {r.returncode})"]
        failed += names
    return failed


def run_whole(log):
    r = subprocess.run([sys.executable, "-c", RSS_WRAPPER, "ctest", "-j", str(os.cpu_count() or 2), "--timeout", "600",
                        "--output-on-failure"], cwd=BUILD, capture_output=True, text=True)
    log.write(r.stdout + r.stderr)
    return re.findall(r"^\s*\d+ - (\S+).*\((?:Failed|Timeout|SEGFAULT|Subprocess aborted|Exception|Not Run)\)\s*$",
                      r.stdout, re.M)


def main(argv):
    whole = "--whole" in argv
    names = [a for a in argv if not a.startswith("--")]
    mutants = load(names)
    if "--list" in argv:
        for m in mutants:
            print(f"{m.name}: {m.what} ({', '.join(m.files)}; caught by {' '.join(f for _, f in m.catch)})")
        return 0
    if "--check" in argv:  # every patch applies to the tree as it is and names tests that exist (nothing changed)
        bad = 0
        for m in mutants:
            r = m.git_apply("--check")
            if r.returncode != 0:
                print(f"{m.name}: does not apply: {r.stderr.strip()}")
                bad += 1
            for why in missing_tests(m):
                print(f"{m.name}: {why}")
                bad += 1
        print(f"{len(mutants)} mutants, {bad} problem(s)")
        return 1 if bad else 0
    if not os.path.isdir(BUILD):
        raise SystemExit("no build/: run bash scripts/build.sh first")
    os.makedirs(LOGS, exist_ok=True)
    rows, targets = [], set()
    try:
        for m in mutants:
            r = m.git_apply()
            if r.returncode != 0:
                raise SystemExit(f"{m.name}: the patch does not apply: {r.stderr.strip()}")
            t0 = time.time()
            try:
                print(f"[mutation_audit] {m.name}: {m.what}", flush=True)
                mine = build_targets(m)
                targets.update(mine)
                ok, out = build(None if whole else mine)
                with open(os.path.join(LOGS, m.name + ".log"), "w") as log:
                    if not ok:  # a mutant that does not compile is not a test's catch: report it as such
                        log.write(out)
                        failed = None
                    else:
                        failed = run_whole(log) if whole else run_targeted(m, log)
            finally:
                m.git_apply("-R")
            seconds = time.time() - t0
            rows.append((m, failed, seconds))
            verdict = ("DOES NOT BUILD" if failed is None else
                       f"caught by {len(failed)}: {', '.join(failed)}" if failed else "SURVIVED")
            print(f"  {verdict} ({seconds:.0f} s)", flush=True)
    finally:
        build(None if whole else sorted(targets))  # the code as it is, again
    caught = sum(1 for _, f, _ in rows if f)
    print(f"\n{caught} of {len(rows)} mutants caught ({'whole suite' if whole else 'targeted tests'})\n")
    print("| mutant | what | tests that fail | time |\n|---|---|---|---|")
    for m, failed, seconds in rows:
        if failed is None:
            cell = "**does not build**"
        elif failed:
            cell = ", ".join(f"`{n}`" for n in failed[:4]) + (f", ... ({len(failed)})" if len(failed) > 4 else "")
        else:
            cell = "**survived**" + (f": {m.note}" if m.note else "")
        print(f"| {m.name} | {m.what} | {cell} | {seconds:.0f} s |")
    return 0 if caught == len(rows) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
