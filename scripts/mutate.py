#!/usr/bin/python3
"""Random mutation testing: small errors drawn at random in the lines a change touched, each built and run
against the tests that cover its file, one at a time, in a worktree of its own.

Where scripts/mutation_audit.py keeps hand-written mutants (tests/mutants/*.patch), this draws them: a test that
fails "catches" a mutant, none failing lets it "survive".

Usage: /usr/bin/python3 scripts/mutate.py [--since REV] [--count N] [--seed S] [--files GLOB ...]
           [--tests TEST ...] [--timeout S] [--jobs J] [--min-rate R] [--no-replace-stillborn]
           [--tree DIR --build DIR] [--all-tests] [--list | --only ID ... | --resume | --report]
  --list         draw and print the mutants (and their tests where build-mutate/build is there); builds nothing
  --only ID ...  run just these (ids from --list or build-mutate/results.jsonl): survivors, after new tests
  --resume       reuse the verdicts build-mutate/results.jsonl holds for the same ids (same id: same line text)
  --report       the report of those verdicts for the mutants drawn, with tests/mutants/equivalent.txt's judgements
                 of survivors applied; builds and runs nothing

The lines: those `git diff -U0 REV` (default c6340d4) adds or changes in src analysis verify app python/rotleak
(.cpp .hpp .ipp .py; not src/sim/gpu/*.cu, which needs nvcc), less what holds no code to mutate: comments,
docstrings, preprocessor lines, static_assert, the thrown or raised expression (an error's text). The operators,
each one edit on one line:
  relational    < <= > >= flipped or loosened, == and != swapped   logical   && <-> ||, and <-> or
  off_by_one    an integer n -> n+1 or n-1; [i] -> [i + 1] or [i - 1]; a loop's `< X;` -> `< X - 1;` or `< X + 1;`
  drop_term     a + b, a - b, a * b, a / b -> a                     constant  a float c -> (c * (1 + 1e-3)) or (1 - 1e-3)
  swap_args     f(a, b) -> f(b, a), a and b alike (names or member accesses)
  force_branch  if (c) -> if (true) or if (false); Python's if/elif c: -> True or False
N of them (--count, default 40) are drawn by random.Random(--seed, default 1): a line (every line once before any
twice), then one of its mutants. An id, FILE:LINE:OPERATOR:COLUMN:VARIANT@HASH, ends in a hash of the line's text,
so that an id whose line has changed is known as stale.

Where: HEAD, checked out as a git worktree in build-mutate/tree and built in build-mutate/build (Release, tests,
Python module; ccache serves the first build mostly), so the checkout is never touched: commit what is to be
mutated. --tree and --build name others (a tree of the user's own is mutated in place and restored). The tests
of a file: the test binaries whose object includes it or its header (ninja -t deps; failing that, the headers
of its includers or beside it, or test_cli for the command's own code), for python/rotleak the ctest tests
Python.*; --tests overrides (test_NAME: a test binary; anything else: a `ctest -R` pattern). A test binary runs
once on the unmutated code first; what fails there is not counted as a catch. Against a mutant the tests are built
and run one at a time, those named for a part of its path first, then the quickest, and stop at the first catch
(--all-tests: every one, to list them all).

Verdicts: caught (a test fails, crashes or runs past --timeout, 600 s), survived, equivalent (the same object code,
the same Python AST, or a line `ID reason` in tests/mutants/equivalent.txt by a person who judged it so; its tests
still run), does not build (not counted; another mutant is drawn in its place). The catch rate is
caught / (caught + survived); the exit status is 0 when it is at least --min-rate (0.9). Written: build-mutate/
report.md, results.jsonl (a line per mutant run, appended as each ends; a run without --resume or --only starts it
afresh) and logs/ID.log. Every mutant is restored, also on Ctrl-C, and the build rebuilt at the end.
"""
import argparse
import ast
import bisect
import concurrent.futures
import fnmatch
import hashlib
import io
import json
import keyword
import os
import random
import re
import signal
import subprocess
import sys
import time
import tokenize
from collections import namedtuple

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "build-mutate")
LOGS = os.path.join(OUT, "logs")
RESULTS = os.path.join(OUT, "results.jsonl")
BASELINE = os.path.join(OUT, "baseline.json")
EQUIVALENT = os.path.join(ROOT, "tests", "mutants", "equivalent.txt")
SOURCES = ("src", "analysis", "verify", "app", "python/rotleak")
EXTENSIONS = (".cpp", ".hpp", ".ipp", ".cu", ".py")
PYTHON_TESTS = r"^Python\."
DELTA = "1e-3"
FAILED = re.compile(r"^\[  FAILED  \] ([A-Za-z_][\w/.]*)(?:, where| \(|$)", re.M)  # as mutation_audit.py reads it
CTEST_FAILED = re.compile(
    r"^\s*\d+ - (\S+).*\((?:Failed|Timeout|SEGFAULT|Subprocess aborted|Exception|Not Run)\)\s*$", re.M)
TEST_OBJECT = re.compile(r"^tests/CMakeFiles/(test_\w+)\.dir/")
COMMAND_OBJECT = "app/CMakeFiles/rotleak.dir/"  # the objects of the rotleak command itself (app/cli)
# tests run with this: a .pyc of a mutant, written in the second its copy was, could outlive the mutant
TEST_ENV = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")

Tok = namedtuple("Tok", "kind s start end")  # kind: id num op string (C++ also: char), newline (Python), eof
Code = namedtuple("Code", "text toks match lang")
Mutant = namedtuple("Mutant", "id file line op col var start end new before after")

# ---------------------------------------------------------------------------------------------------------------
# Tokens. Comments and preprocessor lines are no tokens at all, strings one each: no edit reaches into them.

