#!/usr/bin/env python3
"""Hostile pass: try the talus program as a careless or hostile user would, and classify what
each input does.

It makes several hundred bad inputs from two tiny valid cases (2D: a Drucker-Prager block on a
rigid floor read from a polygon CSV, with an interface, a probe and K0; 3D: a box, a sphere, an
extruded slab and a rigid ground read from an ESRI ASCII raster with a footprint CSV, each run
well under a second): every numeric, array and string key set to 0, -1, nan, inf, 1e300, 1e-300
and wrong types; missing, unknown, misspelt and duplicate keys and tables; non-UTF-8 bytes, NULs
and terminal escapes; huge and deeply nested arrays; broken polygon CSVs and rasters; missing
files, folders, FIFOs, devices and symbolic-link loops as inputs; command-line misuse (run,
check, bench, verify, --set, --out, --overwrite, --restart) and hostile environments; and
run-folder faults (kill -9, signals, deleted, truncated and corrupted files, links planted at
temporary names, concurrent runs, a folder removed under a run, a full disk, bad [[run]]
entries). Each input runs with a time limit (a timeout is "hang") and a 4 GiB address-space
limit (an abort under it is "memory"), and its outcome is one of

  clear error            exit 1, 2 or 3 and a message on stderr naming the file and the key or
                         the problem (each input lists the substrings it looks for)
  valid                  exit 0, and that is right
  vague                  an error whose message does not name what is wrong, or an exit status
                         other than 1, 2 or 3, or raw control characters echoed to the terminal
  accepted though wrong  exit 0 where an error was expected
  refused though valid   an error where success was expected
  crash                  killed by a signal nobody sent, or "terminate called", "Segmentation",
                         "Aborted", "Traceback", ... in the output
  memory                 std::bad_alloc or an abort for lack of memory under the 4 GiB limit
  hang                   no exit within the time limit (the process group is killed)
  lost or mixed data     a user's file changed or removed, a file written outside the input's
                         folder, a symbolic link's target modified, a run folder reported
                         completed or stopped but missing files its particles.pvd lists, with
                         repeated steps in energy.csv or an unreadable summary.json, or a
                         restarted run that differs from one that never stopped
  harness error          this script failed (not a finding about talus)

Usage, from the source folder:

  python3 tools/hostile_pass.py --talus build/release/talus --work /tmp/hostile
  python3 tools/hostile_pass.py --talus build/release/talus --work /tmp/hostile --list
  python3 tools/hostile_pass.py ... --limit 10               # the first 10 inputs: a smoke test
  python3 tools/hostile_pass.py ... --classes raster,signals # only these classes (see --list)
  python3 tools/hostile_pass.py ... --only NAME,NAME         # only these inputs, by name

Everything is created under --work (made if missing; a non-empty --work must be one an earlier
pass made, marked by WORK/.hostile-pass): WORK/inputs/NNNN-name/ is each input's folder and the
working directory of its commands, WORK/home and WORK/tmp are talus's HOME and TMPDIR, and
WORK/results.jsonl gets one JSON object per input (id, name, class, command, exit code, the first
200 printable characters of stderr, outcome, why). The script never deletes or writes anything
outside --work; the only paths outside it handed to talus are read-only probes (/, /proc,
/dev/zero, /dev/null, /dev/urandom, /dev/full). A summary table follows the run: counts per
outcome and per class, then every outcome other than "clear error" and "valid" with its command
and message, for a human to review. Exit status 1 if any input crashed, hung or lost data.

Standard library only (Python 3.8 or later). Run as root, it also runs the permission inputs as
the user nobody (root reads and writes any file).
"""
import argparse
import copy
import hashlib
import json
import math
import os
import random
import re
import resource
import shlex
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional

GIB = 1 << 30
MEMORY_LIMIT = 4 * GIB
TIMEOUT = 60.0
FIFO_TIMEOUT = 20.0
MARKER = ".hostile-pass"
CASE2D = "hostile2d.toml"
CASE3D = "hostile3d.toml"
STOP = ["--max-steps", "5"]
NOBODY = 65534
SECRET = "AWS_SECRET_ACCESS_KEY=wJalrXUtnFEMIK7MDENGbPxRfiCYEXAMPLEKEY"
OUTCOMES = ["clear error", "valid", "vague", "accepted though wrong", "refused though valid",
            "crash", "memory", "hang", "lost or mixed data", "harness error"]
FAILING = {"crash", "hang", "lost or mixed data"}
CRASH_MARKERS = ("terminate called", "Segmentation", "Aborted", "Traceback", "core dumped",
                 "AddressSanitizer", "runtime error:", "stack smashing", "double free",
                 "free(): invalid", "malloc(): ", "Illegal instruction", "Bus error")
MEMORY_MARKERS = ("std::bad_alloc", "Cannot allocate memory", "out of memory", "Out of memory")

# ------------------------------------------------------------------------------------------------
# Inputs


@dataclass
class Fifo:
    """A named pipe (os.mkfifo): a reader that opens it blocks until someone writes."""


@dataclass
class Link:
    """A symbolic link to `target` ({d} is the input's folder)."""
    target: str


@dataclass
class Dir:
    """A folder, optionally with a mode and owner (uid)."""
    mode: Optional[int] = None
    owner: Optional[int] = None


@dataclass
class File:
    """A file with a mode: `data` is str, bytes or a callable returning either."""
    data: object
    mode: Optional[int] = None


@dataclass
class Input:
    """One hostile input. `argv` follows the talus path ({d}: the input's folder, {work}: the
    pass's folder); `files` maps paths in the input's folder to str, bytes, a callable returning
    either, File, Dir, Fifo or Link, and every regular file among them must be left unchanged.
    `expect` holds the substrings an error message must contain (a tuple: any one of them);
    `expect_success` is True (must exit 0), False (must be refused) or None (either is fine).
    `post(ctx, result)` may return an (outcome, why) that overrides the plain judgement, and
    `action(ctx)` replaces the single command with a scenario (returns the result to judge)."""
    name: str
    cls: str
    argv: list = field(default_factory=list)
    files: dict = field(default_factory=dict)
    expect: list = field(default_factory=list)
    expect_success: Optional[bool] = False
    post: Optional[Callable] = None
    action: Optional[Callable] = None
    env: dict = field(default_factory=dict)
    timeout: float = TIMEOUT
    user: Optional[int] = None
    allow_control: bool = False
    note: str = ""


@dataclass
class Result:
    cmd: str
    rc: Optional[int]
    out: str
    err: str
    timed_out: bool
    seconds: float
    sent_signal: Optional[int] = None


class SetupFailed(Exception):
    """A step that prepares a scenario (a first run) did not do what it must."""

    def __init__(self, result, what):
        super().__init__(what)
        self.result = result
        self.what = what


# ------------------------------------------------------------------------------------------------
# The two base cases, as editable documents: a list of [header, entries], an entry [key, value],
# a value TOML text or, for an inline table, a list of entries.

FLOOR_CSV = "x,y\n0.0,0.0\n1.0,0.0\n1.0,0.2\n0.0,0.2\n"
FOOTPRINT_CSV = "x,y\n0.05,0.05\n0.55,0.05\n0.55,0.55\n0.05,0.55\n"


def asc(ncols=6, nrows=6, xll="0.0", yll="0.0", cell="0.1", nodata="-9999", value="0.15",
        rows=None, header=None, eol="\n"):
    """An ESRI ASCII grid: a constant `value`, or `rows` (a list of row strings)."""
    head = header if header is not None else [f"ncols {ncols}", f"nrows {nrows}",
                                              f"xllcorner {xll}", f"yllcorner {yll}",
                                              f"cellsize {cell}", f"NODATA_value {nodata}"]
    body = rows if rows is not None else [" ".join([str(value)] * int(ncols))] * int(nrows)
    return eol.join(head + body) + eol


GROUND_ASC = asc()


def base2d():
    return [
        ["", [["title", '"hostile 2D"']]],
        ["[simulation]", [["dimension", "2"], ["end_time", "0.05"], ["cfl", "0.4"],
                          ["gravity", "[0.0, -9.81]"], ["scheme", '"musl"'], ["flip", "0.99"],
                          ["damping", "0.0"]]],
        ["[grid]", [["origin", "[0.0, 0.0]"], ["extent", "[1.0, 0.6]"], ["cell_size", "0.1"],
                    ["shape_function", '"gimp"']]],
        ["[grid.boundary]", [["x_min", '"slip"'], ["y_min", '"fixed"']]],
        ["[[material]]", [["name", '"soil"'], ["model", '"drucker_prager"'],
                          ["density", "2000.0"], ["youngs_modulus", "1.0e6"],
                          ["poisson_ratio", "0.3"], ["friction_angle", "30.0"],
                          ["dilation_angle", "0.0"], ["cohesion", "1000.0"]]],
        ["[[material]]", [["name", '"rock"'], ["density", "2500.0"],
                          ["youngs_modulus", "1.0e7"], ["poisson_ratio", "0.25"]]],
        ["[[body]]", [["name", '"block"'], ["material", '"soil"'],
                      ["box", [["min", "[0.2, 0.2]"], ["max", "[0.5, 0.4]"]]],
                      ["particles_per_cell", "2"], ["velocity", "[0.0, 0.0]"]]],
        ["[[body]]", [["name", '"floor"'], ["material", '"rock"'], ["rigid", "true"],
                      ["polygon", '"floor.csv"'], ["particles_per_cell", "2"]]],
        ["[[contact]]", [["friction", "0.3"]]],
        ["[[interface]]", [["bodies", '["block", "floor"]'],
                           ["friction", [["initial", "0.5"], ["residual", "0.3"],
                                         ["slip", "0.01"]]],
                           ["cohesion", [["initial", "1000.0"], ["residual", "0.0"],
                                         ["slip", "0.01"]]]]],
        ["[initial_state]", [["method", '"k0"'], ["k0", "0.5"]]],
        ["[[probe]]", [["name", '"top"'], ["body", '"block"'], ["near", "[0.35, 0.4]"]]],
        ["[results]", [["body", '"block"'], ["stop_speed", "0.5"]]],
        ["[output]", [["every", "0.01"]]],
        ["[checkpoint]", [["keep", "2"], ["wall_minutes", "3"]]],
    ]


def base3d():
    return [
        ["", [["title", '"hostile 3D"']]],
        ["[simulation]", [["dimension", "3"], ["end_time", "0.05"],
                          ["gravity", "[0.0, 0.0, -9.81]"]]],
        ["[grid]", [["origin", "[0.0, 0.0, 0.0]"], ["extent", "[0.6, 0.6, 0.6]"],
                    ["cell_size", "0.1"]]],
        ["[[material]]", [["name", '"rock"'], ["density", "2000.0"], ["youngs_modulus", "1.0e6"],
                          ["poisson_ratio", "0.3"]]],
        ["[[body]]", [["name", '"cube"'], ["material", '"rock"'],
                      ["box", [["min", "[0.2, 0.2, 0.2]"], ["max", "[0.4, 0.4, 0.4]"]]]]],
        ["[[body]]", [["name", '"ball"'], ["material", '"rock"'],
                      ["sphere", [["center", "[0.3, 0.3, 0.5]"], ["radius", "0.05"]]]]],
        ["[[body]]", [["name", '"slab"'], ["material", '"rock"'],
                      ["polygon", "[[0.1, 0.45], [0.5, 0.45], [0.5, 0.55], [0.1, 0.55]]"],
                      ["extrude", [["axis", '"y"'], ["from", "0.05"], ["to", "0.15"]]]]],
        ["[[body]]", [["name", '"ground"'], ["material", '"rock"'], ["rigid", "true"],
                      ["terrain", [["top", '"ground.asc"'], ["bottom", [["depth", "0.1"]]],
                                   ["footprint", '"footprint.csv"']]]]],
        ["[terrain]", [["origin", "[0.0, 0.0, 0.0]"]]],
        ["[[contact]]", [["friction", "0.2"]]],
        ["[output]", [["every", "0.01"]]],
    ]


def value_text(v):
    if isinstance(v, list):
        return "{ " + ", ".join(f"{k} = {value_text(x)}" for k, x in v) + " }"
    return v


def render(doc):
    lines = []
    for header, entries in doc:
        if header:
            lines += ["", header]
        lines += [f"{k} = {value_text(v)}" for k, v in entries]
    return "\n".join(lines).lstrip("\n") + "\n"


def nodes(doc):
    """(path, entries, index) of every key, inline tables and their keys included; paths as talus
    names them: simulation.end_time, material[0].density, body[0].box.min."""
    counts = {}
    for header, entries in doc:
        name = header.strip("[]").strip()
        if header.startswith("[["):
            counts[name] = counts.get(name, -1) + 1
            prefix = f"{name}[{counts[name]}]"
        else:
            prefix = name
        yield from _walk(entries, prefix)


def _walk(entries, prefix):
    for i, (k, v) in enumerate(entries):
        path = f"{prefix}.{k}" if prefix else k
        yield path, entries, i
        if isinstance(v, list):
            yield from _walk(v, path)


def generic(path):
    """material[0].density -> material.density"""
    return re.sub(r"\[\d+\]", "", path)


def find(doc, path):
    for p, entries, i in nodes(doc):
        if p == path:
            return entries, i
    raise KeyError(path)


def with_value(doc, path, value):
    d = copy.deepcopy(doc)
    entries, i = find(d, path)
    entries[i][1] = value
    return d


def without(doc, path):
    d = copy.deepcopy(doc)
    entries, i = find(d, path)
    del entries[i]
    return d


def with_key(doc, section, key, value):
    """Adds key = value to the first section whose header is `section` ("" for the top level),
    to the n-th array entry given as (header, n) (see section_path), or to an inline table given
    by its path (body[0].box)."""
    d = copy.deepcopy(doc)
    if isinstance(section, tuple):
        d[section_index(d, *section)][1].append([key, value])
        return d
    for header, entries in d:
        if header == section:
            entries.append([key, value])
            return d
    entries, i = find(d, section)
    entries[i][1].append([key, value])
    return d


def section_path(doc, header, n):
    """The n-th [[header]] entry, for with_key()."""
    section_index(doc, header, n)
    return (header, n)


def section_index(doc, header, n=0):
    k = -1
    for i, (h, _) in enumerate(doc):
        if h == header:
            k += 1
            if k == n:
                return i
    raise KeyError(header)


NUMBER = re.compile(r"[+-]?\d[\d_]*(\.\d+)?([eE][+-]?\d+)?")


def is_number(v):
    return isinstance(v, str) and NUMBER.fullmatch(v) is not None


def is_number_array(v):
    return isinstance(v, str) and v.startswith("[") and not v.startswith("[[") and '"' not in v


def is_string(v):
    return isinstance(v, str) and v.startswith('"')


def case_files(dim, text, **extra):
    """The files of a case: the case file and what it reads."""
    files = {CASE2D: text, "floor.csv": FLOOR_CSV} if dim == 2 else {
        CASE3D: text, "ground.asc": GROUND_ASC, "footprint.csv": FOOTPRINT_CSV}
    files.update(extra)
    return files


