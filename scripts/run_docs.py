#!/usr/bin/python3
"""Runs every code block of README.md and docs/ (the executable documentation) and checks what it prints.

Each Markdown file runs in its own scratch copy of the repository's tracked files, its blocks in order
(a later block may read what an earlier one wrote), with the build's `rotleak` first on PATH,
PYTHONPATH at the build's Python package and ROTLEAK_BINARY set. What a block is decides what happens:

- ```sh / ```bash: run by `bash -e -o pipefail`; ```python: run by the runner's own interpreter (the suite
  runs it with the one scripts/setup.sh names, Debian's, with numpy and pandas; the blocks name it by its
  path, as a user must). Exit status 0 required.
- ```toml: a scene; loaded by `rotleak predict` (which validates every key and runs nothing), or, for a scene
  on another table or with a list of leaks (which predict refuses), by `rotleak simulate` of one particle.
- ```text right after a runnable block (only blank lines or a directive between): that block's output.
  Every shown line must appear in the printed output (stdout and stderr together), in order, with the same words;
  its numbers are not compared unless the directive says so (timings and rates differ between runs):
  `exact` compares every number and shows every printed line (a block that leaves lines out says so with a
  line of its own, `...`; python.md's once left out a line its snippet printed); `figures NAME=TOL ...` compares the number right after NAME (at the
  start of a shown line, or, for a quoted name of two characters or more, "t P =", anywhere in it; only
  blanks, =, : or < between) with the printed one, within a relative TOL (5%) or an absolute one (0.002). A shown line may use `...` for
  text left out.
- any other ```text block must say what it is: `synopsis` (each `rotleak CMD --option` shown must be an
  option of `rotleak CMD --help`) or `not code: WHY` (a diagram, a table layout).

A directive is an HTML comment on the line right before the fence: `<!-- docs: WORDS -->`. For runnable
blocks: `scale` lets the runner multiply the block's `--particles N` and `--seeds K` (and a shell or
Python `particles=N`) by the scale (the environment's ROTLEAK_DOCS_SCALE, or --scale; 1 when neither is
set; at least 1000 particles and 4 seeds); `scale=F` scales the block by the smaller of F and the scale
when the scale is below 1 (a block of 10^10 particles); `timeout=S` (default 300); `skip: WHY` leaves the block unrun and says why (the suite's own
command). Where a block was scaled by s, a `figures` tolerance is widened by 1/sqrt(s): the statistical
error of a figure grows so with fewer particles; the tolerance written is the one at full size.

Every failure is printed; exit status 1 if there is one, 0 when every block holds.
`--stale` lists every figure of a full-size block that is not what this build prints (to the digits shown), within
its tolerance or not: the README once showed kappa 0.0043876 to builds that printed 0.0043865; `--fail-stale` makes
one a failure (the suite runs it on getting-started.md, whose quick-start lines the README repeats).

Usage: /usr/bin/python3 scripts/run_docs.py [--build DIR] [--scale S] [--list] [--show] [--stale [--fail-stale]]
       [FILE.md ...]"""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNNABLE = ("sh", "bash", "python")
FENCE = re.compile(r"^```(\w*)\s*$")
DIRECTIVE = re.compile(r"^<!--\s*docs:\s*(.*?)\s*-->\s*$")
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


class Block:
    def __init__(self, path, line, lang, text, directive):
        self.path, self.line, self.lang, self.text, self.directive = path, line, lang, text, directive
        self.output = None  # the text block that shows this block's output

    def where(self):
        return "%s:%d" % (os.path.relpath(self.path, ROOT), self.line)

    def has(self, word):
        return re.search(r"(^|\s)%s(\s|=|:|$)" % re.escape(word), self.directive) is not None

    def value(self, key, default=None):
        m = re.search(r"(?:^|\s)%s=(\S+)" % re.escape(key), self.directive)
        return m.group(1) if m else default

    def reason(self, key):
        m = re.search(r"%s:\s*(.+)$" % re.escape(key), self.directive)
        return m.group(1).strip() if m else None


