"""cmake --install puts the package into the prefix's lib/python3/dist-packages,
where the Debian Python imports it and it works on its own."""
import os
import shutil
import subprocess

from conftest import BUILD, DATA


def test_install_into_a_prefix(tmp_path):
    prefix = tmp_path / "prefix"
    cmake = shutil.which("cmake")
    r = subprocess.run([cmake, "--install", str(BUILD), "--prefix", str(prefix)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    package = prefix / "lib" / "python3" / "dist-packages" / "texbake"
    assert (package / "__init__.py").is_file()
    assert any(p.name.startswith("_texbake") and p.suffix == ".so" for p in package.iterdir())
    code = ("import texbake; m = texbake.read_mesh(%r); "
            "c, s = texbake.bake_vertex(m, texbake.read_image(%r), texbake.Proxy.sphere(), "
            "filter='bilinear'); print(texbake.__file__, c.shape)") % (
                str(DATA / "mushroom.off"), str(DATA / "earth.jpg"))
    env = dict(os.environ, PYTHONPATH=str(package.parent))
    r = subprocess.run(["/usr/bin/python3", "-c", code], capture_output=True, text=True,
                       cwd=tmp_path, env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout == f"{package / '__init__.py'} (2337, 4)\n"