def run_case(dim, command="run"):
    name = CASE2D if dim == 2 else CASE3D
    if command == "check":
        return ["check", name]
    return ["run", name, "--out", "{d}/run", *STOP]


def case_input(name, cls, dim, doc_or_text, expect=(), ok=False, command="run", extra=None,
               post=None, **kw):
    """An input that runs a whole case file; its errors must name the case file and `expect`."""
    text = doc_or_text if isinstance(doc_or_text, (str, bytes)) or callable(doc_or_text) \
        else render(doc_or_text)
    files = case_files(dim, text, **(extra or {}))
    return Input(name, cls, run_case(dim, command), files,
                 [CASE2D if dim == 2 else CASE3D, *expect], ok, post=post, **kw)


def sets(*values):
    out = []
    for v in values:
        out += ["--set", v]
    return out


def circle(n, cx, cy, r):
    return [(cx + r * math.cos(2 * math.pi * k / n), cy + r * math.sin(2 * math.pi * k / n))
            for k in range(n)]


def no_secret(ctx, res):
    """The error must not quote a secret-looking line of the file it read."""
    if SECRET in res.out + res.err or SECRET[:20] in res.out + res.err:
        return "vague", "the message quotes the file's secret line to the terminal"
    return None


# ------------------------------------------------------------------------------------------------
# Class case-numbers: every numeric key of both cases set to 0, -1, nan, inf, 1e300, 1e-300 and
# wrong types.

NUMBER_MUTATIONS = [("zero", "0"), ("negative", "-1"), ("nan", "nan"), ("inf", "inf"),
                    ("huge", "1e300"), ("tiny", "1e-300"), ("string", '"12"'),
                    ("array", "[1, 2]"), ("table", "{ a = 1 }")]

# Values a key may take (True: must run; None: running or a clear refusal are both fine); every
# other mutation must be refused.
NUMBER_OK = {
    "simulation.end_time": {"tiny": None},
    "simulation.flip": {"zero": True, "tiny": True},
    "simulation.damping": {"zero": True, "tiny": True},
    "material.poisson_ratio": {"zero": True, "tiny": True},
    "material.friction_angle": {"zero": True, "tiny": True},
    "material.dilation_angle": {"zero": True, "tiny": True},
    "material.cohesion": {"zero": True, "tiny": True, "huge": None},
    "contact.friction": {"zero": True, "tiny": True, "huge": None},
    "interface.friction.initial": {"huge": None},
    "interface.friction.residual": {"zero": True, "tiny": True},
    "interface.friction.slip": {"zero": None, "tiny": None, "huge": None},
    "interface.cohesion.initial": {"zero": True, "tiny": True, "huge": None},
    "interface.cohesion.residual": {"zero": True, "tiny": True},
    "interface.cohesion.slip": {"zero": None, "tiny": None, "huge": None},
    "initial_state.k0": {"zero": True, "tiny": True},
    "results.stop_speed": {"zero": None, "tiny": None, "huge": None},
    "output.every": {"zero": True, "huge": None, "inf": None},
    "checkpoint.wall_minutes": {"zero": True, "tiny": None, "huge": None},
    "body.extrude.from": {"zero": True, "tiny": True},
}
# Keys whose extreme values are refused by the step-count limit (a message that names the time
# step rather than the key).
TIMESTEP_KEYS = {"simulation.end_time", "simulation.cfl", "material.density",
                 "material.youngs_modulus", "material.poisson_ratio"}
NUMBERS_3D = ["simulation.dimension", "body[1].sphere.radius", "body[2].extrude.from",
              "body[2].extrude.to", "body[3].terrain.bottom.depth"]


def gen_case_numbers():
    for dim, doc, only in ((2, base2d(), None), (3, base3d(), NUMBERS_3D)):
        for path, entries, i in list(nodes(doc)):
            value = entries[i][1]
            if not is_number(value) or (only is not None and path not in only):
                continue
            g = generic(path)
            for label, new in NUMBER_MUTATIONS:
                ok = NUMBER_OK.get(g, {}).get(label, False)
                alts = (path,) + (("1e+09",) if g in TIMESTEP_KEYS else ())
                yield case_input(f"{dim}d:{path}={label}", "case-numbers", dim,
                                 with_value(doc, path, new), [alts], ok,
                                 note=f"{path} = {new}")


# ------------------------------------------------------------------------------------------------
# Class case-arrays: every vector key with a bad component, the wrong length or the wrong type.

def array_mutations(n):
    zeros = ["0.0"] * n
    return [("nan0", "[" + ", ".join(["nan"] + zeros[1:]) + "]"),
            ("inf0", "[" + ", ".join(["inf"] + zeros[1:]) + "]"),
            ("huge0", "[" + ", ".join(["1e300"] + zeros[1:]) + "]"),
            ("short", "[" + ", ".join(zeros[:-1]) + "]"),
            ("long", "[" + ", ".join(zeros + ["0.0"]) + "]"),
            ("empty", "[]"), ("string", '"0, 0"'), ("table", "{ x = 0 }"),
            ("nested", "[" + ", ".join(f"[{z}]" for z in zeros) + "]"),
            ("mixed", '[0.0, "a"' + ", 0.0" * (n - 2) + "]"),
            ("bool", "[" + ", ".join(["true"] * n) + "]")]


ARRAY_OK = {"simulation.gravity": {"huge0": None}, "probe.near": {"huge0": None}}
ARRAY_ALTS = {"grid.origin": ("outside the grid",), "body.box.min": ("outside the grid",),
              "body.box.max": ("outside the grid",), "body.velocity": ("not finite", "1e+09"),
              "simulation.gravity": ("not finite", "1e+09"), "terrain.origin": ("raster",),
              "body.sphere.center": ("outside the grid",)}
ARRAYS_2D = ["simulation.gravity", "grid.origin", "grid.extent", "body[0].box.min",
             "body[0].box.max", "body[0].velocity", "probe[0].near"]
ARRAYS_3D = ["simulation.gravity", "grid.origin", "grid.extent", "body[0].box.min",
             "body[1].sphere.center", "terrain.origin"]


def gen_case_arrays():
    for dim, doc, paths in ((2, base2d(), ARRAYS_2D), (3, base3d(), ARRAYS_3D)):
        for path in paths:
            g = generic(path)
            for label, new in array_mutations(dim):
                ok = ARRAY_OK.get(g, {}).get(label, False)
                yield case_input(f"{dim}d:{path}={label}", "case-arrays", dim,
                                 with_value(doc, path, new), [(path,) + ARRAY_ALTS.get(g, ())],
                                 ok, note=f"{path} = {new}")


# ------------------------------------------------------------------------------------------------
# Class case-strings: names, titles, enumerations, references and file names: numbers, empty,
# unknown, terminal escapes, NUL, line breaks, 100,000 characters, non-ASCII, wrong case, arrays.

def string_mutations(current):
    return [("number", "1"), ("empty", '""'), ("unknown", '"nosuch"'),
            ("escape", '"\\u001b[31mRED\\u001b[0m\\u001b]0;pwned\\u0007"'),
            ("nul", '"a\\u0000b"'), ("newline", '"a\\nb"'), ("long", '"' + "x" * 100_000 + '"'),
            ("unicode", '"ħøstïlé 名前"'), ("array", '["a"]'), ("upper", current.upper())]


STRING_OK = {
    "title": {"empty": True, "unknown": True, "long": None, "unicode": True, "upper": True},
    "probe.name": {"unknown": True, "long": None, "unicode": True, "upper": True, "empty": None},
}
STRING_ALTS = {"material.name": ("no material named",), "body.name": ("no body named",),
               "body.polygon": ("no such file", "floor.csv"),
               "body.terrain.top": ("no such file",),
               "body.terrain.footprint": ("no such file",)}
STRINGS_2D = ["title", "simulation.scheme", "grid.shape_function", "grid.boundary.x_min",
              "material[0].name", "material[0].model", "body[0].name", "body[0].material",
              "body[1].polygon", "initial_state.method", "probe[0].name", "probe[0].body",
              "results.body"]
STRINGS_3D = ["body[2].extrude.axis", "body[3].terrain.top", "body[3].terrain.footprint"]
PAIRS = [("one", '["block"]', False), ("three", '["block", "floor", "block"]', False),
         ("same", '["block", "block"]', False), ("unknown", '["block", "nosuch"]', False),
         ("empty", "[]", False), ("string", '"block"', False), ("numbers", "[1, 2]", False),
         ("reversed", '["floor", "block"]', True),
         ("escape", '["\\u001b[2J", "floor"]', False)]


def gen_case_strings():
    for dim, doc, paths in ((2, base2d(), STRINGS_2D), (3, base3d(), STRINGS_3D)):
        for path in paths:
            entries, i = find(doc, path)
            g = generic(path)
            for label, new in string_mutations(entries[i][1]):
                ok = STRING_OK.get(g, {}).get(label, False)
                alts = (path, "control character") + STRING_ALTS.get(g, ())
                yield case_input(f"{dim}d:{path}={label}", "case-strings", dim,
                                 with_value(doc, path, new), [alts], ok,
                                 note=f"{path} = {new[:60]}")
    doc = base2d()
    for label, new, ok in PAIRS:
        yield case_input(f"2d:interface[0].bodies={label}", "case-strings", 2,
                         with_value(doc, "interface[0].bodies", new),
                         [("interface[0].bodies", "interface[0]")], ok,
                         note=f"interface[0].bodies = {new}")


# ------------------------------------------------------------------------------------------------
# Class case-structure: missing, unknown, misspelt and duplicated keys and tables, the wrong
# shapes, TOML oddities, conflicting geometry, huge and deeply nested values, [[run]] entries.

def renamed(doc, header, new, n=0):
    d = copy.deepcopy(doc)
    d[section_index(d, header, n)][0] = new
    return d


def dropped(doc, header):
    return [s for s in copy.deepcopy(doc) if s[0] != header]


def appended(doc, text):
    return render(doc) + text


def many_bodies_doc(n):
    doc = [["", [["title", '"many bodies"']]],
           ["[simulation]", [["end_time", "0.05"], ["gravity", "[0.0, -9.81]"]]],
           ["[grid]", [["extent", f"[{0.2 * n + 0.2:.1f}, 0.6]"], ["cell_size", "0.1"]]],
           ["[[material]]", [["name", '"m"'], ["density", "2000.0"], ["youngs_modulus", "1e6"],
                             ["poisson_ratio", "0.3"]]]]
    for k in range(n):
        x = 0.1 + 0.2 * k
        doc.append(["[[body]]", [["name", f'"b{k}"'], ["material", '"m"'],
                                 ["box", [["min", f"[{x:.1f}, 0.1]"],
                                          ["max", f"[{x + 0.1:.1f}, 0.2]"]]],
                                 ["particles_per_cell", "1"]]])
    return doc


