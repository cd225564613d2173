"""The docs' Python code blocks run as written, so the guide cannot rot.

Every fenced ``python`` block of each page in PAGES runs in order in one namespace per page (a
block may use the names an earlier block of the same page defined), in a temporary working
directory (blocks that write files write there; ``tests/`` is linked into it, for the files the
guide reads), with matplotlib's non-interactive backend. A block that needs objects a reader
would have from elsewhere (a body, a mechanism of an earlier section) gets them from an HTML
comment just above its fence, hidden in the rendered page::

    <!-- docs-test-setup
    body = m.add_rigid_body("body", 1.0, 1e-3 * np.eye(3))
    -->

A block that is not meant to run is fenced ``text`` or ``pycon`` instead. Run alone:
``.venv/bin/python -m pytest -q tests/test_docs_examples.py``.
"""
from __future__ import annotations

import os
import re
import warnings
from pathlib import Path
from typing import Callable, Optional

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: pages whose python blocks are run, relative to the repository
PAGES = ("docs/user_guide.md",)

_FENCE = re.compile(r"(?:^<!-- docs-test-setup[ \t]*\n(?P<setup>.*?)^-->[ \t]*\n\s*)?"
                    r"^```python[ \t]*\n(?P<code>.*?)^```[ \t]*$", re.S | re.M)


def code_blocks(page: str) -> list[tuple[int, str]]:
    """The page's python blocks as (first line number of the code, source), in page order; a
    block's hidden setup (see the module's docstring) comes first in its source."""
    text = (ROOT / page).read_text(encoding="utf-8")
    return [(text.count("\n", 0, m.start("code")) + 1, (m.group("setup") or "") + m.group("code"))
            for m in _FENCE.finditer(text)]


def run_blocks(page: str, stop: Optional[Callable[[], bool]] = None) -> None:
    """Run the page's python blocks in order in one namespace, in the current directory (which
    should hold a link ``tests`` to the repository's tests/, for the files the guide reads), with
    warnings silenced; after each block, ``stop()`` (if given) may end the run early. A failing
    block raises AssertionError naming the page and the block's line. Also used by
    docs/figures/make_figures.py, which keeps the PNGs the blocks write."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    blocks = code_blocks(page)
    assert blocks, f"{page}: no python blocks found"
    ns: dict = {"__name__": "__docs__"}
    for line, src in blocks:
        code = compile(src, f"{page}:{line}", "exec")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                exec(code, ns)
            except Exception as exc:  # the block's page and line in the failure
                raise AssertionError(f"{page}, block at line {line}: {exc!r}") from exc
        if stop is not None and stop():
            break
    plt.close("all")


#: a figure the guide shows, ![...](figures/NAME.png): docs/figures/NAME.png
_SHOWN = re.compile(r"!\[[^\]]*\]\(figures/(?P<name>[\w.-]+\.png)\)")


def shown_figures(page: str) -> list[str]:
    """The file names of the figures ``page`` shows from docs/figures/, in page order."""
    return [m.group("name") for m in _SHOWN.finditer((ROOT / page).read_text(encoding="utf-8"))]


@pytest.mark.parametrize("page", PAGES)
def test_page_blocks_run(page: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "tests").symlink_to(ROOT / "tests")
    monkeypatch.chdir(tmp_path)
    run_blocks(page)
    # the figures the page shows are those its blocks write (docs/figures/make_figures.py
    # copies them there)
    for name in shown_figures(page):
        assert (tmp_path / name).is_file(), f"{page}: no block writes {name}, which it shows"


@pytest.mark.parametrize("page", PAGES)
def test_shown_figures_are_in_the_repository(page: str) -> None:
    for name in shown_figures(page):
        assert (ROOT / "docs" / "figures" / name).is_file(), \
            f"{page} shows figures/{name}: run docs/figures/make_figures.py"
