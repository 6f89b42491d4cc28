"""The Python package against the command line: read_run and read_scan on what rotleak writes,
rotleak.simulate's run (the same bytes as the command's files), its keyword overrides and errors, the
progress callback, the GIL released while it runs, Ctrl-C, omega and covering.

Run by CTest as: PYTHONPATH=BUILD/python /usr/bin/python3 -m unittest tests/python/test_package.py
with ROTLEAK_BINARY and ROTLEAK_SOURCE set."""
import csv
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest
from fractions import Fraction

import pandas as pd

import rotleak

BIN = os.environ["ROTLEAK_BINARY"]
SRC = os.environ["ROTLEAK_SOURCE"]
QUICK = os.path.join(SRC, "data", "scenes", "quickstart.toml")


def cli(*args):
    subprocess.run([BIN, *args, "--no-progress"] if args[0] in ("simulate", "scan") else [BIN, *args], check=True,
                   stdout=subprocess.DEVNULL)


def seeded():
    """(seed, random.Random(seed)) for a test that draws random cases: ROTLEAK_TEST_SEED, else 32."""
    import random
    seed = int(os.environ.get("ROTLEAK_TEST_SEED", "32"))
    return seed, random.Random(seed)


def damaged_copy(rng, source_dir, name, copy_dir, cut, alphabet):
    """copy_dir: a copy of source_dir whose file `name` is cut at a random place (cut) or has one random
    character replaced by one of `alphabet`; returns nothing, the copy is on disk."""
    with open(os.path.join(source_dir, name)) as f:
        good = f.read()
    if cut:
        text = good[:rng.randrange(len(good))]
    else:
        at = rng.randrange(len(good))
        text = good[:at] + rng.choice(alphabet) + good[at + 1:]
    shutil.rmtree(copy_dir, ignore_errors=True)
    shutil.copytree(source_dir, copy_dir)
    with open(os.path.join(copy_dir, name), "w") as f:
        f.write(text)


def without_execution(doc):
    doc = dict(doc)
    doc.pop("execution")
    return doc


