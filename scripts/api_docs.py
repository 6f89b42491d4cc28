#!/usr/bin/python3
"""Writes docs/python-api.md, the Python package's API page, from its docstrings: Sphinx (Debian's
python3-sphinx; autodoc with napoleon for the NumPy convention) builds docs/api as text against the
source tree's python/rotleak, and the page wraps that text. --check compares instead of writing and
exits 1 when the page is stale (the suite's Docs.PythonApiPageIsCurrent). -W: a malformed docstring fails.

Usage: /usr/bin/python3 scripts/api_docs.py [--check]"""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PAGE = os.path.join(ROOT, "docs", "python-api.md")
HEADER = """# The Python API

Generated from the docstrings of `python/rotleak` by `/usr/bin/python3 scripts/api_docs.py` (Sphinx's text
builder over `docs/api`); do not edit by hand, and the suite checks it is current. The guide:
[Python](guide/python.md). For HTML: `PYTHONPATH=python /usr/bin/python3 -m sphinx -b html docs/api runs/api-html`.

<!-- docs: not code: the API reference as Sphinx writes it -->
```text
"""


def build():
    with tempfile.TemporaryDirectory(prefix="rotleak-api-") as out:
        env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"), MPLBACKEND="Agg", PYTHONDONTWRITEBYTECODE="1")
        res = subprocess.run([sys.executable, "-m", "sphinx", "-b", "text", "-W", "-q", "-E",
                              "-d", os.path.join(out, ".doctrees"), os.path.join(ROOT, "docs", "api"), out],
                             env=env, capture_output=True, text=True)
        if res.returncode != 0:
            sys.exit("api_docs: sphinx failed:\n" + res.stdout + res.stderr)
        with open(os.path.join(out, "index.txt"), encoding="utf-8") as f:
            text = f.read()
    # the fence would end at a line of three backquotes; the text builder writes none, but say so if it did
    if "\n```" in text:
        sys.exit("api_docs: the API text holds a line starting with ```")
    return HEADER + text.rstrip("\n") + "\n```\n"


def main():
    page = build()
    if "--check" in sys.argv[1:]:
        with open(PAGE, encoding="utf-8") as f:
            if f.read() != page:
                print("docs/python-api.md is stale: run /usr/bin/python3 scripts/api_docs.py")
                return 1
        print("docs/python-api.md is current")
        return 0
    tmp = PAGE + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(page)
    os.replace(tmp, PAGE)
    print("wrote docs/python-api.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
