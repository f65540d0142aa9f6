"""The Python examples of the documentation run as written and give the CLI's
bytes: the full one in docs/python.md and the short one in the README."""
import os
import re
import subprocess

from conftest import DATA, ROOT, run_cli


def python_example(name):
    """The first ```python block of the file `name` (relative to the root)."""
    text = (ROOT / name).read_text()
    return re.search(r"```python\n(.*?)```", text, re.S).group(1)


def run_example(code, name, tmp_path):
    """Runs `code` in tmp_path (with data/ linked in), as a user would."""
    os.symlink(DATA, tmp_path / "data")
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        exec(compile(code, name, "exec"), {})
    finally:
        os.chdir(here)


def cli_vertex_bake(tmp_path):
    """The README's per-vertex bake through the CLI, into tmp_path/cli.ply."""
    r = run_cli("bake", "data/bunny00.off", "--texture", "data/earth.jpg", "--proxy", "sphere",
                "--center", "0,0,0", "--radius", "1", "--pole", "0,1,0", "--equator", "0,0,1",
                "-q", "-o", "cli.ply", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    return (tmp_path / "cli.ply").read_bytes()


def test_readme_example_runs_and_equals_the_cli(tmp_path):
    code = python_example("README.md")
    assert len(code.strip().splitlines()) == 6
    run_example(code, "README.md", tmp_path)
    assert (tmp_path / "bunny.ply").read_bytes() == cli_vertex_bake(tmp_path)


def test_python_docs_example_runs_and_equals_the_cli(tmp_path, capfd):
    code = python_example("docs/python.md")
    assert len(code.strip().splitlines()) == 10
    run_example(code, "docs/python.md", tmp_path)
    out = capfd.readouterr().out
    assert out.endswith(" occluded vertices filled\n") and int(out.split()[0]) > 0
    assert (tmp_path / "bunny.ply").read_bytes() == cli_vertex_bake(tmp_path)
    r = run_cli("bake", "data/bunny00.off", "--texture", "data/earth.jpg", "--proxy", "sphere",
                "--center", "0,0,0", "--radius", "1", "--pole", "0,1,0", "--equator", "0,0,1",
                "--uv", "generate", "--size", "512", "-q", "-o", "cli.obj", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "bunny.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def test_help_reads_like_the_readme():
    import texbake
    doc = texbake.__doc__
    assert "bake 2D images onto 3D meshes" in doc and "ValueError" in doc
    for name in texbake.__all__:
        assert getattr(texbake, name).__doc__, name
