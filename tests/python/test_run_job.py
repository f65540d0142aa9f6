"""Whole jobs from Python (texbake.run_job, texbake.run_batch) against the
command line: the same option table (texbake.JOB_OPTIONS is `texbake bake
--help`'s flags), the same bytes for every kind of job and target, the same
refusals with the same messages, and a batch whose per-job records equal
`texbake batch --results`'s."""
import json
import re

import pytest

import texbake
from conftest import DATA, run_cli

BUNNY = DATA / "bunny00.off"
EARTH = DATA / "earth.jpg"


def read(path):
    with open(path, "rb") as f:
        return f.read()


def bake_help_flags():
    """The long flags of `texbake bake --help` (without --help and --quiet)."""
    r = run_cli("bake", "--help")
    assert r.returncode == 0, r.stderr
    flags = set()
    for line in r.stdout.splitlines():
        m = re.match(r"  (-[^\s]*(?:,\s*-[^\s]*)*)", line)
        if m:
            flags.update(re.findall(r"--[a-z][a-z0-9-]*", m.group(1)))
    return flags - {"--help", "--quiet"}


def test_the_option_table_is_the_command_lines():
    keys = [o["key"] for o in texbake.JOB_OPTIONS]
    assert len(keys) == len(set(keys))
    flags = {o["flag"] for o in texbake.JOB_OPTIONS if o["flag"]}
    assert flags == bake_help_flags()
    for o in texbake.JOB_OPTIONS:
        if o["flag"]:
            assert o["flag"] == "--" + o["key"].replace("_", "-")
    by_key = {o["key"]: o for o in texbake.JOB_OPTIONS}
    assert by_key["samples"]["type"] == "integer"
    assert by_key["size"]["default"] == "2048"
    assert by_key["blend"]["bakes"] == ["photos vertex", "photos atlas"]
    assert by_key["linear"]["type"] == "flag"


@pytest.mark.parametrize("name, options", [
    ("v.ply", dict(proxy="sphere", up="y", samples=4)),
    ("v.glb", dict(proxy="sphere", center=(0, 0, 0), radius=1.0, pole=[0, 1, 0],
                   filter="bilinear", occluded=(1, 0, 0))),
    ("a.obj", dict(proxy="sphere", up="y", size=128, samples=2, uv="generate")),
    ("a.glb", dict(proxy="sphere", up="y", size=64, filter="ewa", linear=True)),
])
def test_a_proxy_job_writes_the_command_lines_bytes(tmp_path, name, options):
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    cli_out, py_out = tmp_path / "cli" / name, tmp_path / "py" / name
    args = []
    for key, value in options.items():
        flag = "--" + key.replace("_", "-")
        if value is True:
            args.append(flag)
        elif isinstance(value, (tuple, list)):
            args += [flag, ",".join(str(v) for v in value)]
        else:
            args += [flag, str(value)]
    r = run_cli("bake", BUNNY, "--texture", EARTH, *args, "--threads", "2", "-q",
                "--report", tmp_path / "cli" / "r.json", "-o", cli_out)
    assert r.returncode == 0, r.stderr
    result = texbake.run_job(BUNNY, py_out, texture=EARTH, threads=1,
                             report=tmp_path / "py" / "r.json", **options)
    assert result["outputs"][-1] == str(tmp_path / "py" / "r.json")
    assert len(result["outputs"]) == (4 if name.endswith(".obj") else 2)
    for cli_file, py_file in zip(sorted((tmp_path / "cli").iterdir()),
                                 sorted((tmp_path / "py").iterdir())):
        assert cli_file.name == py_file.name
        if cli_file.suffix in (".json", ".obj"):
            continue  # the report's paths and timings; the OBJ names its own MTL
        assert read(cli_file) == read(py_file), cli_file.name
    # The report: the same counts, as a dict.
    cli_report = json.loads((tmp_path / "cli" / "r.json").read_text())
    assert result["report"]["counts"] == cli_report["counts"]
    assert result["summary"].startswith("baked ")
    # The report's options are the table's keys, with the values the job used.
    keys = {o["key"] for o in texbake.JOB_OPTIONS}
    report_options = result["report"]["inputs"]["options"]
    assert set(report_options) <= keys, set(report_options) - keys
    if "samples" in options and name.endswith(".ply"):
        assert report_options["samples"] == options["samples"]


