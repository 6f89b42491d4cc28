"""scripts/mutate.py's mutants, drawn on sample lines with known answers (no build): each operator edits what it
should and nothing in comments, strings, templates, declarations or error texts; ids carry their line's hash;
coverage from a made-up dependency map; the draw takes every line once before any twice, and is the same for a
seed. Run by CTest as MutationAudit.RandomMutantsAreWellFormed."""
import hashlib
import os
import shutil
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                                "scripts"))
import mutate  # noqa: E402


def edits(src, path="x.cpp", op=None):
    return sorted((m.op, m.after.strip()) for m in mutate.mutants_of(path, src) if op is None or m.op == op)


def afters(src, op, path="x.cpp"):
    return sorted(a for o, a in edits(src, path, op))


class Mutants(unittest.TestCase):
    def test_each_operator_edits_what_it_should_and_nothing_else(self):
        failures = []

        def check(name, got, want):
            if got != sorted(want):
                failures.append(f"{name}:\n  got  {got}\n  want {sorted(want)}")

        tree = tempfile.mkdtemp()
        try:
            # relational: spaced only; no templates, shifts, arrows, spaceship, includes, comments, strings
            check("rel basic", afters("if (a < b) f();\n", "relational"), ["if (a >= b) f();", "if (a <= b) f();"])
            check("rel template", afters("std::vector<int> v; std::map<int, std::vector<double>> m;\n", "relational"), [])
            check("rel template decl", afters("template <typename T> struct S;\n", "relational"), [])
            check("rel shift arrow", afters("x = a << 2; y = p->q; z = a <=> b; s >> t;\n", "relational"), [])
            check("rel comment", afters("int x;  // a < b\n/* c > d\n e == f */\n", "relational"), [])
            check("rel string", afters('auto s = "a < b";\n', "relational"), [])
            check("rel include", afters("#include <vector>\n#if A > 1\n#endif\n", "relational"), [])
            check("rel eq", afters("return a == b;\n", "relational"), ["return a != b;"])
            check("rel py", afters("if a <= b:\n    pass\n", "relational", "x.py"), ["if a < b:", "if a > b:"])
            check("rel static_assert", afters("static_assert(N > 0, \"n\");\n", "relational"), [])
            check("rel throw", afters('if (n < 0) throw std::invalid_argument(n > 1 ? "a" : "b");\n', "relational"),
                  ['if (n <= 0) throw std::invalid_argument(n > 1 ? "a" : "b");',
                   'if (n >= 0) throw std::invalid_argument(n > 1 ? "a" : "b");'])
            check("rel raise", afters('if n < 0: raise ValueError("n < 0: %d" % (n > 1))\n', "relational", "x.py"),
                  ['if n <= 0: raise ValueError("n < 0: %d" % (n > 1))', 'if n >= 0: raise ValueError("n < 0: %d" % (n > 1))'])
            check("rel raw string", afters('auto s = R"(a < b\nc > d)";\nint y = p < q;\n', "relational"),
                  ["int y = p <= q;", "int y = p >= q;"])
            check("rel docstring", afters('def f():\n    """a < b\n    c > d"""\n    return 1\n', "relational", "x.py"), [])

            # logical
            check("logical", afters("if (a && b || c) f(x&&y);\n", "logical"), ["if (a && b && c) f(x&&y);", "if (a || b || c) f(x&&y);"])
            check("logical rvalue", afters("void f(T&& x, auto&& y);\n", "logical"), [])
            check("logical py", afters("x = a and b or c\n", "logical", "x.py"), ["x = a and b and c", "x = a or b or c"])

            # off_by_one
            check("obo ints", afters("int x = 3; double y = 1.5; auto z = 0x10; uint64_t w = 2u;\n", "off_by_one"),
                  ["int x = 2; double y = 1.5; auto z = 0x10; uint64_t w = 2u;", "int x = 3; double y = 1.5; auto z = 0x10; uint64_t w = 1u;",
                   "int x = 3; double y = 1.5; auto z = 0x10; uint64_t w = 3u;", "int x = 4; double y = 1.5; auto z = 0x10; uint64_t w = 2u;"])
            check("obo zero", afters("int x = 0;\n", "off_by_one"), ["int x = 1;"])
            check("obo array decl", afters("double a[3];\nint x[N], y[N];\n", "off_by_one"), [])
            check("obo index", afters("y = a[i];\n", "off_by_one"), ["y = a[i + 1];", "y = a[i - 1];"])
            check("obo lambda", afters("auto f = [x](int k) { return k; };\n", "off_by_one"), [])
            check("obo loop", afters("for (int i = 0; i < n; ++i) {}\n", "off_by_one"),
                  ["for (int i = 0; i < n + 1; ++i) {}", "for (int i = 0; i < n - 1; ++i) {}", "for (int i = 1; i < n; ++i) {}"])
            check("obo index const", afters("y = a[3];\n", "off_by_one"), ["y = a[2];", "y = a[4];"])
            check("obo py", afters("x = f(2)[k]\ny: list[int] = []\n", "off_by_one", "x.py"),
                  ["x = f(1)[k]", "x = f(2)[k + 1]", "x = f(2)[k - 1]", "x = f(3)[k]"])
            check("obo identifier digits", afters("uint64_t x2 = int32_t(y);\n", "off_by_one"), [])

            # drop_term
            check("drop plus", afters("x = a + b * c;\n", "drop_term"), ["x = a + b;", "x = a;"])
            check("drop minus call", afters("x = f(a) - std::max<int>(b, c)[0].y;\n", "drop_term"), ["x = f(a);"])
            check("drop unary", afters("x = -a * -b;\n", "drop_term"), ["x = -a;"])
            check("drop pointer", afters("Foo* p = nullptr; auto& r = *q;\n", "drop_term"), [])
            check("drop string", afters('s = t + "x"; u = "a" + v;\n', "drop_term"), [])
            check("drop py", afters("y = a * b ** 2 + c.d(e)[1]\n", "drop_term", "x.py"), ["y = a * b ** 2", "y = a + c.d(e)[1]"])
            check("drop py star", afters("f(*args, **kw)\ndef g(a, *, b): pass\n", "drop_term", "x.py"), [])

            # constant
            check("const", afters("x = 1.5 * y + 1e-3f + 0.0 + 3;\n", "constant"),
                  ["x = (1.5 * (1 + 1e-3)) * y + 1e-3f + 0.0 + 3;", "x = (1.5 * (1 - 1e-3)) * y + 1e-3f + 0.0 + 3;",
                   "x = 1.5 * y + (1e-3f * (1 + 1e-3)) + 0.0 + 3;", "x = 1.5 * y + (1e-3f * (1 - 1e-3)) + 0.0 + 3;"])
            check("const py", afters("x = .5 + 2e3 + 1j\n", "constant", "x.py"),
                  ["x = (.5 * (1 + 1e-3)) + 2e3 + 1j", "x = (.5 * (1 - 1e-3)) + 2e3 + 1j",
                   "x = .5 + (2e3 * (1 + 1e-3)) + 1j", "x = .5 + (2e3 * (1 - 1e-3)) + 1j"])

            # swap_args
            check("swap", afters("z = f(a, b, 3); g(p.x, p.y); h(a, p.x); max(a, b); k(a, a);\n", "swap_args"),
                  ["z = f(b, a, 3); g(p.x, p.y); h(a, p.x); max(a, b); k(a, a);", "z = f(a, b, 3); g(p.y, p.x); h(a, p.x); max(a, b); k(a, a);"])
            check("swap decl", afters("double f(double a, double b);\n", "swap_args"), [])
            check("swap py", afters("def f(a, b):\n    return g(a, b=c) + h(x, y)\n", "swap_args", "x.py"),
                  ["return g(a, b=c) + h(y, x)"])

            # force_branch
            check("if", afters("if (a < b) f();\n} else if (c) {\n", "force_branch"),
                  ["if (false) f();", "if (true) f();", "} else if (false) {", "} else if (true) {"])
            check("if constexpr/init", afters("if constexpr (N > 1) f();\nif (auto x = g(); x) h();\n", "force_branch"), [])
            check("if multiline", afters("if (a &&\n    b) f();\n", "force_branch"), [])
            check("py if", afters("if a:\n    pass\nelif b(c):\n    pass\ny = 1 if c else 2\nz = [x for x in y if x]\n", "force_branch", "x.py"),
                  ["elif False:", "elif True:", "if False:", "if True:"])
            check("py if dict", afters("if d[{1: 2}[1]]:\n    pass\n", "force_branch", "x.py"), ["if False:", "if True:"])

            # ids: stable, hash of the line
            ms = mutate.mutants_of("src/a.cpp", "int f() {\n  return a < b;\n}\n")
            check("id", [m.id for m in ms if m.op == "relational"], ["src/a.cpp:2:relational:12:0@" + hashlib.sha1(b"  return a < b;").hexdigest()[:8],
                                                                    "src/a.cpp:2:relational:12:1@" + hashlib.sha1(b"  return a < b;").hexdigest()[:8]])
            # apply
            m = [m for m in ms if m.op == "relational"][0]
            check("apply", [mutate.apply("int f() {\n  return a < b;\n}\n", m)], ["int f() {\n  return a >= b;\n}\n"])

            # deps parsing and coverage
            deps = {
                "tests/CMakeFiles/test_calibration.dir/test_calibration.cpp.o": {"tests/test_calibration.cpp", "analysis/calibration.hpp", "src/sim/tally/survival.hpp"},
                "tests/CMakeFiles/test_simd.dir/test_simd.cpp.o": {"tests/test_simd.cpp", "src/sim/kernel/simd_engine.hpp"},
                "tests/CMakeFiles/test_cli.dir/test_cli.cpp.o": {"tests/test_cli.cpp", "tests/paths.hpp"},
                "analysis/CMakeFiles/rotleak_analysis.dir/calibration.cpp.o": {"analysis/calibration.cpp", "analysis/calibration.hpp"},
                "src/CMakeFiles/rotleak_core.dir/sim/kernel/simd_engine.cpp.o": {"src/sim/kernel/simd_engine.cpp", "src/sim/kernel/simd_engine.hpp", "src/sim/kernel/simd_kernel.ipp"},
                "src/CMakeFiles/rotleak_core.dir/sim/kernel/simd_avx512.cpp.o": {"src/sim/kernel/simd_avx512.cpp", "src/sim/kernel/simd_engine.hpp", "src/sim/kernel/simd_kernel.ipp"},
                "app/CMakeFiles/rotleak.dir/Unity/unity_rotleak_1_cxx.cxx.o": {"app/cli/main.cpp", "app/cli/commands.hpp"},
            }
            os.makedirs(os.path.join(tree, "tests"))
            with open(os.path.join(tree, "tests", "test_cli.cpp"), "w") as f:
                f.write("run(rotleak_binary());")
            with open(os.path.join(tree, "tests", "test_simd.cpp"), "w") as f:
                f.write("")
            check("cover hpp", mutate.covering_tests("analysis/calibration.hpp", deps, tree), ["test_calibration"])
            check("cover cpp", mutate.covering_tests("analysis/calibration.cpp", deps, tree), ["test_calibration"])
            check("cover ipp", mutate.covering_tests("src/sim/kernel/simd_kernel.ipp", deps, tree), ["test_simd"])
            check("cover beside", mutate.covering_tests("src/sim/kernel/simd_avx512.cpp", deps, tree), ["test_simd"])
            check("cover command", mutate.covering_tests("app/cli/main.cpp", deps, tree), ["test_cli"])
            check("cover none", mutate.covering_tests("src/nowhere.cpp", deps, tree), [])
            check("targets", mutate.targets_for(["test_cli"], "app/cli/commands.hpp", deps, tree, "/nonexistent"),
                  ["rotleak", "test_cli"])

            # the draw: lines uniformly, no repeats, deterministic
            pool = {("a", 1): ["a1x", "a1y", "a1z"], ("b", 2): ["b2x"], ("c", 3): ["c3x", "c3y"]}
            d1 = list(mutate.draws(pool, 1)); d2 = list(mutate.draws(pool, 1))
            check("draw all once", sorted(d1), ["a1x", "a1y", "a1z", "b2x", "c3x", "c3y"])
            check("draw stable", [d1 == d2, d1 != list(mutate.draws(pool, 2))], [True, True])
            check("draw round", sorted(x[0] for x in d1[:3]), ["a", "b", "c"])

            # report escaping
            r = mutate.record(ms[0], "caught", ["A.B"], seconds=3)
            text, rate = mutate.report([r, dict(r, verdict="survived", failed=[])], "t")
            check("rate", [rate], [0.5])
            check("pipe escaped", ["\\|" in mutate.code("a || b")], [True])
            check("obo negative", afters("int p = -1; x = a - 1;\n", "off_by_one"),
                  ["int p = -2; x = a - 1;", "int p = 0; x = a - 1;", "int p = -1; x = a - 0;", "int p = -1; x = a - 2;"])
            check("obo py negative", afters("y = n[-1]\n", "off_by_one", "x.py"), ["y = n[-2]", "y = n[0]"])
        finally:
            shutil.rmtree(tree)
        self.assertEqual(failures, [], "\n".join(failures))


if __name__ == "__main__":
    unittest.main()
