"""The command-line options the examples share (each adds its own after these)."""
import argparse
import os


def example_parser(doc: str, quick_help: str) -> argparse.ArgumentParser:
    """A parser with --quick, --json, --elements, --t-end, --rtol, --atol, --no-plot and --outdir
    (default: examples/output); ``doc``: the example's module docstring (its first line is the
    description)."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help=quick_help)
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--elements", type=int, default=None)
    ap.add_argument("--t-end", type=float, default=None)
    ap.add_argument("--rtol", type=float, default=None, help="default: phmech's")
    ap.add_argument("--atol", type=float, default=None, help="default: phmech's")
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--outdir", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "output"))
    return ap