def gen_case_structure():
    d2, d3 = base2d(), base3d()
    c = "case-structure"
    missing = [("simulation.end_time", d2), ("grid.extent", d2), ("grid.cell_size", d2),
               ("material[0].name", d2), ("material[0].density", d2),
               ("material[0].youngs_modulus", d2), ("material[0].poisson_ratio", d2),
               ("material[0].friction_angle", d2), ("body[0].name", d2),
               ("body[0].material", d2), ("body[0].box", d2), ("body[0].box.max", d2),
               ("interface[0].bodies", d2), ("interface[0].friction", d2),
               ("interface[0].cohesion", d2), ("interface[0].friction.slip", d2),
               ("probe[0].body", d2), ("probe[0].near", d2), ("probe[0].name", d2),
               ("body[3].terrain.top", d3), ("body[2].extrude.to", d3),
               ("body[1].sphere.radius", d3)]
    for path, doc in missing:
        dim = 2 if doc is d2 else 3
        ok = None if path == "probe[0].name" else False
        prefix = path.rsplit(".", 1)[0] if path.endswith(("box", ".name")) else path
        yield case_input(f"{dim}d:missing:{path}", c, dim, without(doc, path),
                         [(path, prefix)], ok, note=f"without {path}")
    for header in ("[simulation]", "[grid]", "[[material]]", "[[body]]", "[[interface]]",
                   "[[probe]]"):
        name = header.strip("[]")
        ok = None if name in ("interface", "probe") else False
        doc = dropped(d2, header)
        if name == "probe":
            doc = dropped(doc, "[results]")
        if name == "body":
            doc = [s for s in doc if s[0] not in ("[[interface]]", "[[probe]]", "[results]")]
        yield case_input(f"2d:missing-section:{name}", c, 2, doc, [(name,)], ok,
                         note=f"no {header} at all")
    unknown = [("", "foo", "1", "foo"), ("[simulation]", "gravty", "[0.0, -9.81]", "gravty"),
               ("[grid]", "cellsize", "0.1", "cellsize"), ("[[material]]", "densty", "1.0",
                                                             "densty"),
               ("[[body]]", "partciles_per_cell", "2", "partciles_per_cell"),
               ("[output]", "evry", "0.1", "evry"), ("[checkpoint]", "kep", "2", "kep"),
               ("[[contact]]", "frction", "0.1", "frction"),
               ("interface[0].friction", "inital", "0.5", "inital"),
               ("body[0].box", "mid", "[0.3, 0.3]", "mid"),
               ("[grid.boundary]", "z_min", '"fixed"', "z_min"),
               ("[simulation]", "Dimension", "2", "Dimension"),
               ("[initial_state]", "settle_tim", "0.1", "settle_tim")]
    for section, key, value, word in unknown:
        yield case_input(f"2d:unknown-key:{section.strip('[]') or 'top'}.{key}", c, 2,
                         with_key(d2, section, key, value), [(word,)],
                         note=f"{key} = {value} in {section or 'the top level'}")
    yield case_input("2d:key-of-another-model", c, 2,
                     with_key(d2, section_path(d2, "[[material]]", 1), "friction_angle", "30.0"),
                     [("material[1].friction_angle",)],
                     note="friction_angle on a linear_elastic material")
    yield case_input("2d:unknown-table", c, 2, appended(d2, "\n[foo]\nbar = 1\n"), [("foo",)])
    yield case_input("2d:unknown-array-table", c, 2, appended(d2, "\n[[foo]]\nbar = 1\n"),
                     [("foo",)])
    misspelt = [("[simulation]", "[simulaton]"), ("[grid]", "[grids]"),
                ("[[material]]", "[[materials]]"), ("[[body]]", "[[bodies]]"),
                ("[[contact]]", "[[contacts]]"), ("[[interface]]", "[[interfaces]]"),
                ("[initial_state]", "[initialstate]"), ("[[probe]]", "[[probes]]"),
                ("[checkpoint]", "[checkpoints]"), ("[output]", "[Output]"),
                ("[grid.boundary]", "[grid.boundry]"), ("[results]", "[result]")]
    for header, wrong in misspelt:
        yield case_input(f"2d:misspelt-section:{wrong.strip('[]')}", c, 2,
                         renamed(d2, header, wrong), [(wrong.strip("[]"),)],
                         note=f"{header} written {wrong}")
    yield case_input("2d:section-with-spaces", c, 2, renamed(d2, "[simulation]", "[ simulation ]"),
                     ok=True, note="[ simulation ] (valid TOML)")
    dup = [("simulation", "\n[simulation]\nend_time = 0.1\n"),
           ("grid.boundary", "\n[grid.boundary]\nx_max = \"slip\"\n"),
           ("output", "\n[output]\nevery = 0.02\n")]
    for name, text in dup:
        yield case_input(f"2d:duplicate-table:{name}", c, 2, appended(d2, text),
                         [(name, "redefine")])
    yield case_input("2d:duplicate-key", c, 2,
                     with_key(d2, "[simulation]", "end_time", "0.1"), [("end_time",)])
    yield case_input("2d:duplicate-title", c, 2, with_key(d2, "", "title", '"again"'),
                     [("title",)])
    yield case_input("2d:duplicate-material-name", c, 2,
                     with_value(d2, "material[1].name", '"soil"'), [("material[1].name",)])
    yield case_input("2d:duplicate-body-name", c, 2, with_value(d2, "body[1].name", '"block"'),
                     [("body[1].name",)])
    yield case_input("2d:two-default-contacts", c, 2,
                     appended(d2, "\n[[contact]]\nfriction = 0.1\n"), [("contact[1]",)])
    yield case_input("2d:duplicate-interface", c, 2, appended(
        d2, '\n[[interface]]\nbodies = ["floor", "block"]\n'
            'friction = { initial = 0.5, residual = 0.3, slip = 0.01 }\n'
            'cohesion = { initial = 0.0, residual = 0.0, slip = 0.01 }\n'),
        [("interface[1]",)])
    yield case_input("2d:duplicate-probe-name", c, 2, appended(
        d2, '\n[[probe]]\nname = "top"\nbody = "floor"\nnear = [0.5, 0.1]\n'),
        [("probe[1]",)], None)
    shapes = [("simulation-scalar", "simulation = 1\n" + render(dropped(d2, "[simulation]")),
               ("simulation",)),
              ("material-scalar", "material = 1\n" + render(dropped(d2, "[[material]]")),
               ("material",)),
              ("body-table", "body = {}\n" + render(
                  [s for s in d2 if s[0] not in ("[[body]]",)]), ("body",)),
              ("simulation-array", render(renamed(d2, "[simulation]", "[[simulation]]")),
               ("simulation",)),
              ("body-not-array", render(renamed(d2, "[[body]]", "[body]")), ("body",))]
    for label, text, alts in shapes:
        yield case_input(f"2d:shape:{label}", c, 2, text, [alts])
    oddities = [("end_time-datetime", "simulation.end_time", "1979-05-27T07:32:00Z", False),
                ("end_time-bool", "simulation.end_time", "true", False),
                ("dimension-binary-2", "simulation.dimension", "0b10", True),
                ("dimension-octal-3", "simulation.dimension", "0o3", False),
                ("modulus-underscores", "material[0].youngs_modulus", "1_000_000", True),
                ("cell-hex", "grid.cell_size", "0x1", False),
                ("ppc-int64-max", "body[0].particles_per_cell", "9223372036854775807", False),
                ("ppc-overflow", "body[0].particles_per_cell", "99999999999999999999", False),
                ("end_time-plus-inf", "simulation.end_time", "+inf", False),
                ("end_time-minus-nan", "simulation.end_time", "-nan", False),
                ("end_time-1e400", "simulation.end_time", "1e400", False),
                ("end_time-denormal", "simulation.end_time", "4.9e-324", None),
                ("cfl-negative-zero", "simulation.cfl", "-0.0", False),
                ("ppc-float", "body[0].particles_per_cell", "2.0", False),
                ("flip-int-1", "simulation.flip", "1", True)]
    for label, path, value, ok in oddities:
        yield case_input(f"2d:toml:{label}", c, 2, with_value(d2, path, value),
                         [(path, "line")], ok, note=f"{path} = {value}")
    # Geometry that does not fit the dimension or the grid.
    geo = [("box-and-polygon", 2, with_key(d2, section_path(d2, "[[body]]", 1), "box",
                                           "{ min = [0.0, 0.0], max = [0.1, 0.1] }"),
            ("body[1]",), False),
           ("sphere-in-2d", 2, with_key(without(d2, "body[0].box"), section_path(d2, "[[body]]", 0),
                                        "sphere", "{ center = [0.3, 0.3], radius = 0.1 }"),
            ("body[0]",), False),
           ("terrain-in-2d", 2, with_key(without(d2, "body[0].box"),
                                         section_path(d2, "[[body]]", 0), "terrain",
                                         '{ top = 0.4, bottom = 0.2 }'), ("body[0]",), False),
           ("extrude-in-2d", 2, with_key(d2, section_path(d2, "[[body]]", 1), "extrude",
                                         '{ axis = "y", from = 0.0, to = 0.1 }'),
            ("body[1]",), False),
           ("disk-in-3d", 3, with_key(without(d3, "body[0].box"), section_path(d3, "[[body]]", 0),
                                      "disk", "{ center = [0.3, 0.3], radius = 0.1 }"),
            ("body[0]",), False),
           ("dimension-3-on-2d", 2, with_value(d2, "simulation.dimension", "3"),
            ("simulation", "grid", "gravity"), False),
           ("dimension-2-on-3d", 3, with_value(d3, "simulation.dimension", "2"),
            ("simulation", "grid", "gravity"), False),
           ("overlapping-bodies", 2, with_value(d2, "body[0].box.min", "[0.2, 0.1]"),
            ("overlap",), False),
           ("body-outside-grid", 2, with_value(d2, "body[0].box.max", "[0.5, 0.9]"),
            ("body[0]",), False),
           ("body-no-particle", 2, with_value(d2, "body[0].box.max", "[0.2001, 0.2001]"),
            ("body[0]", "block"), False),
           ("interface-not-touching", 2, with_value(with_value(
               d2, "body[0].box.min", "[0.2, 0.35]"), "body[0].box.max", "[0.5, 0.5]"),
            ("interface",), None),
           ("water-2d", 2, appended(d2, "\n[water]\nlevel = 0.3\n"), ("water",), True),
           ("water-denser-than-soil", 2, appended(d2, "\n[water]\nlevel = 0.3\ndensity = 1e5\n"),
            ("water.density",), False),
           ("water-nan", 2, appended(d2, "\n[water]\nlevel = nan\n"), ("water.level",), False)]
    for label, dim, doc, alts, ok in geo:
        yield case_input(f"{dim}d:geometry:{label}", c, dim, doc, [alts], ok)
    # Huge and deeply nested values.
    big_polygon = lambda n, r: "[" + ", ".join(f"[{x:.9f}, {y:.9f}]" for x, y in
                                              circle(n, 0.75, 0.45, r)) + "]"
    huge = [("gravity-100k", lambda: render(with_value(
        d2, "simulation.gravity", "[" + ", ".join(["0.0"] * 100_000) + "]")),
        ("simulation.gravity",), False),
        ("fields-100k", lambda: render(with_key(d2, "[output]", "fields", "[" + ", ".join(
            ['"velocity"'] * 100_000) + "]")), ("output.fields",), None),
        ("fields-unknown", lambda: render(with_key(d2, "[output]", "fields", '["nosuch"]')),
         ("output.fields",), False),
        ("polygon-100k-inline", lambda: render(with_value(
            d2, "body[1].polygon", big_polygon(100_000, 0.1))), ("body[1].polygon",), False),
        ("polygon-20000-inline", lambda: render(with_value(
            with_value(d2, "body[1].polygon", big_polygon(20_000, 0.1)), "body[1].rigid",
            "true")), ("body[1].polygon", "overlap"), None),
        ("bodies-2000", lambda: render(many_bodies_doc(2000)), ("body",), None),
        ("materials-10000", lambda: render(d2) + "".join(
            f'\n[[material]]\nname = "m{k}"\ndensity = 2000.0\nyoungs_modulus = 1e6\n'
            f'poisson_ratio = 0.3\n' for k in range(10_000)), ("material",), None),
        ("probes-20000", lambda: render(d2) + "".join(
            f'\n[[probe]]\nname = "p{k}"\nbody = "block"\nnear = [0.3, 0.3]\n'
            for k in range(20_000)), ("probe",), None),
        ("checks-10000", lambda: render(d2) + "".join(
            f'\n[[check]]\nname = "c{k}"\nquantity = "energy.kinetic_energy"\ntime = 0.05\n'
            f'min = 0\nmax = 1\n' for k in range(10_000)), ("check",), None),
        ("nested-arrays-100k", lambda: render(with_value(
            d2, "simulation.gravity", "[" * 100_000 + "]" * 100_000)), ("gravity", "line"),
         False),
        ("nested-inline-tables-100k", lambda: render(with_value(
            d2, "body[0].box.min", "{ a = " * 100_000 + "1" + " }" * 100_000)),
         ("box", "line"), False),
        ("dotted-key-100k", lambda: render(d2) + "\n[foo]\n" + ".".join(["a"] * 100_000)
         + " = 1\n", ("foo", "line"), False),
        ("key-1MB", lambda: render(with_key(d2, "[simulation]", "k" * 1_000_000, "1")),
         ("simulation",), False),
        ("title-1MB", lambda: render(with_value(d2, "title", '"' + "t" * 1_000_000 + '"')),
         ("title",), None),
        ("comment-8MB", lambda: ("#" + "c" * 999 + "\n") * 8000 + render(d2), (), True),
        ("integer-1M-digits", lambda: render(with_value(d2, "simulation.end_time",
                                                         "1" * 1_000_000)),
         ("end_time", "line"), False),
        ("float-1M-digits", lambda: render(with_value(d2, "simulation.end_time",
                                                       "0." + "0" * 1_000_000 + "5")),
         ("end_time", "line"), None)]
    for label, text, alts, ok in huge:
        yield case_input(f"2d:huge:{label}", c, 2, text, [alts] if alts else [], ok)
    # [[run]] entries and verification tables written into a user's case.
    runs = [("run-set-bad-value", '\n[[run]]\nset = ["grid.cell_size=abc"]\n', ("[[run]]",), False),
            ("run-set-not-array", '\n[[run]]\nset = "grid.cell_size=0.2"\n', ("run",), False),
            ("run-set-number", "\n[[run]]\nset = [1]\n", ("run",), False),
            ("run-unknown-key", "\n[[run]]\nfoo = 1\n", ("foo", "run"), False),
            ("run-files-etc-passwd", '\n[[run]]\nfiles = { "floor.csv" = "/etc/passwd" }\n',
             ("floor.csv", "passwd", "polygon"), False),
            ("run-files-number", "\n[[run]]\nfiles = 1\n", ("files", "run"), False),
            ("check-garbage", '\n[[check]]\nname = 1\nbogus = "x"\n', ("check",), None),
            ("verify-garbage", "\n[verify]\nquick = 1\n", ("verify",), None)]
    for label, text, alts, ok in runs:
        yield case_input(f"2d:extra:{label}", c, 2, appended(d2, text), [alts], ok)


# ------------------------------------------------------------------------------------------------
# Class case-bytes: encodings and raw bytes: non-UTF-8, overlong sequences, Latin-1, UTF-16,
# BOM, NUL, raw escapes, CR line ends, binary noise, empty and unterminated files.

def gen_case_bytes():
    t = render(base2d()).encode()
    title = b'title = "hostile 2D"'
    c = "case-bytes"
    rnd = random.Random(7)
    variants = [
        ("ff-in-comment", b"# \xff\xfe comment\n" + t, False),
        ("ff-in-title", t.replace(title, b'title = "bad \xff byte"'), False),
        ("ff-in-key", t.replace(b"end_time", b"end_\xfftime"), False),
        ("ff-in-body-name", t.replace(b'name = "block"', b'name = "bl\xffock"'), False),
        ("overlong-utf8", t.replace(title, b'title = "\xc0\xaf"'), False),
        ("utf8-surrogate", t.replace(title, b'title = "\xed\xa0\x80"'), False),
        ("latin1-file", t.replace(title, 'title = "éboulement"'.encode("latin-1")), False),
        ("utf16-file", render(base2d()).encode("utf-16"), False),
        ("utf8-bom", b"\xef\xbb\xbf" + t, None),
        ("nul-in-comment", b"# a\x00b\n" + t, False),
        ("nul-in-string", t.replace(title, b'title = "a\x00b"'), False),
        ("nul-first-byte", b"\x00" + t, False),
        ("all-nul", b"\x00" * 4096, False),
        ("raw-escape-in-comment", b"# \x1b[2J\x1b[31m\n" + t, False),
        ("raw-escape-in-title", t.replace(title, b'title = "\x1b[2J\x1b]0;pwned\x07"'), False),
        ("raw-del-in-title", t.replace(title, b'title = "a\x7fb"'), False),
        ("raw-tab-in-title", t.replace(title, b'title = "a\tb"'), True),
        ("crlf", t.replace(b"\n", b"\r\n"), True),
        ("cr-only", t.replace(b"\n", b"\r"), False),
        ("no-final-newline", t.rstrip(b"\n"), True),
        ("binary-noise", bytes(rnd.randrange(256) for _ in range(4096)), False),
        ("empty", b"", False),
        ("whitespace-only", b"   \n\t\n\n", False),
        ("single-bracket", b"[", False),
        ("unterminated-string", t.replace(title, b'title = "hostile'), False),
        ("unterminated-multiline", t.replace(title, b'title = """hostile'), False),
        ("unterminated-array", t.replace(b"[0.0, -9.81]", b"[0.0, -9.81"), False),
        ("elf-binary", Path("/bin/true").read_bytes()[:65536] if Path("/bin/true").exists()
         else b"\x7fELF" + bytes(4000), False),
    ]
    for label, data, ok in variants:
        yield case_input(f"2d:bytes:{label}", c, 2, data, [], ok, note=f"{len(data)} bytes")


# ------------------------------------------------------------------------------------------------
# Class polygon-csv: the 2D floor's polygon file, broken every way a CSV can be.

def csv_rows(points, header="x,y"):
    return (header + "\n" if header else "") + "".join(f"{x!r},{y!r}\n" for x, y in points)


