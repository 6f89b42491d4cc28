#!/usr/bin/python3
"""Checks that the documentation stands alone and names what the code accepts:

- no file of the repository cites the issue tracker ("issue 21") or the shared specification ("SPEC
  section 4", SPEC.md): the repository cites its own docs (docs/model.md ...);
- docs/scenes.md names every scene key the loader accepts (src/io/scene_file.cpp's kSchema), each
  as `key = ...` in its section of the example;
- every relative link and image of every Markdown file points at a file that exists, and a link's
  #fragment at a heading of that file (GitHub's anchors);
- the docs, scripts and benchmarks run the Python interpreter scripts/setup.sh names, by its path (no bare
  python3, no `#!/usr/bin/env python3`): another python3 first on PATH may lack numpy and pandas;
- every path of the repository a Markdown file names (`src/sim/engine/engine.hpp`, scripts/run_docs.py:
  a path under one of the tracked top-level folders) exists, so that docs/design.md's map and the
  guide cannot point at a room that moved (the generated study reports excepted: they name their runs).

Prints every violation and exits 1 if there is one.   Usage: /usr/bin/python3 scripts/check_docs.py [ROOT]"""
import functools
import os
import re
import subprocess
import sys

CITATION = re.compile(r"SPEC section|SPEC\.md|SPEC §|\bissue #?\d+\b", re.IGNORECASE)
TEXT = (".md", ".py", ".sh", ".cpp", ".hpp", ".ipp", ".in", ".txt", ".toml", ".tsv", ".csv", ".cff", ".cmake", ".json",
        ".ipynb", ".yaml")


def tracked(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files"], check=True, capture_output=True, text=True).stdout
        return [f for f in out.splitlines() if f]
    except (OSError, subprocess.CalledProcessError):  # not a checkout: walk it
        return [os.path.relpath(os.path.join(d, f), root) for d, dirs, files in os.walk(root)
                for f in files if "/build" not in d and "/." not in d]


LINK = re.compile(r"\]\(([^)\s]+)\)")


@functools.lru_cache(maxsize=None)
def anchors(path):
    """GitHub's heading anchors of a Markdown file: lower case, punctuation dropped, blanks to hyphens"""
    found, fenced = set(), False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("```"):
                fenced = not fenced
            m = None if fenced else re.match(r"#{1,6}\s+(.*?)\s*$", line)
            if m:
                slug = re.sub(r"[^\w\- ]", "", m.group(1).lower()).replace(" ", "-")
                found.add(slug)
    return found


def broken_links(root, files):
    bad = []
    for f in files:
        if not f.endswith(".md"):
            continue
        with open(os.path.join(root, f), encoding="utf-8") as fh:
            text = re.sub(r"```.*?```", "", fh.read(), flags=re.S)
        for m in LINK.finditer(text):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):
                continue
            path, _, fragment = target.partition("#")
            full = os.path.normpath(os.path.join(root, os.path.dirname(f), path)) if path else os.path.join(root, f)
            if not os.path.exists(full):
                bad.append("%s: link to %s: no such file" % (f, target))
            elif fragment and full.endswith(".md") and fragment not in anchors(full):
                bad.append("%s: link to %s: no heading with that anchor" % (f, target))
    return bad


NAMED_PATH = re.compile(r"(?<![\w/.-])((?:src|analysis|verify|scripts|bench|tests|data|python|docs|cmake|packaging)/"
                        r"[\w./-]*\w)")


def missing_paths(root, files):
    bad = []
    for f in files:
        if not f.endswith(".md") or f.startswith(("docs/study/", "docs/bench/")):
            continue
        with open(os.path.join(root, f), encoding="utf-8") as fh:
            for no, line in enumerate(fh, 1):
                for m in NAMED_PATH.finditer(line):
                    path = m.group(1)
                    if any(c in line[m.end():m.end() + 1] for c in "*<{$") or "XXXX" in path:
                        continue  # a pattern (points/*, DIR.checkpoint-rank<r>), not a path
                    if not os.path.exists(os.path.join(root, path)):
                        bad.append("%s:%d: names %s, which does not exist" % (f, no, path))
    return bad


# A python3 run as a command, not as a package name (python3-numpy) nor the path of one (/usr/bin/python3)
BARE_PYTHON = re.compile(r"(?<![\w/.-])python3(?= -[mcS]\b| scripts/| bench/| -$|$)")


def bare_python(root, files):
    """The docs, the scripts and the benchmarks run the interpreter scripts/setup.sh names, by its path: a bare
    python3 is whatever comes first on PATH (a pyenv or conda one may lack numpy and pandas)."""
    python = subprocess.run(["bash", os.path.join(root, "scripts", "setup.sh"), "--python"], check=True,
                            capture_output=True, text=True).stdout.strip()
    bad = []
    for f in files:
        if not (f.endswith((".md", ".sh", ".py")) and f.startswith(("README", "docs/", "scripts/", "bench/", ".ci/"))):
            continue
        with open(os.path.join(root, f), encoding="utf-8", errors="replace") as fh:
            for no, line in enumerate(fh, 1):
                if no == 1 and line.startswith("#!") and "python" in line and line.strip() != "#!" + python:
                    bad.append("%s:1: starts with %s; the interpreter is %s (scripts/setup.sh --python)"
                               % (f, line.strip(), python))
                elif BARE_PYTHON.search(line) and not line.lstrip().startswith("#"):
                    bad.append("%s:%d: runs a bare python3; run %s (scripts/setup.sh --python)" % (f, no, python))
    return bad


