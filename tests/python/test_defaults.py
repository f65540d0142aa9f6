"""Every keyword default of every Python bake call is the job option table's
(texbake.JOB_OPTIONS, the table that makes `texbake bake`'s flags and a batch
line's keys), for the call's bake and target, and `texbake bake --help`
states the same default for the flag.

The table's defaults are read here as the command line takes them ("16",
"area", "false") and turned into Python values by this file's own rules;
the few keywords that are Python's own are listed with the reason."""
import inspect
import json
import os
import re
import subprocess
import sys

import pytest

import texbake
from conftest import BUILD, run_cli

OPTIONS = {o["key"]: o for o in texbake.JOB_OPTIONS}

# Each per-call function: the bake it runs (a name of JOB_OPTIONS' "bakes"),
# and its keywords that are spelled otherwise than the table's key.
CALLS = {
    texbake.bake_vertex: ("proxy vertex", {}),
    texbake.bake_atlas: ("proxy atlas", {}),
    texbake.bake_vertex_from_photos: ("photos vertex", {"colorspace": "texture_colorspace"}),
    texbake.bake_atlas_from_photos: ("photos atlas", {"colorspace": "texture_colorspace"}),
    texbake.bake_vertex_from_camera: ("camera vertex", {"colorspace": "texture_colorspace"}),
    texbake.bake_atlas_from_camera: ("camera atlas", {"colorspace": "texture_colorspace"}),
    texbake.bake_vertex_from_layers: ("layers vertex", {}),
    texbake.bake_atlas_from_layers: ("layers atlas", {}),
}

# Keywords whose default is Python's own, with why.
PYTHON_ONLY = {
    "threads": 0,  # all cores (the table's default in words; its range starts at 1)
    "progress": None,  # the callback; the command line's progress bar is its own
}
# (call, keyword): a default the table gives in words for this bake.
IN_WORDS = {
    # None: the base texture's size, else the table's atlas size (SPEC section 10).
    (texbake.bake_atlas_from_layers, "size"): None,
}


def table_value(key, target):
    """The table's default of `key` for `target` as a Python value."""
    option = OPTIONS[key]
    text = option["defaults"][target]
    if text is None:
        return None
    if option["type"] == "integer":
        return int(text)
    if option["type"] == "flag":
        return {"false": False, "true": True}[text]
    assert option["type"] in ("choice", "text"), option
    return text  # a choice, or a keyword of occluded / outside


def keyword_defaults(call):
    return {name: p.default for name, p in inspect.signature(call).parameters.items()
            if p.kind == p.KEYWORD_ONLY or p.default is not p.empty}


def table_keywords():
    """(call, keyword, key, target, Python default) of every keyword that is
    a job option."""
    rows = []
    for call, (bake, renamed) in CALLS.items():
        target = bake.split()[1]
        for name, default in keyword_defaults(call).items():
            if name in PYTHON_ONLY or default is inspect.Parameter.empty:
                continue
            rows.append((call, name, renamed.get(name, name), target, default))
    return rows


def test_the_table_gives_values_and_words():
    """The defaults in the table's "defaults" by target, worked out from
    SPEC sections 4, 5, 9 and 10 (the documented defaults of the flags)."""
    values = {k: (o["defaults"]["vertex"], o["defaults"]["atlas"]) for k, o in OPTIONS.items()
              if o["defaults"] != {"vertex": None, "atlas": None}}
    assert values == {
        "up": ("z", "z"), "size": ("2048", "2048"), "uv": ("auto", "auto"),
        "format": ("png8", "png8"), "ascii": ("false", "false"),
        "filter": ("area", "bilinear"), "samples": ("16", "4"),
        "visibility": ("first", "first"), "occluded": ("fill", "fill"),
        "outside": ("clamp", "clamp"), "wrap": ("clamp", "clamp"),
        "linear": ("false", "false"), "texture_colorspace": ("auto", "auto"),
        "cache_mb": ("1024", "1024"), "blend": ("soft", "soft"), "exposure": ("gain", "gain"),
        "no_alignment_check": ("false", "false"), "strict_photos": ("false", "false")}
    # Worked out by the job: in words.
    for key in ("target", "padding", "threads", "images", "center", "radius"):
        assert OPTIONS[key]["defaults"] == {"vertex": None, "atlas": None}, key
        assert OPTIONS[key]["default"], key