def gen_polygon_csv():
    c = "polygon-csv"
    rnd = random.Random(11)
    alts = ("body[1].polygon", "floor.csv")
    ring = [(0.0, 0.0), (1.0, 0.0), (1.0, 0.2), (0.0, 0.2)]
    variants = [
        ("empty", "", False), ("header-only", "x,y\n", False),
        ("whitespace", "   \n\n\t\n", False),
        ("binary", bytes(rnd.randrange(256) for _ in range(4096)), False),
        ("one-column", "x\n0.0\n1.0\n1.0\n0.0\n", False),
        ("three-columns", "0,0,0\n1,0,0\n1,0.2,0\n0,0.2,0\n", False),
        ("nan-row", "x,y\n0,0\nnan,0\n1,0.2\n0,0.2\n", False),
        ("inf-row", "x,y\n0,0\n1,0\ninf,0.2\n0,0.2\n", False),
        ("overflow-row", "x,y\n0,0\n1e999,0\n1,0.2\n0,0.2\n", False),
        ("self-crossing", "x,y\n0,0\n1,0.2\n1,0\n0,0.2\n", False),
        ("two-vertices", "x,y\n0,0\n1,0.2\n", False),
        ("collinear", "x,y\n0,0\n0.5,0.1\n1,0.2\n", False),
        ("duplicates-only", "0,0\n0,0\n0,0\n0,0\n", False),
        ("semicolons", "x;y\n0;0\n1;0\n1;0.2\n0;0.2\n", False),
        ("tabs", "x\ty\n0\t0\n1\t0\n1\t0.2\n0\t0.2\n", None),
        ("bom-header", "\ufeffx,y\n0,0\n1,0\n1,0.2\n0,0.2\n", None),
        ("crlf", FLOOR_CSV.replace("\n", "\r\n"), True),
        ("trailing-comma", "x,y\n0,0,\n1,0,\n1,0.2,\n0,0.2,\n", None),
        ("quoted-numbers", 'x,y\n"0","0"\n"1","0"\n"1","0.2"\n"0","0.2"\n', None),
        ("line-1MB", "x,y\n" + "1" * 1_000_000 + ",0\n1,0\n1,0.2\n0,0.2\n", False),
        ("secret-line", f"{SECRET}\n0,0\n1,0\n1,0.2\n0,0.2\n", False),
        ("escape-row", "x,y\n\x1b[2J\x1b[31m,0\n1,0\n1,0.2\n0,0.2\n", False),
        ("nul-bytes", b"x,y\n0,0\n1\x00,0\n1,0.2\n0,0.2\n", False),
        ("two-header-lines", "x,y\nmetres,metres\n0,0\n1,0\n1,0.2\n0,0.2\n", False),
        ("outside-grid", csv_rows([(0.0, 0.0), (2.0, 0.0), (2.0, 0.2), (0.0, 0.2)]), False),
        ("overlaps-block", csv_rows([(0.0, 0.0), (1.0, 0.0), (1.0, 0.3), (0.0, 0.3)]), False),
        ("huge-coordinates", csv_rows([(0.0, 0.0), (1e300, 0.0), (1e300, 0.2), (0.0, 0.2)]),
         False),
        ("no-particle", csv_rows([(0.5, 0.1), (0.5001, 0.1), (0.5001, 0.1001)]), False),
        ("clockwise", csv_rows(list(reversed(ring))), True),
        ("closed-ring", csv_rows(ring + [ring[0]]), True),
        ("hex-floats", "x,y\n0x0p+0,0\n0x1p+0,0\n0x1p+0,0x1.999999999999ap-3\n0,0x1.999999999999ap-3\n",
         None),
        ("negative-zero", "x,y\n-0.0,-0.0\n1,0\n1,0.2\n0,0.2\n", True),
        ("spaces", "x , y\n 0.0 , 0.0 \n 1.0 , 0.0\n1.0 ,0.2\n0.0, 0.2 \n", None),
        ("comment-lines", "# floor\nx,y\n0,0\n1,0\n# mid\n1,0.2\n0,0.2\n", None),
        ("exponents", "x,y\n0e0,0e0\n1e0,0e0\n1e0,2e-1\n0e0,2e-1\n", True),
        ("circle-100k", lambda: csv_rows(circle(100_000, 0.75, 0.1, 0.09)), False),
        ("circle-20001", lambda: csv_rows(circle(20_001, 0.75, 0.1, 0.09)), False),
        ("circle-20000", lambda: csv_rows(circle(20_000, 0.75, 0.1, 0.09)), None),
        ("utf16", FLOOR_CSV.encode("utf-16"), False),
        ("10MB-of-rows", lambda: "x,y\n" + "0.5,0.1\n0.6,0.1\n" * 625_000, False),
    ]
    for label, data, ok in variants:
        post = no_secret if label == "secret-line" else None
        yield case_input(f"2d:floor.csv:{label}", c, 2, render(base2d()), [alts], ok,
                         extra={"floor.csv": data}, post=post)


# ------------------------------------------------------------------------------------------------
# Class raster: the 3D ground's ESRI ASCII grid (and its footprint), broken every way.

def gen_raster():
    c = "raster"
    rnd = random.Random(13)
    alts = ("ground.asc", "body[3].terrain")
    head = ["ncols 6", "nrows 6", "xllcorner 0.0", "yllcorner 0.0", "cellsize 0.1",
            "NODATA_value -9999"]
    row = " ".join(["0.15"] * 6)

    def hdr(i, line):
        h = list(head)
        if line is None:
            del h[i]
        else:
            h[i] = line
        return asc(header=h)

    variants = [
        ("header-nrowz", hdr(1, "nrowz 6"), False),
        ("header-ncol", hdr(0, "ncol 6"), False),
        ("header-no-cellsize", hdr(4, None), False),
        ("header-unknown-key", asc(header=head + ["foo 1"]), False),
        ("header-ncols-twice", asc(header=["ncols 6"] + head), False),
        ("ncols-above-values", asc(header=["ncols 7"] + head[1:]), False),
        ("nrows-below-values", asc(header=[head[0], "nrows 5"] + head[2:]), False),
        ("values-missing", asc(rows=[row] * 5 + [" ".join(["0.15"] * 3)]), False),
        ("values-extra", asc(rows=[row] * 7), False),
        ("negative-cellsize", asc(cell="-0.1"), False),
        ("zero-cellsize", asc(cell="0"), False),
        ("nan-cellsize", asc(cell="nan"), False),
        ("huge-cellsize", asc(cell="1e300"), False),
        ("tiny-cellsize", asc(cell="1e-300"), False),
        ("all-nodata", asc(value="-9999"), False),
        ("half-nodata", asc(rows=[row] * 3 + [" ".join(["-9999"] * 6)] * 3), None),
        ("nan-values", asc(value="nan"), False),
        ("value-1e30", asc(rows=[row] * 5 + ["0.15 0.15 1e30 0.15 0.15 0.15"]), False),
        ("value-minus-1e30", asc(rows=[row] * 5 + ["0.15 0.15 -1e30 0.15 0.15 0.15"]), False),
        ("value-word", asc(rows=[row] * 5 + ["0.15 0.15 abc 0.15 0.15 0.15"]), False),
        ("header-only", asc(rows=[]), False),
        ("empty", "", False),
        ("binary", bytes(rnd.randrange(256) for _ in range(4096)), False),
        ("claims-1e9-by-1e9", asc(header=["ncols 1000000000", "nrows 1000000000"] + head[2:]),
         False),
        ("negative-ncols", asc(header=["ncols -6"] + head[1:]), False),
        ("fractional-ncols", asc(header=["ncols 6.5"] + head[1:]), False),
        ("one-cell", asc(ncols=1, nrows=1, cell="0.6"), False),
        ("does-not-cover", asc(xll="10.0"), False),
        ("nan-xllcorner", asc(xll="nan"), False),
        ("nan-nodata", asc(nodata="nan"), None),
        ("crlf", asc(eol="\r\n"), True),
        ("tabs", asc().replace(" ", "\t"), None),
        ("xllcenter", asc(header=["ncols 6", "nrows 6", "xllcenter 0.05", "yllcenter 0.05",
                                  "cellsize 0.1", "NODATA_value -9999"]), True),
        ("lowercase-keys", asc(header=[h.lower() for h in head]), None),
        ("vrt-inside", '<VRTDataset rasterXSize="6" rasterYSize="6"></VRTDataset>\n', False),
        ("utf16", GROUND_ASC.encode("utf-16"), False),
        ("escape-in-values", asc(rows=[row] * 5 + ["0.15 \x1b[2J 0.15 0.15 0.15 0.15"]), False),
    ]
    for label, data, ok in variants:
        yield case_input(f"3d:ground.asc:{label}", c, 3, render(base3d()), [alts], ok,
                         extra={"ground.asc": data})
    d3 = base3d()
    others = [
        ("bottom-raster-above-top", with_value(d3, "body[3].terrain.bottom", '"high.asc"'),
         {"high.asc": asc(value="0.5")}, ("bottom", "above"), False),
        ("rasters-do-not-overlap", with_value(d3, "body[3].terrain.bottom", '"far.asc"'),
         {"far.asc": asc(xll="100.0", value="0.05")}, ("far.asc", "overlap"), False),
        ("garbage-prj", d3, {"ground.prj": "GEOGCS[garbage"}, ("ground",), None),
        ("prj-in-degrees", d3, {"ground.prj": 'GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID['
                                              '"WGS 84",6378137,298.257223563]],PRIMEM['
                                              '"Greenwich",0],UNIT["degree",0.0174532925199433]]'},
         ("degree", "ground"), False),
        ("geotiff-garbage", with_value(d3, "body[3].terrain.top", '"ground.tif"'),
         {"ground.tif": b"II*\x00" + bytes(rnd.randrange(256) for _ in range(2000))},
         ("ground.tif",), False),
        ("escape-in-raster-name", with_value(d3, "body[3].terrain.top",
                                             '"\\u001b[31mground.asc"'),
         {"\x1b[31mground.asc": GROUND_ASC}, ("body[3].terrain.top",), False),
        ("footprint-geojson-garbage", with_value(d3, "body[3].terrain.footprint",
                                                 '"foot.geojson"'),
         {"foot.geojson": '{"type": "FeatureCollection", "features": [{'}, ("foot.geojson",),
         False),
        ("footprint-geojson-valid", with_value(d3, "body[3].terrain.footprint", '"foot.geojson"'),
         {"foot.geojson": json.dumps({"type": "FeatureCollection", "features": [
             {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [
                 [[0.05, 0.05], [0.55, 0.05], [0.55, 0.55], [0.05, 0.55], [0.05, 0.05]]]}}]})},
         ("foot.geojson",), None),
        ("footprint-self-crossing", d3, {"footprint.csv": "x,y\n0.05,0.05\n0.55,0.55\n"
                                                          "0.55,0.05\n0.05,0.55\n"},
         ("footprint", "crosses"), False),
        ("footprint-one-vertex", d3, {"footprint.csv": "x,y\n0.1,0.1\n"}, ("footprint",), False),
        ("footprint-outside-raster", d3, {"footprint.csv": "x,y\n0.05,0.05\n5.0,0.05\n5.0,0.55\n"
                                                           "0.05,0.55\n"},
         ("footprint", "cover", "vertex"), False),
        ("footprint-nan", d3, {"footprint.csv": "x,y\n0.05,0.05\nnan,0.05\n0.55,0.55\n"},
         ("footprint",), False),
        ("footprint-empty", d3, {"footprint.csv": ""}, ("footprint",), False),
        ("two-constants-no-footprint", with_value(d3, "body[3].terrain",
                                                  [["top", "0.15"], ["bottom", "0.05"]]),
         {}, ("body[3].terrain",), False),
        ("depth-and-height", with_value(d3, "body[3].terrain",
                                        [["top", "{ height = 0.1 }"], ["bottom",
                                                                       "{ depth = 0.1 }"]]),
         {}, ("body[3].terrain",), False),
    ]
    for label, doc, extra, alts2, ok in others:
        yield case_input(f"3d:terrain:{label}", c, 3, doc, [alts2], ok, extra=extra)


# ------------------------------------------------------------------------------------------------
# Class input-files: the case file, a polygon, a raster and a footprint that are missing, a folder,
# a FIFO, a device, a link loop, a dangling link, unreadable, named with an escape, empty, or
# /proc/self/environ (which holds a secret).

def gen_input_files():
    c = "input-files"
    slots = [("case", None), ("polygon", ("body[1].polygon", 2)),
             ("raster", ("body[3].terrain.top", 3)), ("footprint", ("body[3].terrain.footprint", 3))]
    kinds = [("missing", "nope.dat", {}, None),
             ("folder", "folder.dat", {"folder.dat": Dir()}, None),
             ("fifo", "fifo.dat", {"fifo.dat": Fifo()}, None),
             ("dev-zero", "/dev/zero", {}, None),
             ("dev-null", "/dev/null", {}, None),
             ("dev-urandom", "/dev/urandom", {}, None),
             ("link-loop", "loop1.dat", {"loop1.dat": Link("loop2.dat"),
                                         "loop2.dat": Link("loop1.dat")}, None),
             ("dangling-link", "dangling.dat", {"dangling.dat": Link("nowhere.dat")}, None),
             ("link-to-folder", "tofolder.dat", {"tofolder.dat": Link("."), }, None),
             ("unreadable", "secret.dat", {"secret.dat": File("x,y\n0,0\n1,0\n1,1\n", 0o000)},
              NOBODY),
             ("escape-name", "\x1b[31mred.dat", {"\x1b[31mred.dat": "x,y\n0,0\n1,0\n1,1\n"}, None),
             ("empty-name", "", {}, None),
             ("proc-environ", "/proc/self/environ", {}, None)]
    for slot, where in slots:
        for kind, path, files, user in kinds:
            env = {"HOSTILE_SECRET": SECRET} if kind == "proc-environ" else {}
            post = no_secret if kind == "proc-environ" else None
            timeout = FIFO_TIMEOUT if kind in ("fifo", "dev-zero", "dev-urandom") else TIMEOUT
            if slot == "case":
                files = dict(files)
                if kind == "escape-name":
                    files[path] = render(base2d())
                    files["floor.csv"] = FLOOR_CSV
                ok = None if kind == "escape-name" else False
                yield Input(f"case:{kind}", c, ["check", path], files,
                            [(path or "case", "case", "file")] if path else [], ok, post=post,
                            env=env, timeout=timeout, user=user,
                            note=f"talus check {path!r}")
                continue
            key, dim = where
            doc = base2d() if dim == 2 else base3d()
            text = render(with_value(doc, key, json.dumps(path)))
            command = "check" if user is not None else "run"
            yield case_input(f"{slot}:{kind}", c, dim, text, [(key,)], False, command=command,
                             extra=files, post=post, env=env, timeout=timeout, user=user,
                             note=f"{key} = {path!r}")


# ------------------------------------------------------------------------------------------------
# Class command-line: talus run/check misuse, --set, --threads, --max-steps, --out and the
# environment.