CPP_PUNCT = ("<=>", "<<=", ">>=", "...", "->*", "->", "++", "--", "<<", ">>", "<=", ">=", "==", "!=", "&&", "||",
             "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "::", ".*")
RAW_STRING = re.compile(r'(?:u8|[uUL])?R"([^()\\ \t\n]{0,16})\(')
STRING = re.compile(r"""(?:u8|[uUL])?(["'])""")
NUMBER = re.compile(r"\.?\d(?:[eEpP][+-]|'(?=\w)|[\w.])*")  # a pp-number: 1e-3, 0x1F, 1'000, 2.5f
IDENT = re.compile(r"[A-Za-z_]\w*")


def lex_cpp(text):
    toks, i, n, line_start = [], 0, len(text), True
    while i < n:
        c = text[i]
        if c == "\n":
            i, line_start = i + 1, True
            continue
        if c in " \t\r\f\v" or (c == "\\" and text.startswith("\n", i + 1)):
            i += 1
            continue
        if line_start and c == "#":  # a directive, with the lines a backslash continues it on
            e = text.find("\n", i)
            while e >= 0 and text[e - 2 if text[e - 1] == "\r" else e - 1] == "\\":
                e = text.find("\n", e + 1)
            i = n if e < 0 else e
            continue
        line_start = False
        if text.startswith("//", i):
            e = text.find("\n", i)
            i = n if e < 0 else e
            continue
        if text.startswith("/*", i):
            e = text.find("*/", i + 2)
            i = n if e < 0 else e + 2
            continue
        m = RAW_STRING.match(text, i)
        if m:
            close = ")" + m.group(1) + '"'
            e = text.find(close, m.end())
            e = n if e < 0 else e + len(close)
            toks.append(Tok("string", text[i:e], i, e))
            i = e
            continue
        m = STRING.match(text, i)
        if m:
            q, j = m.group(1), m.end()
            while j < n and text[j] not in (q, "\n"):
                j += 2 if text[j] == "\\" else 1
            s = IDENT.match(text, j + 1)  # a user-defined literal's suffix: "abc"sv
            e = s.end() if s else min(j + 1, n)
            toks.append(Tok("string" if q == '"' else "char", text[i:e], i, e))
            i = e
            continue
        m = NUMBER.match(text, i) or IDENT.match(text, i)
        if m:
            toks.append(Tok("num" if text[i] in "0123456789." else "id", m.group(), i, m.end()))
            i = m.end()
            continue
        p = next((p for p in CPP_PUNCT if text.startswith(p, i)), c)
        toks.append(Tok("op", p, i, i + len(p)))
        i += len(p)
    toks.append(Tok("eof", "", n, n))
    return toks


PY_KINDS = {tokenize.NAME: "id", tokenize.NUMBER: "num", tokenize.OP: "op", tokenize.STRING: "string",
            tokenize.NEWLINE: "newline", tokenize.INDENT: "newline", tokenize.DEDENT: "newline"}


def lex_py(text):
    starts = line_starts(text)

    def offset(row, col):
        return starts[row - 1] + col if row - 1 < len(starts) else len(text)

    toks = [Tok(PY_KINDS[t.type], t.string, offset(*t.start), offset(*t.end))
            for t in tokenize.generate_tokens(io.StringIO(text).readline) if t.type in PY_KINDS]
    return toks + [Tok("eof", "", len(text), len(text))]


def line_starts(text):
    return [0] + [m.end() for m in re.finditer("\n", text)]


def match_brackets(toks):
    match, stack = {}, []
    closing = {")": "(", "]": "[", "}": "{"}
    for i, t in enumerate(toks):
        if t.kind != "op":
            continue
        if t.s in ("(", "[", "{"):
            stack.append(i)
        elif t.s in closing:
            while stack and toks[stack[-1]].s != closing[t.s]:  # a stray bracket (a macro's half)
                stack.pop()
            if stack:
                j = stack.pop()
                match[i], match[j] = j, i
    return match


def frozen_tokens(c):
    """The tokens no edit may touch: a static_assert, and what a throw or raise throws (an error's text: mutating it
    proves nothing). A condition before them on the line stays open."""
    toks, frozen = c.toks, [False] * len(c.toks)
    for i, t in enumerate(toks):
        if t.kind != "id":
            continue
        if c.lang == "cpp" and t.s == "static_assert" and i + 1 in c.match:
            end = c.match[i + 1] + 1
        elif t.s == ("throw" if c.lang == "cpp" else "raise"):
            end, depth = i + 1, 0
            while toks[end].kind not in ("eof", "newline") and not (toks[end].s == ";" and depth == 0):
                if toks[end].kind == "op" and toks[end].s in ("(", "[", "{"):
                    depth += 1
                elif toks[end].kind == "op" and toks[end].s in (")", "]", "}"):
                    depth -= 1
                    if depth < 0:
                        break
                end += 1
        else:
            continue
        frozen[i:end] = [True] * (end - i)
    return frozen


# ---------------------------------------------------------------------------------------------------------------
# Operators: each yields (operator, first token, end token, start, end, new text) of one edit.

CPP_KEYWORDS = set("""alignas alignof asm auto bool break case catch char char8_t char16_t char32_t class concept const
    consteval constexpr constinit const_cast continue co_await co_return co_yield decltype default delete do double
    dynamic_cast else enum explicit export extern false float for friend goto if inline int long mutable namespace new
    noexcept nullptr operator private protected public register reinterpret_cast requires return short signed sizeof
    static static_assert static_cast struct switch template this throw true try typedef typeid typename union unsigned
    using virtual void volatile wchar_t while""".split())
PY_KEYWORDS = set(keyword.kwlist)
VALUES = {"cpp": {"this", "true", "false", "nullptr"}, "py": {"True", "False", "None"}}
# C++ words that start an operand though keywords: casts, sizeof, a functional cast double(x)
CPP_CALLS = {"static_cast", "const_cast", "reinterpret_cast", "dynamic_cast", "sizeof", "alignof", "double", "float",
             "int", "long", "unsigned", "bool", "char", "short", "signed"}
PY_TYPE_NAMES = {"int", "float", "str", "bool", "bytes", "object", "list", "dict", "tuple", "set", "type"}
# swapping their arguments changes nothing worth a test (but NaNs or which of two equals is returned)
COMMUTATIVE = {"min", "max", "fmin", "fmax", "hypot", "swap", "gcd", "lcm", "isclose", "maximum", "minimum"}
RELATIONAL = {"<": (">=", "<="), "<=": (">", "<"), ">": ("<=", ">="), ">=": ("<", ">"), "==": ("!=",),
              "!=": ("==",)}
CPP_INT = re.compile(r"([1-9][0-9']*|0)([uU](?:ll|LL|l|L|z|Z)?|(?:ll|LL|l|L|z|Z)[uU]?)?")
PY_INT = re.compile(r"([1-9][0-9_]*|0+)()")
CPP_FLOAT = re.compile(r"(?:\d[\d']*\.[\d']*|\.\d[\d']*|\d[\d']*(?=[eE]))(?:[eE][+-]?\d+)?[fFlL]?")
PY_FLOAT = re.compile(r"(?:\d[\d_]*\.[\d_]*|\.\d[\d_]*|\d[\d_]*(?=[eE]))(?:[eE][+-]?\d[\d_]*)?")


def is_name(c, t):
    return t.kind == "id" and t.s not in (CPP_KEYWORDS if c.lang == "cpp" else PY_KEYWORDS)


def spaced(c, t):
    """A binary operator: clang-format puts a space on both sides of one, none inside a template's <...>."""
    return c.text[t.start - 1:t.start] == " " and c.text[t.end:t.end + 1] == " "


def ends_operand(c, t):
    if t.kind == "num" or (t.kind == "id" and (is_name(c, t) or t.s in VALUES[c.lang])):
        return True
    return t.kind == "op" and t.s in ((")", "]") if c.lang == "cpp" else (")", "]", "}"))


def span(c, a, b):
    return c.text[c.toks[a].start:c.toks[b - 1].end]


def template_end(c, k):
    """The end of the template arguments whose < is at k, or None."""
    depth, toks = 0, c.toks
    while toks[k].kind != "eof":
        s = toks[k].s if toks[k].kind == "op" else ""
        if s in ("(", "[") and k in c.match:
            k = c.match[k]
        elif s in (";", "{", "}", ")", "]", "&&", "||"):
            return None
        depth += {"<": 1, ">": -1, ">>": -2}.get(s, 0)
        k += 1
        if depth <= 0:
            return k if depth == 0 else None
    return None


def factor_end(c, k):
    """The end of the factor starting at token k: a unary sign, then a number, a parenthesised expression or a name
    with what follows it (::, ., ->, template arguments, a call, an index, Python's **); None where it is none."""
    toks, py = c.toks, c.lang == "py"
    if toks[k].kind == "op" and toks[k].s in ("-", "+", "!", "~", "*") and toks[k + 1].start == toks[k].end:
        k += 1
    t = toks[k]
    if t.kind == "num":
        return k + 1
    if t.kind == "op" and (t.s == "(" or (py and t.s in ("[", "{"))) and k in c.match:
        k = c.match[k] + 1
    elif is_name(c, t) or (t.kind == "id" and t.s in VALUES[c.lang]):
        k += 1
    elif not py and t.kind == "id" and t.s in CPP_CALLS and toks[k + 1].s in ("(", "<", "{"):
        k += 1
    elif not py and t.s == "::" and toks[k + 1].kind == "id":
        k += 2
    else:
        return None
    while toks[k].kind == "op":
        t, adjacent = toks[k], toks[k].start == toks[k - 1].end
        if t.s in ((".",) if py else (".", "->", "::")) and toks[k + 1].kind == "id":
            k += 2
        elif t.s in ("(", "[") and adjacent and k in c.match:
            k = c.match[k] + 1
        elif not py and t.s == "{" and adjacent and toks[k - 1].kind == "id" and k in c.match:
            k = c.match[k] + 1
        elif not py and t.s == "<" and adjacent and toks[k - 1].kind == "id":
            k = template_end(c, k)
        elif py and t.s == "**":
            k = factor_end(c, k + 1)
        else:
            break
        if k is None:
            return None
    return k


def operand_end(c, k, level):
    """The end of the operand at k: a factor (level 0), a product of factors (1), a sum of products (2)."""
    ops = ((), ("*", "/", "%", "//", "@"), ("*", "/", "%", "//", "@", "+", "-"))[level]
    k = factor_end(c, k)
    while k is not None and c.toks[k].kind == "op" and c.toks[k].s in ops and spaced(c, c.toks[k]):
        k = factor_end(c, k + 1)
    return k


def declares(c, i):
    """Whether the name at i is declared (`double a[3]`, `std::array<int, 2> b[4]`, `int x[N], y[N]`): a [...]
    after it is a size, not an index."""
    toks = c.toks
    q = toks[i - 1]
    if c.lang != "cpp" or toks[i].kind != "id":
        return False
    if q.kind == "id":
        return q.s not in ("return", "case", "co_return", "co_yield", "throw", "else", "do", "delete", "new")
    if q.s != ",":
        return q.kind == "op" and q.s in (">", "*", "&", "&&") and not spaced(c, q)
    k = i - 1  # a later declarator of a list: does the statement start with a declaration?
    while k > 0 and toks[k - 1].s not in (";", "{", "}"):
        k -= 1
        if toks[k].s in (")", "]") and k in c.match:
            k = c.match[k]
        elif toks[k].s in ("(", "["):
            return False  # an argument list: f(a, b[i])
    while toks[k].s in ("static", "constexpr", "const", "inline", "thread_local", "mutable", "alignas"):
        k = c.match[k + 1] + 1 if toks[k].s == "alignas" and k + 1 in c.match else k + 1
    if toks[k].kind != "id" or not (is_name(c, toks[k]) or toks[k].s in CPP_CALLS or toks[k].s == "auto"):
        return False
    k += 1
    while toks[k].s == "::" and toks[k + 1].kind == "id":
        k += 2
    if toks[k].s == "<" and toks[k].start == toks[k - 1].end:
        k = template_end(c, k) or k
    while toks[k].s in ("*", "&", "const"):
        k += 1
    return is_name(c, toks[k]) and k < i


def relational(c):
    for i, t in enumerate(c.toks):
        if t.kind == "op" and t.s in RELATIONAL and (c.lang == "py" or spaced(c, t)) and \
                c.toks[i - 1].s not in ("template", "operator"):
            for new in RELATIONAL[t.s]:
                yield "relational", i, i + 1, t.start, t.end, new


def off_by_one(c):
    toks, ints = c.toks, CPP_INT if c.lang == "cpp" else PY_INT
    for i, t in enumerate(toks):
        m = ints.fullmatch(t.s) if t.kind == "num" else None
        if m and not (toks[i - 1].s == "[" and toks[i + 1].s == "]" and declares(c, i - 2)):
            n = int(m.group(1).replace("'", "").replace("_", ""))
            # -1 is the number: -1 -> 0 or -2 (not -0 or -2); 0 -> 1 only (0u - 1 would wrap)
            a = i - 1 if toks[i - 1].s == "-" and toks[i - 1].end == t.start and \
                not ends_operand(c, toks[i - 2]) else i
            n = -n if a < i else n
            for v in (n + 1, n - 1) if n != 0 or a < i else (n + 1,):
                yield "off_by_one", a, i + 1, toks[a].start, t.end, str(v) + (m.group(2) or "")
        elif t.kind == "op" and t.s == "[" and is_name(c, toks[i + 1]) and toks[i + 2].s == "]" and \
                toks[i - 1].end == t.start and (is_name(c, toks[i - 1]) or toks[i - 1].s in (")", "]")) and \
                not declares(c, i - 1) and \
                not (c.lang == "py" and (toks[i + 1].s[:1].isupper() or toks[i + 1].s in PY_TYPE_NAMES)):
            a = toks[i + 1]
            for d in (" + 1", " - 1"):
                yield "off_by_one", i + 1, i + 2, a.start, a.end, a.s + d
        elif c.lang == "cpp" and t.kind == "op" and t.s in ("<", "<=") and spaced(c, t):
            e = operand_end(c, i + 1, 2)  # a loop's bound: `i < n;`
            if e is not None and toks[e].s == ";":
                for d in (" - 1", " + 1"):
                    yield "off_by_one", i + 1, e, toks[e - 1].end, toks[e - 1].end, d


def drop_term(c):
    for i, t in enumerate(c.toks):
        if t.kind == "op" and t.s in ("+", "-", "*", "/") and spaced(c, t) and ends_operand(c, c.toks[i - 1]):
            # the right operand of + and - is a product (a + b * c loses b * c), of * and / a factor
            e = operand_end(c, i + 1, 1 if t.s in "+-" else 0)
            if e is not None:
                yield "drop_term", i, e, t.start - 1, c.toks[e - 1].end, ""


def logical(c):
    pairs = {"&&": "||", "||": "&&"} if c.lang == "cpp" else {"and": "or", "or": "and"}
    for i, t in enumerate(c.toks):
        if t.s in pairs and (spaced(c, t) if c.lang == "cpp" else t.kind == "id"):
            yield "logical", i, i + 1, t.start, t.end, pairs[t.s]


def constant(c):
    floats = CPP_FLOAT if c.lang == "cpp" else PY_FLOAT
    for i, t in enumerate(c.toks):
        if t.kind == "num" and floats.fullmatch(t.s) and float(re.sub(r"[fFlL'_]", "", t.s)) != 0:
            for sign in "+-":
                yield "constant", i, i + 1, t.start, t.end, f"({t.s} * (1 {sign} {DELTA}))"


def chain_end(c, k):
    """A plain name or member access (a, a.b, p->x, ns::x) at k: its end and its shape, or (None, None)."""
    toks = c.toks
    if not (is_name(c, toks[k]) or toks[k].s == "this"):
        return None, None
    shape, k = "a", k + 1
    while toks[k].kind == "op" and toks[k].s in ((".", "->", "::") if c.lang == "cpp" else (".",)) and \
            is_name(c, toks[k + 1]):
        shape, k = shape + toks[k].s + "a", k + 2
    return k, shape


def swap_args(c):
    toks = c.toks
    for i, t in enumerate(toks):
        if not (is_name(c, t) and toks[i + 1].s == "(" and toks[i + 1].start == t.end) or t.s in COMMUTATIVE or \
                (c.lang == "py" and toks[i - 1].s in ("def", "class")):
            continue
        e1, shape1 = chain_end(c, i + 2)
        if e1 is None or toks[e1].s != ",":
            continue
        e2, shape2 = chain_end(c, e1 + 1)
        if e2 is None or toks[e2].s not in (",", ")") or shape1 != shape2:
            continue
        x, y = span(c, i + 2, e1), span(c, e1 + 1, e2)
        if x != y:
            yield "swap_args", i + 2, e2, toks[i + 2].start, toks[e2 - 1].end, f"{y}, {x}"


def force_branch(c):
    toks = c.toks
    for i, t in enumerate(toks):
        if t.kind != "id":
            continue
        if c.lang == "cpp" and t.s == "if" and toks[i + 1].s == "(" and i + 1 in c.match:
            a, b = i + 2, c.match[i + 1]
            k = a
            while k < b and toks[k].s != ";":  # no `if (init; cond)`: the init's names are used below
                k = c.match[k] + 1 if toks[k].s in ("(", "[", "{") and k in c.match else k + 1
            if k < b:
                continue
            words = ("true", "false")
        elif c.lang == "py" and t.s in ("if", "elif") and toks[i - 1].kind in ("newline", "eof"):  # not `x if c else y`
            a = b = i + 1
            depth = 0
            while toks[b].kind not in ("newline", "eof") and toks[b].s != "lambda" and \
                    not (depth == 0 and toks[b].s == ":"):
                depth += (toks[b].s in ("(", "[", "{")) - (toks[b].s in (")", "]", "}"))
                b += 1
            if toks[b].s != ":":
                continue
            words = ("True", "False")
        else:
            continue
        if b > a:
            for w in words:
                if span(c, a, b) != w:
                    yield "force_branch", a, b, toks[a].start, toks[b - 1].end, w


OPERATORS = (relational, off_by_one, drop_term, logical, constant, swap_args, force_branch)


def mutants_of(path, text, lines=None):
    """Every mutant of a file, on the given lines (all when None), in a fixed order: the same text, the same ids."""
    lang = "py" if path.endswith(".py") else "cpp"
    try:
        toks = lex_py(text) if lang == "py" else lex_cpp(text)
    except (tokenize.TokenError, SyntaxError) as e:
        print(f"[mutate] {path}: not read ({e}); no mutants from it", file=sys.stderr)
        return []
    c = Code(text, toks, match_brackets(toks), lang)
    frozen, starts, sites = frozen_tokens(c), line_starts(text), {}
    for operator in OPERATORS:
        for op, i0, i1, start, end, new in operator(c):
            line = bisect.bisect_right(starts, start)
            if any(frozen[i0:i1]) or "\n" in text[start:end] or (lines is not None and line not in lines):
                continue
            sites.setdefault((line, start - starts[line - 1] + 1, op), []).append((start, end, new))
    out = []
    for (line, col, op), edits in sorted(sites.items()):
        lo = starts[line - 1]
        hi = text.find("\n", lo)
        before = text[lo:len(text) if hi < 0 else hi].rstrip("\r")
        h = hashlib.sha1(before.encode()).hexdigest()[:8]
        for var, (start, end, new) in enumerate(edits):
            after = before[:start - lo] + new + before[end - lo:]
            out.append(Mutant(f"{path}:{line}:{op}:{col}:{var}@{h}", path, line, op, col, var, start, end, new,
                              before, after))
    return out


def apply(text, m):
    return text[:m.start] + m.new + text[m.end:]


def change(m, width=32):
    """The edit in a few words of its line: ('a < b', 'a >= b')."""
    s = m.col - 1
    e = s + (m.end - m.start)
    indent = len(m.before) - len(m.before.lstrip())
    lo, hi = max(indent, s - width), min(len(m.before), e + width)
    pre = ("..." if lo > indent else "") + m.before[lo:s]
    post = m.before[e:hi] + ("..." if hi < len(m.before) else "")
    return (pre + m.before[s:e] + post).strip(), (pre + m.new + post).strip()


# ---------------------------------------------------------------------------------------------------------------
# The lines, and the draw.

def git(*args, cwd=ROOT, check=True):
    r = subprocess.run(["git", "-C", cwd, *args], capture_output=True, text=True)
    if check and r.returncode:
        raise SystemExit(f"[mutate] git {' '.join(args)}: {r.stderr.strip()}")
    return r.stdout


def wanted(path, globs):
    return path.endswith(EXTENSIONS) and not (path.startswith("src/sim/gpu/") and path.endswith(".cu")) and \
        (not globs or any(fnmatch.fnmatch(path, g) for g in globs))


def changed_lines(since, tree, globs):
    """{file: {line, ...}}: the lines of the current version that `git diff -U0 SINCE` adds or changes; those of
    HEAD where tree is None, else those of the tree's files as they are."""
    revs = [since] if tree else [since, "HEAD"]
    out = git("diff", "-U0", "-M", "--no-color", "--no-ext-diff", *revs, "--", *SOURCES, cwd=tree or ROOT)
    files, path = {}, None
    for line in out.splitlines():
        if line.startswith("+++ "):
            path = line[6:] if line.startswith("+++ b/") else None
        elif line.startswith("@@") and path and wanted(path, globs):
            m = re.match(r"@@ -\S+ \+(\d+)(?:,(\d+))? @@", line)
            first, count = int(m.group(1)), int(m.group(2) if m.group(2) is not None else 1)
            files.setdefault(path, set()).update(range(first, first + count))
    return files


def read_source(tree, path):
    if tree:
        with open(os.path.join(tree, path), "rb") as f:
            return f.read().decode("utf-8")
    r = subprocess.run(["git", "-C", ROOT, "show", "HEAD:" + path], capture_output=True, check=True)
    return r.stdout.decode("utf-8")


def mutant_pool(since, tree, globs):
    """{(file, line): [mutant, ...]} over the changed lines that have a mutant."""
    pool = {}
    for path, lines in sorted(changed_lines(since, tree, globs).items()):
        for m in mutants_of(path, read_source(tree, path), lines):
            pool.setdefault((path, m.line), []).append(m)
    return pool


def draws(pool, seed):
    """Mutants in the order the seed draws them: a line first, every line once a round, then one of its mutants."""
    rng = random.Random(seed)
    left = {k: list(v) for k, v in pool.items()}
    while left:
        keys = sorted(left)
        rng.shuffle(keys)
        for k in keys:
            ms = left[k]
            yield ms.pop(rng.randrange(len(ms)))
            if not ms:
                del left[k]


def resolve(ids, tree):
    """The mutants these ids name, in the tree as it is; an id whose line changed is stale."""
    out, bad = [], []
    for i in ids:
        base, _, _ = i.rpartition("@")
        parts = base.split(":")
        if len(parts) < 5 or not parts[-4].isdigit():
            bad.append(f"{i}: not an id (FILE:LINE:OPERATOR:COLUMN:VARIANT@HASH)")
            continue
        path, line = ":".join(parts[:-4]), int(parts[-4])
        try:
            ms = mutants_of(path, read_source(tree, path), {line})
        except (OSError, subprocess.CalledProcessError):
            bad.append(f"{i}: no file {path}")
            continue
        found = [m for m in ms if m.id == i]
        if found:
            out.append(found[0])
        elif any(m.id.rpartition("@")[0] == base for m in ms) or any(m.line == line for m in ms):
            bad.append(f"{i}: stale, {path}:{line} has changed since (draw again)")
        else:
            bad.append(f"{i}: no such mutant in {path}:{line}")
    if bad:
        raise SystemExit("[mutate] " + "\n[mutate] ".join(bad))
    return out


def read_equivalents():
    """{id: reason} from tests/mutants/equivalent.txt: `ID reason` a line, # comments."""
    out = {}
    if os.path.isfile(EQUIVALENT):
        with open(EQUIVALENT, encoding="utf-8") as f:
            for line in f:
                line = line.strip()
                if line and not line.startswith("#"):
                    i, reason = (line.split(None, 1) + [""])[:2]
                    out[i] = reason.strip() or "judged equivalent"
    return out


# ---------------------------------------------------------------------------------------------------------------
# The tree, the build, and which tests cover a file.

LIVE = set()  # the process groups running now: killed with us


def execute(cmd, cwd=None, timeout=None, env=None):
    """(exit status, output, timed out) of a command in a process group of its own, killed whole on a timeout."""
    p = subprocess.Popen(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                         errors="replace", start_new_session=True)
    LIVE.add(p)
    try:
        out, _ = p.communicate(timeout=timeout)
        return p.returncode, out, False
    except subprocess.TimeoutExpired:
        kill(p)
        out, _ = p.communicate()
        return p.returncode, out, True
    except BaseException:
        kill(p)
        p.wait()
        raise
    finally:
        LIVE.discard(p)


def kill(p):
    try:
        os.killpg(p.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def prepare_worktree(tree):
    """build-mutate/tree: a worktree of HEAD, added or brought to HEAD; a file a killed run left mutated (and marked
    assume-unchanged) is restored by the checkout."""
    head = git("rev-parse", "HEAD").strip()
    if not os.path.exists(os.path.join(tree, ".git")):
        if os.path.exists(tree):
            raise SystemExit(f"[mutate] {tree} is there but no git worktree: remove it")
        os.makedirs(os.path.dirname(tree), exist_ok=True)
        git("worktree", "prune")
        git("worktree", "add", "--detach", tree, head)
        return
    hidden = [line[2:] for line in git("ls-files", "-v", cwd=tree).splitlines() if line[:1].islower()]
    if hidden:
        git("update-index", "--no-assume-unchanged", "--", *hidden, cwd=tree)
    left = git("status", "--porcelain", "--untracked-files=no", cwd=tree).splitlines()
    if left:
        print(f"[mutate] restoring what a stopped run left changed in {tree}: " + ", ".join(x[3:] for x in left))
    git("checkout", "--quiet", "--force", "--detach", head, cwd=tree)


def warn_uncommitted(files):
    changed = [line[3:] for line in git("status", "--porcelain", "--untracked-files=no", "--", *files).splitlines()]
    if changed:
        print(f"[mutate] warning: the checkout has uncommitted changes to {len(changed)} file(s) mutants may touch "
              f"({', '.join(changed[:5])}{', ...' if len(changed) > 5 else ''}); the worktree mutates HEAD's "
              "version of them: commit to have the changes mutated", file=sys.stderr)


def hide(tree, path, on):
    """Marks a mutated file assume-unchanged while it is: else `git describe --dirty` writes another version.hpp
    and most objects rebuild (and none would have the same code)."""
    flag = git("ls-files", "-v", "--", path, cwd=tree, check=False)[:1]
    if flag and flag.isupper() == on:  # tracked, and not so marked already (by someone else: then left as it is)
        git("update-index", "--assume-unchanged" if on else "--no-assume-unchanged", "--", path, cwd=tree,
            check=False)
        return True
    return False


def configure(tree, build):
    cache = os.path.join(build, "CMakeCache.txt")
    if os.path.isfile(os.path.join(build, "build.ninja")) and os.path.isfile(cache):
        with open(cache, errors="replace") as f:
            home = re.search(r"^CMAKE_HOME_DIRECTORY:INTERNAL=(.*)$", f.read(), re.M)
        if home and os.path.realpath(home.group(1)) != os.path.realpath(tree):
            raise SystemExit(f"[mutate] {build} is the build of {home.group(1)}, not of {tree}")
        return
    cmd = ["cmake", "-G", "Ninja", "-S", tree, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DROTLEAK_TESTS=ON",
           "-DROTLEAK_BENCH=OFF", "-DROTLEAK_WARNINGS=ON", "-DROTLEAK_PYTHON_MODULE=ON"]
    print("[mutate] configuring: " + " ".join(cmd), flush=True)
    rc, out, _ = execute(cmd)
    with open(os.path.join(LOGS, "configure.log"), "w") as log:
        log.write(out)
    if rc:
        raise SystemExit(f"[mutate] configuring failed; {LOGS}/configure.log:\n" + out[-2000:])


def build(build_dir, targets, jobs, log=None):
    cmd = ["cmake", "--build", build_dir, "-j", str(jobs)] + (["--target", *targets] if targets else [])
    rc, out, _ = execute(cmd)
    if log:
        log.write(f"$ {' '.join(cmd)}\n{out}\n")
    return rc == 0, out


def scan_objects(build_dir, seen):
    """The objects (*.o) written since the last scan; seen (path -> ((mtime, size), sha256)) is brought up to date."""
    written = set()
    for d, _, files in os.walk(build_dir):
        for f in files:
            if f.endswith(".o"):
                p = os.path.join(d, f)
                st = os.stat(p)
                key = (st.st_mtime_ns, st.st_size)
                if p not in seen or seen[p][0] != key:
                    with open(p, "rb") as fh:
                        seen[p] = (key, hashlib.sha256(fh.read()).hexdigest())
                    written.add(p)
    return written


def read_deps(build_dir, tree):
    """{object: {file, ...}} from ninja's deps log (`OBJ: #deps N, ...` then its files indented), the files those
    of the tree, relative to it."""
    r = subprocess.run(["ninja", "-C", build_dir, "-t", "deps"], capture_output=True, text=True)
    prefixes = {os.path.abspath(tree) + os.sep, os.path.realpath(tree) + os.sep}
    deps, obj = {}, None
    for line in r.stdout.splitlines():
        if not line.strip():
            continue
        if not line[0].isspace():
            obj = line.rsplit(": #deps", 1)[0]
            deps[obj] = set()
            continue
        p = os.path.normpath(os.path.join(build_dir, line.strip()))
        for pre in prefixes:
            if p.startswith(pre):
                deps[obj].add(p[len(pre):])
                break
    return deps


KNOWN = {}  # what was looked up once: (question, name) -> answer


def runs_command(tree, test):
    """Whether a test binary runs the rotleak command (its source calls rotleak_binary()): it needs it built."""
    if ("command", test) not in KNOWN:
        try:
            with open(os.path.join(tree, "tests", test + ".cpp"), encoding="utf-8", errors="replace") as f:
                KNOWN["command", test] = "rotleak_binary(" in f.read()
        except OSError:
            KNOWN["command", test] = False
    return KNOWN["command", test]


def covering_tests(path, deps, tree):
    """The test binaries that cover a C++ file: those whose object includes it or, for a .cpp or .ipp, its .hpp;
    failing that, those that cover its includers' sources or the headers beside it that they include; failing that,
    for the command's own code, the tests that run the command."""
    tests = {m.group(1): d for o, d in deps.items() for m in [TEST_OBJECT.match(o)] if m}

    def direct(f):
        hpp = os.path.splitext(f)[0] + ".hpp"
        return {t for t, d in tests.items() if f in d or (f.endswith((".cpp", ".ipp")) and hpp in d)}

    found = direct(path)
    includers = [o for o, d in deps.items() if path in d and not TEST_OBJECT.match(o)]
    if not found:
        here = os.path.dirname(path)
        for o in includers:
            for f in deps[o] - {path}:
                if (f.endswith(".cpp") and not path.endswith(".cpp")) or \
                        (f.endswith(".hpp") and os.path.dirname(f) == here):
                    found |= direct(f)
    if not found and any(o.startswith(COMMAND_OBJECT) for o in includers):
        found = {t for t in tests if runs_command(tree, t)}
    return sorted(found)


def has_target(build_dir, name):
    if ("target", name) not in KNOWN:
        r = subprocess.run(["ninja", "-C", build_dir, "-t", "query", name], capture_output=True)
        KNOWN["target", name] = r.returncode == 0
    return KNOWN["target", name]


def test_specs(m, args, deps, tree, build_dir):
    """What runs against a mutant: `test_NAME` a test binary, `ctest:PATTERN` the ctest tests it matches."""
    if args.tests:
        return [t if re.fullmatch(r"test_\w+", t) else "ctest:" + t for t in args.tests]
    if m.file.endswith(".py"):
        return ["ctest:" + PYTHON_TESTS]
    return covering_tests(m.file, deps, tree)


def targets_for(specs, path, deps, tree, build_dir):
    """The targets to build for these tests (None: everything): their own objects, which is all "the same object
    code" speaks for (the objects the tests link)."""
    targets = set()
    for s in specs:
        if s == "ctest:" + PYTHON_TESTS:
            targets |= {"rotleak", "rotleak_python_files"} | ({"rotleak_python"} if has_target(
                build_dir, "rotleak_python") else set())
        elif s.startswith("ctest:"):
            return None
        else:
            targets |= {s, "rotleak"} if runs_command(tree, s) else {s}
    return sorted(targets)


def gtest_brief(binary):
    """Whether GoogleTest takes --gtest_brief=1 (1.11 on: only the failures' output); every binary links the same."""
    if "brief" not in KNOWN:
        KNOWN["brief"] = "gtest_brief" in execute([binary, "--help"], timeout=10)[1]
    return KNOWN["brief"]


SECONDS = {}  # each spec's wall seconds, as its last run took


def run_spec(spec, build_dir, timeout, jobs):
    """(the tests that fail, the output) of one spec; its wall seconds in SECONDS."""
    t0 = time.time()
    try:
        return run_one(spec, build_dir, timeout, jobs)
    finally:
        SECONDS[spec] = time.time() - t0


def run_one(spec, build_dir, timeout, jobs):
    if spec.startswith("ctest:"):
        cmd = ["ctest", "-R", spec[6:], "-j", str(jobs), "--timeout", str(timeout), "--no-tests=error",
               "--output-on-failure"]
        rc, out, timed_out = execute(cmd, cwd=build_dir, timeout=timeout * 10, env=TEST_ENV)
        names = list(dict.fromkeys(CTEST_FAILED.findall(out)))
        if timed_out or (rc and not names):
            names.append(f"ctest -R {spec[6:]} ({'timeout' if timed_out else f'exit {rc}'})")
        return names, f"$ {' '.join(cmd)}\n{out}\n"
    binary = os.path.join(build_dir, "tests", spec)
    if not os.path.isfile(binary):
        return [f"{spec} (no such binary)"], f"no test binary {binary}\n"
    cmd = [binary] + (["--gtest_brief=1"] if gtest_brief(binary) else [])
    rc, out, timed_out = execute(cmd, cwd=build_dir, timeout=timeout, env=TEST_ENV)
    names = list(dict.fromkeys(FAILED.findall(out)))
    if timed_out:
        names.append(f"{spec} (timeout {timeout} s)")
    elif rc < 0:
        names.append(f"{spec} (signal {-rc})")
    elif rc and not names:
        names.append(f"{spec} (exit {rc})")
    return names, f"$ {' '.join(cmd)}\n{out}\n"


def run_specs(specs, build_dir, timeout, jobs):
    """[(failures, output)] of the specs, `jobs` at a time (a mutant's tests run one step at a time and stop at the
    first catch: run_mutant)."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        futures = [pool.submit(run_spec, s, build_dir, timeout, jobs) for s in specs]
        try:
            return [f.result() for f in futures]
        except BaseException:
            for p in list(LIVE):
                kill(p)
            raise


def baseline(specs, state, ctx):
    """What fails on the unmutated code, of these specs: each run once (built first, restoring what an earlier
    mutant left in its objects), remembered in build-mutate/baseline.json for the same commit."""
    need = [s for s in specs if s not in state["tests"]]
    if need:
        print(f"[mutate] the unmutated code first: {', '.join(need)}", flush=True)
        with open(os.path.join(LOGS, "baseline.log"), "a") as log:
            ok, out = build(ctx["build"], targets_for(need, None, ctx["deps"], ctx["tree"], ctx["build"]),
                            ctx["jobs"], log)
            if not ok:
                raise SystemExit(f"[mutate] the unmutated tree does not build ({LOGS}/baseline.log):\n" + out[-2000:])
            for s, (names, text) in zip(need, run_specs(need, ctx["build"], ctx["timeout"], ctx["jobs"])):
                log.write(text)
                state["tests"][s] = names
                state.setdefault("seconds", {})[s] = round(SECONDS.get(s, 0), 1)
                if names:
                    print(f"[mutate] {s} fails on the unmutated code ({', '.join(names[:4])}"
                          f"{', ...' if len(names) > 4 else ''}): not counted as catches", flush=True)
        if state.get("commit"):
            with open(BASELINE, "w") as f:
                json.dump(state, f, indent=1)
    return {n for s in specs for n in state["tests"][s]}


# ---------------------------------------------------------------------------------------------------------------
# One mutant.

def record(m, verdict, failed=(), reason="", seconds=0.0, tests=()):
    before, after = change(m)
    return {"id": m.id, "file": m.file, "line": m.line, "operator": m.op, "before": before, "after": after,
            "verdict": verdict, "failed": list(failed), "reason": reason, "seconds": round(seconds, 1),
            "tests": list(tests)}


def test_order(spec, path, ctx):
    """Which test to build and run first: one named for a part of the file's path (test_table for
    src/geometry/table.hpp, test_geometry too), then the quickest (their unmutated times)."""
    words = set(re.split(r"[/_.]", path)) - {"src", "hpp", "cpp", "ipp", "py"}
    named = any(w in words for w in spec.removeprefix("test_").split("_"))
    return (0 if named else 1, ctx["state"].get("seconds", {}).get(spec, 1e9))


def same_object_code(m, ctx, written, log, complete):
    """Whether the mutant compiled to what the unmutated file did: objects that include the file were rebuilt and no
    object written differs from the unmutated build's. Only once `complete` (every test built, or a .cpp's own
    objects, which every test links alike); Python never (its AST is judged before)."""
    if m.file.endswith(".py") or not complete:
        return False
    mine = {os.path.join(ctx["build"], o) for o, d in ctx["deps"].items() if m.file in d} & written
    changed = [p for p in written if ctx["seen"][p][1] != ctx["base"].get(p)]
    log.write(f"objects rebuilt: {len(written)}, of them including the file: {len(mine)}; changed: "
              f"{' '.join(os.path.relpath(p, ctx['build']) for p in changed) or 'none'}\n")
    return bool(mine) and not changed


def run_mutant(m, specs, ctx, equivalents):
    t0 = time.time()
    judged = equivalents.get(m.id)
    path = os.path.join(ctx["tree"], m.file)
    with open(path, "rb") as f:
        original = f.read()
    text = original.decode("utf-8")
    mutated = apply(text, m)
    if m.file.endswith(".py"):  # nothing to build: the AST says as much as object code
        try:
            if ast.dump(ast.parse(mutated)) == ast.dump(ast.parse(text)):
                return record(m, "equivalent", reason="same AST")
        except SyntaxError as e:
            return record(m, "does not build", reason=f"does not parse: {e.msg}")
    if not specs:
        return record(m, "equivalent" if judged else "survived",
                      reason=judged or "no test covers its file (ninja -t deps); --tests names some")
    ignore = baseline(specs, ctx["state"], ctx)
    t0 = time.time()  # the mutant's own time, not the unmutated run's
    with open(os.path.join(LOGS, re.sub(r"[^\w.-]+", "_", m.id) + ".log"), "w") as log:
        log.write(f"{m.id}\n{m.before}\n{m.after}\ntests: {' '.join(specs)}\n\n")
        scan_objects(ctx["build"], ctx["seen"])  # what the mutant's build writes, from here
        hidden = False
        failed, written = [], set()
        try:
            hidden = hide(ctx["tree"], m.file, True)
            with open(path, "wb") as f:
                f.write(mutated.encode("utf-8"))
            # the likeliest tests first, each built just before it runs: a catch needs one test binary built,
            # not every one that covers the file (Python: the Python.* tests, one step)
            order = sorted(specs, key=lambda s: test_order(s, m.file, ctx))
            steps = [order] if m.file.endswith(".py") or ctx["all_tests"] else [[s] for s in order]
            for step in steps:
                ok, out = build(ctx["build"], targets_for(step, m.file, ctx["deps"], ctx["tree"], ctx["build"]),
                                ctx["jobs"], log)
                if not ok:
                    error = re.search(r"^.*\berror\b.*$", out, re.M)
                    why = error.group().strip().replace(ctx["tree"] + os.sep, "")[:160] if error else "build failed"
                    return record(m, "does not build", reason=why, seconds=time.time() - t0, tests=specs)
                written |= scan_objects(ctx["build"], ctx["seen"])
                if same_object_code(m, ctx, written, log, complete=step is steps[-1] or m.file.endswith(".cpp")):
                    return record(m, "equivalent", reason="same object code", seconds=time.time() - t0,
                                  tests=specs)
                for names, out in run_specs(step, ctx["build"], ctx["timeout"], ctx["jobs"]):
                    log.write(out)
                    failed += [n for n in names if n not in ignore]
                if failed and not ctx["all_tests"]:
                    break
        finally:
            held = signal.signal(signal.SIGINT, signal.SIG_IGN)  # a second Ctrl-C must not stop the restore
            with open(path, "wb") as f:
                f.write(original)
            if hidden:
                hide(ctx["tree"], m.file, False)
            signal.signal(signal.SIGINT, held)
    seconds = time.time() - t0
    if failed:
        if judged:
            print(f"[mutate] warning: tests/mutants/equivalent.txt calls {m.id} equivalent, but it is caught: "
                  "the entry is wrong", file=sys.stderr)
        return record(m, "caught", failed, seconds=seconds, tests=specs)
    if judged:
        return record(m, "equivalent", reason=judged, seconds=seconds, tests=specs)
    return record(m, "survived", seconds=seconds, tests=specs)


def verdict_text(r):
    if r["verdict"] == "caught":
        f = r["failed"]
        return f"caught by {len(f)}: {', '.join(f[:4])}{', ...' if len(f) > 4 else ''}"
    return r["verdict"] + (f" ({r['reason']})" if r["reason"] else "")


# ---------------------------------------------------------------------------------------------------------------
# The report.

def code(s):
    s = s.replace("|", "\\|")
    return f"`` {s} ``" if "`" in s else f"`{s}`"


def report(records, title):
    counts = {v: sum(r["verdict"] == v for r in records) for v in ("caught", "survived", "equivalent",
                                                                    "does not build")}
    rated = counts["caught"] + counts["survived"]
    rate = counts["caught"] / rated if rated else None
    out = [f"# {title}", "",
           ", ".join(f"{n} {v}" for v, n in counts.items()) + "; catch rate " +
           (f"{rate:.2f} ({counts['caught']} of {rated})" if rate is not None else "n/a (nothing caught or survived)"),
           "", "| # | mutant | change | verdict | tests that fail or reason | time |", "|---|---|---|---|---|---|"]
    for k, r in enumerate(records, 1):
        if r["verdict"] == "caught":
            f = r["failed"]
            cell = ", ".join(code(n) for n in f[:4]) + (f", ... ({len(f)})" if len(f) > 4 else "")
        else:
            cell = r["reason"].replace("|", "\\|")
        verdict = r["verdict"] if r["verdict"] in ("caught", "equivalent") else f"**{r['verdict']}**"
        out.append(f"| {k} | {code(r['id'])} | {code(r['before'])} → {code(r['after'])} | {verdict} | {cell} | "
                   f"{r['seconds']:.0f} s |")
    return "\n".join(out) + "\n", rate


def load_results():
    out = {}
    if os.path.isfile(RESULTS):
        with open(RESULTS) as f:
            for line in f:
                if line.strip():
                    r = json.loads(line)
                    out[r["id"]] = r  # the later line for an id counts
    return out


# ---------------------------------------------------------------------------------------------------------------

def interrupted(signum, frame):
    raise KeyboardInterrupt


def parse(argv):
    p = argparse.ArgumentParser(prog="scripts/mutate.py", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter, usage=argparse.SUPPRESS)
    p.add_argument("--since", default="c6340d4", metavar="REV")
    p.add_argument("--count", type=int, default=40, metavar="N")
    p.add_argument("--seed", type=int, default=1, metavar="S")
    p.add_argument("--files", nargs="+", metavar="GLOB")
    p.add_argument("--tests", nargs="+", metavar="TEST")
    p.add_argument("--timeout", type=int, default=600, metavar="S", help="seconds a test binary (a ctest test) may run")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 2, metavar="J",
                   help="build jobs, and test binaries run at a time")
    p.add_argument("--min-rate", type=float, default=0.9, metavar="R")
    p.add_argument("--all-tests", action="store_true",
                   help="run every covering test against a mutant, not only until the first catches it")
    p.add_argument("--replace-stillborn", action=argparse.BooleanOptionalAction, default=True)
    p.add_argument("--tree", metavar="DIR")
    p.add_argument("--build", metavar="DIR")
    p.add_argument("--list", action="store_true")
    p.add_argument("--only", nargs="+", metavar="ID")
    p.add_argument("--resume", action="store_true")
    p.add_argument("--report", action="store_true",
                   help="print the report of results.jsonl's verdicts for the mutants drawn; runs nothing")
    return p.parse_args(argv)


def judged_survivor(r, equivalents):
    """A survivor of an earlier run that tests/mutants/equivalent.txt now calls equivalent (its tests ran, none
    caught it): equivalent, with the person's reason."""
    if r["verdict"] == "survived" and r["id"] in equivalents:
        return dict(r, verdict="equivalent", reason=equivalents[r["id"]])
    return r


