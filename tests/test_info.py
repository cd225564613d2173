"""phmech.info() and phmech.blas_threads(): what the C core is linked against."""
import io
import os
import subprocess
import sys

import pytest

import phmech as ph


def test_info_names_the_libraries():
    buf = io.StringIO()
    d = ph.info(file=buf)
    # 6.x (Debian 12's 6.4.1, the default) or 7.x (make sundials7-check sets the major it built
    # against: docs/building.md)
    major = d["sundials"].split(".")[0]
    assert major in ("6", "7")
    assert major == os.environ.get("PHMECH_EXPECT_SUNDIALS_MAJOR", major)
    assert "KLU" in d["linear_solvers"]
    assert d["blas_threads"] in (None, 1)          # phmech sets one thread at import
    for key in ("phmech", "sundials", "lapack", "blas_threads", "numpy"):
        assert key in buf.getvalue()


def test_blas_threads_set_and_query():
    n = ph.blas_threads()
    if n is None:
        pytest.skip("the core's LAPACK is not OpenBLAS (single-threaded reference BLAS)")
    try:
        assert ph.blas_threads(2) == 2 and ph.blas_threads() == 2
    finally:
        assert ph.blas_threads(1) == 1


@pytest.mark.parametrize("bad", [-1, 1.5, "2", True])
def test_blas_threads_bad_input(bad):
    with pytest.raises(ph.ModelError):
        ph.blas_threads(bad)


def test_environment_variable_sets_the_count():
    if ph.blas_threads() is None:
        pytest.skip("the core's LAPACK is not OpenBLAS")
    env = dict(os.environ, PHMECH_BLAS_THREADS="2")
    out = subprocess.run([sys.executable, "-c", "import phmech; print(phmech.blas_threads())"],
                         env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "2"
    env["PHMECH_BLAS_THREADS"] = "many"
    bad = subprocess.run([sys.executable, "-c", "import phmech"], env=env, capture_output=True, text=True)
    assert bad.returncode != 0 and "PHMECH_BLAS_THREADS must be an integer" in bad.stderr


def test_one_version_number():
    """meson.build's project() version is the only place it is written: the core reports it,
    phmech.__version__ and info() read it, and meson-python puts it in the package metadata
    (pyproject.toml: dynamic = ["version"])."""
    import importlib.metadata
    import pathlib
    import re

    meson = pathlib.Path(__file__).resolve().parents[1] / "meson.build"
    written = re.search(r"project\([^)]*?version\s*:\s*'([^']+)'", meson.read_text()).group(1)
    assert ph.__version__ == written
    assert ph.info(file=io.StringIO())["phmech"] == ph.info(file=io.StringIO())["phmech_core"] == written
    assert importlib.metadata.version("phmech") == written
    text = (meson.parent / "pyproject.toml").read_text()
    assert 'dynamic = ["version"]' in text and not re.search(r"^version\s*=", text, re.M)
