#!/usr/bin/python3
"""Every file rotleak writes, read back with the readers a user would use (Python's csv and json, and
pandas), checked against the schemas in docs/output.md: a CSV's header against its documented columns,
every row's field count, every field's type; a JSON document's top-level keys and their types (for a
run's summary.json: the summary.json table, with no undocumented key). A file the docs do not describe
is a failure too.

Usage: scripts/check_output_schema.py DIR...   (every file under each DIR)
Prints one line per file checked; exits 1 after listing every violation.
"""
import csv
import json
import math
import os
import re
import sys

import pandas as pd

DOCS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "docs", "output.md")


# ---- the schemas, from docs/output.md ------------------------------------------------------------


def table_rows(text, heading):
    """The rows (lists of cells, pipes escaped as \\| kept as |) of the first table after `heading`."""
    at = text.index(heading)
    rows = []
    for line in text[at:].splitlines()[1:]:
        if line.startswith("|"):
            cells = [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line)[1:-1]]
            if not all(set(c) <= set("-: ") for c in cells):
                rows.append(cells)
        elif rows:
            break
    return rows[1:]  # without the header row


def code(cell):
    m = re.search(r"`([^`]*)`", cell)
    return m.group(1) if m else cell


def parse_columns(spec):
    """'a:int (b[<W>]:float c:int?)+' -> a list of ('col', regex, type, optional) and ('group', items, min)."""
    tokens = re.findall(r"\(|\)[+*]|[^\s()]+", spec)
    pos = 0

    def items(until_close):
        nonlocal pos
        out = []
        while pos < len(tokens):
            tok = tokens[pos]
            pos += 1
            if tok == "(":
                inner = items(True)
                out.append(("group", inner, 1 if tokens[pos - 1] == ")+" else 0))
            elif tok in (")+", ")*"):
                if not until_close:
                    raise ValueError("unbalanced ) in " + spec)
                return out
            else:
                name, _, typ = tok.rpartition(":")
                optional = typ.endswith("?")
                typ = typ.rstrip("?")
                regex = "".join(".+" if part.startswith("<") else re.escape(part)
                                for part in re.split(r"(<[^>]+>)", name) if part)
                out.append(("col", "^" + regex + "$", typ, optional))
        if until_close:
            raise ValueError("unclosed ( in " + spec)
        return out

    return items(False)


def match_header(items, header):
    """The column spec of each header name, or None when the header does not fit the items."""

    def go(k, j):
        if k == len(items):
            return [] if j == len(header) else None
        it = items[k]
        if it[0] == "col":
            if j < len(header) and re.match(it[1], header[j]):
                rest = go(k + 1, j + 1)
                return None if rest is None else [it] + rest
            return None
        # a group: try as many repetitions as fit, the most first (names are distinct enough)
        reps = []
        jj = j
        while True:
            sub = match_fixed(it[1], header, jj)
            if sub is None:
                break
            reps.append((jj + len(sub), sub))
            jj += len(sub)
            if not sub:
                break
        for n in range(len(reps), it[2] - 1, -1):
            end = reps[n - 1][0] if n else j
            rest = go(k + 1, end)
            if rest is not None:
                return [c for _, s in reps[:n] for c in s] + rest
        return None

    def match_fixed(group, hdr, j):
        out = []
        for it in group:
            if j + len(out) >= len(hdr) or not re.match(it[1], hdr[j + len(out)]):
                return None
            out.append(it)
        return out

    return go(0, 0)


def load_schemas():
    text = open(DOCS).read()
    heading = "### Schemas, as the suite checks them"
    csv_schemas = {}
    for cells in table_rows(text, heading):
        name = re.sub(r"`", "", cells[0])  # a file name, or "NAME of COMMAND" where commands share a name
        if name.split(" of ")[0].endswith(".csv"):
            csv_schemas[name] = parse_columns(code(cells[1]))
    json_schemas = {}
    rest = text[text.index(heading):]
    for cells in table_rows(rest, "JSON documents"):
        name = re.sub(r"`", "", cells[0])
        spec = code(cells[1])
        json_schemas[name] = None if spec == cells[1] else [tok.split(":") for tok in spec.split()]
    # summary.json of simulate: its field table
    summary = {}
    for cells in table_rows(text, "### summary.json"):
        names = re.findall(r"`([^`]+)`", cells[0])
        types = [t.strip() for t in re.split(r",", cells[1].split(" only")[0].split(", only")[0])]
        types = [t for t in types if t in ("string", "integer", "number", "object", "array")]
        optional = "only" in cells[1] or cells[2].startswith("only")
        for i, n in enumerate(names):
            top, _, sub = n.partition(".")
            typ = types[i] if len(types) == len(names) else types[0]
            if sub:
                summary.setdefault(top, ["object", False, {}])[2][sub] = (typ, optional)
            else:
                summary[top] = [typ, optional, summary.get(top, [None, None, {}])[2]]
    return csv_schemas, json_schemas, summary


