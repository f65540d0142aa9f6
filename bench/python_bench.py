"""Benchmarks of issue #15 (run: /usr/bin/python3 bench/python_bench.py [BUILD]):

1. Python call overhead: the bunny baked per vertex (Earth, the README's
   sphere) from Python vs the command line. Figures, median of REPEAT runs:
   - py_call: texbake.bake_vertex's wall time, and the API's own total
     (stats timings.total) inside it: their difference is the binding's cost
     (argument conversion, GIL, the result's numpy array);
   - py_job: read_mesh + read_image + bake_vertex + write_vertex_colors in
     Python, vs cli_job: the same job's `texbake bake --report` timings.total
     (the command's own time, without process start), and cli_wall (the
     whole process) with cli_start (`texbake --version`, process start);
     the two alternate run by run; py_cold is the Python job as the first
     of a fresh interpreter (one-time library start-up included).
2. Batch: 100 small jobs (mushroom, 2337 vertices, per vertex) as one shard
   with all threads vs two shards at once (GNU parallel,
   examples/batch/parallel.sh) with half the threads each: jobs per second.
"""
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
BUILD = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ROOT / "build")
sys.path.insert(0, str(BUILD / "python"))
import texbake  # noqa: E402

DATA = ROOT / "data"
TEXBAKE = str(BUILD / "texbake")
REPEAT = int(os.environ.get("REPEAT", "7"))
SPHERE = ["--proxy", "sphere", "--center", "0,0,0", "--radius", "1", "--pole", "0,1,0",
          "--equator", "0,0,1"]


def median_time(f, repeat=None):
    times = []
    for _ in range(repeat or REPEAT):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def call_overhead(tmp):
    mesh = texbake.read_mesh(DATA / "bunny00.off")
    image = texbake.read_image(DATA / "earth.jpg")
    proxy = texbake.Proxy.sphere(center=(0, 0, 0), radius=1, pole=(0, 1, 0), equator=(0, 0, 1))
    inner = []

    def call():
        _, stats = texbake.bake_vertex(mesh, image, proxy)
        inner.append(stats["timings"]["total"])

    py_call = median_time(call)
    api = statistics.median(inner)

    def job():
        m = texbake.read_mesh(DATA / "bunny00.off")
        img = texbake.read_image(DATA / "earth.jpg")
        colors, _ = texbake.bake_vertex(m, img, proxy)
        texbake.write_vertex_colors(tmp / "py.ply", m, colors)

    cli_totals = []

    def cli():
        subprocess.run([TEXBAKE, "bake", DATA / "bunny00.off", "--texture", DATA / "earth.jpg",
                        *SPHERE, "-q", "--report", tmp / "r.json", "-o", tmp / "cli.ply"],
                       check=True)
        cli_totals.append(json.loads((tmp / "r.json").read_text())["timings"]["total"])

    # The same Python job once in a fresh interpreter (its time inside, as
    # the CLI's report): what one-time library start-up (OpenImageIO's
    # plugins, Embree's device, oneTBB's threads) adds to a first job.
    cold_code = (
        "import sys, time; sys.path.insert(0, %r); import texbake; t = time.perf_counter(); "
        "m = texbake.read_mesh(%r); img = texbake.read_image(%r); "
        "p = texbake.Proxy.sphere(center=(0, 0, 0), radius=1, pole=(0, 1, 0), equator=(0, 0, 1)); "
        "c, _ = texbake.bake_vertex(m, img, p); texbake.write_vertex_colors(%r, m, c); "
        "print(time.perf_counter() - t)") % (str(BUILD / "python"), str(DATA / "bunny00.off"),
                                            str(DATA / "earth.jpg"), str(tmp / "cold.ply"))
    colds = [float(subprocess.run([sys.executable, "-c", cold_code], check=True,
                                  capture_output=True, text=True).stdout) for _ in range(REPEAT)]
    py_cold = statistics.median(colds)
    # Alternated, so that the load of a shared machine weighs on both alike.
    py_times, cli_walls = [], []
    for _ in range(REPEAT):
        py_times.append(median_time(job, 1))
        cli_walls.append(median_time(cli, 1))
    py_job, cli_wall = statistics.median(py_times), statistics.median(cli_walls)
    cli_job = statistics.median(cli_totals)
    cli_start = median_time(lambda: subprocess.run([TEXBAKE, "--version"], check=True,
                                                   capture_output=True))
    print(f"bake_vertex, bunny (37706 vertices), median of {REPEAT}:")
    print(f"  py_call  {py_call * 1e3:8.1f} ms   (API inside: {api * 1e3:.1f} ms, "
          f"binding cost {(py_call - api) * 1e3:.2f} ms = {100 * (py_call - api) / api:.2f} %)")
    print(f"  py_job   {py_job * 1e3:8.1f} ms   read + bake + write in Python")
    print(f"  py_cold  {py_cold * 1e3:8.1f} ms   the same, first job of a fresh interpreter")
    print(f"  cli_job  {cli_job * 1e3:8.1f} ms   the CLI's own total (--report): "
          f"py_job / cli_job = {py_job / cli_job:.3f}, py_cold / cli_job = {py_cold / cli_job:.3f}")
    print(f"  cli_wall {cli_wall * 1e3:8.1f} ms   whole process; process start "
          f"(texbake --version) {cli_start * 1e3:.1f} ms")


def batch(tmp):
    manifest = tmp / "jobs.jsonl"
    with open(manifest, "w") as f:
        for i in range(100):
            f.write(json.dumps({"mesh": str(DATA / "mushroom.off"),
                                "texture": str(DATA / "earth.jpg"), "proxy": "sphere",
                                "center": [0, 0, 0.5], "output": str(tmp / f"m{i:03d}.ply")})
                    + "\n")
    env = dict(os.environ, TEXBAKE=TEXBAKE)
    cores = os.cpu_count()

    def one():
        subprocess.run([TEXBAKE, "batch", manifest, "-q", "--threads", str(cores)], check=True)

    def two():
        subprocess.run([str(ROOT / "examples" / "batch" / "parallel.sh"), manifest, "2",
                        tmp / "r.jsonl", "-q"], check=True, env=env)

    t1, t2 = median_time(one), median_time(two)
    print(f"batch of 100 small jobs (mushroom, 2337 vertices), {cores} cores, median of {REPEAT}:")
    print(f"  1 shard,  {cores} threads:   {t1:6.2f} s  {100 / t1:6.1f} jobs/s")
    print(f"  2 shards, {max(1, cores // 2)} thread(s) each: {t2:6.2f} s  {100 / t2:6.1f} jobs/s"
          f"  ({t1 / t2:.2f}x)")


with tempfile.TemporaryDirectory() as d:
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    call_overhead(pathlib.Path(d))
    batch(pathlib.Path(d))
    print(f"load average after: {os.getloadavg()[0]:.2f}")