def gen_command_line():
    c = "command-line"
    case = case_files(2, render(base2d()))
    simple = [
        ("no-arguments", [], ("subcommand",), False),
        ("unknown-subcommand", ["frobnicate"], ("frobnicate",), False),
        ("subcommand-upper", ["RUN", CASE2D], ("RUN",), False),
        ("run-nothing", ["run"], ("case",), False),
        ("restart-no-value", ["run", "--restart"], ("--restart",), False),
        ("check-nothing", ["check"], ("case",), False),
        ("check-two-cases", ["check", CASE2D, CASE2D], (CASE2D, "argument"), False),
        ("out-no-value", ["run", CASE2D, "--out"], ("--out",), False),
        ("unknown-option", ["run", CASE2D, "--bogus", *STOP], ("--bogus",), False),
        ("unknown-short-option", ["run", CASE2D, "-x", *STOP], ("-x",), False),
        ("double-dash", ["run", "--", "--out"], ("--out", "case"), False),
        ("version", ["--version"], (), True),
        ("help", ["--help"], (), True),
        ("run-help", ["run", "--help"], (), True),
        ("set-with-restart", ["run", "--restart", "run", "--set", "grid.cell_size=0.2"],
         ("--set", "--restart"), False),
        ("case-with-restart", ["run", CASE2D, "--restart", "run"], ("--restart", CASE2D), False),
        ("overwrite-with-restart", ["run", "--restart", "run", "--overwrite"],
         ("--overwrite", "--restart"), False),
        ("empty-case-path", ["check", ""], ("case", "file"), False),
    ]
    for label, argv, alts, ok in simple:
        yield Input(f"cli:{label}", c, argv, dict(case), [alts] if alts else [], ok)
    bad_sets = ["", "=", "foo", "=1", "grid.cell_size=", "grid.cell_size==0.1",
                "grid..cell_size=1", ".grid=1", "grid.cell_size=abc def", "grid.cell_size=[",
                'simulation.gravity=[0,"a"]', "body.99.name=x", "body.-1.name=x",
                "body.nosuch.rigid=true", "material.0=1", "simulation=1",
                "title=\x1b[31mred\x1b[0m", "grid.cell_size=0x10", "grid.cell_size=nan",
                "a.b.c.d.e.f=1", "end_time=1", "simulation.end_time=1e400",
                "simulation.end_time=" + "9" * 100_000, "body.block.name=floor",
                "grid.cell_size=-0", "body.0.box.min.0=nan", "simulation.gravity=[0, -9.81",
                "title=a\nb", "body.block.box={}", "material.soil.model=linear_elastic"]
    for k, value in enumerate(bad_sets):
        key = value.split("=", 1)[0]
        yield Input(f"cli:set-{k:02d}", c, ["check", CASE2D, "--set", value], dict(case),
                    [("--set", "from --set") + ((key,) if key else ())], False,
                    note=f"--set {value[:60]!r}")
    yield Input("cli:set-non-utf8", c, ["check", CASE2D, "--set", b"title=\xff\xfe"], dict(case),
                [("--set", "title")], False)
    yield Input("cli:set-10000-times", c, ["check", CASE2D] + sets(*["grid.cell_size=0.1"] * 10_000),
                dict(case), [], True)
    yield Input("cli:set-with-spaces", c, ["check", CASE2D, "--set", "simulation.end_time = 0.1"],
                dict(case), [("--set",)], None)
    for label, opt, values in (("threads", "--threads", ["0", "-1", "abc", "1e3", "1025", "",
                                                         "99999999999999999999"]),
                               ("max-steps", "--max-steps", ["0", "-1", "abc", "1.5", "",
                                                             "99999999999999999999999"])):
        for v in values:
            argv = ["run", CASE2D, "--out", "{d}/run", opt, v]
            if opt != "--max-steps":
                argv += STOP
            ok = None if v == "1e3" else False  # 1000 threads is in range, if "1e3" reads as 1000
            yield Input(f"cli:{label}={v[:12] or 'empty'}", c, argv, dict(case), [(opt,)], ok)
    # --out onto things that are not a fresh folder.
    user = {"mine/notes.txt": "my notes\n", "mine/data.csv": "1,2\n"}
    outs = [
        ("onto-regular-file", "afile", {"afile": "precious\n"}, ("afile",), False, None),
        ("onto-root", "/", {}, ("/",), False, None),
        ("onto-proc", "/proc/hostile_talus_run", {}, ("/proc",), False, None),
        ("empty", "", {}, ("--out",), None, None),
        ("under-regular-file", "afile/sub", {"afile": "precious\n"}, ("afile",), False, None),
        ("dangling-link", "dangling", {"dangling": Link("{d}/nowhere")}, ("dangling",), None,
         None),
        ("link-loop", "loop1", {"loop1": Link("loop2"), "loop2": Link("loop1")}, ("loop1",),
         False, None),
        ("path-too-long", "x" * 300 + "/" + "y" * 5000, {}, ("File name too long", "xxxx"),
         False, None),
        ("read-only-folder", "ro", {"ro": Dir(0o555, NOBODY)}, ("ro",), False, NOBODY),
        ("under-read-only-folder", "ro/sub", {"ro": Dir(0o555, NOBODY)}, ("ro",), False, NOBODY),
        ("user-folder", "mine", user, ("mine",), False, None),
        ("cwd", ".", {}, (".", "not empty", "earlier"), False, None),
        ("user-folder-overwrite", "mine", user, ("not a talus run folder",), False, None),
        ("cwd-overwrite", ".", {}, ("not a talus run folder",), False, None),
        ("parent-overwrite", "..", {}, ("not a talus run folder",), False, None),
        ("link-to-user-folder-overwrite", "link", dict(user, link=Link("mine")),
         ("not a talus run folder",), False, None),
        ("escape-in-name", "\x1b[31mred", {}, (), None, None),
        ("newline-in-name", "a\nb", {}, (), None, None),
    ]
    for label, out, files, alts, ok, uid in outs:
        argv = ["run", CASE2D, "--out", out, *STOP]
        if "overwrite" in label:
            argv.append("--overwrite")
        yield Input(f"out:{label}", c, argv, dict(case, **files), [alts] if alts else [], ok,
                    user=uid, allow_control=label in ("escape-in-name", "newline-in-name"))
    # The environment.
    envs = [("lc-all-german", {"LC_ALL": "de_DE.UTF-8", "LANG": "de_DE.UTF-8"}, True),
            ("omp-threads-0", {"OMP_NUM_THREADS": "0"}, True),
            ("omp-threads-negative", {"OMP_NUM_THREADS": "-1"}, True),
            ("omp-threads-word", {"OMP_NUM_THREADS": "abc"}, True),
            ("omp-threads-100000", {"OMP_NUM_THREADS": "100000"}, True),
            ("omp-stacksize-100G", {"OMP_STACKSIZE": "100G"}, None),
            ("omp-wait-policy-bogus", {"OMP_WAIT_POLICY": "bogus"}, True),
            ("inject-signal-word", {"TALUS_INJECT_SIGNAL": "abc"}, None),
            ("inject-signal-no-step", {"TALUS_INJECT_SIGNAL": "2"}, None),
            ("inject-signal-99", {"TALUS_INJECT_SIGNAL": "99:1"}, None),
            ("inject-signal-negative", {"TALUS_INJECT_SIGNAL": "-9:1"}, None),
            ("inject-signal-step-negative", {"TALUS_INJECT_SIGNAL": "2:-1"}, None),
            ("no-home", {"HOME": None}, True),
            ("tmpdir-missing", {"TMPDIR": "/nonexistent/tmp"}, True),
            ("empty-path", {"PATH": ""}, True)]
    for label, env, ok in envs:
        yield Input(f"env:{label}", c, ["run", CASE2D, "--out", "{d}/run", *STOP], dict(case),
                    [], ok, env=env)
    yield Input("env:stdout-dev-full", c, [], dict(case), [], None,
                action=lambda ctx: ctx.run(["run", CASE2D, "--out", "run", *STOP],
                                           stdout_path="/dev/full"),
                note="talus run ... > /dev/full")
    yield Input("env:stdout-closed-pipe", c, [], dict(case), [], None, action=closed_pipe,
                note="talus run ... | (a reader that has gone)")
    yield Input("env:3d-gdal-data-missing", c, run_case(3), case_files(3, render(base3d())), [],
                True, env={"GDAL_DATA": "/nonexistent", "PROJ_LIB": "/nonexistent",
                           "PROJ_DATA": "/nonexistent"})


def closed_pipe(ctx):
    r, w = os.pipe()
    os.close(r)  # the reader is gone before talus writes its first line
    try:
        p = ctx.start(["run", CASE2D, "--out", "run", *STOP], stdout=w)
    finally:
        os.close(w)
    return ctx.finish(p)


# ------------------------------------------------------------------------------------------------
# Class bench-verify: talus bench and talus verify with bad options. verify reads a copy of the
# benchmark cases under WORK/source, so it never writes into the source folder.

def gen_bench_verify():
    c = "bench-verify"
    bench = [
        ("threads-0", ["--threads", "0"], ("--threads",)),
        ("threads-negative", ["--threads", "-1"], ("--threads",)),
        ("threads-1025", ["--threads", "1025"], ("--threads",)),
        ("threads-huge", ["--threads", "99999999999"], ("--threads",)),
        ("threads-word", ["--threads", "abc"], ("--threads",)),
        ("threads-empty", ["--threads", ""], ("--threads",)),
        ("threads-list-with-0", ["--threads", "1,0"], ("--threads",)),
        ("threads-empty-item", ["--threads", "2,,3"], ("--threads",)),
        ("problems-unknown", ["--problems", "nosuch"], ("--problems",)),
        ("problems-empty", ["--problems", ""], ("--problems",)),
        ("problems-commas", ["--problems", ",,"], ("--problems",)),
        ("problems-one-unknown", ["--problems", "column,nosuch"], ("--problems",)),
        ("problems-upper", ["--problems", "COLUMN"], ("--problems",)),
        ("json-folder", ["--json", "{d}"], ("folder",)),
        ("json-missing-folder", ["--json", "{d}/nope/x.json"], ("does not exist",)),
        ("json-root", ["--json", "/"], ("folder", "/")),
        ("json-empty", ["--json", ""], ("--json",)),
        ("unknown-option", ["--bogus"], ("--bogus",)),
    ]
    for label, argv, alts in bench:
        yield Input(f"bench:{label}", c, ["bench", *argv], {}, [alts], False, timeout=TIMEOUT)
    src = ["--source", "{work}/source"]
    verify = [
        ("cases-unknown", ["--cases", "nosuch", "--out", "{d}/v", *src], ("nosuch",), False),
        ("out-regular-file", ["--cases", "bar_vibration", "--out", "{d}/afile", *src],
         ("afile",), False),
        ("out-proc", ["--cases", "bar_vibration", "--out", "/proc/hostile_verify", *src],
         ("/proc",), False),
        ("threads-word", ["--threads", "abc", "--cases", "bar_vibration", "--out", "{d}/v", *src],
         ("--threads",), False),
        ("threads-negative", ["--threads", "-1", "--cases", "bar_vibration", "--out", "{d}/v",
                              *src], ("--threads",), False),
        ("quick-and-full", ["--quick", "--full", "--cases", "nosuch", *src],
         ("--quick", "--full"), False),
        ("source-missing", ["--cases", "bar_vibration", "--out", "{d}/v", "--source",
                            "{d}/nowhere"], ("nowhere",), False),
        ("cases-no-value", ["--cases", "--out", "{d}/v", *src], ("--cases",), False),
        ("update-docs-unknown-case", ["--update-docs", "--cases", "nosuch", "--out", "{d}/v",
                                      *src], ("nosuch",), False),
        ("unknown-option", ["--bogus"], ("--bogus",), False),
    ]
    for label, argv, alts, ok in verify:
        yield Input(f"verify:{label}", c, ["verify", *argv], {"afile": "precious\n"}, [alts], ok)


# ------------------------------------------------------------------------------------------------
# Run-folder scenarios. A first run of the 2D case stops after 10 steps with two checkpoints
# (every 0.005 s); each scenario then damages the folder and restarts it, or starts a second run.

TWO_CHECKPOINTS = ["checkpoint.every=0.005", "checkpoint.wall_minutes=0"]
REFERENCE = ["simulation.end_time=0.1", "output.every=0.02", "checkpoint.every=0.02",
             "checkpoint.wall_minutes=0"]
LONG = ["simulation.end_time=60", "output.every=0.5", "checkpoint.every=0.2",
        "checkpoint.wall_minutes=0"]


def first_run(ctx, out="run", extra=(), steps=10, case=CASE2D):
    """Runs the 2D case into `out` and returns its path; a failure is a SetupFailed."""
    res = ctx.run(["run", case, "--out", out, "--max-steps", str(steps),
                   *sets(*TWO_CHECKPOINTS, *extra)])
    if res.rc != 0:
        raise SetupFailed(res, f"the first run exited {res.rc}")
    return ctx.path(out)


def checkpoints(run):
    return sorted((run / "checkpoints").glob("step_*.ckpt"))


def restart_scenario(damage, steps=5, threads=None):
    """First run, damage(ctx, run_folder), then `talus run --restart run --max-steps N`."""
    def action(ctx):
        run = first_run(ctx)
        damage(ctx, run)
        argv = ["run", "--restart", "run", "--max-steps", str(steps)]
        if threads:
            argv += ["--threads", str(threads)]
        return ctx.run(argv)
    return action


def remove(rel):
    def damage(ctx, run):
        p = run / rel
        if rel == "checkpoints/*":
            for f in checkpoints(run):
                f.unlink()
        elif rel == "newest":
            checkpoints(run)[-1].unlink()
        elif p.is_dir() and not p.is_symlink():
            shutil.rmtree(p)
        else:
            p.unlink()
    return damage