class Package(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="rotleak-py-")
        cls.run_dir = os.path.join(cls.tmp, "run")
        cli("simulate", QUICK, "--particles", "20000", "--set", "leak.omega=2/3", "--set", "observe.escapes=true",
            "--out", cls.run_dir)
        cls.scan_dir = os.path.join(cls.tmp, "scan")
        cli("scan", QUICK, "--over", "leak.omega=0,1,2/3", "--set", "ensemble.particles=4000", "--out", cls.scan_dir)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def test_read_run_gives_the_files_as_tables(self):
        run = rotleak.read_run(self.run_dir)
        self.assertEqual(run.survival.columns.tolist(), ["t", "survivors", "P", "P_err"])
        self.assertEqual(int(run.survival["survivors"].iloc[0]), 20000)
        self.assertEqual(run.fc.columns[0], "s")
        self.assertEqual(len(run.escapes), 20000)
        self.assertEqual(set(run.escapes["fate"]) - {"escaped", "survived", "stuck"}, set())
        self.assertEqual(run.scene["leak"]["omega"], "2/3")  # exact texts stay texts
        with open(os.path.join(self.run_dir, "summary.json")) as f:
            self.assertEqual(run.summary, json.load(f))
        # the same table pandas reads from the file itself
        pd.testing.assert_frame_equal(run.survival, pd.read_csv(os.path.join(self.run_dir, "survival.csv")))
        # the tail amplitude: summary.json's tail.amplitude, a value with its errors or null with the reason
        doc = run.summary["tail"]["amplitude"]
        self.assertEqual(set(doc), {"value", "error", "systematic", "from", "to", "points", "height", "height_error",
                                    "slope", "slope_error", "note"})
        amp = run.tail_amplitude
        self.assertIsInstance(amp, rotleak.Amplitude)
        self.assertEqual((amp.value, amp.error, amp.systematic, amp.stretch, amp.note),
                         (doc["value"], doc["error"], doc["systematic"],
                          None if doc["from"] is None else (doc["from"], doc["to"]), doc["note"]))
        self.assertTrue(amp.value is not None or amp.note)
        # kappa and alpha as small dataclasses, each field summary.json's
        k, a = run.kappa, run.alpha
        self.assertEqual((k.value, k.error, k.systematic, list(k.window)),
                         (run.summary["kappa"]["value"], run.summary["kappa"]["error"],
                          run.summary["kappa"]["window_systematic"], run.summary["kappa"]["window"]))
        self.assertAlmostEqual(k.total_error, (k.error ** 2 + k.systematic ** 2) ** 0.5)
        self.assertEqual((a.value, a.upper_bound, a.crossing_time),
                         (run.summary["alpha"]["value"], run.summary["alpha"]["upper_bound"],
                          run.summary["alpha"]["crossing_time"]))

    def test_simulate_in_process_writes_the_bytes_the_command_writes(self):
        r = rotleak.simulate(QUICK, particles=20000, threads=2,
                             overrides={"leak.omega": Fraction(2, 3), "observe.escapes": True})
        d = rotleak.read_run(self.run_dir)
        for name in ("survival.csv", "fc.csv", "escapes.csv", "scene.toml"):
            self.assertEqual(r.text(name), d.text(name), name)
        self.assertEqual(without_execution(r.summary), without_execution(d.summary))
        self.assertEqual(r.summary["execution"]["rotleak"]["version"], rotleak.__version__)
        # one version, from git describe, in the binary, the package and summary.json
        binary = subprocess.run([BIN, "--version"], check=True, capture_output=True, text=True).stdout.split()[0]
        self.assertEqual(binary, rotleak.__version__)
        self.assertEqual(d.summary["execution"]["rotleak"]["version"], rotleak.__version__)
        # and written out, it reads back as the same run
        out = r.write(os.path.join(self.tmp, "written"))
        self.assertEqual(rotleak.read_run(out).text("survival.csv"), d.text("survival.csv"))

    def test_a_scene_built_in_python_is_the_file_the_command_runs(self):
        # a dict once gave a raw TypeError and a TOML string "no such file": a Scene is built from keys or
        # sections, checked by rotleak's reader (its one-line messages), saved as TOML exactly, and runs bit
        # for bit as the command runs the saved file
        by_keys = rotleak.Scene({"leak.omega": "2/3", "ensemble.particles": 3000, "run.t_max": 2000,
                                 "fit.kappa_window": [0, 300]})
        by_sections = rotleak.Scene(leak={"omega": Fraction(2, 3)}, ensemble={"particles": 3000},
                                    run={"t_max": 2000}, fit={"kappa_window": [0, 300]})
        self.assertEqual(by_keys, by_sections)
        self.assertIn('omega = "2/3"', by_keys.to_toml())
        self.assertEqual(rotleak.Scene.from_toml(by_keys.to_toml()), by_keys)
        path = os.path.join(self.tmp, "built.toml")
        by_keys.save(path)
        self.assertEqual(rotleak.Scene.read(path), by_keys)
        self.assertEqual(by_keys.replace(leak={"omega": "3/4"}), rotleak.Scene.read(path, {"leak.omega": "3/4"}))
        r = rotleak.simulate(by_keys, threads=2)
        cmd = os.path.join(self.tmp, "built_cmd")
        subprocess.run([BIN, "simulate", path, "--threads", "2", "--no-progress", "--out", cmd], check=True,
                       capture_output=True)
        for name in ("survival.csv", "scene.toml"):
            self.assertEqual(r.text(name), rotleak.read_run(cmd).text(name), name)
        self.assertEqual(rotleak.simulate({"leak.omega": "2/3", "ensemble.particles": 3000, "run.t_max": 2000,
                                           "fit.kappa_window": [0, 300]}, threads=2).text("survival.csv"),
                         r.text("survival.csv"), "a dict is a Scene")
        self.assertEqual(rotleak.predict(by_keys)["amplitude"], rotleak.predict(path)["amplitude"])
        # bad input: the command line's one line for the key, or the argument named
        cli_err = subprocess.run([BIN, "simulate", path, "--set", "leak.width=1", "--out", os.path.join(self.tmp, "x")],
                                 capture_output=True, text=True).stderr.strip()
        with self.assertRaises(ValueError) as e:
            rotleak.Scene({"leak.width": "1"})
        self.assertEqual("rotleak: error: " + str(e.exception), cli_err)
        for bad in ({"leak.omega": 0.5}, {"omega": "2/3"}):
            with self.assertRaises(ValueError):
                rotleak.Scene(bad)
        with self.assertRaisesRegex(ValueError, "leak = '2/3'"):
            rotleak.Scene(leak="2/3")  # type: ignore[arg-type]
        with self.assertRaisesRegex(ValueError, "Scene.from_toml"):
            rotleak.simulate("[leak]\nomega = \"2/3\"\n")
        self.assertEqual([n for n in dir(rotleak) if not n.startswith("_") and n not in rotleak.__all__], [],
                         "dir(rotleak) shows what the package offers, not its imports")

    def test_an_importance_sampled_run_starts_at_one_and_keeps_its_weight_sums(self):
        # mupo runs once started at P(0) = 0.996 +- 0.003 (the weights' mean); P is now the survivors' share of the
        # sample's weight, and survival.csv keeps the sums W, W2 it is made from (docs/output.md)
        run = rotleak.simulate(QUICK, particles=3000, overrides={"ensemble.sampling": "mupo", "run.t_max": 500,
                                                                "fit.kappa_window": [0, 300],
                                                                "observe.collision_density": {"bins": 10}})
        out = os.path.join(self.tmp, "mupo-run")
        run.write(out)
        table = pd.read_csv(os.path.join(out, "survival.csv"), float_precision="round_trip")
        self.assertEqual(list(table.columns), ["t", "survivors", "P", "P_err", "W", "W2"])
        self.assertEqual((table["P"][0], table["P_err"][0]), (1.0, 0.0))
        self.assertNotEqual(table["W"][0], 1.0)  # the weights' mean, which P once started at
        self.assertTrue(all(p == w / table["W"][0] for p, w in zip(table["P"], table["W"])))
        pd.testing.assert_frame_equal(rotleak.read_run(out).survival, table)
        damaged = os.path.join(self.tmp, "mupo-damaged")
        shutil.copytree(out, damaged)
        with open(os.path.join(damaged, "survival.csv")) as f:
            rows = f.read().split("\n")
        f3 = rows[3].split(",")
        f3[2] = repr(float(f3[2]) * (1 + 2 ** -40))  # P no longer W / W(0)
        rows[3] = ",".join(f3)
        with open(os.path.join(damaged, "survival.csv"), "w") as f:
            f.write("\n".join(rows))
        with self.assertRaisesRegex(rotleak.RotleakError, "survival.csv line 4: P is not W / W at t = 0"):
            rotleak.read_run(damaged)
        r = subprocess.run([BIN, "fit", damaged], capture_output=True, text=True)
        self.assertEqual(r.returncode, 2)
        self.assertIn("survival.csv line 4: P is not W / W at t = 0", r.stderr)

    def test_a_split_run_keeps_its_tallies_in_process_and_on_disk(self):
        """A split run's tally.bin (its exact tallies, from which rotleak fit rebuilds its curve): the same bytes
        in process and from the command; read_run keeps it, write() writes it back, rotleak fit reads it."""
        sets = {"ensemble.sampling": "mupo", "run.splitting": True}
        r = rotleak.simulate(QUICK, particles=3000, threads=2, overrides=sets)
        self.assertIn("tally.bin", r.summary["files"])
        out = r.write(os.path.join(self.tmp, "split"))
        cmd = os.path.join(self.tmp, "split_cmd")
        subprocess.run([BIN, "simulate", QUICK, "--particles", "3000", "--threads", "2", "--no-progress", "--out", cmd,
                        "--set", "ensemble.sampling=mupo", "--set", "run.splitting=true"],
                       check=True, capture_output=True)
        with open(os.path.join(out, "tally.bin"), "rb") as a, open(os.path.join(cmd, "tally.bin"), "rb") as b:
            self.assertEqual(a.read(), b.read())
        again = rotleak.read_run(cmd)
        self.assertEqual(without_execution(again.summary), without_execution(r.summary))
        subprocess.run([BIN, "fit", out], check=True, capture_output=True)
        self.assertEqual(rotleak.read_run(out).kappa, r.kappa)

    def test_overrides_and_bad_input_name_the_key(self):
        r = rotleak.simulate(QUICK, particles="1e4", overrides={
            "run.t_max": 3000, "observe.escapes": False, "observe.collision_density": {"bins": 10, "windows": [[0, 3000]]}})
        self.assertEqual(r.summary["particles"], 10000)
        self.assertEqual(r.scene["run"]["t_max"], 3000.0)
        self.assertIsNone(r.escapes)
        self.assertEqual(len(r.fc), 10)
        with self.assertRaisesRegex(ValueError, r"^leak\.omega = \"x\""):
            rotleak.simulate(QUICK, overrides={"leak.omega": "x"})
        with self.assertRaisesRegex(ValueError, "particles = 0.5"):
            rotleak.simulate(QUICK, particles=0.5)
        with self.assertRaisesRegex(ValueError, r"overrides\['omegas'\]: a scene key is \"section.key\""):
            rotleak.simulate(QUICK, overrides={"omegas": 1})
        with self.assertRaisesRegex(ValueError, r"overrides\['leak_omega'\]: a scene key is \"section.key\""):
            rotleak.simulate(QUICK, overrides={"leak_omega": "2/3"})  # the old keyword form names the dotted one
        with self.assertRaises(TypeError):  # keyword overrides are gone: nothing is split on underscores
            rotleak.simulate(QUICK, leak_omega="2/3")  # type: ignore[call-arg]
        with self.assertRaisesRegex(ValueError, "no such file"):
            rotleak.simulate(os.path.join(self.tmp, "missing.toml"))

    def test_readers_refuse_what_is_not_a_complete_run(self):
        with self.assertRaisesRegex(rotleak.RotleakError, "no summary.json"):
            rotleak.read_run(self.tmp)
        bad = os.path.join(self.tmp, "incomplete")
        shutil.copytree(self.run_dir, bad)
        os.remove(os.path.join(bad, "fc.csv"))
        with self.assertRaisesRegex(rotleak.RotleakError, "summary.json lists fc.csv, which is missing"):
            rotleak.read_run(bad)
        newer = os.path.join(self.tmp, "newer")
        shutil.copytree(self.run_dir, newer)
        with open(os.path.join(newer, "summary.json")) as f:
            doc = json.load(f)
        doc["schema"] = rotleak.SCHEMA + 1
        with open(os.path.join(newer, "summary.json"), "w") as f:
            json.dump(doc, f)
        with self.assertRaisesRegex(rotleak.RotleakError, "has schema 2; this rotleak package reads schema 1"):
            rotleak.read_run(newer)
        with self.assertRaisesRegex(rotleak.RotleakError, "no scan.json"):
            rotleak.read_scan(self.run_dir)

    def test_read_run_refuses_what_fit_refuses_with_the_same_reason(self):
        # damage a user met: a survival.csv cut mid-row (it loaded as 478 rows with a last P of 0.0) or at a
        # row's end, a garbage row (t became object dtype), an empty file (pandas' EmptyDataError), a cut
        # summary.json (a raw JSONDecodeError); rotleak plot printed an IndexError on them
        with open(os.path.join(self.run_dir, "survival.csv")) as f:
            good = f.read()
        with open(os.path.join(self.run_dir, "summary.json")) as f:
            summary = f.read()
        lines = good.splitlines(keepends=True)
        damages = {
            "cut mid-row": ("survival.csv", good[:len(good) // 3]),
            "cut at a row's end": ("survival.csv", "".join(lines[:479])),
            "garbage row": ("survival.csv", "".join(lines[:99] + ["abc,def,1,2\n"] + lines[100:])),
            "a field too many": ("survival.csv", "".join(lines[:50] + [lines[50].rstrip("\n") + ",7\n"] + lines[51:])),
            "empty": ("survival.csv", ""),
            "summary cut": ("summary.json", summary[:300]),
            "summary not an object": ("summary.json", "[1, 2]\n"),
        }
        for what, (name, text) in damages.items():
            with self.subTest(what):
                bad = os.path.join(self.tmp, "damaged")
                shutil.rmtree(bad, ignore_errors=True)
                shutil.copytree(self.run_dir, bad)
                with open(os.path.join(bad, name), "w") as f:
                    f.write(text)
                fit = subprocess.run([BIN, "fit", bad], capture_output=True, text=True)
                self.assertEqual(fit.returncode, 2, fit.stderr)
                prefix = 'rotleak: error: DIR = "%s": ' % bad
                self.assertTrue(fit.stderr.startswith(prefix), fit.stderr)
                reason = fit.stderr[len(prefix):].strip()
                with self.assertRaises(rotleak.RotleakError) as caught:
                    rotleak.read_run(bad).survival
                self.assertEqual(str(caught.exception), "%s: %s" % (bad, reason))
                plot = subprocess.run([BIN, "plot", bad], capture_output=True, text=True)
                self.assertEqual(plot.returncode, 2, plot.stderr)
                self.assertEqual(plot.stderr.strip(), "rotleak.plot: cannot draw %s: %s" % (bad, reason))
                self.assertNotIn("Traceback", plot.stderr)
        shutil.rmtree(bad)

    def test_random_damage_is_refused_alike_by_fit_and_read_run(self):
        # Random cuts and byte changes of survival.csv (seed ROTLEAK_TEST_SEED, printed on failure): whatever
        # rotleak fit accepts, read_run accepts; whatever fit refuses (exit 2), read_run refuses with the same
        # reason. Both read the same grammar, row count and header, so this holds for every damage.
        seed, rng = seeded()
        bad = os.path.join(self.tmp, "random_damage")
        for case in range(40):
            damaged_copy(rng, self.run_dir, "survival.csv", bad, case % 2 == 0, "0123456789.,-e\nx ")
            fit = subprocess.run([BIN, "fit", bad], capture_output=True, text=True)
            where = "seed %d case %d" % (seed, case)
            self.assertIn(fit.returncode, (0, 2), where + ": " + fit.stderr)
            if fit.returncode == 0:
                shutil.copyfile(os.path.join(self.run_dir, "summary.json"), os.path.join(bad, "summary.json"))
                rotleak.read_run(bad).survival  # noqa: B018 -- accepted by both
                continue
            reason = fit.stderr.strip().split('": ', 1)[1]
            with self.assertRaises(rotleak.RotleakError, msg=where) as caught:
                rotleak.read_run(bad).survival  # noqa: B018
            self.assertEqual(str(caught.exception), "%s: %s" % (bad, reason), where)
        shutil.rmtree(bad)

    def test_random_damage_of_a_scan_is_a_rotleak_error(self):
        # read_scan on scan.json or table.csv cut or changed at random (seed ROTLEAK_TEST_SEED): it reads
        # them, or refuses with a RotleakError naming the file; never a JSONDecodeError, a pandas error, a
        # KeyError or a TypeError
        seed, rng = seeded()
        bad = os.path.join(self.tmp, "random_scan")
        for case in range(60):
            damaged_copy(rng, self.scan_dir, ("scan.json", "table.csv")[case % 2], bad, case % 4 < 2,
                         '0123456789.,-e\n"{}[]:x ')
            try:
                scan = rotleak.read_scan(bad)
                scan.table  # noqa: B018
                scan.keys  # noqa: B018
                scan.points  # noqa: B018
            except rotleak.RotleakError as e:
                self.assertIn(bad, str(e), "seed %d case %d" % (seed, case))
        shutil.rmtree(bad)

    def test_random_damage_of_a_certified_sample_is_a_rotleak_error(self):
        # read_certification on summary.json, escapes.csv or bracket.csv cut or changed at random (seed
        # ROTLEAK_TEST_SEED): it reads them, or refuses with a RotleakError naming the directory; never a
        # JSONDecodeError, a pandas error, a KeyError or a TypeError
        seed, rng = seeded()
        good = os.path.join(self.tmp, "certified_good")
        subprocess.run([BIN, "certify", os.path.join(SRC, "data", "scenes", "quickstart.toml"), "--sample", "12",
                        "--t-cap", "200", "--tiers", "double", "--no-progress", "--out", good], check=True,
                       stdout=subprocess.DEVNULL)
        bad = os.path.join(self.tmp, "random_certified")
        for case in range(60):
            damaged_copy(rng, good, ("summary.json", "escapes.csv", "bracket.csv")[case % 3], bad, case % 2 == 0,
                         '0123456789.,-e\n"{}[]:x ')
            try:
                c = rotleak.read_certification(bad)
                c.escapes  # noqa: B018
                c.bracket  # noqa: B018
                repr(c)
            except rotleak.RotleakError as e:
                self.assertIn(bad, str(e), "seed %d case %d" % (seed, case))
        shutil.rmtree(bad)

    def test_python_arguments_of_the_wrong_type_are_refused_by_name(self):
        # each once ran something other than what was written, or dumped a pybind11 signature
        cases = [
            (dict(overrides={"leak.omega": 2 / 3}), r"^overrides\['leak.omega'\] = 0\.6666666666666666: leak\.omega is exact"),
            (dict(overrides={"stadium.r": 1.0}), r"^overrides\['stadium.r'\] = 1\.0: stadium\.r is exact"),
            (dict(particles=True), r"^particles = True: must be an integer >= 1"),
            (dict(threads=2.7), r"^threads = 2\.7: must be an integer >= 0"),
            (dict(threads="two"), r"^threads = 'two': must be an integer >= 0"),
            (dict(progress=5), r"^progress = 5: must be None or a function"),
            (dict(overrides=["run.t_max=5"]), r"^overrides = \['run.t_max=5'\]: must be a dict of scene keys"),
        ]
        for kw, message in cases:
            with self.subTest(kw=repr(kw)):
                with self.assertRaisesRegex(ValueError, message):
                    rotleak.simulate(QUICK, **kw)
        # the serious one: a split run with a default split_every above t_max killed the interpreter
        with self.assertRaisesRegex(ValueError, r"^run\.split_every = 151\.2\d* \(the default\)"):
            rotleak.simulate(QUICK, overrides={"run.splitting": True, "ensemble.sampling": "mupo", "run.t_max": 100,
                                               "fit.kappa_window": [0, 50]})
        with self.assertRaisesRegex(ValueError, r"ensemble\.sampling = \"mupo\""):
            rotleak.simulate(QUICK, overrides={"run.splitting": True})

    def test_plots_take_the_readers_objects_or_directories(self):
        from rotleak import plot

        run_copy, scan_copy = os.path.join(self.tmp, "plot-run"), os.path.join(self.tmp, "plot-scan")
        shutil.copytree(self.run_dir, run_copy)
        shutil.copytree(self.scan_dir, scan_copy)
        drew = plot.draw(rotleak.read_run(run_copy))
        self.assertEqual(drew, [os.path.join(run_copy, "survival.png"), os.path.join(run_copy, "fc.png")])
        self.assertTrue(all(os.path.getsize(p) > 0 for p in drew))
        drew = plot.draw(rotleak.read_scan(scan_copy))
        self.assertIn(os.path.join(scan_copy, "scan_survival.png"), drew)
        # an in-process run has no directory: its pictures go where it is told
        r = rotleak.simulate(QUICK, particles=5000, overrides={"run.t_max": 2000,
                                                               "observe.collision_density": {"bins": 20}})
        with self.assertRaisesRegex(ValueError, "give out=DIR"):
            plot.run.draw(r)
        out = os.path.join(self.tmp, "plot-in-process")
        os.makedirs(out)
        self.assertEqual(plot.run.draw(r, out=out), [os.path.join(out, "survival.png"), os.path.join(out, "fc.png")])

    def test_read_scan_keeps_exact_values_as_text(self):
        scan = rotleak.read_scan(self.scan_dir)
        t = scan.table
        self.assertEqual(t["leak.omega"].tolist(), ["0", "1", "2/3"])
        self.assertEqual(t.shape, (3, 27))  # the swept key, then the 26 columns docs/output.md lists
        self.assertTrue(pd.api.types.is_float_dtype(t["kappa"]))
        self.assertEqual(t["particles"].tolist(), [4000] * 3)
        self.assertEqual(sorted(scan.points), sorted(scan.point_names))
        p = scan.point(scan.point_names[2])
        self.assertEqual(p.summary["kappa"], scan.document["points"][2]["kappa"])

    def test_certified_sample_reads_back_with_csv_json_and_pandas(self):
        """rotleak certify --sample's files (docs/output.md) with the standard readers and the package's
        Certification, and its picture drawn from the directory."""
        import csv
        scene = os.path.join(SRC, "data", "scenes", "quickstart.toml")
        out = os.path.join(self.tmp, "certified")
        subprocess.run([BIN, "certify", scene, "--sample", "30", "--t-cap", "300", "--tiers", "double,dd",
                        "--no-progress", "--out", out], check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "escapes.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(list(rows[0]), ["id", "status", "t_lo", "t_hi", "collisions", "bits", "t_double", "t_dd"])
        self.assertEqual([int(r["id"]) for r in rows], list(range(30)))
        self.assertTrue(all(r["status"] in ("proven", "survives", "undecided") for r in rows))
        self.assertTrue(all(float(r["t_lo"]) <= float(r["t_hi"]) <= 300 for r in rows))
        with open(os.path.join(out, "summary.json")) as f:
            doc = json.load(f)
        self.assertEqual(doc["command"], "certify")
        self.assertEqual(doc["sample"], 30)
        self.assertEqual([t["tier"] for t in doc["tiers"]], ["double", "dd"])
        bracket = pd.read_csv(os.path.join(out, "bracket.csv"))
        self.assertEqual(list(bracket.columns), ["t", "lower", "upper", "p_double", "p_dd"])
        self.assertTrue((bracket["lower"] <= bracket["upper"]).all())
        self.assertEqual(bracket["lower"].iloc[0], 1.0)
        c = rotleak.read_certification(out)
        self.assertEqual(c.tiers, ["double", "dd"])
        self.assertEqual(len(c.escapes), 30)
        self.assertAlmostEqual(c.proven_fraction, doc["proven_fraction"])
        from rotleak import plot
        self.assertEqual(plot.draw(out), [os.path.join(out, "certify.png")])
        with self.assertRaises(rotleak.RotleakError):
            rotleak.read_certification(self.scan_dir)  # a scan is not a certified sample

    def table_run(self, name, toml, particles):
        """The run directory of scene text `toml` (written to NAME.toml) with `particles`, under self.tmp."""
        scene = os.path.join(self.tmp, name + ".toml")
        with open(scene, "w") as f:
            f.write(toml)
        out = os.path.join(self.tmp, name)
        cli("simulate", scene, "--particles", str(particles), "--out", out)
        return out

    def test_a_tables_density_figure_names_no_stadium_pieces(self):
        """f_c on a table other than the stadium: its figure is drawn, with no top axis naming the stadium's
        edges and arcs (a table has no such pieces; naming them on a table raised a matplotlib error)."""
        out = self.table_run("circle_fc", '[table]\nkind = "circle"\nradius = "1"\n\n[run]\nt_max = 200.0\n\n'
                             '[observe]\ncollision_density = { bins = 20, windows = [[0, 200]] }\n', 2000)
        from rotleak import plot
        drawings = {d.name: d for d in plot.figures(out)}
        self.assertIn("fc", drawings)
        def named(fig):  # the tick labels of every axis, the secondary ones (child axes) too
            axes = [a for ax in fig.axes for a in [ax, *ax.child_axes]]
            return [t.get_text() for a in axes for t in a.get_xticklabels()]
        self.assertNotIn("right arc", named(drawings["fc"].figure))
        def legend(fig):
            return [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
        self.assertIn("t in [0:200]", legend(drawings["fc"].figure))
        self.assertNotIn("arcs", legend(drawings["fc"].figure))  # nothing shaded, nothing in the legend
        # the converse: the stadium's f_c names its pieces along the top and shades its arcs
        stadium = {d.name: d for d in plot.figures(self.run_dir)}
        self.assertIn("right arc", named(stadium["fc"].figure))
        self.assertIn("arcs", legend(stadium["fc"].figure))

    def test_a_start_splitting_run_reads_back_with_csv_json_and_pandas(self):
        """Splitting over initial conditions (docs/model.md): survival.csv's four columns and summary.json's
        start_splitting (docs/output.md) with the standard readers; P from the replicates' mean, its error their
        spread, the replicates' scene read back as it ran."""
        import csv
        out = os.path.join(self.tmp, "starts")
        cli("simulate", os.path.join(SRC, "data", "scenes", "stationary_sL_0.toml"), "--set", "run.t_max=600",
            "--set", "observe.survival_dt=10", "--set", "start_splitting.on=true", "--set",
            "start_splitting.replicates=4", "--set", "start_splitting.moves=2", "--particles", "500", "--out", out)
        with open(os.path.join(out, "summary.json")) as f:
            doc = json.load(f)
        g = doc["start_splitting"]
        self.assertEqual((g["replicates"], g["starts"], g["factor"]), (4, 500, 4))  # factor: the default
        self.assertEqual(g["stratum"], {"p": [0.0, 1.0], "edges": False, "share": 1.0})
        self.assertGreaterEqual(len(g["levels"]), 1)
        self.assertEqual(len(g["factors"]), len(g["levels"]))
        self.assertEqual(g["levels"], sorted(g["levels"]))
        self.assertLessEqual(g["accepted"], g["proposals"])
        # each level's window and its chains' genealogy: acceptance a share, ancestors at most a stage's starts
        self.assertEqual(len(g["windows"]), len(g["levels"]))
        for w in g["windows"]:
            if w["ancestors"] is None:
                continue
            self.assertTrue(0 <= w["acceptance"] <= 1)
            self.assertTrue(1 <= w["ancestors"]["fewest"] <= w["ancestors"]["mean"] <= 500)
        with open(os.path.join(out, "survival.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(list(rows[0]), ["t", "survivors", "P", "P_err"])
        self.assertEqual(len(rows), 61)
        table = pd.read_csv(os.path.join(out, "survival.csv"), float_precision="round_trip")
        self.assertEqual(table["P"].iloc[0], 1.0)
        self.assertTrue((table["P_err"].iloc[1:] > 0).all())  # four replicates: a spread at every later time
        self.assertTrue(pd.api.types.is_integer_dtype(table["survivors"]))
        for point in g["at"]:
            row = table[table["t"] == point["t"]].iloc[0]
            self.assertEqual((row["P"], row["P_err"]), (point["P"], point["P_err"]))
        run = rotleak.read_run(out)
        self.assertEqual(run.survival["P"].tolist(), table["P"].tolist())
        # the same from Python: a Scene with the section, run in-process, gives the command's bytes
        scene = rotleak.Scene.read(os.path.join(SRC, "data", "scenes", "stationary_sL_0.toml")).replace(
            {"run.t_max": 600, "observe.survival_dt": 10, "start_splitting.on": True,
             "start_splitting.replicates": 4, "start_splitting.moves": 2})
        r = rotleak.simulate(scene, particles=500)
        self.assertEqual(r.text("survival.csv"), rotleak.read_run(out).text("survival.csv"))
        self.assertEqual(r.summary["start_splitting"]["levels"], g["levels"])
        # the scene as run, read back: the same run again gives the same bytes
        again = os.path.join(self.tmp, "starts_again")
        cli("simulate", os.path.join(out, "scene.toml"), "--out", again)
        with open(os.path.join(out, "survival.csv")) as a, open(os.path.join(again, "survival.csv")) as b:
            self.assertEqual(a.read(), b.read())

    def test_a_two_leak_table_run_reads_back_with_csv_json_and_pandas(self):
        """A circle with two leaks (docs/tables.md): leaks.csv and summary.json's table and leaks (docs/output.md)
        with the standard readers and the package's Run, each leak's escapes adding up to the run's."""
        import csv
        out = self.table_run("circle", '[table]\nkind = "circle"\nradius = "1"\n\n[[leaks]]\nwidth = "0.02"\n\n'
                             '[[leaks]]\nwidth = "0.01"\nstart = "1/4"\nomega = "1/3"\n\n[run]\nt_max = 2000.0\n',
                             5000)
        with open(os.path.join(out, "summary.json")) as f:
            doc = json.load(f)
        self.assertEqual(doc["table"]["kind"], "circle")
        self.assertAlmostEqual(doc["table"]["mean_free_path"], math.pi / 2, places=12)  # pi A / L = r pi / 2
        self.assertEqual([leak["width"] for leak in doc["leaks"]], ["0.02", "0.01"])
        self.assertIsNone(doc["predicted"]["tail"])  # the tail model is the stadium's
        with open(os.path.join(out, "leaks.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(list(rows[0]), ["t_from", "t_to", "escaped_0", "escaped_1"])
        self.assertEqual(len(rows), 2000)
        table = pd.read_csv(os.path.join(out, "leaks.csv"))
        self.assertTrue(pd.api.types.is_integer_dtype(table["escaped_1"]))
        for j, leak in enumerate(doc["leaks"]):
            self.assertEqual(int(table["escaped_%d" % j].sum()), leak["escaped"])
            self.assertAlmostEqual(leak["fraction"], leak["escaped"] / 5000)
        self.assertEqual(sum(leak["escaped"] for leak in doc["leaks"]), doc["escaped"])
        run = rotleak.read_run(out)
        self.assertEqual(run.leaks["escaped_0"].tolist(), table["escaped_0"].tolist())
        self.assertIsNone(rotleak.read_run(self.run_dir).leaks)  # one leak: no leaks.csv
        # its pictures: the caption names the table and both leaks
        from rotleak import plot
        drawings = plot.figures(out)
        self.assertEqual([d.name for d in drawings], ["survival"])
        self.assertIn("circle radius = 1; leak at s_L = 0, width 0.02", drawings[0].caption)
        self.assertIn("leak at s_L = 1/4, width 0.01, omega = 1/3", drawings[0].caption)

    def test_a_scene_on_any_table_with_leaks_is_built_in_python_and_runs_as_the_command(self):
        """Scene(table=..., leaks=[...]) (docs/tables.md): checked by rotleak's reader, saved as TOML exactly, run in
        process to the command's bytes; listed leaks changed by leaks.N.key or replaced whole."""
        scene = rotleak.Scene(table={"kind": "sinai", "side": 2, "radius": Fraction(1, 2)},
                              leaks=[{"width": "0.02"}, {"loop": 1, "width": Fraction(1, 20), "omega": "1/7"}],
                              ensemble={"particles": 2000}, run={"t_max": 1000})
        toml = scene.to_toml()
        self.assertIn('kind = "sinai"', toml)
        self.assertEqual(toml.count("[[leaks]]"), 2)
        self.assertIn('width = "1/20"', toml)
        self.assertEqual(rotleak.Scene.from_toml(toml), scene)
        path = os.path.join(self.tmp, "sinai.toml")
        scene.save(path)
        cmd = os.path.join(self.tmp, "sinai_cmd")
        subprocess.run([BIN, "simulate", path, "--threads", "2", "--no-progress", "--out", cmd], check=True,
                       capture_output=True)
        r = rotleak.simulate(scene, threads=1)
        for name in ("survival.csv", "leaks.csv", "scene.toml"):
            self.assertEqual(r.text(name), rotleak.read_run(cmd).text(name), name)
        self.assertEqual([leak["loop"] for leak in r.summary["leaks"]], [0, 1])
        # a listed leak's key, and the list replaced whole (not appended to)
        wider = scene.replace({"leaks.1.width": "0.1"})
        self.assertIn('width = "0.1"', wider.to_toml())
        one = scene.replace(leaks=[{"width": "0.03", "loop": 1}])
        self.assertEqual(one.to_toml().count("[[leaks]]"), 1)
        for bad in ({"table": {"kind": "circle", "radius": 1.5}}, {"leaks": [{"width": 0.01}]},
                    {"leaks": [{"width": "0.01", "size": 2}]}, {"leaks": "0.01"},
                    {"table": {"kind": "circle", "radius": 1}, "leaks": [{"width": "0.01", "loop": 1}]}):
            with self.assertRaises(ValueError, msg=str(bad)):
                rotleak.Scene(**bad)

    def test_a_listed_leaks_exact_keys_refuse_floats(self):
        """leaks.N.width, .start and .omega are read exactly, as leak.width is: a float is refused by name (it would
        pass its rounding off as the value meant); exact texts, ints and Fractions are taken; leaks.N.loop is an
        integer, not an exact text, and a float there is the reader's to refuse."""
        scene = rotleak.Scene(leaks=[{"width": "0.02"}, {"width": "0.01", "start": "1/2"}])
        for key in ("leaks.1.width", "leaks.0.start", "leaks.1.omega"):
            with self.subTest(key=key):
                with self.assertRaisesRegex(ValueError, r"^overrides\['%s'\] = 0\.1: %s is exact" % (
                        re.escape(key), re.escape(key))):
                    scene.replace({key: 0.1})
        for value in ("1/10", Fraction(1, 10)):
            self.assertIn('width = "1/10"', scene.replace({"leaks.1.width": value}).to_toml())
        self.assertIn("omega = \"3\"", scene.replace({"leaks.1.omega": 3}).to_toml())

    def test_a_table_is_drawn_from_rotleaks_own_geometry(self):
        """rotleak.plot.table's points (analysis/output/table_output.hpp): the circle's lie on it, the Sinai table has
        two loops with its disc's leak on the disc, and a figure of every example scene is drawn."""
        from rotleak.plot import table as tables
        circle = tables.drawing(os.path.join(SRC, "data", "scenes", "tables", "circle.toml"))
        self.assertEqual(circle["kind"], "circle")
        self.assertAlmostEqual(circle["area"], math.pi)
        ring = circle["loops"][0]
        self.assertTrue(all(abs(math.hypot(x, y) - 1) < 1e-14 for x, y in zip(ring["x"], ring["y"])))
        self.assertEqual((ring["x"][0], ring["y"][0]), (ring["x"][-1], ring["y"][-1]))  # closed
        self.assertEqual(ring["origin"], [0.0, 1.0])  # s = 0 at the top, clockwise: towards +x
        self.assertAlmostEqual(ring["direction"][0], 1.0)
        sinai = tables.drawing(os.path.join(SRC, "data", "scenes", "tables", "sinai.toml"))
        self.assertEqual(len(sinai["loops"]), 2)
        disc_leak = [leak for leak in sinai["leaks"] if leak["loop"] == 1][0]
        self.assertTrue(all(abs(math.hypot(x, y) - 0.5) < 1e-14 for x, y in zip(disc_leak["x"], disc_leak["y"])))
        scenes = sorted(os.path.join(SRC, "data", "scenes", "tables", f)
                        for f in os.listdir(os.path.join(SRC, "data", "scenes", "tables")))
        out = os.path.join(self.tmp, "tables.png")
        self.assertEqual(tables.main([out] + scenes), 0)
        self.assertGreater(os.path.getsize(out), 10000)

    def test_calibration_reads_back_with_csv_json_and_pandas(self):
        """rotleak calibrate's files (docs/output.md "Calibration") with the standard readers, the package's
        Calibration the same, and rotleak.calibrate in process writing the same bytes as the command."""
        import csv
        scene = os.path.join(SRC, "data", "scenes", "stationary_sL_0.toml")
        out = os.path.join(self.tmp, "calibration")
        subprocess.run([BIN, "calibrate", scene, "--seeds", "4", "--particles", "3000", "--set", "run.t_max=400",
                        "--no-progress", "--out", out], check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "calibration.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(list(rows[0]), ["t", "resolved", "seeds", "P", "P_err", "P_err_model", "sd_over_err",
                                         "chi2_dof", "coverage1", "coverage2", "max_over_median"])
        self.assertEqual(len(rows), 401)  # the grid t = 0..400
        self.assertTrue(all(r["resolved"] in ("0", "1") and r["seeds"] == "4" for r in rows))
        with open(os.path.join(out, "calibration.json")) as f:
            doc = json.load(f)
        for key, kind in (("command", str), ("schema", int), ("scene", str), ("seeds", list), ("particles", int),
                          ("P", dict), ("statistics", dict), ("alpha_bounds", dict), ("pooled", dict),
                          ("files", list)):
            self.assertIsInstance(doc[key], kind, key)
        self.assertEqual(doc["seeds"], [1, 2, 3, 4])
        self.assertIn("kappa", doc["statistics"])
        table = pd.read_csv(os.path.join(out, "calibration.csv"))
        self.assertEqual(len(table), 401)
        self.assertTrue(pd.api.types.is_float_dtype(table["sd_over_err"]))
        cal = rotleak.read_calibration(out)
        self.assertEqual(cal.statistics, doc["statistics"])
        self.assertEqual(len(cal.table), 401)
        self.assertEqual(len(cal.scan.point_names), 4)
        again = rotleak.calibrate(scene, 4, os.path.join(self.tmp, "calibration2"), particles=3000,
                                  overrides={"run.t_max": 400})
        with open(os.path.join(out, "calibration.csv")) as a, \
                open(os.path.join(again.path, "calibration.csv")) as b:
            self.assertEqual(a.read(), b.read())
        with self.assertRaises(rotleak.RotleakError):
            rotleak.read_calibration(self.scan_dir)  # a scan is not a calibration
        with self.assertRaises(ValueError):
            rotleak.calibrate(scene, 1, os.path.join(self.tmp, "calibration3"))

    def test_scan_fit_regimes_and_calibrate_take_a_scene_and_write_what_the_commands_write(self):
        # Python once drove commands only: no scan, fit, regimes in process, and calibrate refused a Scene
        scene = rotleak.Scene(stadium={"d": 1}, leak={"width": "0.02", "start": "1/4"},
                              ensemble={"particles": 3000}, run={"t_max": 1500})
        path = os.path.join(self.tmp, "py_scene.toml")
        scene.save(path)
        over = {"leak.omega": ["1/2", Fraction(2, 3), "golden-1", "1e-3"]}
        ours = rotleak.scan(scene, over, os.path.join(self.tmp, "py_scan"))
        theirs = os.path.join(self.tmp, "cli_scan")
        cli("scan", path, "--over", "leak.omega=1/2,2/3,golden-1,1e-3", "--out", theirs)
        self.assertEqual(ours.document["scene"], "rotleak.Scene")
        self.assertEqual(len(ours.point_names), 4)
        for name in ours.point_names:  # every point's files byte for byte (scene.toml names its source)
            for f in ("survival.csv", "fc.csv"):
                if os.path.exists(os.path.join(theirs, "points", name, f)):
                    with open(os.path.join(ours.path, "points", name, f)) as a, \
                            open(os.path.join(theirs, "points", name, f)) as b:
                        self.assertEqual(a.read(), b.read(), (name, f))
        pd.testing.assert_frame_equal(ours.table, rotleak.read_scan(theirs).table)
        refit = rotleak.fit(ours, kappa_window=[100, 600])
        cli("fit", theirs, "--set", "fit.kappa_window=[100, 600]")
        self.assertIsInstance(refit, rotleak.Scan)
        pd.testing.assert_frame_equal(refit.table, rotleak.read_scan(theirs).table)
        self.assertNotEqual(refit.table["kappa"].tolist(), ours.table["kappa"].tolist())
        run = rotleak.fit(os.path.join(ours.path, "points", ours.point_names[0]), {"fit.alpha_factor": 5})
        self.assertEqual(run.summary["alpha"]["factor"], 5)
        with self.assertRaisesRegex(ValueError, "write it first"):
            rotleak.fit(rotleak.simulate(scene))
        with self.assertRaisesRegex(ValueError, "fit.kappa_window"):
            rotleak.fit(ours, kappa_window=[600, 100])
        with self.assertRaisesRegex(ValueError, r"leak\.omega.*exact"):
            rotleak.scan(scene, {"leak.omega": [0.5]}, os.path.join(self.tmp, "never"))
        with self.assertRaisesRegex(ValueError, "^over = "):
            rotleak.scan(scene, {}, os.path.join(self.tmp, "never"))
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "never")))
        found = rotleak.regimes(scene, os.path.join(self.tmp, "py_regimes"), coarse="1e-3,1e-1", steps=0)
        self.assertEqual(set(found["boundaries"]), {"low_mid", "mid_high"})
        self.assertEqual(found["scene"], "rotleak.Scene")
        cal = rotleak.calibrate(scene, 2, os.path.join(self.tmp, "py_calibration"), overrides={"run.t_max": 300})
        self.assertEqual(cal.document["seeds"], [1, 2])

    def test_progress_reaches_the_end_and_its_exception_stops_the_run(self):
        calls = []
        rotleak.simulate(QUICK, particles=20000, progress=lambda *a: calls.append(a))
        self.assertTrue(calls)
        self.assertEqual(calls[-1][0], 20000)
        self.assertTrue(calls[-1][3])

        def fail(done, total, collisions, final):
            raise RuntimeError("stop here")

        with self.assertRaisesRegex(RuntimeError, "stop here"):
            rotleak.simulate(QUICK, particles=200000, progress=fail)

    def test_the_gil_is_released_while_it_runs(self):
        ticks = []
        done = threading.Event()

        def count():
            while not done.is_set():
                ticks.append(time.monotonic())
                time.sleep(0.001)

        t = threading.Thread(target=count)
        t.start()
        start = time.monotonic()
        rotleak.simulate(QUICK, particles=1000000, threads=1)
        end = time.monotonic()
        done.set()
        t.join()
        during = [x for x in ticks if start < x < end]
        # a thread holding the GIL for the whole run would leave no tick inside it; a run of ~0.5 s leaves
        # hundreds when the GIL is free, and a few even on a machine busy with other tests
        self.assertGreater(len(during), 3, "%d ticks in a %.2f s run" % (len(during), end - start))

    def test_ctrl_c_interrupts_cleanly(self):
        code = ("import rotleak, sys\n"
                "try:\n"
                "    rotleak.simulate(sys.argv[1], particles=10**9, threads=1, progress=lambda *a: print('p', flush=True))\n"
                "except KeyboardInterrupt as e:\n"
                "    print('interrupted:', e, flush=True)\n"
                "    sys.exit(3)\n")
        p = subprocess.Popen([sys.executable, "-c", code, QUICK], stdout=subprocess.PIPE, text=True,
                             env=dict(os.environ))
        self.assertEqual(p.stdout.readline().strip(), "p")  # running
        p.send_signal(signal.SIGINT)
        out, _ = p.communicate(timeout=60)
        self.assertEqual(p.returncode, 3, out)
        self.assertIn("interrupted: rotleak.simulate interrupted", out)
        self.assertLess(out.count("p\n"), 1000, "the run went on after Ctrl-C")

    def test_predict_matches_the_command_the_summary_and_the_scan_table(self):
        p = rotleak.predict(QUICK, overrides={"leak.omega": "2/3"})
        cl = json.loads(subprocess.run([BIN, "predict", QUICK, "--set", "leak.omega=2/3", "--json"], check=True,
                                       capture_output=True, text=True).stdout)
        self.assertEqual(p, cl)
        self.assertEqual((p["forms"], p["rational"], p["Q"], p["regime"]), (True, "4/3", 3, "high"))
        # the run's summary.json carries the same prediction (less the scene), the scan table its columns
        with open(os.path.join(self.run_dir, "summary.json")) as f:
            tail = json.load(f)["predicted"]["tail"]
        self.assertEqual(tail, {k: v for k, v in p.items() if k != "scene"})
        table = rotleak.read_scan(self.scan_dir).table
        with open(os.path.join(self.scan_dir, "table.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        for (_, row), raw in zip(table.iterrows(), rows):
            want = rotleak.predict(QUICK, overrides={"leak.omega": row["leak.omega"]})
            self.assertEqual(row["predicted_tail"], "forms" if want["forms"] else "none")
            self.assertAlmostEqual(row["predicted_amplitude"], want["amplitude"], delta=1e-12 * want["amplitude"])
            self.assertEqual(raw["predicted_tail_end"], "" if want["end"] is None else raw["predicted_tail_end"])
        with self.assertRaisesRegex(ValueError, "leak.width"):
            rotleak.predict(QUICK, overrides={"leak.width": "0.7"})

    def test_omega_and_covering_match_the_command(self):
        o = rotleak.omega("70/71")
        cl = json.loads(subprocess.run([BIN, "omega", "70/71", "--json"], check=True, capture_output=True,
                                       text=True).stdout)
        self.assertEqual(dict(o), cl)
        self.assertEqual(o.fractions(), [Fraction(0), Fraction(1), Fraction(70, 71)])
        c = rotleak.covering(["2/3", "1e-4"], delta="1e-7", resolution=200)
        out = os.path.join(self.tmp, "cov")
        cli("covering", "--omega", "2/3", "--omega", "1e-4", "--resolution", "200", "--segments", "--out", out)
        with open(os.path.join(out, "summary.json")) as f:
            self.assertEqual(without_execution(c.summary), without_execution(json.load(f)))
        pd.testing.assert_frame_equal(c.f_L, pd.read_csv(os.path.join(out, "f_L.csv")))
        pd.testing.assert_frame_equal(c.segments(1), pd.read_csv(os.path.join(out, "segments_1.csv")))

    def test_covering_picture_names_each_panels_delta_and_N(self):
        # two deltas once shared the first delta's N in the title
        from rotleak.plot import covering as picture

        out = os.path.join(self.tmp, "cov2")
        cli("covering", "--omega", "2/3", "--delta", "1e-7", "1e-9", "--resolution", "100", "--out", out)
        (drawing,) = picture.figures(out)
        texts = [ax.get_title(loc="left") for ax in drawing.figure.axes]  # above each panel: it hides no data
        with open(os.path.join(out, "summary.json")) as f:
            n = [c["N"] for c in json.load(f)["covering"]]
        self.assertNotEqual(n[0], n[1])
        self.assertIn("delta = 1e-7, N = %d" % n[0], texts[0])
        self.assertIn("delta = 1e-9, N = %d" % n[1], texts[1])
        for t in texts:  # delta once; the omega's own label carried it a second time
            self.assertEqual(t.count("delta"), 1, t)

    def test_a_scan_over_expressions_plots_every_point_in_omega_order(self):
        # the scan a user drew once showed 4 of its 7 points (an expression had no value) joined in scan order;
        # table.csv and scan.json carry the exact omega rounded once, and the plot puts every point at it, sorted
        import decimal
        from fractions import Fraction

        from rotleak.plot import scan as scan_plot

        seven = "1/2,2/3,3/5,3/4,golden-1,2/3+1e-4,sqrt(2)-1"
        decimal.getcontext().prec = 60  # the irrationals to 60 digits, then rounded once (float() of a Decimal)
        exact = [Fraction(1, 2), Fraction(2, 3), Fraction(3, 5), Fraction(3, 4), (decimal.Decimal(5).sqrt() - 1) / 2,
                 Fraction(2, 3) + Fraction(1, 10000), decimal.Decimal(2).sqrt() - 1]
        d = os.path.join(self.tmp, "seven")
        cli("scan", QUICK, "--over", "leak.omega=" + seven, "--set", "ensemble.particles=2000", "--out", d)
        sc = rotleak.read_scan(d)
        want = [float(x) for x in exact]
        self.assertEqual(list(sc.table["omega_value"]), want)
        self.assertEqual([p["omega_value"] for p in sc.document["points"]], want)
        self.assertEqual([p["numbers"]["leak.omega"] for p in sc.document["points"]], want)
        fig = scan_plot.against_key(sc.document, "leak.omega").figure
        curves = scan_plot.curves(sc).figure.axes[0]  # every point's P(t), coloured in omega order
        self.assertEqual([line.get_label() for line in curves.lines],
                         ["omega = " + v for _, v in sorted(zip(want, seven.split(",")))])
        strip = [o[0] for c in fig.axes[2].collections for o in c.get_offsets()]
        self.assertEqual(strip, sorted(want), "every point in the regime strip, in omega order")
        kappa = [float(x) for x in fig.axes[0].lines[0].get_xdata()]
        self.assertEqual(kappa, sorted(want), "the kappa line joins the points in omega order")

    def test_labels_of_points_close_together_step_apart(self):
        """rotleak.plot.label_points: a label that would overlap one placed before steps down a line, so labels of
        points at one place never sit on each other (each once did when a placed label was kept without its
        height: mutant tests/mutants/plot-label-box-flat.patch, drawn by scripts/mutate.py)."""
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from rotleak import plot
        fig, ax = plt.subplots(figsize=(plot.ONE_COLUMN, 2.5))
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1)
        plot.label_points(ax, [(0.3, 0.5, "omega = 1/3"), (0.3, 0.5, "omega = 2/3"), (0.31, 0.5, "omega = 1")])
        fig.canvas.draw()
        r = fig.canvas.get_renderer()
        boxes = [t.get_window_extent(r) for t in ax.texts]
        self.assertEqual(len(boxes), 3)
        for i, a in enumerate(boxes):
            for b in boxes[i + 1:]:
                self.assertFalse(a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1, (a, b))
        plt.close(fig)

    def test_pictures_keep_labels_clear_of_the_data_and_of_each_other(self):
        # each once failed as a user saw it: the regimes' legend covered scan_<key>'s x label, f_L's labels sat
        # on the data, fc's legend covered a spike, tick labels overlapped (0 beside 1e-4; minor log labels),
        # regimes.png had one y tick, scan plots had no title, the sampling title ran off the figure
        from rotleak import plot
        from rotleak.plot import sampling, tiers

        seen = {}  # picture name -> its figure, drawn as it would be saved

        def boxes_overlap(a, b):
            return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1

        def labels(texts, r):
            return [t.get_window_extent(r) for t in texts if t.get_visible() and t.get_text()]

        def disjoint(extents):
            return all(not boxes_overlap(a, b) for i, a in enumerate(extents) for b in extents[i + 1:])

        def look(what):  # every picture a column or a page wide, its text 8 pt or more there, with a caption
            import matplotlib.text
            for d in plot.figures(what):
                d.figure.canvas.draw()
                seen[os.path.basename(d.name) + ".png"] = d.figure
                self.assertIn(d.figure.get_size_inches()[0], (plot.ONE_COLUMN, plot.TWO_COLUMN), d.name)
                small = [(t.get_text(), t.get_fontsize()) for t in d.figure.findobj(matplotlib.text.Text)
                         if t.get_visible() and t.get_text() and t.get_fontsize() < 8]
                self.assertEqual(small, [], d.name)
                self.assertTrue(d.caption.endswith("."), d.name)

        try:
            wide = os.path.join(self.tmp, "wide_scan")
            cli("scan", QUICK, "--over", "leak.omega=0,1e-4,1", "--set", "ensemble.particles=2000", "--out", wide)
            look(wide)
            fig = seen["scan_leak_omega.png"]
            r = fig.canvas.get_renderer()
            self.assertTrue(fig.axes[0].get_title())
            bottom = fig.axes[-1]
            legend = fig.legends[0].get_window_extent(r)
            self.assertFalse(boxes_overlap(legend, bottom.xaxis.label.get_window_extent(r)))
            self.assertTrue(disjoint(labels(bottom.get_xticklabels(), r)), [t.get_text() for t in bottom.get_xticklabels()])
            self.assertTrue(seen["scan_survival.png"].axes[0].get_title())
            fig = seen["scan_alpha_covering.png"]
            r = fig.canvas.get_renderer()
            ax = fig.axes[0]
            self.assertTrue(disjoint(labels(ax.get_yticklabels(which="both"), r)))
            self.assertTrue(disjoint(labels(ax.texts, r)), [t.get_text() for t in ax.texts])

            look(self.run_dir)
            fig = seen["survival.png"]  # t_max = 20000: five-digit times, whose labels run together if many
            r = fig.canvas.get_renderer()
            for ax in fig.axes:
                lo, hi = ax.get_xlim()
                shown = [t for t in ax.get_xticklabels() if lo <= t.get_position()[0] <= hi]
                self.assertTrue(disjoint(labels(shown, r)), [t.get_text() for t in shown])
            fig = seen["fc.png"]
            r = fig.canvas.get_renderer()
            ax = fig.axes[0]
            self.assertFalse(boxes_overlap(ax.get_legend().get_window_extent(r), ax.get_window_extent(r)))

            cov = os.path.join(self.tmp, "cov_layout")
            cli("covering", "--omega", "1e-4", "--delta", "1e-12", "--resolution", "200", "--out", cov)
            look(cov)
            fig = seen["f_L.png"]
            for ax in fig.axes:
                self.assertEqual(len(ax.texts), 0)  # the panel's label is its title, above the data
                lo, hi = ax.get_ylim()
                self.assertGreater(lo, 0)  # nearly uniform f_L: the axis spans the data, not 0..max

            reg = os.path.join(self.tmp, "regimes_layout")
            shutil.copytree(wide, os.path.join(reg, "coarse"))
            with open(os.path.join(reg, "regimes.json"), "w") as f:
                json.dump({"boundaries": {"low_mid": None, "mid_high": None}, "predicted": {"omega_sweep": 0.005}}, f)
            look(reg)
            ax = seen["regimes.png"].axes[0]
            lo, hi = ax.get_ylim()
            self.assertGreaterEqual(len([y for y in ax.get_yticks() if lo <= y <= hi]), 2)

            rows = [{"tier": t, "median_horizon_collisions": x, "ratio_to_double": y} for t, x, y in (
                ("double", "24", "1"), ("float128", "66", "25.59"), ("mpfr:128", "76", "28.71"))]
            fig = tiers.draw(rows)
            fig.canvas.draw()
            self.assertTrue(disjoint(labels(fig.axes[0].texts, fig.canvas.get_renderer())))
            fig = sampling.draw([{"t": "100", "survivors_uniform": "10", "P_uniform": "0.5", "err_uniform": "0.01",
                                  "effective_mupo": "100", "P_mupo": "0.5", "err_mupo": "0.01"},
                                 {"t": "200", "survivors_uniform": "5", "P_uniform": "0.25", "err_uniform": "0.01",
                                  "effective_mupo": "50", "P_mupo": "0.25", "err_mupo": "0.01"}])
            fig.canvas.draw()
            title = fig.axes[0].title.get_window_extent(fig.canvas.get_renderer())
            self.assertGreaterEqual(title.x0, 0)
            self.assertLessEqual(title.x1, fig.bbox.x1)
        finally:
            import matplotlib.pyplot as plt
            plt.close("all")

    def test_benchmark_pictures_draw_from_their_csv(self):
        tiers = os.path.join(self.tmp, "tiers.csv")
        with open(tiers, "w") as f:
            f.write("tier,median_horizon_collisions,ratio_to_double\nfloat,12,0.9\ndouble,30,1\ndd,70,9\n")
        sampling = os.path.join(self.tmp, "sampling.csv")
        with open(sampling, "w") as f:
            f.write("t,survivors_uniform,P_uniform,err_uniform,effective_mupo,P_mupo,err_mupo\n")
            for t in range(0, 3000, 100):
                p = 2.718281828 ** (-0.0044 * t)
                f.write("%d,%d,%g,%g,%g,%g,%g\n" % (t, int(1e4 * p), p, p / 50, 500, p, p / 20))
        for name, csv_path in (("tiers", tiers), ("sampling", sampling)):
            out = os.path.join(self.tmp, name + ".png")
            subprocess.run([sys.executable, "-m", "rotleak.plot." + name, csv_path, out], check=True,
                           stdout=subprocess.DEVNULL)
            self.assertGreater(os.path.getsize(out), 1000, name)
        empty = os.path.join(self.tmp, "empty.csv")
        with open(empty, "w") as f:
            f.write("tier,median_horizon_collisions,ratio_to_double\n")
        r = subprocess.run([sys.executable, "-m", "rotleak.plot.tiers", empty, os.path.join(self.tmp, "x.png")],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn("has no rows", r.stderr)


class OtherInterpreter(unittest.TestCase):
    """An interpreter without numpy and pandas (here: the suite's own, with its site packages switched off by
    -S, as a pyenv or conda python3 first on PATH would be) is told what it lacks and which Python has it."""

    def test_import_names_the_missing_modules_and_the_interpreter_built_for(self):
        build_python = os.environ["PYTHONPATH"].split(os.pathsep)[0]
        probe = "import sys; sys.path.insert(0, sys.argv[1]); import rotleak"
        r = subprocess.run([sys.executable, "-S", "-c", probe, build_python], capture_output=True, text=True)
        if r.returncode == 0:
            self.skipTest("this interpreter imports numpy and pandas without its site packages")
        last = r.stderr.strip().splitlines()[-1]
        self.assertTrue(last.startswith("ImportError: rotleak needs numpy and pandas, which this Python"), last)
        from rotleak import _version
        self.assertIn("rotleak is built for %s" % _version.python, last)
        self.assertEqual(_version.python, subprocess.run(["bash", os.path.join(SRC, "scripts", "setup.sh"), "--python"],
                                                         capture_output=True, text=True, check=True).stdout.strip())
        # a Python with numpy and pandas but no matplotlib (find_spec reports a None entry of sys.modules as absent)
        r = subprocess.run([sys.executable, "-c", "import sys; sys.modules['matplotlib'] = None; sys.path.insert(0, "
                            "sys.argv[1]); import rotleak.plot", build_python], capture_output=True, text=True)
        self.assertIn("rotleak.plot needs matplotlib, which this Python", r.stderr.strip().splitlines()[-1])


if __name__ == "__main__":
    unittest.main()