@pytest.mark.parametrize("call", list(CALLS), ids=lambda c: c.__name__)
def test_every_keyword_default_is_the_tables(call):
    bake = CALLS[call][0]
    rows = [r for r in table_keywords() if r[0] is call]
    assert rows, call.__name__
    for _, name, key, target, default in rows:
        assert key in OPTIONS, f"{call.__name__}({name}=): no job option {key!r}"
        # The option is one of this bake's (the table says where it applies).
        assert bake in OPTIONS[key]["bakes"], (call.__name__, name, OPTIONS[key]["bakes"])
        expected = IN_WORDS.get((call, name), table_value(key, target))
        assert default == expected and type(default) is type(expected), \
            (call.__name__, name, default, expected)
    for name, default in keyword_defaults(call).items():
        if name in PYTHON_ONLY:
            assert default == PYTHON_ONLY[name], (call.__name__, name)


def test_defaults_is_a_view_of_the_table():
    """texbake.DEFAULTS' bake groups equal the table's values (SPEC section
    4/5 documents them: filter area, 16 samples, visibility first, ...);
    render's and compare's are those commands' (SPEC section 7)."""
    d = texbake.DEFAULTS
    assert d["vertex"] == {"filter": "area", "samples": 16, "visibility": "first",
                           "occluded": "fill", "outside": "clamp", "linear": False,
                           "wrap": "clamp", "cache_mb": 1024}
    assert d["atlas"] == {"uv": "auto", "size": 2048, "samples": 4, "padding": None,
                          "filter": "bilinear", "visibility": "first", "occluded": "fill",
                          "outside": "clamp", "linear": False, "wrap": "clamp",
                          "cache_mb": 1024}
    assert d["photos"] == {"blend": "soft", "exposure": "gain", "occluded": "fill",
                           "colorspace": "auto"}
    assert d["layers"] == {"occluded": "fill", "cache_mb": 1024}
    assert d["render"]["size"] == (512, 512) and d["render"]["views"] == 1
    assert d["render"]["samples"] == 4 and d["render"]["view"] == (0, 20)


def test_a_default_changed_in_the_table_changes_the_calls():
    """The signatures are made from the table when the module loads: with the
    table's samples default changed (the binding's job_options patched before
    the package reads it), bake_vertex's and DEFAULTS' follow."""
    code = """
import glob, importlib.util, json, sys
sys.path.insert(0, sys.argv[1])
# The binding loaded on its own, patched, then the package over it.
path = glob.glob(sys.argv[1] + "/texbake/_texbake*.so")[0]
spec = importlib.util.spec_from_file_location("texbake._texbake", path)
native = importlib.util.module_from_spec(spec)
spec.loader.exec_module(native)
sys.modules["texbake._texbake"] = native
table = native.job_options()
for o in table:
    if o["key"] == "samples":
        o["defaults"] = {"vertex": "7", "atlas": "3"}
native.job_options = lambda: table
import inspect, texbake
print(json.dumps([inspect.signature(texbake.bake_vertex).parameters["samples"].default,
                  inspect.signature(texbake.bake_atlas).parameters["samples"].default,
                  texbake.DEFAULTS["vertex"]["samples"]]))
"""
    r = subprocess.run([sys.executable, "-c", code, str(BUILD / "python")], capture_output=True,
                       text=True, env=dict(os.environ, PYTHONDONTWRITEBYTECODE="1"))
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout) == [7, 3, 7]


def help_text(flag):
    """The description of `flag` in `texbake bake --help`, on one line."""
    r = run_cli("bake", "--help")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    start = next(i for i, l in enumerate(lines) if re.match(rf"\s+(-\w,)?{flag}\b", l))
    block = [lines[start]]
    for line in lines[start + 1:]:
        if re.match(r"\s+-", line) or not line.startswith(" "):
            break
        block.append(line)
    return " ".join(" ".join(block).split())


def stated_defaults(text):
    """The values a help text calls the default: "(default 2048, ...)",
    "(default: ...)", "png8 (default)", "fill (smooth ..., default)",
    "first: ... (default)"."""
    found = set(re.findall(r"\(default:? ([^\s,;)]+)", text))
    found |= set(re.findall(r"(\S+) \((?:[^()]*, )?default[):,]", text))
    found |= set(re.findall(r"(\w+): [^;:]*\(default\)", text))
    return found


def test_help_states_every_calls_defaults():
    """For every keyword of every call that the table gives a value, the
    flag's --help text names that value as the default (for the call's
    target where the text has a part per target, "...; atlas: ...")."""
    checked = 0
    for call, name, key, target, default in table_keywords():
        option = OPTIONS[key]
        value = option["defaults"][target]
        if value is None or option["type"] == "flag":
            continue  # words (checked above), or a flag: off unless given
        text = help_text(option["flag"])
        vertex_part, _, atlas_part = text.partition("atlas:")
        if option["defaults"]["vertex"] != option["defaults"]["atlas"]:
            text = atlas_part if target == "atlas" else vertex_part
        assert value in stated_defaults(text), (call.__name__, name, value, text)
        checked += 1
    assert checked >= 30
