"""The self-contained binary wheel (`make wheel`): installed into a fresh venv, it imports, runs
the demo and takes every shared library beyond glibc from inside itself (phmech.libs/), not from
the Debian development packages this machine happens to have.

Slow-ish (~1 min: the wheel is built in the venv's build directory build/py, the venv's PyPI packages come from pip's
cache), so it is one test that checks all three."""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# what a manylinux wheel may take from the system (auditwheel's policy: glibc's libraries, the
# dynamic loader, libgcc_s); everything else must be bundled
SYSTEM_OK = re.compile(r"^(linux-vdso|ld-linux|libc|libm|libpthread|libdl|librt|libgcc_s)\b")

pytestmark = pytest.mark.skipif(not (ROOT / "Makefile").is_file() or shutil.which("make") is None,
                                reason="needs the source tree (make wheel)")


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    assert r.returncode == 0, f"{cmd} failed ({r.returncode}):\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
    return r.stdout


def test_wheel_installs_runs_and_bundles_its_libraries(tmp_path):
    run(["make", "-s", "wheel"], cwd=ROOT)
    wheels = sorted((ROOT / "dist").glob("phmech-*manylinux*_x86_64.whl"))
    assert len(wheels) == 1, wheels

    venv = tmp_path / "venv"
    run([sys.executable, "-m", "venv", str(venv)])
    py = venv / "bin" / "python"
    run([str(py), "-m", "pip", "install", "-q", str(wheels[0])])

    # from a folder outside the source tree, so that nothing but the installed wheel is imported
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "LD_LIBRARY_PATH")}
    env["MPLBACKEND"] = "Agg"
    out = run([str(py), "-c", "import phmech; phmech.info(); print('FILE', phmech.__file__)"],
              cwd=tmp_path, env=env)
    installed = Path(out.split("FILE", 1)[1].strip()).parent
    assert installed.is_relative_to(venv), installed
    demo = tmp_path / "leaf_spring.py"
    shutil.copy(ROOT / "examples" / "leaf_spring.py", demo)
    shutil.copy(ROOT / "examples" / "_cli.py", tmp_path / "_cli.py")
    out = run([str(py), str(demo), "--quick"], cwd=tmp_path, env=env)
    assert "Hz" in out

    # every library the extension loads, beyond glibc's, resolves inside the wheel's phmech.libs
    core = next(installed.glob("_core*.so"))
    ldd = run(["ldd", str(core)], env=env)
    bundled = installed.parent / "phmech.libs"
    resolved = [ln.split() for ln in ldd.splitlines() if "=>" in ln]
    outside = [ln for ln in resolved if not SYSTEM_OK.match(ln[0])
               and not Path(ln[2]).resolve().is_relative_to(bundled.resolve())]
    assert not outside, f"libraries taken from the system, not the wheel:\n{ldd}"
    names = " ".join(ln[0] for ln in resolved)
    for lib in ("libsundials_ida", "libklu", "liblapack"):
        assert lib in names, ldd
