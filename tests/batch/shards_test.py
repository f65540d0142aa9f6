"""ctest BatchShards (issue #15): a 20-job manifest with two bad jobs run as
two shards at once by GNU parallel (examples/batch/parallel.sh):
 - every good output equals the single command's output, byte for byte;
 - the merged results hold each line once, the bad ones failed with the
   single command's message;
 - a re-run with --skip-existing does no work (every good job skipped, no
   output rewritten).

usage: shards_test.py TEXBAKE DATA_DIR WORK_DIR
"""
import json
import os
import pathlib
import shutil
import subprocess
import sys

texbake, data, work = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
root = pathlib.Path(__file__).resolve().parents[2]
shutil.rmtree(work, ignore_errors=True)
(work / "batch").mkdir(parents=True)
(work / "single").mkdir()
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


# 18 good jobs: three small meshes, vertex and atlas targets, fitted and
# given proxies; line 7 names a missing mesh, line 14 a missing image.
meshes = ["mushroom.off", "elephant.off", "fandisk.off"]
variants = [
    {"proxy": "sphere", "ext": ".ply"},
    {"proxy": "sphere", "up": "y", "samples": 4, "ext": ".ply"},
    {"proxy": "cylinder", "visibility": "all", "ext": ".ply"},
    {"proxy": "sphere", "uv": "proxy", "size": 64, "ext": ".obj"},
    {"proxy": "disk", "center": [0, 0, 0], "filter": "bilinear", "ext": ".ply"},
    {"proxy": "sphere", "center": [0, 0, 0.1], "occluded": "1,0,0", "ext": ".glb", "target": "vertex"},
]
jobs = []
for i in range(20):
    line = i + 1
    if line == 7:
        jobs.append({"mesh": str(work / "missing.off"), "texture": str(data / "earth.jpg"),
                     "proxy": "sphere", "output": "{dir}/job07.ply"})
        continue
    if line == 14:
        jobs.append({"mesh": str(data / "mushroom.off"), "texture": str(work / "missing.png"),
                     "proxy": "sphere", "output": "{dir}/job14.ply"})
        continue
    v = dict(variants[i % len(variants)])
    ext = v.pop("ext")
    job = {"mesh": str(data / meshes[i % 3]), "texture": str(data / "earth.jpg")}
    job.update(v)
    job["output"] = "{dir}/job%02d%s" % (line, ext)
    jobs.append(job)


def argv_of(job, folder):
    """The single command of a job: texbake bake MESH --key value ..."""
    args = [texbake, "bake", job["mesh"]]
    for k, v in job.items():
        if k == "mesh":
            continue
        if k == "output":
            v = v.format(dir=folder)
        if isinstance(v, list):
            v = ",".join(str(x) for x in v)
        args += ["--" + k.replace("_", "-"), str(v)]
    return args + ["-q"]


manifest = work / "jobs.jsonl"
with open(manifest, "w") as f:
    for job in jobs:
        j = dict(job, output=job["output"].format(dir=work / "batch"))
        f.write(json.dumps(j) + "\n")

env = dict(os.environ, TEXBAKE=texbake)
script = str(root / "examples" / "batch" / "parallel.sh")
results = work / "results.jsonl"
run = subprocess.run([script, str(manifest), "2", str(results)], env=env, capture_output=True,
                     text=True)
print(run.stderr, file=sys.stderr)
check(run.returncode == 1, f"two bad jobs: exit 1 (got {run.returncode})")
merged = [json.loads(l) for l in results.read_text().splitlines()]
check([r["line"] for r in merged] == list(range(1, 21)), "each line once in the merged results")
by_line = {r["line"]: r for r in merged}

for i, job in enumerate(jobs):
    line = i + 1
    single = subprocess.run(argv_of(job, work / "single"), capture_output=True, text=True)
    if line in (7, 14):
        check(by_line[line]["status"] == "failed", f"line {line} failed")
        message = single.stderr.splitlines()[-1].removeprefix("texbake: error: ")
        check(single.returncode == 1 and by_line[line]["error"] == message,
              f"line {line}: the single command's message {message!r}")
        check(f"{manifest}:{line}: {message}" in run.stderr, f"line {line} reported by number")
        continue
    check(single.returncode == 0, f"line {line}: single run: {single.stderr}")
    check(by_line[line]["status"] == "ok", f"line {line} ok")
    outputs = [pathlib.Path(p) for p in by_line[line]["outputs"]]
    check(len(outputs) == (3 if job["output"].endswith(".obj") else 1), f"line {line}: outputs")
    for p in outputs:
        other = work / "single" / p.name
        check(p.read_bytes() == other.read_bytes(), f"line {line}: {p.name} equals the single run's")

# A re-run with --skip-existing does no work.
stamps = {p: p.stat().st_mtime_ns for p in (work / "batch").iterdir()}
again = work / "again.jsonl"
rerun = subprocess.run([script, str(manifest), "2", str(again), "--skip-existing"], env=env,
                       capture_output=True, text=True)
check(rerun.returncode == 1, "the re-run still fails the two bad jobs")
statuses = [json.loads(l)["status"] for l in again.read_text().splitlines()]
check(statuses == ["failed" if n in (7, 14) else "skipped" for n in range(1, 21)],
      f"re-run: 18 skipped, 2 failed (got {statuses})")
check({p: p.stat().st_mtime_ns for p in (work / "batch").iterdir()} == stamps,
      "re-run rewrote no output")

if failures:
    sys.exit(f"{len(failures)} check(s) failed")
shutil.rmtree(work, ignore_errors=True)
print("BatchShards: all checks passed")