def write_report(args, own_tree, tree):
    """--report: the report of results.jsonl's verdicts for the mutants a run draws (or --only names), in order,
    up to --count that build; it stops at the first drawn mutant with no verdict yet."""
    equivalents = read_equivalents()
    source = None if own_tree else tree
    chosen = resolve(args.only, source) if args.only else draws(mutant_pool(args.since, source, args.files), args.seed)
    goal = len(args.only) if args.only else args.count
    previous, records, counted = load_results(), [], 0
    for m in chosen:
        if counted >= goal or m.id not in previous:
            break
        records.append(judged_survivor(previous[m.id], equivalents))
        counted += records[-1]["verdict"] != "does not build"
    if counted < goal:
        print(f"[mutate] results.jsonl has verdicts for {counted} of the {goal} mutants", file=sys.stderr)
    title = (f"Mutation test: {len(records)} mutants of the lines changed since {args.since}, seed {args.seed}"
             if not args.only else f"Mutation test: {len(records)} mutants named")
    text, rate = report(records, title)
    print(text)
    return 0 if rate is None or rate >= args.min_rate else 1


def main(argv):
    args = parse(argv)
    own_tree = args.tree is None
    tree = os.path.abspath(args.tree or os.path.join(OUT, "tree"))
    build_dir = os.path.abspath(args.build or os.path.join(OUT, "build"))
    if args.list:  # what a run would draw: HEAD's lines for the worktree, else the tree's as they are
        source = None if own_tree else tree
        if own_tree:
            warn_uncommitted(sorted(changed_lines(args.since, None, args.files)))
        if args.only:
            chosen, total = resolve(args.only, source), None
        else:
            pool = mutant_pool(args.since, source, args.files)
            it = draws(pool, args.seed)
            chosen = [m for _, m in zip(range(args.count), it)]
            total = pool
        deps = read_deps(build_dir, tree) if os.path.isfile(os.path.join(build_dir, ".ninja_deps")) else None
        if total is not None:
            print(f"{len(total)} lines with mutants in {len({f for f, _ in total})} files changed since {args.since} "
                  f"({sum(len(v) for v in total.values())} mutants); seed {args.seed}, {len(chosen)} drawn")
        for k, m in enumerate(chosen, 1):
            before, after = change(m)
            print(f"[{k:2}] {m.id}\n     {before!r} -> {after!r}")
            if deps is not None:
                print(f"     tests: {' '.join(test_specs(m, args, deps, tree, build_dir)) or '(none)'}")
        return 0

    if args.report:  # what results.jsonl holds for the mutants drawn (or named), in order, without running any
        return write_report(args, own_tree, tree)

    signal.signal(signal.SIGTERM, interrupted)
    os.makedirs(LOGS, exist_ok=True)
    equivalents = read_equivalents()
    if own_tree:
        files = changed_lines(args.since, None, args.files)
        warn_uncommitted(sorted(files))
        prepare_worktree(tree)
    chosen = resolve(args.only, tree) if args.only else draws(mutant_pool(args.since, tree, args.files), args.seed)
    goal = len(args.only) if args.only else args.count
    previous = load_results() if args.resume else {}
    if not args.resume and not args.only and os.path.exists(RESULTS):
        os.remove(RESULTS)

    configure(tree, build_dir)
    print(f"[mutate] building the unmutated tree ({build_dir})", flush=True)
    with open(os.path.join(LOGS, "build.log"), "w") as log:
        ok, out = build(build_dir, None, args.jobs, log)
    if not ok:
        raise SystemExit(f"[mutate] the unmutated tree does not build ({LOGS}/build.log):\n" + out[-2000:])
    seen = {}
    scan_objects(build_dir, seen)
    # the unmutated runs hold while the code and the tests do: a commit of docs or scripts keeps them
    commit = " ".join(git("rev-parse", *(f"HEAD:{d}" for d in (*SOURCES, "tests", "CMakeLists.txt")),
                          cwd=tree).split()) if own_tree else None
    state = {"commit": commit, "tests": {}}
    if commit and os.path.isfile(BASELINE):
        with open(BASELINE) as f:
            old = json.load(f)
        if old.get("commit") == commit:
            state = old
    ctx = {"tree": tree, "build": build_dir, "jobs": args.jobs, "timeout": args.timeout, "seen": seen,
           "base": {p: v[1] for p, v in seen.items()}, "deps": read_deps(build_dir, tree), "state": state,
           "all_tests": args.all_tests}

    records, counted, stopped = [], 0, False
    try:
        for m in chosen:
            if counted >= goal:
                break
            before, after = change(m)
            print(f"[mutate {counted + 1}/{goal}] {m.file}:{m.line} {m.op}: {before!r} -> {after!r}", flush=True)
            for i in equivalents:
                if i != m.id and i.rpartition("@")[0] == m.id.rpartition("@")[0]:
                    print(f"[mutate] warning: tests/mutants/equivalent.txt's {i} is stale: the line has changed",
                          file=sys.stderr)
            r = previous.get(m.id)
            if r:
                r = judged_survivor(r, equivalents)
                print(f"  (from results.jsonl) {verdict_text(r)}", flush=True)
            else:
                specs = test_specs(m, args, ctx["deps"], tree, build_dir)
                print(f"  tests: {' '.join(specs) or '(none)'}", flush=True)
                r = run_mutant(m, specs, ctx, equivalents)
                print(f"  {verdict_text(r)} ({r['seconds']:.0f} s)", flush=True)
                with open(RESULTS, "a") as f:
                    f.write(json.dumps(r) + "\n")
            records.append(r)
            if r["verdict"] != "does not build" or not args.replace_stillborn or args.only:
                counted += 1
    except KeyboardInterrupt:
        stopped = True
        print("\n[mutate] interrupted: the mutant is undone; the report holds the mutants that ended", flush=True)
    finally:
        print("[mutate] rebuilding the unmutated tree", flush=True)
        with open(os.path.join(LOGS, "build.log"), "a") as log:
            build(build_dir, None, args.jobs, log)
    if counted < goal and not args.only and not stopped:
        print(f"[mutate] only {counted} mutants that build could be drawn", file=sys.stderr)

    title = (f"Mutation test: {len(records)} mutants of the lines changed since {args.since}, seed {args.seed}"
             if not args.only else f"Mutation test: {len(records)} mutants named")
    text, rate = report(records, title)
    with open(os.path.join(OUT, "report.md"), "w") as f:
        f.write(text)
    print("\n" + text)
    print(f"[mutate] {OUT}/report.md, results.jsonl, logs/")
    if stopped:
        return 130
    return 0 if rate is None or rate >= args.min_rate else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