def readme_repeats_the_guide(root):
    """The README's quick-start output (after `bash scripts/quickstart.sh`) repeats getting-started.md's lines, which
    Docs.QuickStartFiguresAreThisBuilds holds to this build's figures: a line of the one not in the other is stale."""
    with open(os.path.join(root, "README.md"), encoding="utf-8") as fh:
        readme = fh.read()
    with open(os.path.join(root, "docs", "guide", "getting-started.md"), encoding="utf-8") as fh:
        guide = fh.read()
    at = readme.index("```sh\nbash scripts/quickstart.sh\n```")
    block = readme[readme.index("```text\n", at) + 8:readme.index("```", readme.index("```text\n", at) + 8)]
    return ["README.md: the quick-start line %r is not getting-started.md's" % line
            for line in block.split("\n") if line.startswith(("kappa =", "alpha =", "tail  =", "model :"))
            and line not in guide]


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    bad = []
    for f in tracked(root):
        if not f.endswith(TEXT) or f == "scripts/check_docs.py" or f.startswith("docs/bench/"):
            continue
        with open(os.path.join(root, f), encoding="utf-8", errors="replace") as fh:
            for no, line in enumerate(fh, 1):
                m = CITATION.search(line)
                if m:
                    bad.append("%s:%d: cites %r; cite the repository's own docs instead" % (f, no, m.group(0)))
    with open(os.path.join(root, "src", "io", "scene_file.cpp")) as fh:
        source = fh.read()
    schema = source[source.index("kSchema = {"):source.index("};", source.index("kSchema = {"))]
    with open(os.path.join(root, "docs", "scenes.md")) as fh:
        scenes = fh.read()
    example = scenes[scenes.index("```toml"):scenes.index("```", scenes.index("```toml") + 3)]
    sections = {m.group(1): m.start() for m in re.finditer(r"^\[(\w+)\]", example, re.M)}
    keys = 0
    for m in re.finditer(r'\{"(\w+)",\s*\{([^}]*)\}\}', schema):
        section, names = m.group(1), re.findall(r'"(\w+)"', m.group(2))
        if section not in sections:
            bad.append("docs/scenes.md: no [%s] section in the example" % section)
            continue
        start = sections[section]
        end = min([p for p in sections.values() if p > start] + [len(example)])
        for name in names:
            keys += 1
            # a key that excludes one the example sets is shown commented out: "# key = value"
            if not re.search(r"^(# )?%s\s*=" % re.escape(name), example[start:end], re.M):
                bad.append("docs/scenes.md: the loader accepts %s.%s, the example does not show it" % (section, name))
    # [table]'s kinds and their parameters (src/geometry/table_spec.cpp's table_kinds), and [[leaks]]'s keys, in
    # the section of docs/scenes.md on tables
    with open(os.path.join(root, "src", "geometry", "table_spec.cpp")) as fh:
        kinds_src = fh.read()
    kinds_src = kinds_src[kinds_src.index("table_kinds() {"):]
    tables = scenes[scenes.index("## Tables and several leaks"):]
    tables = tables[:tables.index("\n## ")]
    listed_keys = re.search(r"kListedLeakKeys = \{([^}]*)\}", source)
    for m in re.finditer(r'\{"(\w+)",\s*\{([^}]*)\}', kinds_src):
        for name in [m.group(1)] + re.findall(r'"(\w+)"', m.group(2)):
            keys += 1
            if not re.search(r"\b%s\b" % re.escape(name), tables):
                bad.append("docs/scenes.md: [table] takes %s (table kind %s), the tables section does not name it"
                           % (name, m.group(1)))
    for name in re.findall(r'"(\w+)"', listed_keys.group(1)) if listed_keys else ["loop"]:
        keys += 1
        if not re.search(r"^%s\s*=" % re.escape(name), tables, re.M):
            bad.append("docs/scenes.md: [[leaks]] takes %s, the tables example does not show it" % name)
    bad += broken_links(root, tracked(root))
    bad += missing_paths(root, tracked(root))
    bad += bare_python(root, tracked(root))
    bad += readme_repeats_the_guide(root)
    for b in bad:
        print(b)
    if bad:
        return 1
    print("docs: no tracker or specification citations; docs/scenes.md shows all %d scene keys; every link resolves, every path named exists; every python runs as %s"
          % (keys, subprocess.run(["bash", os.path.join(root, "scripts", "setup.sh"), "--python"],
                                  capture_output=True, text=True).stdout.strip()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
