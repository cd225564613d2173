"""The user guide's figures: docs/figures/NAME.png for every ``![...](figures/NAME.png)`` of
docs/user_guide.md, made by the guide's own code (the block above each figure ends with
``fig.savefig("NAME.png")``).

It runs the guide's python blocks in order, as tests/test_docs_examples.py does (one namespace,
a temporary directory, matplotlib's Agg backend), until every figure the guide shows has been
written, and copies those files here. Run it after changing such an example:

    .venv/bin/python docs/figures/make_figures.py

(about a minute: the blocks before the last figure run too). tests/test_docs_examples.py checks
that every figure the guide shows is written by one of its blocks and is in this directory.
"""
from __future__ import annotations

import os
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
PAGE = "docs/user_guide.md"


def main() -> int:
    """Write the guide's figures into docs/figures/; 0 on success."""
    sys.path.insert(0, str(ROOT / "tests"))
    from test_docs_examples import run_blocks, shown_figures

    import matplotlib
    matplotlib.use("Agg")
    matplotlib.rcParams.update({"figure.dpi": 100, "savefig.dpi": 100})
    names = shown_figures(PAGE)
    here = os.getcwd()
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        (work / "tests").symlink_to(ROOT / "tests")
        os.chdir(work)
        try:
            run_blocks(PAGE, stop=lambda: all((work / n).is_file() for n in names))
        finally:
            os.chdir(here)
        missing = [n for n in names if not (work / n).is_file()]
        for n in names:
            if n not in missing:
                shutil.copyfile(work / n, HERE / n)
                print(f"wrote {(HERE / n).relative_to(ROOT)}")
    if missing:
        print(f"{PAGE} shows figures no block writes: {', '.join(missing)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