# ---- the checks ------------------------------------------------------------------------------------

INT = re.compile(r"^-?\d+$")


def field_ok(value, typ):
    if typ == "int":
        return bool(INT.match(value))
    if typ == "float":
        try:
            float(value)
            return True
        except ValueError:
            return False
    if typ == "text":
        return True
    return value in typ.split("|")


def schema_for(csv_schemas, fname):
    for pattern, items in csv_schemas.items():
        if re.match("^" + re.sub(r"<[^>]+>", ".+", re.escape(pattern).replace(r"\<", "<").replace(r"\>", ">")) + "$",
                    fname):
            return items
    return None


def check_csv(path, items, errors):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    cols = match_header(items, header)
    if cols is None:
        errors.append(f"{path}: header {header} does not match the documented columns")
        return
    for k, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            errors.append(f"{path}: line {k} has {len(row)} fields, the header names {len(header)}")
            return
        for name, value, c in zip(header, row, cols):
            if value == "" and c[3]:
                continue
            if not field_ok(value, c[2]):
                errors.append(f"{path}: line {k}, column {name}: {value!r} is not {c[2]}")
                return
    with open(path, newline="") as f:
        for k, rec in enumerate(csv.DictReader(f), start=2):
            if None in rec or list(rec) != header:
                errors.append(f"{path}: csv.DictReader files line {k} under other names ({list(rec)[:3]}...)")
                return
    df = pd.read_csv(path)
    if list(df.columns) != header or df.shape != (len(rows) - 1, len(header)) or not isinstance(df.index, pd.RangeIndex):
        errors.append(f"{path}: pandas reads columns {list(df.columns)[:4]}... shape {df.shape} (expected the header, "
                      f"{len(rows) - 1} rows)")
        return
    for name, c in zip(header, cols):
        dt = str(df[name].dtype)
        empty = df[name].isna().any()
        if c[2] == "int" and not empty and dt != "int64":
            errors.append(f"{path}: pandas reads the int column {name} as {dt}")
        if c[2] in ("int", "float") and dt not in ("int64", "float64") and not (empty and df[name].isna().all()):
            errors.append(f"{path}: pandas reads the numeric column {name} as {dt}")


def json_type_ok(value, typ):
    return {"string": isinstance(value, str), "integer": isinstance(value, int) and not isinstance(value, bool),
            "number": isinstance(value, (int, float)) and not isinstance(value, bool),
            "object": isinstance(value, dict), "array": isinstance(value, list)}[typ]


def check_keys(path, doc, keys, errors):
    for name, typ in keys:
        optional = typ.endswith("?")
        typ = typ.rstrip("?")
        if name not in doc or doc[name] is None:
            if not optional:
                errors.append(f"{path}: no key {name}")
            continue
        if not json_type_ok(doc[name], typ):
            errors.append(f"{path}: {name} is {type(doc[name]).__name__}, documented as {typ}")