def test_a_layers_job_writes_the_command_lines_bytes(tmp_path):
    layers = DATA / "bottle_layers.json"
    mesh = DATA / "bottle.ply"
    for name in ("l.ply", "l.glb"):
        (tmp_path / "cli").mkdir(exist_ok=True)
        (tmp_path / "py").mkdir(exist_ok=True)
        size = ["--size", "128"] if name.endswith(".glb") else []
        r = run_cli("bake", mesh, "--layers", layers, "-q", "--threads", "2", *size, "-o",
                    tmp_path / "cli" / name)
        assert r.returncode == 0, r.stderr
        extra = dict(size=128) if name.endswith(".glb") else {}
        texbake.run_job(mesh, tmp_path / "py" / name, layers=layers, threads=2, **extra)
        assert read(tmp_path / "cli" / name) == read(tmp_path / "py" / name)


def test_refusals_raise_the_command_lines_message(tmp_path):
    out = tmp_path / "o.ply"
    cases = [
        (dict(proxy="sphere", size=64), "--size applies to --target atlas only"),
        (dict(proxy="sphere", samples=0), "--samples 0 is out of range (1 .. 65536)"),
        (dict(proxy="sphere", blend="best"), "--blend applies to --cameras only"),
        (dict(proxy="sphere", colour=1), "key 'colour' is not an option of texbake bake"),
        (dict(proxy="sphere", linear="yes"), "key 'linear': \"yes\" is not true or false"),
    ]
    for options, message in cases:
        with pytest.raises(ValueError) as e:
            texbake.run_job(BUNNY, out, texture=EARTH, **options)
        assert message in str(e.value)
        if not message.startswith("key"):  # the command line's flags: the same message, exit 2
            r = run_cli("bake", BUNNY, "--texture", EARTH, "-o", out,
                        *[a for k, v in options.items() for a in ("--" + k, str(v))])
            assert r.returncode == 2
            assert message in r.stderr
    assert not out.exists()
    # An input the job cannot read: OSError, nothing written.
    with pytest.raises(OSError) as e:
        texbake.run_job(tmp_path / "missing.ply", out, texture=EARTH, proxy="sphere")
    assert "missing.ply" in str(e.value)
    assert not out.exists()
    # No output may be an input.
    with pytest.raises(ValueError):
        texbake.run_job(BUNNY, EARTH, texture=EARTH, proxy="sphere", target="vertex")


def test_a_batch_equals_the_command_lines_batch(tmp_path):
    jobs = [
        dict(mesh=BUNNY, texture=EARTH, proxy="sphere", up="y", output=tmp_path / "a.ply"),
        dict(mesh=BUNNY, texture=EARTH, proxy="sphere", samples=0, output=tmp_path / "b.ply"),
        dict(mesh=BUNNY, texture=EARTH, proxy="cylinder", up="y", output=tmp_path / "c.ply"),
    ]
    batch = texbake.run_batch(jobs, results=tmp_path / "py.jsonl", threads=2)
    assert (batch["ok"], batch["failed"], batch["skipped"], batch["not_run"]) == (2, 1, 0, 0)
    assert [j["status"] for j in batch["jobs"]] == ["ok", "failed", "ok"]
    assert "--samples 0 is out of range" in batch["jobs"][1]["error"]
    assert batch["jobs"][1]["exit"] == 2
    py_lines = [json.loads(l) for l in (tmp_path / "py.jsonl").read_text().splitlines()]
    assert py_lines == batch["jobs"]
    py_bytes = {n: read(tmp_path / n) for n in ("a.ply", "c.ply")}

    # The same jobs through `texbake batch`: the same files and records.
    manifest = tmp_path / "jobs.jsonl"
    manifest.write_text("".join(
        json.dumps({k: str(v) if hasattr(v, "__fspath__") else v for k, v in j.items()}) + "\n"
        for j in jobs))
    r = run_cli("batch", manifest, "--results", tmp_path / "cli.jsonl", "--threads", "2", "-q")
    assert r.returncode == 1, r.stderr
    cli_lines = [json.loads(l) for l in (tmp_path / "cli.jsonl").read_text().splitlines()]
    for py, cli in zip(py_lines, cli_lines):
        for key in ("line", "status", "exit", "error", "warnings", "outputs", "counts"):
            assert py[key] == cli[key], key
    for n, b in py_bytes.items():
        assert read(tmp_path / n) == b

    # fail_fast stops at the failure; skip_existing skips what is up to date.
    fast = texbake.run_batch(jobs, fail_fast=True)
    assert (len(fast["jobs"]), fast["not_run"]) == (2, 1)
    again = texbake.run_batch(jobs, skip_existing=True)
    assert [j["status"] for j in again["jobs"]] == ["skipped", "failed", "skipped"]