def blocks_of(path):
    """The fenced blocks of a Markdown file, each with the directive right before it; outputs attached."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    found, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        start, lang = i, m.group(1) or "text"
        j = i + 1
        while j < len(lines) and lines[j].rstrip() != "```":
            j += 1
        if j == len(lines):
            raise SystemExit("%s:%d: a code fence that never closes" % (path, start + 1))
        d = DIRECTIVE.match(lines[start - 1]) if start > 0 else None
        block = Block(path, start + 1, lang, "\n".join(lines[start + 1:j]) + "\n", d.group(1) if d else "")
        block.end = j
        if lang == "text" and found and found[-1].lang in RUNNABLE:
            between = lines[found[-1].end + 1:start]
            if all(not s.strip() or DIRECTIVE.match(s) for s in between):
                found[-1].output = block
                block.is_output = True
        found.append(block)
        i = j + 1
    return found


def markdown_files(root):
    files = [os.path.join(root, "README.md")]
    for d, dirs, names in os.walk(os.path.join(root, "docs")):
        dirs.sort()
        files += [os.path.join(d, n) for n in sorted(names) if n.endswith(".md")]
    return files


def count_of(text):
    """a count as a block writes it: 1000000, 1e6 or 10**6"""
    if "**" in text:
        base, power = text.split("**")
        return int(base) ** int(power)
    return int(float(text))


def scaled(text, scale):
    """the block with its particle and seed counts multiplied by scale (see the module's docstring); never
    above what the block says, at least 1000 particles and 4 seeds"""
    if scale >= 1:
        return text, 1.0
    ratios = []

    def particles(m):
        n = count_of(m.group(2))
        k = min(n, max(1000, int(round(n * scale))))
        ratios.append(k / n)
        return "%s%d" % (m.group(1), k)

    def seeds(m):
        n = int(m.group(2))
        return "%s%d" % (m.group(1), min(n, max(4, int(round(n * scale)))))

    text = re.sub(r"(--particles[ =])(\d+(?:e\d+)?)", particles, text)
    text = re.sub(r"(?<!-)(particles=)(10\*\*\d+|\d+(?:e\d+)?)", particles, text)  # not --particles= again; 10**6 before "10"
    text = re.sub(r"(--seeds[ =])(\d+)", seeds, text)
    return text, (min(ratios) if ratios else 1.0)


def tokens(line):
    """a line as words and numbers: ('w', text) or ('n', text)"""
    spaced = NUMBER.sub(lambda m: " \0%s " % m.group(0), line)
    return [("n", t[1:]) if t.startswith("\0") else ("w", t) for t in spaced.split()]


def same(a, b, exact):
    return a[0] == b[0] and (a[1] == b[1] if a[0] == "w" or exact else True)


def line_matches(pattern, line, exact=False):
    """the same words in the same places, numbers as placeholders (equal too when exact); '...' in the
    pattern stands for any text"""
    parts = [tokens(p) for p in pattern.split("...")]
    got = tokens(line)

    def at(part, k):
        return k + len(part) <= len(got) and all(same(x, got[k + i], exact) for i, x in enumerate(part))

    if len(parts) == 1:
        return len(parts[0]) == len(got) and at(parts[0], 0)
    if not at(parts[0], 0):
        return False
    pos = len(parts[0])
    for part in parts[1:-1]:
        k = next((k for k in range(pos, len(got) - len(part) + 1) if at(part, k)), None)
        if k is None:
            return False
        pos = k + len(part)
    last = parts[-1]
    return len(got) - len(last) >= pos and at(last, len(got) - len(last))


def figure_after(name, line):
    """the number right after NAME (only blanks, '=', ':' or '<' between): at the line's start, else after
    NAME's first occurrence; None where there is none"""
    k = len(name) if line.startswith(name) else (line.find(name) + len(name) if name in line else -1)
    m = re.match(r"[\s=:<]*(%s)" % NUMBER.pattern, line[k:]) if k >= 0 else None
    return float(m.group(1)) if m else None


def shown_digits(name, line):
    """The significant digits of the figure right after `name` in a shown line (0.0043865: 5)."""
    k = line.find(name)
    m = re.match(r"[\s=:<]*(%s)" % NUMBER.pattern, line[k + len(name):]) if k >= 0 else None
    mantissa = re.sub(r"[eE].*$", "", m.group(1)).lstrip("-+").replace(".", "").lstrip("0") if m else ""
    return max(1, len(mantissa))


STALE = []  # with --stale: (where, name, shown, printed) of every figure that differs at all from this build's


def check_output(block, printed, widen):
    """every shown line in the printed output, in order; the figures the directive names within tolerance"""
    out = block.output
    exact = out.has("exact")
    m = re.search(r"figures\s+(.*)$", out.directive)
    figures = re.findall(r'("[^"]+"|[^\s=]+)=(\S+)', m.group(1)) if m else []
    lines = printed.split("\n")
    at, errors, matched = 0, [], set()
    shown_lines = [x for x in out.text.rstrip("\n").split("\n") if x.strip()]
    for shown in shown_lines:
        if exact and shown.strip() == "...":
            continue  # printed lines left out here, said so
        pattern = shown.strip()
        found = next((k for k in range(at, len(lines)) if line_matches(pattern, lines[k].strip(), exact)), None)
        if found is None:
            errors.append("shown line not printed (in order%s): %r" % (", numbers equal" if exact else "", shown))
            continue
        matched.add(found)
        at = found + 1
        got = lines[found].strip()
        for name, tol in figures:
            name = name.strip('"')
            if not (pattern.startswith(name) or (name in pattern and len(name) > 1)):
                continue
            x, y = figure_after(name, pattern), figure_after(name, got)
            if x is None:
                continue
            if y is None:
                errors.append("no figure after %r in %r / %r" % (name, shown, got))
                continue
            digits = shown_digits(name, pattern)
            if widen == 1 and float("%.*g" % (digits, y)) != x:  # printed to the digits shown, not the shown figure
                STALE.append((block.output.where(), name, x, y))
            allowed = (float(tol[:-1]) / 100 * abs(x) if tol.endswith("%") else float(tol)) * widen
            if abs(x - y) > allowed:
                errors.append("%s: shown %g, printed %g, allowed +-%g (%s%s)" %
                              (name, x, y, allowed, tol, " widened %.3gx by the scale" % widen if widen != 1 else ""))
    if exact and not errors and not any(x.strip() == "..." for x in shown_lines):
        left = [line for k, line in enumerate(lines) if line.strip() and k not in matched]
        if left:
            errors.append("an exact block leaves out a printed line (show it, or a line '...'): %r" % left[0])
    return errors


def help_options(build, command, cache):
    if command not in cache:
        res = subprocess.run([os.path.join(build, "rotleak"), command, "--help"], capture_output=True, text=True)
        cache[command] = set(re.findall(r"--[a-z][a-z-]*", res.stdout)) if res.returncode == 0 else None
    return cache[command]


def check_synopsis(block, build, cache):
    errors = []
    for line in block.text.split("\n"):
        m = re.search(r"\brotleak ([a-z]+)", line)
        if not m:
            continue
        for command in m.group(1).split("|"):
            options = help_options(build, command, cache)
            if options is None:
                errors.append("rotleak %s: not a command (its --help failed)" % command)
                continue
            for opt in set(re.findall(r"--[a-z][a-z-]*", line[m.end():])):
                if opt not in options:
                    errors.append("rotleak %s: %s is not among its options" % (command, opt))
    return errors


def has_mpi(build):
    res = subprocess.run([os.path.join(build, "rotleak"), "--version"], capture_output=True, text=True)
    return "MPI: yes" in res.stdout


def copy_tree(root, dest, build):
    try:
        files = subprocess.run(["git", "-C", root, "ls-files"], check=True, capture_output=True,
                               text=True).stdout.split("\n")
    except (OSError, subprocess.CalledProcessError):
        files = [os.path.relpath(os.path.join(d, f), root) for d, dirs, names in os.walk(root) for f in names
                 if not re.match(r"(build|runs|\.git)", os.path.relpath(d, root))]
    for f in files:
        if not f or not os.path.isfile(os.path.join(root, f)):
            continue
        os.makedirs(os.path.join(dest, os.path.dirname(f)), exist_ok=True)
        shutil.copy2(os.path.join(root, f), os.path.join(dest, f))
    os.symlink(build, os.path.join(dest, "build"))


def run_file(path, build, scale, bindir, show=False):
    blocks = blocks_of(path)
    errors, ran, skipped = [], 0, []
    if not blocks:
        return errors, ran, skipped
    work = tempfile.mkdtemp(prefix="rotleak-docs-")
    cache = {}
    try:
        copy_tree(ROOT, work, build)
        env = dict(os.environ)
        env["PATH"] = bindir + os.pathsep + env.get("PATH", "")
        env["PYTHONPATH"] = os.path.join(build, "python")
        env["ROTLEAK_BINARY"] = os.path.join(build, "rotleak")
        env["ROTLEAK_PREBUILT"] = build
        env["MPLBACKEND"] = "Agg"
        env["HOME"] = work  # what a block writes under ~ stays in the copy
        env["OMPI_ALLOW_RUN_AS_ROOT"] = env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"  # CI runs as root
        env.pop("ROTLEAK_DATA", None)
        for b in blocks:
            if getattr(b, "is_output", False):
                continue
            if b.lang == "text":
                if b.has("synopsis"):
                    errors += ["%s: %s" % (b.where(), e) for e in check_synopsis(b, build, cache)]
                elif b.reason("not code") is None:
                    errors.append("%s: a text block that is no block's output says what it is (synopsis, not code: WHY)"
                                  % b.where())
                continue
            if b.lang == "toml":
                scene = os.path.join(work, ".docs_scene.toml")
                with open(scene, "w") as f:
                    f.write(b.text)
                if "[table]" in b.text or "[[leaks]]" in b.text:  # predict runs the stadium with one leak only
                    out = os.path.join(work, ".docs_scene_run")
                    res = subprocess.run([os.path.join(build, "rotleak"), "simulate", scene, "--particles", "1",
                                          "--no-progress", "--force", "--out", out], cwd=work, env=env,
                                         capture_output=True, text=True)
                    shutil.rmtree(out, ignore_errors=True)
                else:
                    res = subprocess.run([os.path.join(build, "rotleak"), "predict", scene], cwd=work, env=env,
                                         capture_output=True, text=True)
                os.remove(scene)
                ran += 1
                if res.returncode != 0:
                    errors.append("%s: the scene does not load: %s" % (b.where(), res.stderr.strip()))
                continue
            if b.lang not in RUNNABLE:
                errors.append("%s: a ```%s block: the runner knows sh, bash, python, toml and text" % (b.where(), b.lang))
                continue
            why = b.reason("skip")
            if why is None and "mpirun" in b.text and not has_mpi(build):
                why = "this build has no MPI (rotleak --version)"
            if why is not None:
                skipped.append("%s: %s" % (b.where(), why))
                continue
            factor = scale if scale >= 1 or b.value("scale") is None else min(scale, float(b.value("scale")))
            text, ratio = scaled(b.text, factor) if b.has("scale") else (b.text, 1.0)
            cmd = ["bash", "-e", "-o", "pipefail", "-c", text] if b.lang in ("sh", "bash") else [sys.executable, "-c", text]
            t0 = time.time()
            try:
                res = subprocess.run(cmd, cwd=work, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True, timeout=float(b.value("timeout", 300)))
            except subprocess.TimeoutExpired:
                errors.append("%s: ran past its %s s" % (b.where(), b.value("timeout", 300)))
                continue
            ran += 1
            note = " (counts scaled by %.3g)" % ratio if ratio != 1 else ""
            print("  %-40s %6.1f s%s" % (b.where(), time.time() - t0, note), flush=True)
            if show:
                print("    " + res.stdout.rstrip().replace("\n", "\n    "))
            if res.returncode != 0:
                tail = res.stdout.strip().split("\n")[-5:]
                errors.append("%s: exit status %d%s\n    %s" % (b.where(), res.returncode, note, "\n    ".join(tail)))
                continue
            if b.output is not None:
                errs = check_output(b, res.stdout, 1 / math.sqrt(ratio))
                errors += ["%s: %s%s" % (b.output.where(), e, note) for e in errs]
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return errors, ran, skipped


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="*")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--scale", type=float, default=float(os.environ.get("ROTLEAK_DOCS_SCALE", "1")))
    ap.add_argument("--list", action="store_true", help="list the blocks and what each is, run nothing")
    ap.add_argument("--show", action="store_true", help="print what each block prints")
    ap.add_argument("--fail-stale", action="store_true", help="with --stale: a stale figure is a failure (exit 1)")
    ap.add_argument("--stale", action="store_true",
                    help="also list every figure (of a block run at full size) that differs at all from what this "
                         "build prints, within its tolerance or not: what a docs refresh should rewrite")
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    files = [os.path.abspath(f) for f in a.files] or markdown_files(ROOT)
    if a.list:
        for f in files:
            for b in blocks_of(f):
                kind = "output" if getattr(b, "is_output", False) else b.lang
                print("%-40s %-8s %s" % (b.where(), kind, b.directive))
        return 0
    bindir = tempfile.mkdtemp(prefix="rotleak-docs-bin-")
    try:
        os.symlink(os.path.join(build, "rotleak"), os.path.join(bindir, "rotleak"))
        total, failed, t0 = 0, [], time.time()
        for f in files:
            print("%s" % os.path.relpath(f, ROOT), flush=True)
            errors, ran, skipped = run_file(f, build, a.scale, bindir, a.show)
            total += ran
            for s in skipped:
                print("  not run: %s" % s)
            for e in errors:
                print("  FAIL %s" % e)
            if errors:
                failed.append(f)
        if a.stale:
            for where, name, shown, printed in STALE:
                print("  stale %s: %s shown %.10g, this build prints %.10g" % (where, name, shown, printed))
            print("docs: %d figures differ from this build's" % len(STALE))
            if a.fail_stale and STALE:
                failed.append("stale figures")
        print("docs: %d blocks run in %d files, %.0f s, scale %g; %s" %
              (total, len(files), time.time() - t0, a.scale, "all hold" if not failed else "%d files FAIL" % len(failed)))
        return 1 if failed else 0
    finally:
        shutil.rmtree(bindir, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
