"""The README's "Python" example runs as written and gives the CLI's bytes."""
import os
import re
import subprocess

from conftest import DATA, ROOT, run_cli


def readme_example():
    text = (ROOT / "README.md").read_text()
    section = text[text.index("\n## Python\n"):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_readme_example_runs_and_equals_the_cli(tmp_path, capfd):
    code = readme_example()
    assert len(code.strip().splitlines()) == 10
    os.symlink(DATA, tmp_path / "data")
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        exec(compile(code, "README.md", "exec"), {})
    finally:
        os.chdir(here)
    out = capfd.readouterr().out
    assert out.endswith(" occluded vertices filled\n") and int(out.split()[0]) > 0
    r = run_cli("bake", "data/bunny00.off", "--texture", "data/earth.jpg", "--proxy", "sphere",
                "--center", "0,0,0", "--radius", "1", "--pole", "0,1,0", "--equator", "0,0,1",
                "-q", "-o", "cli.ply", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "bunny.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
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