def check_json(path, schemas, summary, errors):
    with open(path) as f:
        doc = json.load(f)
    flat = pd.json_normalize(doc) if isinstance(doc, dict) else None  # pandas reads it too
    if flat is None or len(flat) != 1:
        errors.append(f"{path}: not one JSON object (pandas.json_normalize gives {None if flat is None else len(flat)} rows)")
        return
    fname = os.path.basename(path)
    kind = fname
    if fname in ("summary.json", "summary.prev.json"):
        if doc.get("command") == "simulate":
            for key, (typ, optional, subs) in summary.items():
                if key not in doc:
                    if not optional:
                        errors.append(f"{path}: no key {key} (docs/output.md, summary.json)")
                    continue
                if doc[key] is not None and not json_type_ok(doc[key], typ):
                    errors.append(f"{path}: {key} is {type(doc[key]).__name__}, documented as {typ}")
                for sub, (st, sub_optional) in subs.items():
                    if not isinstance(doc[key], dict) or (sub_optional and sub not in doc[key]):
                        continue
                    if not json_type_ok(doc[key].get(sub), st):
                        errors.append(f"{path}: {key}.{sub} is not {st}")
            for key in doc:
                if key not in summary:
                    errors.append(f"{path}: key {key} is not in docs/output.md's summary.json table")
            return
        kind = ("summary.json of shadow" if "truth" in doc else "summary.json of covering" if "covering" in doc
                else "summary.json of audit" if doc.get("command") == "audit"
                else "summary.json of orbits" if doc.get("command") == "orbits"
                else "summary.json of certify" if doc.get("command") == "certify" else None)
        if kind is None:
            errors.append(f"{path}: a summary.json that docs/output.md does not describe")
            return
    if kind not in schemas:
        errors.append(f"{path}: not described in docs/output.md")
        return
    if kind == "points.json":
        if not all(isinstance(v, str) for v in doc.values()):
            errors.append(f"{path}: every value must be a string")
        return
    check_keys(path, doc, schemas[kind], errors)


def check_tally(path, errors):
    """tally.bin (src/io/tally_file.hpp): the format line docs/output.md names, the header's length and JSON
    header with its keys, and the FNV-1a 64 checksum of everything before the last 8 bytes."""
    with open(path, "rb") as f:
        data = f.read()
    with open(DOCS) as f:
        named = re.search(r"format `(rotleak-tallies \d+)`", f.read())
    magic = (named.group(1) + "\n").encode() if named else b"?"
    if not data.startswith(magic):
        errors.append(f"{path}: does not start with the format line docs/output.md names ({magic!r})")
        return
    nl = data.index(b"\n", len(magic))
    length = int(data[len(magic):nl])
    header = json.loads(data[nl + 1:nl + 1 + length])
    keys = {"inputs", "particles", "first_id", "of", "block_size", "done", "survival_bins", "density_bins",
            "weighted", "split", "records"}
    if not keys <= set(header) or set(header) - keys - {"wall_seconds"}:
        errors.append(f"{path}: header keys {sorted(header)}")
    h = 1469598103934665603
    for b in data[:-8]:
        h = ((h ^ b) * 1099511628211) % (1 << 64)
    if h != int.from_bytes(data[-8:], "little"):
        errors.append(f"{path}: checksum mismatch")


def command_of(directory):
    """The command whose summary.json lies in `directory` (None without one): a file name two commands
    write (escapes.csv) takes the schema of the command that wrote it."""
    try:
        with open(os.path.join(directory, "summary.json")) as f:
            doc = json.load(f)
        return doc.get("command") if isinstance(doc, dict) else None
    except (OSError, ValueError):
        return None


def main(dirs):
    csv_schemas, json_schemas, summary = load_schemas()
    errors, checked = [], 0
    for d in dirs:
        for root, _, files in os.walk(d):
            for fname in sorted(files):
                path = os.path.join(root, fname)
                before = len(errors)
                if fname.endswith(".csv"):
                    items = csv_schemas.get(f"{fname} of {command_of(root)}") or schema_for(csv_schemas, fname)
                    if items is None:
                        errors.append(f"{path}: no schema in docs/output.md")
                    else:
                        check_csv(path, items, errors)
                elif fname.endswith(".json"):
                    check_json(path, json_schemas, summary, errors)
                elif fname.endswith(".toml"):
                    import tomllib
                    with open(path, "rb") as f:
                        tomllib.load(f)
                elif fname == "tally.bin":
                    check_tally(path, errors)
                elif fname.endswith(".png"):
                    continue
                else:
                    errors.append(f"{path}: a file docs/output.md does not describe")
                checked += 1
                print(("ok    " if len(errors) == before else "FAIL  ") + os.path.relpath(path, d))
    for e in errors:
        print("schema: " + e, file=sys.stderr)
    print(f"{checked} files, {len(errors)} violations")
    return 1 if errors else 0


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1:]))
