"""Hard cases, long versions: the published problems of tests/hard/_scenes.py on finer meshes,
longer runs and their full sizes (the short versions run in pytest, tests/hard/). Writes
benchmarks/results/hard_cases.json and prints the table of docs/validation.md.

    python benchmarks/hard_cases.py              # long versions (~5 min CPU on 2 shared cores)
    python benchmarks/hard_cases.py --short      # the pytest versions
    python benchmarks/hard_cases.py --only andrews four_bar
"""
from __future__ import annotations

import argparse
import io
import json
import os
import platform
import sys
import time
import traceback

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "tests", "hard"))
import _scenes as S  # noqa: E402

import phmech as ph  # noqa: E402


def _plain(x):
    """JSON-friendly copies of NumPy scalars and arrays (inf as the string 'inf')."""
    if isinstance(x, dict):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, np.ndarray):
        return _plain(x.tolist())
    if isinstance(x, (np.floating, float)):
        return float(x) if np.isfinite(x) else str(float(x))
    if isinstance(x, (np.integer, np.bool_)):
        return x.item()
    return x


def table(rows: list) -> str:
    """The markdown table of docs/validation.md."""
    lines = ["| case | source | reference | phmech | error (tolerance) | CPU s | ledger | notes |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "failed_with" in r:
            lines.append(f"| {r['case']} | | | raised {r['failed_with']} | | | | |")
            continue
        err = r["error"] if isinstance(r["error"], str) else f"{r['error']:.2g}"
        verdict = "" if r["passed"] else " **fails**"
        led = "n/a (static)" if r["ledger"] is None else (
            f"{r['ledger']:.1e}" + ("" if r["ledger_ok"] else " **> 1e-3**"))
        lines.append(f"| {r['case']} | {r['source']} | {r['reference']} | {r['value']} | "
                     f"{err} {r['unit']} ({r['tolerance']:g}){verdict} | {r['cpu']:.2f} | {led} | "
                     f"{r['notes']} |")
    return "\n".join(lines)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--short", action="store_true", help="the pytest versions")
    ap.add_argument("--only", nargs="*", help="case names (default: all)")
    ap.add_argument("--out", default=None, help="JSON file (default benchmarks/results/"
                    "hard_cases.json, or hard_cases_short.json with --short)")
    args = ap.parse_args(argv)
    cases = [c for c in S.CASES if not args.only or c.__name__ in args.only]
    rows = []
    for case in cases:
        t0 = time.time()
        try:
            with S.no_redundancy_warning():
                o = case(long=not args.short)
            row = o.row()
        except Exception as err:   # a case that raises is a finding too: record it
            row = dict(case=case.__name__, failed_with=f"{type(err).__name__}: {err}",
                       traceback=traceback.format_exc())
        row["wall"] = time.time() - t0
        rows.append(_plain(row))
        print(f"{row['case']}: " + (f"error {row.get('error')} (tol {row.get('tolerance')}), "
                                    f"CPU {row.get('cpu', 0):.2f} s, ledger {row.get('ledger')}"
                                    if "failed_with" not in row else row["failed_with"]),
              flush=True)
    findings = {}
    if not args.only:
        findings["elastica_default_load_steps"] = S.elastica_default_steps()
        findings["beck_modes_at_P10"] = S.beck_modes(10.0).tolist()
        findings["beck_simulated_omega_at_P10"] = S.beck_simulated_frequency(10.0)
        findings["swinging_strip"] = {f"dt_out {dt:g}": S.swinging_strip(dt) for dt in (0.05, 0.01, 0.005)}
    info = ph.info(file=io.StringIO())
    report = dict(version="short" if args.short else "long", date=time.strftime("%Y-%m-%d %H:%M"),
                  machine=dict(platform=platform.platform(), cpus=os.cpu_count(),
                               load_average=os.getloadavg(), note="shared with other developers"),
                  phmech=info, ledger_tolerance=S.LEDGER_TOL, cases=rows, findings=_plain(findings))
    out = args.out or os.path.join(os.path.dirname(os.path.abspath(__file__)), "results",
                                   "hard_cases_short.json" if args.short else "hard_cases.json")
    os.makedirs(os.path.dirname(out), exist_ok=True)
    with open(out, "w") as f:
        json.dump(report, f, indent=1)
    print()
    print(table(rows))
    if findings:
        print("\nfindings:", json.dumps(_plain(findings)))
    print(f"\nwritten {out}")
    return report


if __name__ == "__main__":
    main()