def corrupt(how):
    def damage(ctx, run):
        cks = checkpoints(run)
        if not cks:
            raise SetupFailed(None, "the first run left no checkpoint")
        newest = cks[-1]
        data = newest.read_bytes()
        if how == "half":
            newest.write_bytes(data[:len(data) // 2])
        elif how == "zero":
            newest.write_bytes(b"")
        elif how == "16-bytes":
            newest.write_bytes(data[:16])
        elif how == "flip-middle":
            b = bytearray(data)
            b[len(b) // 2] ^= 0xFF
            newest.write_bytes(bytes(b))
        elif how == "flip-last":
            b = bytearray(data)
            b[-1] ^= 0x01
            newest.write_bytes(bytes(b))
        elif how == "flip-first":
            b = bytearray(data)
            b[0] ^= 0x01
            newest.write_bytes(bytes(b))
        elif how == "append":
            newest.write_bytes(data + b"garbage" * 100)
        elif how == "random":
            newest.write_bytes(bytes(ctx.rng.randrange(256) for _ in range(len(data))))
        elif how == "all-truncated":
            for f in cks:
                f.write_bytes(f.read_bytes()[:100])
        elif how == "link-outside":
            newest.unlink()
            os.symlink(ctx.path("outside/victim.txt"), newest)
        elif how == "fifo":
            newest.unlink()
            os.mkfifo(newest)
        elif how == "folder":
            newest.unlink()
            newest.mkdir()
            ctx.guard(newest)
        elif how == "renamed-higher":
            newest.rename(newest.with_name("step_9999999999.ckpt"))
        elif how == "older-as-newest":
            newest.write_bytes(cks[0].read_bytes())
        elif how == "other-case":
            other = first_run(ctx, out="other", extra=["material.soil.density=2100"])
            newest.write_bytes(checkpoints(other)[-1].read_bytes())
        elif how == "case-comment":
            with open(run / "case.toml", "a") as f:
                f.write("# a comment added by hand\n")
        elif how == "case-edited":
            t = (run / "case.toml").read_text()
            (run / "case.toml").write_text(t.replace("end_time = 0.05", "end_time = 0.07"))
        elif how == "case-binary":
            (run / "case.toml").write_bytes(bytes(ctx.rng.randrange(256) for _ in range(2000)))
        elif how == "summary-folder":
            (run / "summary.json").unlink()
            (run / "summary.json").mkdir()
        elif how == "energy-folder":
            (run / "energy.csv").unlink()
            (run / "energy.csv").mkdir()
        elif how == "user-note-in-checkpoints":
            (run / "checkpoints/notes.txt").write_text("mine\n")
            ctx.guard(run / "checkpoints/notes.txt")
        elif how == "user-file-in-run":
            (run / "notes.txt").write_text("mine\n")
            ctx.guard(run / "notes.txt")
        else:
            raise ValueError(how)
    return damage


def plant_link(rel, to_dir=False):
    """A link at RUN/rel to the user's file (or folder) outside the run folder."""
    def damage(ctx, run):
        p = run / rel.replace("NEXT", next_checkpoint(run, 5))
        if p.exists() or p.is_symlink():
            if p.is_dir() and not p.is_symlink():
                shutil.rmtree(p)
            else:
                p.unlink()
        os.symlink(ctx.path("outside/folder" if to_dir else "outside/victim.txt"), p)
    return damage


def next_checkpoint(run, steps):
    cks = checkpoints(run)
    step = int(cks[-1].stem.split("_")[1]) if cks else 0
    return f"step_{step + steps:010d}.ckpt"


def run_set_scenario(text, restart=False):
    """A [[run]] entry with a bad value appended to RUN/case.toml, then the run folder's case is
    run again (or restarted)."""
    def action(ctx):
        run = first_run(ctx)
        with open(run / "case.toml", "a") as f:
            f.write(text)
        if restart:
            return ctx.run(["run", "--restart", "run", *STOP])
        return ctx.run(["run", "run/case.toml", "--out", "run2", *STOP])
    return action


def overwrite_scenario(damage, ok):
    def action(ctx):
        run = first_run(ctx)
        damage(ctx, run)
        return ctx.run(["run", CASE2D, "--out", "run", "--overwrite", *STOP])
    return action


def gen_run_folder():
    c = "run-folder"
    base = case_files(2, render(base2d()), **{"outside/victim.txt": "precious\n",
                                               "outside/folder/keep.txt": "keep me\n"})
    for rel, ok, alts in [("summary.json", None, ()), ("energy.csv", None, ()),
                          ("bodies.csv", None, ()), ("probes.csv", None, ()),
                          ("interfaces.csv", None, ()), ("particles.pvd", None, ()),
                          ("particles_000000.vtu", None, ()),
                          ("case.toml", False, ("case.toml",)), ("case_as_run.toml", None, ()),
                          ("legend.json", None, ()), ("inputs/floor.csv", False, ("floor.csv",)),
                          ("inputs", False, ("floor.csv", "inputs")), (".talus-run", None, ()),
                          ("checkpoints", False, ("checkpoint",)),
                          ("checkpoints/*", False, ("checkpoint",)), ("newest", True, ())]:
        yield Input(f"restart:deleted:{rel}", c, [], dict(base), [alts] if alts else [], ok,
                    action=restart_scenario(remove(rel)),
                    note=f"rm RUN/{rel}; talus run --restart RUN")
    corruptions = [("half", True, ()), ("zero", True, ()), ("16-bytes", True, ()),
                   ("flip-middle", True, ()), ("flip-last", True, ()), ("flip-first", True, ()),
                   ("append", None, ("checkpoint",)), ("random", True, ()),
                   ("all-truncated", False, ("checkpoint",)), ("link-outside", True, ()),
                   ("fifo", True, ()), ("folder", True, ()),
                   ("renamed-higher", None, ("checkpoint",)),
                   ("older-as-newest", None, ("checkpoint",)),
                   ("other-case", None, ("another case", "checkpoint")),
                   ("case-comment", None, ("case.toml", "another case")),
                   ("case-edited", False, ("another case",)),
                   ("case-binary", False, ("case.toml",)),
                   ("summary-folder", False, ("summary.json",)),
                   ("energy-folder", False, ("energy.csv",)),
                   ("user-note-in-checkpoints", True, ()), ("user-file-in-run", True, ())]
    for how, ok, alts in corruptions:
        yield Input(f"restart:damaged:{how}", c, [], dict(base), [alts] if alts else [], ok,
                    action=restart_scenario(corrupt(how)), timeout=FIFO_TIMEOUT * 3,
                    note=f"{how}; talus run --restart RUN")
    for rel in ["summary.json.tmp", "energy.csv.tmp", "bodies.csv.tmp", "probes.csv.tmp",
                "interfaces.csv.tmp", "particles.pvd.tmp", "legend.json.tmp",
                "case_as_run.toml.tmp", "particles_000001.vtu.tmp", "checkpoints/NEXT.tmp",
                ".talus-run.tmp", "summary.json", "energy.csv", "particles.pvd"]:
        yield Input(f"restart:link-at:{rel}", c, [], dict(base), [], True,
                    action=restart_scenario(plant_link(rel)),
                    note=f"ln -s OUTSIDE/victim.txt RUN/{rel}; talus run --restart RUN")
    for rel in ["checkpoints", "inputs"]:
        yield Input(f"restart:folder-link:{rel}", c, [], dict(base), [], None,
                    action=restart_scenario(plant_link(rel, to_dir=True)),
                    note=f"RUN/{rel} replaced by a link to a user's folder")
    runs = [("bad-value", '\n[[run]]\nset = ["grid.cell_size=abc"]\n', ("[[run]]",)),
            ("nonsense", '\n[[run]]\nset = ["nonsense"]\n', ("[[run]]", "nonsense")),
            ("number", "\n[[run]]\nset = [1]\n", ("[[run]]", "run")),
            ("string", '\n[[run]]\nset = "grid.cell_size=0.2"\n', ("run",)),
            ("end-time-1e300", '\n[[run]]\nset = ["simulation.end_time=1e300"]\n',
             ("[[run]]", "1e+09")),
            ("unknown-body", '\n[[run]]\nset = ["body.nosuch.rigid=true"]\n',
             ("[[run]]", "nosuch")),
            ("escape", '\n[[run]]\nset = ["title=\\u001b[2J"]\n', ("[[run]]", "title")),
            ("files-outside", '\n[[run]]\nfiles = { "floor.csv" = "../outside/secret.csv" }\n',
             ("floor.csv", "secret.csv")),
            ("files-number", "\n[[run]]\nfiles = 1\n", ("files", "run")),
            ("unknown-key", "\n[[run]]\nbogus = 1\n", ("bogus", "run"))]
    files = dict(base, **{"outside/secret.csv": f"{SECRET}\n0,0\n1,0\n1,0.2\n"})
    for label, text, alts in runs:
        yield Input(f"run-entry:{label}", c, [], dict(files), [alts], False,
                    action=run_set_scenario(text), post=no_secret,
                    note="a [[run]] entry appended to RUN/case.toml; talus run RUN/case.toml")
    yield Input("run-entry:restart-after-edit", c, [], dict(files), [("another case",)], False,
                action=run_set_scenario('\n[[run]]\nset = ["grid.cell_size=0.2"]\n',
                                        restart=True))
    # --overwrite and --restart onto folders that are not what they seem.
    def note(rel, text="mine\n"):
        def damage(ctx, run):
            p = run / rel
            p.parent.mkdir(parents=True, exist_ok=True)
            p.write_text(text)
            ctx.guard(p)
        return damage

    def user_link(ctx, run):
        os.symlink(ctx.path("outside/folder"), run / "plots")

    def fake_marker(ctx, run):
        shutil.rmtree(run)
        run.mkdir()
        (run / ".talus-run").write_text("")
        (run / "notes.txt").write_text("mine\n")
        ctx.guard(run / "notes.txt")

    overwrites = [("user-file", note("notes.txt"), ("notes.txt",)),
                  ("user-file-in-checkpoints", note("checkpoints/notes.txt"), ("notes.txt",)),
                  ("user-file-in-inputs", note("inputs/mine.csv"), ("mine.csv",)),
                  ("user-file-in-plots", note("plots/my_notes.txt"), ("my_notes.txt",)),
                  ("user-folder-link-as-plots", user_link, ("plots",)),
                  ("planted-marker", fake_marker, ("notes.txt",))]
    for label, damage, alts in overwrites:
        yield Input(f"overwrite:{label}", c, [], dict(base), [alts], False,
                    action=overwrite_scenario(damage, False),
                    note="talus run CASE --out RUN --overwrite")
    yield Input("overwrite:own-run-folder", c, [], dict(base), [], True,
                action=overwrite_scenario(lambda ctx, run: None, True))
    restarts = [("not-a-run", "mine", {"mine/notes.txt": "mine\n"}, ("mine", "checkpoint")),
                ("empty-folder", "empty", {"empty": Dir()}, ("empty", "checkpoint")),
                ("regular-file", "afile", {"afile": "precious\n"}, ("afile",)),
                ("missing", "nowhere", {}, ("nowhere",)),
                ("root", "/", {}, ("/", "checkpoint")),
                ("marker-only", "marked", {"marked/.talus-run": ""}, ("marked", "checkpoint")),
                ("empty-path", "", {}, ("--restart", "checkpoint")),
                ("fifo", "fifo", {"fifo": Fifo()}, ("fifo",)),
                ("dev-null", "/dev/null", {}, ("/dev/null",))]
    for label, path, files, alts in restarts:
        yield Input(f"restart:{label}", c, ["run", "--restart", path, *STOP],
                    dict(base, **files), [alts], False, timeout=FIFO_TIMEOUT)
    yield Input("restart:max-steps-0", c, [], dict(base), [("--max-steps",)], False,
                action=lambda ctx: (first_run(ctx),
                                    ctx.run(["run", "--restart", "run", "--max-steps", "0"]))[1])
    yield Input("restart:moved-folder-other-cwd", c, [], dict(base), [], True,
                action=moved_restart)
    yield Input("restart:threads-2", c, [], dict(base), [], True,
                action=restart_scenario(lambda ctx, run: None, threads=2))


def moved_restart(ctx):
    """The run folder moved, the case and its CSV deleted, --restart from another folder."""
    run = first_run(ctx)
    run.rename(ctx.path("moved"))
    ctx.path("elsewhere").mkdir()
    for f in (CASE2D, "floor.csv"):
        ctx.forget(ctx.path(f))
        ctx.path(f).unlink()
    return ctx.run(["run", "--restart", str(ctx.path("moved")), *STOP], cwd=ctx.path("elsewhere"))


# ------------------------------------------------------------------------------------------------
# Class signals: kill -9 at a random time, injected and real signals, concurrent runs on one
# folder, a folder removed or replaced under a run, a full disk.

def compare_runs(ref, other):
    """Names of the CSV, VTU and PVD files that differ between two run folders."""
    names = sorted(p.name for p in ref.iterdir() if p.suffix in (".csv", ".vtu", ".pvd"))
    diff = [n for n in names if not (other / n).exists()
            or (ref / n).read_bytes() != (other / n).read_bytes()]
    extra = sorted(p.name for p in other.iterdir() if p.suffix in (".csv", ".vtu", ".pvd")
                   and p.name not in names)
    return diff + [f"{n} (extra)" for n in extra]


def injected(sig, step, threads=(1, 1)):
    """TALUS_INJECT_SIGNAL=SIG:STEP on a 65-step run, then --restart to the end: the folder must
    be the bits of a run that never stopped."""
    def action(ctx):
        ctx.write_case2d()
        ref = ctx.run(["run", CASE2D, "--out", "ref", "--threads", str(threads[0]),
                       *sets(*REFERENCE)])
        if ref.rc != 0:
            raise SetupFailed(ref, f"the reference run exited {ref.rc}")
        first = ctx.run(["run", CASE2D, "--out", "run", "--threads", str(threads[0]),
                         *sets(*REFERENCE)], env={"TALUS_INJECT_SIGNAL": f"{sig}:{step}"},
                        sent_signal=sig)
        ctx.extra["first"] = first
        if sig != 9 and first.rc not in (0, 128 + sig):
            ctx.extra["problem"] = (f"the interrupted run exited {first.rc}, expected "
                                    f"{128 + sig}")
        if sig != 9 and first.rc == 128 + sig:
            s = read_summary(ctx.path("run"))
            if s.get("status") != "interrupted":
                ctx.extra["problem"] = f"summary.json says {s.get('status')!r} after signal {sig}"
        res = ctx.run(["run", "--restart", "run", "--threads", str(threads[1])])
        if res.rc == 0:
            ctx.extra["diff"] = compare_runs(ctx.path("ref"), ctx.path("run"))
        return res
    return action


def injected_post(ctx, res):
    if ctx.extra.get("diff"):
        return ("lost or mixed data", "after the restart these differ from the run that never "
                f"stopped: {', '.join(ctx.extra['diff'][:6])}")
    if ctx.extra.get("problem"):
        return "vague", ctx.extra["problem"]
    return None


def read_summary(run):
    try:
        return json.loads((run / "summary.json").read_text())
    except (OSError, ValueError):
        return {}


def long_run(ctx, out="run", extra=(), **kw):
    return ctx.start(["run", CASE2D, "--out", out, "--max-steps", "40000", *sets(*LONG, *extra)],
                     **kw)


def wait_for(cond, seconds=30.0):
    deadline = time.time() + seconds
    while time.time() < deadline:
        if cond():
            return True
        time.sleep(0.02)
    return False


def started(ctx, out="run", proc=None, need_checkpoint=True):
    run = ctx.path(out)
    ok = wait_for(lambda: (checkpoints(run) if need_checkpoint else (run / "summary.json").exists())
                  or (proc is not None and proc.popen.poll() is not None))
    if not ok or (proc is not None and proc.popen.poll() is not None):
        res = ctx.finish(proc, timeout=5) if proc is not None else None
        raise SetupFailed(res, "the long run did not reach its first checkpoint")


def random_kill(sig):
    def action(ctx):
        ctx.write_case2d()
        p = long_run(ctx)
        started(ctx, proc=p, need_checkpoint=sig == signal.SIGKILL)
        time.sleep(ctx.rng.uniform(0.0, 0.8))
        p.popen.send_signal(sig)
        first = ctx.finish(p, sent_signal=sig)
        ctx.extra["first"] = first
        if sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            s = read_summary(ctx.path("run"))
            if first.rc != 128 + sig or s.get("status") != "interrupted":
                ctx.extra["problem"] = (f"after signal {sig} the run exited {first.rc} with "
                                        f"status {s.get('status')!r} (expected {128 + sig}, "
                                        "interrupted)")
        return ctx.run(["run", "--restart", "run", "--max-steps", "20"])
    return action


def double_sigint(ctx):
    ctx.write_case2d()
    p = long_run(ctx)
    started(ctx, proc=p)
    p.popen.send_signal(signal.SIGINT)
    time.sleep(0.001)
    p.popen.send_signal(signal.SIGINT)
    ctx.finish(p, sent_signal=signal.SIGINT)
    return ctx.run(["run", "--restart", "run", "--max-steps", "20"])


def stop_continue(ctx):
    ctx.write_case2d()
    p = ctx.start(["run", CASE2D, "--out", "run", "--max-steps", "3000", *sets(*LONG)])
    started(ctx, proc=p, need_checkpoint=False)
    p.popen.send_signal(signal.SIGSTOP)
    time.sleep(1.0)
    p.popen.send_signal(signal.SIGCONT)
    return ctx.finish(p)


def sigusr1(ctx):
    ctx.write_case2d()
    p = long_run(ctx)
    started(ctx, proc=p)
    p.popen.send_signal(signal.SIGUSR1)
    ctx.finish(p, sent_signal=signal.SIGUSR1)
    return ctx.run(["run", "--restart", "run", "--max-steps", "20"])


def two_fresh_runs(ctx):
    """Two fresh runs started together on one folder that does not exist yet: one must win, the
    other be refused; both exiting 0 would mix two runs in one folder."""
    ctx.write_case2d()
    a = ctx.start(["run", CASE2D, "--out", "run", "--max-steps", "2000", *sets(*LONG)])
    b = ctx.start(["run", CASE2D, "--out", "run", "--max-steps", "2000", *sets(*LONG)])
    ra, rb = ctx.finish(a), ctx.finish(b)
    ctx.extra["pair"] = (ra, rb)
    return rb if ra.rc == 0 else ra


def two_fresh_post(ctx, res):
    ra, rb = ctx.extra["pair"]
    if ra.rc == 0 and rb.rc == 0:
        return "lost or mixed data", "both runs exited 0 into the same folder"
    if ra.rc != 0 and rb.rc != 0:
        return "refused though valid", f"neither run completed (exit {ra.rc} and {rb.rc})"
    return None


def onto_running(second):
    """A long run goes; `second` (argv) targets its folder; then the first is stopped with SIGTERM
    and must still have its folder whole."""
    def action(ctx):
        ctx.write_case2d()
        p = long_run(ctx)
        started(ctx, proc=p)
        res = ctx.run(second)
        alive = p.popen.poll() is None
        p.popen.send_signal(signal.SIGTERM)
        first = ctx.finish(p, sent_signal=signal.SIGTERM)
        if not alive:
            ctx.extra["problem"] = f"the first run had ended (exit {first.rc}) when the second came"
        elif first.rc != 128 + signal.SIGTERM:
            ctx.extra["problem"] = f"the first run exited {first.rc} after SIGTERM, not 143"
        return res
    return action


def running_post(ctx, res):
    if ctx.extra.get("problem"):
        return "lost or mixed data" if res.rc == 0 else "vague", ctx.extra["problem"]
    return None


def concurrent_restarts(ctx):
    first_run(ctx, extra=["simulation.end_time=60", "checkpoint.every=0.2"])
    a = ctx.start(["run", "--restart", "run", "--max-steps", "3000"])
    b = ctx.start(["run", "--restart", "run", "--max-steps", "3000"])
    ra, rb = ctx.finish(a), ctx.finish(b)
    ctx.extra["pair"] = (ra, rb)
    return rb if ra.rc == 0 else ra


def folder_fault(kind):
    """A long run whose folder is removed, moved, replaced by a user's folder or loses its marker
    while it writes: it must stop with an output error and write nothing more."""
    def action(ctx):
        ctx.write_case2d()
        p = long_run(ctx)
        started(ctx, proc=p)
        run = ctx.path("run")
        if kind == "removed":
            for _ in range(100):
                shutil.rmtree(run, ignore_errors=True)
                if not run.exists():
                    break
                time.sleep(0.02)
        elif kind == "moved":
            run.rename(ctx.path("moved"))
        elif kind == "replaced":
            run.rename(ctx.path("moved"))
            run.mkdir()
            (run / "notes.txt").write_text("mine\n")
            ctx.guard(run / "notes.txt")
        elif kind == "marker-removed":
            (run / ".talus-run").unlink()
        res = ctx.finish(p, timeout=60)
        if kind in ("removed", "moved") and run.exists():
            ctx.extra["problem"] = "a folder was written again at the run folder's old path"
        if kind == "replaced":
            extra = sorted(x.name for x in run.iterdir() if x.name != "notes.txt")
            if extra:
                ctx.extra["problem"] = f"the run wrote into the user's folder in its place: {extra}"
        return res
    return action


def folder_fault_post(ctx, res):
    if ctx.extra.get("problem"):
        return "lost or mixed data", ctx.extra["problem"]
    return None


def disk_full(limit, then_restart):
    def action(ctx):
        run = first_run(ctx)
        for f in checkpoints(run):
            ctx.guard(f)
        res = ctx.run(["run", "--restart", "run", "--max-steps", "30"], fsize=limit)
        if not then_restart:
            return res
        for f in list(ctx.guards):
            if "checkpoints" in str(f):
                ctx.forget(f)
        return ctx.run(["run", "--restart", "run", "--max-steps", "5"])
    return action


def fresh_disk_full(ctx):
    ctx.write_case2d()
    return ctx.run(["run", CASE2D, "--out", "run", *STOP], fsize=0)


def early_kill(ctx):
    """kill -9 before any checkpoint (default settings: the first after 30 s)."""
    ctx.write_case2d()
    p = ctx.start(["run", CASE2D, "--out", "run", "--max-steps", "40000",
                   *sets("simulation.end_time=60", "output.every=0.5")])
    started(ctx, proc=p, need_checkpoint=False)
    p.popen.send_signal(signal.SIGKILL)
    ctx.finish(p, sent_signal=signal.SIGKILL)
    return ctx.run(["run", "--restart", "run", *STOP])


def gen_signals():
    c = "signals"
    base = case_files(2, render(base2d()))
    for k in range(4):
        yield Input(f"kill9:random-{k}", c, [], dict(base), [], True,
                    action=random_kill(signal.SIGKILL), post=injected_post,
                    note="kill -9 at a random time after the first checkpoint; --restart")
    for name, sig in (("sigint", signal.SIGINT), ("sigterm", signal.SIGTERM),
                      ("sighup", signal.SIGHUP)):
        for k in range(2):
            yield Input(f"{name}:random-{k}", c, [], dict(base), [], True,
                        action=random_kill(sig), post=injected_post,
                        note=f"kill -{name[3:].upper()} at a random time; --restart")
    plan = [(9, 1), (9, 7), (9, 30), (9, 64), (2, 1), (2, 10), (2, 65), (15, 10), (15, 33),
            (1, 10), (1, 50)]
    for sig, step in plan:
        yield Input(f"inject:{sig}:{step}", c, [], dict(base), [], True,
                    action=injected(sig, step), post=injected_post,
                    note=f"TALUS_INJECT_SIGNAL={sig}:{step}; --restart; compare with a run that "
                         "never stopped")
    yield Input("inject:2:20:threads-2-then-1", c, [], dict(base), [], True,
                action=injected(2, 20, threads=(2, 1)), post=injected_post)
    yield Input("inject:9:20:threads-1-then-2", c, [], dict(base), [], True,
                action=injected(9, 20, threads=(1, 2)), post=injected_post)
    yield Input("inject:2:9999-never", c, [], dict(base), [("completed", "checkpoint")], None,
                action=injected(2, 9999), post=injected_post)
    yield Input("double-sigint", c, [], dict(base), [("checkpoint",)], None, action=double_sigint)
    yield Input("sigstop-sigcont", c, [], dict(base), [], True, action=stop_continue)
    yield Input("sigusr1-then-restart", c, [], dict(base), [("checkpoint",)], None,
                action=sigusr1)
    yield Input("kill9-before-any-checkpoint", c, [], dict(base), [("checkpoint",)], None,
                action=early_kill)
    yield Input("concurrent:two-fresh-runs", c, [], dict(base),
                [("in use", "earlier run", "not empty", "talus process")], False,
                action=two_fresh_runs, post=two_fresh_post)
    yield Input("concurrent:second-run", c, [], dict(base),
                [("talus process", "in use", "earlier run")], False,
                action=onto_running(["run", CASE2D, "--out", "run", *STOP]),
                post=running_post)
    yield Input("concurrent:overwrite", c, [], dict(base), [("talus process", "in use")],
                False, action=onto_running(["run", CASE2D, "--out", "run", "--overwrite", *STOP]),
                post=running_post)
    yield Input("concurrent:restart", c, [], dict(base), [("in use",)], False,
                action=onto_running(["run", "--restart", "run", *STOP]), post=running_post)
    yield Input("concurrent:two-restarts", c, [], dict(base), [("in use",)], False,
                action=concurrent_restarts, post=two_fresh_post)
    for kind in ("removed", "moved", "replaced", "marker-removed"):
        yield Input(f"folder-{kind}-mid-run", c, [], dict(base),
                    [("removed", "replaced", "run folder")], False, action=folder_fault(kind),
                    post=folder_fault_post)
    yield Input("disk-full:restart", c, [], dict(base), [("File too large", "write failed")],
                False, action=disk_full(20000, False))
    yield Input("disk-full:then-restart", c, [], dict(base), [], True,
                action=disk_full(20000, True))
    yield Input("disk-full:fresh-run", c, [], dict(base), [("File too large", "write")], False,
                action=fresh_disk_full)


GENERATORS = [gen_case_numbers, gen_case_arrays, gen_case_strings, gen_case_structure,
              gen_case_bytes, gen_polygon_csv, gen_raster, gen_input_files, gen_command_line,
              gen_bench_verify, gen_run_folder, gen_signals]


# ------------------------------------------------------------------------------------------------
# Running an input


def limits(fsize=None, user=None):
    def apply():
        hard = resource.getrlimit(resource.RLIMIT_AS)[1]
        cap = MEMORY_LIMIT if hard == resource.RLIM_INFINITY else min(MEMORY_LIMIT, hard)
        resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if fsize is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
        if user is not None and os.geteuid() == 0:  # only root can be someone else
            os.setgroups([])
            os.setgid(user)
            os.setuid(user)
    return apply


def show_arg(a):
    s = os.fsdecode(a) if isinstance(a, bytes) else a
    if len(s) > 200:
        s = s[:80] + f"...({len(s)} characters)"
    return shlex.quote(s)


def printable(text, n=200):
    text = text.replace("\r\n", "\n").replace("\n", " | ")
    return "".join(ch for ch in text if ch.isprintable())[:n]


@dataclass
class Proc:
    popen: subprocess.Popen
    cmd: str
    t0: float
    timeout: float


class Ctx:
    """What a scenario sees: its folder (d), a random generator, commands that run talus there
    with the limits, and the files it guards."""

    def __init__(self, talus, work, d, inp, rng):
        self.talus, self.work, self.d, self.inp, self.rng = talus, work, d, inp, rng
        self.steps = []
        self.guards = {}
        self.extra = {}
        self.procs = []

    def path(self, *parts):
        return self.d.joinpath(*parts)

    def fmt(self, a):
        if isinstance(a, bytes):
            return a.replace(b"{d}", os.fsencode(str(self.d))).replace(
                b"{work}", os.fsencode(str(self.work)))
        return a.replace("{d}", str(self.d)).replace("{work}", str(self.work))

    def environment(self, extra):
        env = {k: v for k, v in os.environ.items() if not k.startswith(("TALUS_", "OMP_", "GOMP"))}
        env.update(HOME=str(self.work / "home"), TMPDIR=str(self.work / "tmp"))
        for k, v in (extra or {}).items():
            if v is None:
                env.pop(k, None)
            else:
                env[k] = v
        return env

    def start(self, argv, env=None, timeout=None, user=None, fsize=None, cwd=None,
              stdout=None, stdout_path=None):
        args = [self.talus] + [self.fmt(a) for a in argv]
        merged = dict(self.inp.env, **(env or {}))
        shown = " ".join(f"{k}={shlex.quote(str(v))}" for k, v in merged.items() if v is not None)
        cmd = (shown + " " if shown else "") + " ".join(show_arg(a) for a in args)
        if stdout_path:
            cmd += f" > {stdout_path}"
        out = open(stdout_path, "wb") if stdout_path else (stdout or subprocess.PIPE)
        popen = subprocess.Popen(args, cwd=str(cwd or self.d), env=self.environment(merged),
                                 stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.PIPE,
                                 preexec_fn=limits(fsize, user if user is not None
                                                   else self.inp.user),
                                 start_new_session=True)
        if stdout_path:
            out.close()
        proc = Proc(popen, cmd, time.time(), timeout or self.inp.timeout)
        self.procs.append(proc)
        return proc

    def finish(self, proc, timeout=None, sent_signal=None):
        timed_out = False
        try:
            out, err = proc.popen.communicate(timeout=timeout or proc.timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            kill_group(proc.popen)
            out, err = proc.popen.communicate()
        res = Result(proc.cmd, proc.popen.returncode, (out or b"").decode("utf-8", "replace"),
                     (err or b"").decode("utf-8", "replace"), timed_out,
                     time.time() - proc.t0, sent_signal)
        self.steps.append(res)
        return res

    def run(self, argv, sent_signal=None, **kw):
        timeout = kw.pop("timeout", None)
        return self.finish(self.start(argv, timeout=timeout, **kw), sent_signal=sent_signal)

    def guard(self, p):
        self.guards[Path(p)] = digest(Path(p))

    def forget(self, p):
        self.guards.pop(Path(p), None)

    def write_case2d(self):
        if not self.path(CASE2D).exists():
            self.path(CASE2D).write_text(render(base2d()))
            self.path("floor.csv").write_text(FLOOR_CSV)
        return CASE2D


def kill_group(popen):
    try:
        os.killpg(popen.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def digest(p):
    try:
        st = os.lstat(p)
    except FileNotFoundError:
        return "missing"
    except OSError as e:
        return f"error {e.errno}"
    if os.path.islink(p):
        return "link:" + os.readlink(p)
    if os.path.isdir(p) and not os.path.islink(p):
        return "folder"
    if not os.path.isfile(p):
        return f"special {st.st_mode:o}"
    h = hashlib.sha256()
    try:
        with open(p, "rb") as f:
            for chunk in iter(lambda: f.read(1 << 20), b""):
                h.update(chunk)
    except OSError as e:
        return f"unreadable {st.st_mode:o} {st.st_size} {st.st_mtime_ns} ({e.errno})"
    return h.hexdigest() + f" {st.st_mode:o}"


def materialise(ctx, files):
    """Creates the input's files; regular files, folders and links are guarded."""
    for rel, spec in files.items():
        p = ctx.d / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(spec, Fifo):
            os.mkfifo(p)
            continue
        if isinstance(spec, Link):
            os.symlink(ctx.fmt(spec.target), p)
        elif isinstance(spec, Dir):
            p.mkdir(exist_ok=True)
            if spec.owner is not None and os.geteuid() == 0:
                os.chown(p, spec.owner, spec.owner)
            if spec.mode is not None:
                os.chmod(p, spec.mode)
        else:
            data, mode = (spec.data, spec.mode) if isinstance(spec, File) else (spec, None)
            data = data() if callable(data) else data
            p.write_bytes(data.encode("utf-8", "surrogateescape") if isinstance(data, str)
                          else data)
            if mode is not None:
                os.chmod(p, mode)
        if p.name != ".talus-run":  # talus's own marker: a run or restart may rewrite it
            ctx.guard(p)


def run_folders(d, depth=3):
    """Folders under d that hold talus's marker (a run folder), links not followed."""
    found = []
    for root, dirs, files in os.walk(d):
        if len(Path(root).relative_to(d).parts) >= depth:
            dirs[:] = []
        if ".talus-run" in files:
            found.append(Path(root))
        dirs[:] = [x for x in dirs if not os.path.islink(os.path.join(root, x))]
    return found


def check_run_folder(run):
    """A finished run folder must be whole: a summary that parses, every file its PVD lists, and
    each step once in energy.csv."""
    problems = []
    sp = run / "summary.json"
    if not sp.exists() or sp.is_dir():
        return problems
    try:
        s = json.loads(sp.read_text())
    except (OSError, ValueError) as e:
        return [f"{sp.name} does not parse ({e.__class__.__name__})"]
    if s.get("status") not in ("completed", "stopped"):
        return problems
    for pvd in ("particles.pvd", "contact_nodes.pvd"):
        p = run / pvd
        if p.is_file():
            listed = re.findall(r'file="([^"]+)"', p.read_text(errors="replace"))
            missing = [f for f in listed if not (run / f).is_file()]
            if missing:
                problems.append(f"{run.name}/{pvd} lists {len(missing)} missing file(s) "
                                f"({missing[0]}) though the run says {s.get('status')}")
    e = run / "energy.csv"
    if e.is_file():
        steps = []
        for line in e.read_text(errors="replace").splitlines()[1:]:
            parts = line.split(",")
            if len(parts) > 1:
                try:
                    steps.append(int(parts[1]))
                except ValueError:
                    problems.append(f"{run.name}/energy.csv has a broken row: {line[:40]!r}")
                    break
        if any(b <= a for a, b in zip(steps, steps[1:])):
            problems.append(f"{run.name}/energy.csv repeats or reorders steps")
    return problems


def integrity(ctx, top_before, siblings_before, refused=False):
    problems = []
    for p, before in ctx.guards.items():
        now = digest(p)
        if now != before:
            what = "removed" if now == "missing" else "changed"
            problems.append(f"{p.relative_to(ctx.work)} {what}")
    top = set(os.listdir(ctx.work)) - top_before
    if top:
        problems.append(f"new entries in the pass's folder: {sorted(top)[:5]}")
    siblings = set(os.listdir(ctx.work / "inputs")) - siblings_before - {ctx.d.name}
    if siblings:
        problems.append(f"written beside the input's folder: {sorted(siblings)[:5]}")
    if not refused:  # a refused command wrote nothing: a folder's state is not its claim
        for run in run_folders(ctx.d):
            problems += check_run_folder(run)
    return "; ".join(problems)


def signal_name(n):
    try:
        return signal.Signals(n).name
    except ValueError:
        return f"signal {n}"


CONTROL = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]")


def matches(alternatives, text):
    if isinstance(alternatives, str):
        alternatives = (alternatives,)
    low = text.lower()
    return any(a.lower() in low for a in alternatives)


def judge(inp, ctx, res, top_before, siblings_before):
    for st in ctx.steps:
        if st.timed_out:
            return "hang", f"no exit within {st.seconds:.0f} s: {st.cmd[:120]}"
    for st in ctx.steps:
        text = st.out + st.err
        crashed = (st.rc is not None and st.rc < 0 and -st.rc != st.sent_signal) or any(
            m in text for m in CRASH_MARKERS)
        if "std::bad_alloc" in text or (crashed and any(m in text for m in MEMORY_MARKERS)):
            return "memory", f"out of memory under the 4 GiB limit (exit {st.rc})"
    for st in ctx.steps:
        text = st.out + st.err
        if st.rc is not None and st.rc < 0 and -st.rc != st.sent_signal:
            where = "" if st is res else f" (in: {st.cmd[:120]})"
            return "crash", f"killed by {signal_name(-st.rc)}{where}"
        marker = next((m for m in CRASH_MARKERS if m in text), None)
        if marker:
            return "crash", f"'{marker}' in the output of {st.cmd[:120]}"
    lost = integrity(ctx, top_before, siblings_before, refused=res.rc in (1, 2, 3))
    if lost:
        return "lost or mixed data", lost
    if inp.post:
        verdict = inp.post(ctx, res)
        if verdict:
            return verdict
    if not inp.allow_control and CONTROL.search(res.err + res.out):
        ch = CONTROL.search(res.err + res.out).group()
        return ("accepted though wrong" if res.rc == 0 else "vague",
                f"a raw control character ({ch!r}) reaches the terminal")
    rc = res.rc
    if inp.expect_success is True:
        if rc == 0:
            return "valid", "exit 0, as it should"
        return "refused though valid", f"exit {rc} where success was expected"
    if rc == 0:
        if inp.expect_success is None:
            return "valid", "exit 0 (running it is acceptable)"
        return "accepted though wrong", "exit 0 where an error was expected"
    if rc not in (1, 2, 3):
        return "vague", f"exit status {rc} (not 1, 2 or 3)"
    if not res.err.strip():
        return "vague", f"exit {rc} with nothing on stderr"
    wanted = inp.expect
    missing = [e for e in wanted if not matches(e, res.err)]
    if missing:
        return "vague", "the message lacks " + "; ".join(
            " or ".join(repr(a) for a in ((m,) if isinstance(m, str) else m)) for m in missing)
    return "clear error", f"exit {rc}, the message names " + (
        ", ".join(repr(next(a for a in ((m,) if isinstance(m, str) else m)
                            if a.lower() in res.err.lower())) for m in wanted) or "the problem")


def slug(name):
    return re.sub(r"[^A-Za-z0-9_.=-]+", "_", name)[:70]


def safe_rmtree(work, p):
    """Removes p, which must lie inside work (links are removed, never followed)."""
    rp = Path(os.path.abspath(p))
    if rp == work or work not in rp.parents:
        raise RuntimeError(f"refusing to remove {p}: not inside {work}")
    for root, dirs, _ in os.walk(rp):
        for x in dirs:
            q = os.path.join(root, x)
            if not os.path.islink(q):
                os.chmod(q, 0o700)
    os.chmod(rp, 0o700)
    shutil.rmtree(rp)


def run_input(talus, work, index, inp, seed):
    d = work / "inputs" / f"{index:04d}-{slug(inp.name)}"
    if d.exists() or d.is_symlink():
        safe_rmtree(work, d)
    d.mkdir(parents=True)
    ctx = Ctx(talus, work, d, inp, random.Random(f"{seed}:{inp.name}"))
    ctx.guard(work / "canary" / "precious.txt")
    top_before = set(os.listdir(work))
    siblings_before = set(os.listdir(work / "inputs"))
    t0 = time.time()
    res = None
    try:
        materialise(ctx, inp.files)
        if inp.action:
            res = inp.action(ctx)
        else:
            res = ctx.run(inp.argv, timeout=inp.timeout)
        outcome, why = judge(inp, ctx, res, top_before, siblings_before)
    except SetupFailed as e:
        res = e.result or (ctx.steps[-1] if ctx.steps else None)
        if res is not None:
            outcome, why = judge(Input(inp.name, inp.cls, expect_success=True), ctx, res,
                                 top_before, siblings_before)
            if outcome in ("valid", "refused though valid"):
                outcome, why = "refused though valid", f"scenario setup: {e.what}"
        else:
            outcome, why = "harness error", f"scenario setup: {e.what}"
    except Exception as e:  # a bug in this script, not a finding about talus
        outcome, why = "harness error", f"{e.__class__.__name__}: {e}"
        for st in ctx.steps:
            if st.timed_out:
                outcome, why = "hang", f"no exit within {st.seconds:.0f} s: {st.cmd[:120]}"
    finally:
        for proc in ctx.procs:  # a scenario that failed half-way leaves no process behind
            if proc.popen.poll() is None:
                kill_group(proc.popen)
                proc.popen.wait()
            for f in (proc.popen.stdout, proc.popen.stderr):
                if f:
                    f.close()
    commands = [st.cmd for st in ctx.steps]
    return {
        "id": f"{index:04d}", "name": inp.name, "class": inp.cls,
        "command": res.cmd if res else (commands[-1] if commands else ""),
        "steps": commands if len(commands) > 1 else [],
        "exit_code": res.rc if res else None,
        "stderr": printable(res.err.strip()) if res else "",
        "outcome": outcome, "why": why,
        "seconds": round(time.time() - t0, 2),
    }


# ------------------------------------------------------------------------------------------------
# The pass


def all_inputs():
    inputs = []
    for gen in GENERATORS:
        inputs.extend(gen())
    names = [i.name for i in inputs]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise SystemExit(f"duplicate input names: {sorted(dup)[:5]}")
    return inputs


def prepare_work(work, source):
    if work.exists() and not work.is_dir():
        raise SystemExit(f"--work {work}: not a folder")
    if work.exists() and any(work.iterdir()) and not (work / MARKER).exists():
        raise SystemExit(f"--work {work}: not empty and not made by this script (no {MARKER}); "
                         "give a new or empty folder")
    for sub in ("inputs", "home", "tmp", "canary"):
        (work / sub).mkdir(parents=True, exist_ok=True)
    (work / MARKER).write_text("made by tools/hostile_pass.py; it deletes only inside here\n")
    (work / "canary" / "precious.txt").write_text("a user's file outside every input folder\n")
    # A copy of what `talus verify --source` reads, so that verify never writes in the source.
    copy_src = work / "source"
    if copy_src.exists():
        safe_rmtree(work, copy_src)
    (copy_src / "tools").mkdir(parents=True)
    (copy_src / "cases" / "vaiont").mkdir(parents=True)
    if (source / "tools" / "verify.py").exists():
        shutil.copy(source / "tools" / "verify.py", copy_src / "tools" / "verify.py")
    if (source / "cases" / "benchmarks").is_dir():
        shutil.copytree(source / "cases" / "benchmarks", copy_src / "cases" / "benchmarks")
    for f in (source / "cases" / "vaiont").glob("*"):
        if f.is_file() and (f.suffix == ".csv" or f.name == "three_bodies.toml"):
            shutil.copy(f, copy_src / "cases" / "vaiont" / f.name)


def summarise(results, out=sys.stdout):
    w = out.write
    counts = {o: 0 for o in OUTCOMES}
    by_class = {}
    for r in results:
        counts[r["outcome"]] += 1
        by_class.setdefault(r["class"], {o: 0 for o in OUTCOMES})[r["outcome"]] += 1
    w(f"\n{len(results)} inputs\n")
    w("outcomes: " + ", ".join(f"{o} {n}" for o, n in counts.items() if n) + "\n\n")
    shown = [o for o in OUTCOMES if counts[o]]
    short = {"clear error": "clear", "accepted though wrong": "accepted", "refused though valid":
             "refused", "lost or mixed data": "lost", "harness error": "harness"}
    head = f"{'class':<16}{'inputs':>7}" + "".join(f"{short.get(o, o):>10}" for o in shown)
    w(head + "\n" + "-" * len(head) + "\n")
    for cls, row in by_class.items():
        w(f"{cls:<16}{sum(row.values()):>7}" + "".join(f"{row[o]:>10}" for o in shown) + "\n")
    review = [r for r in results if r["outcome"] not in ("clear error", "valid")]
    w(f"\nfor review ({len(review)}):\n")
    order = {o: i for i, o in enumerate(["crash", "hang", "lost or mixed data", "memory",
                                         "accepted though wrong", "refused though valid",
                                         "vague", "harness error"])}
    for r in sorted(review, key=lambda r: (order.get(r["outcome"], 99), r["id"])):
        w(f"[{r['id']}] {r['outcome']} | {r['class']} | {r['name']}\n")
        w(f"    $ {printable(r['command'], 300)}\n")
        for s in r["steps"][:-1]:
            w(f"      (before: {printable(s, 160)})\n")
        w(f"    exit {r['exit_code']}; stderr: {r['stderr']}\n")
        w(f"    why: {printable(r['why'], 300)}\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--talus", required=True, help="the talus program")
    ap.add_argument("--work", required=True, help="folder for every file the pass makes")
    ap.add_argument("--limit", type=int, default=0, help="run only the first N inputs")
    ap.add_argument("--classes", default="", help="comma-separated input classes to run")
    ap.add_argument("--only", default="", help="comma-separated input names to run")
    ap.add_argument("--list", action="store_true", help="print the inputs, run nothing")
    ap.add_argument("--seed", default="1", help="seed of the random choices (kill times, noise)")
    a = ap.parse_args()

    inputs = all_inputs()
    classes = list(dict.fromkeys(i.cls for i in inputs))
    chosen = inputs
    if a.classes:
        wanted = [c.strip() for c in a.classes.split(",") if c.strip()]
        unknown = [c for c in wanted if c not in classes]
        if unknown:
            raise SystemExit(f"unknown class(es) {unknown}; the classes are {classes}")
        chosen = [i for i in chosen if i.cls in wanted]
    if a.only:
        names = set(a.only.split(","))
        chosen = [i for i in chosen if i.name in names]
    if a.limit > 0:
        chosen = chosen[:a.limit]
    index = {id(i): k + 1 for k, i in enumerate(inputs)}

    if a.list:
        for i in chosen:
            flag = {True: "ok ", False: "bad", None: "any"}[i.expect_success]
            what = " ".join(show_arg(x) for x in i.argv) if i.argv else "(scenario)"
            note = f"  # {printable(i.note, 100)}" if i.note else ""
            print(f"{index[id(i)]:04d} {i.cls:<15} {flag} {printable(i.name, 60):<60} "
                  f"{printable(what, 80)}{note}")
        print("\ninputs per class:")
        for cls in classes:
            n = sum(1 for i in chosen if i.cls == cls)
            if n:
                print(f"  {cls:<16}{n:>5}")
        print(f"  {'total':<16}{len(chosen):>5}")
        return 0

    talus = str(Path(a.talus).resolve())
    if not os.access(talus, os.X_OK):
        raise SystemExit(f"--talus {a.talus}: not an executable file")
    work = Path(os.path.abspath(a.work))
    source = Path(__file__).resolve().parent.parent
    prepare_work(work, source)
    results = []
    with open(work / "results.jsonl", "w") as log:
        for k, inp in enumerate(chosen):
            r = run_input(talus, work, index[id(inp)], inp, a.seed)
            results.append(r)
            log.write(json.dumps(r) + "\n")
            log.flush()
            print(f"[{k + 1}/{len(chosen)}] {r['id']} {r['outcome']:<22} {r['seconds']:>6.1f} s  "
                  f"{printable(inp.name, 70)}", flush=True)
    summarise(results)
    print(f"\nresults: {work / 'results.jsonl'}")
    return 1 if any(r["outcome"] in FAILING for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())
