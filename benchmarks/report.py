"""The markdown tables of README.md, docs/performance.md and docs/perf_*.md from the stored results.

    python benchmarks/report.py [--results DIR] [--only transient whip modes scaling leaf modal scenes large overhead]
    python benchmarks/report.py --write-docs      # rewrite the marked blocks of the docs in place

Reads benchmarks/results/*.json (written by `make bench` or `make bench BENCH_ARGS=--quick`) and
prints, per benchmark, the command and date of its run and its table (nothing here measures). A
missing result file is reported, not an error. ``--write-docs`` replaces, in README.md and
docs/performance.md, docs/perf_*.md, the text between ``<!-- report:NAME -->`` and
``<!-- /report:NAME -->`` by part NAME (``headline``: README's one-paragraph summary), so a
rerun's figures reach the docs in one command (`make bench` runs it).
"""
from __future__ import annotations

import argparse
import json
import os
import time

HERE = os.path.dirname(os.path.abspath(__file__))
LEVELS = ["1e-02", "3e-03", "1e-03", "3e-04"]


def load(results: str, name: str):
    path = os.path.join(results, name)
    if not os.path.exists(path):
        return None, None
    with open(path) as f:
        return json.load(f), path


def header(d: dict, path: str, default_cmd: str) -> str:
    m = d.get("machine", {}) if isinstance(d, dict) else {}
    date = m.get("date_utc") or time.strftime("%Y-%m-%d %H:%M", time.gmtime(os.path.getmtime(path))) + " (file time)"
    cmd = m.get("command") or default_cmd
    mode = " --smoke" if d.get("smoke") and "--smoke" not in cmd else ""
    src = os.path.relpath(path, os.path.dirname(HERE))
    src = path if src.startswith("..") else src
    ver = ", ".join(f"{k} {m[k]}" for k in ("phmech", "git_head", "exudyn", "mujoco", "pyelastica") if m.get(k))
    return (f"Run: `python benchmarks/{cmd}`{mode} on {date} UTC ({m.get('cpus', '?')} CPUs, {m.get('cpu_model', '?')};"
            f" {ver}). Source: `{src}`.")


def ms(x) -> str:
    return "--" if x is None else f"{x * 1e3:.3g} ms" if x < 1 else f"{x:.3g} s"


def cell(row: dict, g: str, key: str = "cpu_s") -> str:
    c = (row or {}).get(g)
    if not c or key not in c:
        return "not reached"
    p = c[key + "_point"]
    what = ", ".join(f"{k} {p[k]:g}" if isinstance(p[k], float) else f"{k} {p[k]}"
                     for k in ("N", "h", "rtol", "step") if k in p)
    return f"{ms(c[key])} ({p.get('variant', '')}, {what})"


def ratio(row: dict, a: str, b: str, key: str = "cpu_s") -> str:
    ca, cb = (row or {}).get(a), (row or {}).get(b)
    if not ca or not cb or key not in ca or key not in cb:
        return "--"
    return f"{ca[key] / cb[key]:.2g}"


def level_table(d: dict, cols: list, ratios: list, key: str) -> list:
    out = ["| error / L | " + " | ".join(cols) + " | " + " | ".join(f"{a} / {b}" for a, b in ratios) + " |",
           "|---" * (1 + len(cols) + len(ratios)) + "|"]
    for lev in LEVELS:
        row = d["cheapest_at_level"].get(lev, {})
        out.append(f"| {lev} | " + " | ".join(cell(row, g, key) for g in cols) + " | "
                   + " | ".join(ratio(row, a, b, key) for a, b in ratios) + " |")
    return out


def transient(results: str) -> list:
    d, path = load(results, "bench_transient.json")
    if d is None:
        return ["(no bench_transient.json)"]
    ref = d["reference"]
    sc = ref["self_convergence"]
    lines = ["### Released cantilever (Table I beam, tip force released)", "", header(d, path, "run.py"), "",
             f"Problem: {d['problem']}. Error: {d['error']}. Reference: {ref['code']}, IDA rtol {ref['rtol']:g} on "
             f"N = {ref['N']}, Richardson-extrapolated; its own convergence: N/2 vs N {sc['space_N_half_vs_N']:.1e} L, "
             f"Richardson correction {sc['richardson_correction']:.1e} L, consistent-mass N vs reference "
             f"{sc['consistent_mass_N_vs_reference']:.1e} L (an independent discretization).", ""]
    # MuJoCo's cable converges to another beam (no shear, inextensible): no matched-error column
    peers = [g for g in ("exudyn-ge2d", "exudyn-ge3d", "pyelastica")]
    lines += ["Total CPU (build + static + integration; cheapest measured point reaching the level):", ""]
    lines += level_table(d, ["phmech", "phmech-default", "phmech-3d", "exudyn-ge2d", "exudyn-ge2d-dense",
                             "exudyn-ge2d-sparse"],
                         [("phmech", "exudyn-ge2d"), ("phmech-default", "exudyn-ge2d"),
                          ("phmech-3d", "exudyn-ge2d")], "cpu_s")
    lines += ["", "Integration CPU only (PyElastica has no static solver: its initial state is a damped "
              "relaxation, not counted; MuJoCo's cable is left out: it converges to another beam, below):", ""]
    lines += level_table(d, ["phmech"] + peers, [("phmech", p) for p in peers], "sim_cpu_s")
    # where each peer's error stops (its most accurate point)
    best, finest = {}, {}
    for r in d["runs"]:
        if "error" in r:
            k = r["code"] + " " + r["variant"].split("-")[0]
            if k not in best or r["error"] < best[k]["error"]:
                best[k] = r
            if k not in finest or (r["N"], -r["error"]) > (finest[k]["N"], -finest[k]["error"]):
                finest[k] = r
    lines += ["", "Each code's most accurate point, and its best point on its finest mesh (where a model that "
              "converges elsewhere shows its distance): " + "; ".join(
                  f"{k} {r['error']:.1e} L (N {r['N']}), finest N {finest[k]['N']}: {finest[k]['error']:.1e} L"
                  for k, r in sorted(best.items())) + "."]
    return lines


def whip(results: str) -> list:
    d, path = load(results, "bench_whip.json")
    if d is None:
        return ["(no bench_whip.json)"]
    ref = d["reference"]
    lines = ["### Rod whipped by its driven base", "", header(d, path, "run.py --only whip"), "",
             f"Problem: {d['problem']}. Error: {d['error']}. Reference: {ref['code']}, rtol {ref['rtol']:g}, "
             f"N = {ref['N']}, Richardson; N/2 vs N {ref['self_convergence']['space_N_half_vs_N']:.1e} L.", ""]
    lines += ["Integration CPU (all three start from rest):", ""]
    lines += level_table(d, ["phmech", "exudyn-ge2d", "pyelastica"],
                         [("phmech", "exudyn-ge2d"), ("phmech", "pyelastica")], "sim_cpu_s")
    return lines


def modes(results: str) -> list:
    d, path = load(results, "bench_modes.json")
    if d is None:
        return ["(no bench_modes.json)"]
    r = d["cpu_ratio_at_equal_error"]
    lines = ["### Cantilever modes (first five, Table I)", "", header(d, path, "run.py --only modes"), "",
             "| error | se3 (consistent) / Exudyn GE2D | se3 (lumped) / Exudyn GE2D | mixed / Exudyn GE2D |",
             "|---|---|---|---|"]
    for lev in ["1e-01", "3e-02", "1e-02", "3e-03", "1e-03"]:
        f = lambda k: "--" if not (r.get(k) or {}).get(lev) else f"{r[k][lev]['ratio']:.2f}"  # noqa: E731
        lines.append(f"| {lev} | {f('se3_consistent_over_exudyn')} | {f('se3_over_exudyn')} | {f('mixed_over_exudyn')} |")
    lines += ["", "| N | " + " | ".join(d["runs"]) + " |", "|---" * (1 + len(d["runs"])) + "|"]
    for i, N in enumerate(x["N"] for x in next(iter(d["runs"].values()))):
        lines.append(f"| {N} | " + " | ".join(
            f"{ms(rs[i]['cpu_s'])}, {rs[i]['max_abs_rel_error']:.1e}" if rs[i]["max_abs_rel_error"] is not None
            else ms(rs[i]["cpu_s"]) for rs in d["runs"].values()) + " |")
    return lines


def scaling(results: str) -> list:
    d, path = load(results, "bench_scaling.json")
    if d is None:
        return ["(no bench_scaling.json)"]
    lines = ["### Element and chain scaling", "", header(d, path, "bench_scaling.py"), "",
             f"{d['rate']}; output period {d.get('dt_out', 'T-dependent (before issue 31)')} s "
             "(fixed: the default integrator's band is the same for T and T/5).", ""]
    for prefix, title in (("", "elements N"), ("chain-", "bodies n")):
        codes = sorted({r["code"] for r in d["runs"] if r["code"].startswith("chain-") == (prefix == "chain-")})
        sizes = sorted({r["size"] for r in d["runs"] if r["code"] in codes})
        lines += [f"| {title} | " + " | ".join(str(s) for s in sizes) + " | exponent |",
                  "|---" * (2 + len(sizes)) + "|"]
        for c in codes:
            by = {r["size"]: r for r in d["runs"] if r["code"] == c}
            def val(r):
                v = f"{r['cpu_per_sim_s']:.3g}"
                return v + (f" ({r['error_m']:.0e} m)" if "error_m" in r else "")
            f = d["fits"].get(c, {}).get("cpu_exponent")
            lines.append(f"| {c} | " + " | ".join(val(by[s]) if s in by else "--" for s in sizes)
                         + f" | {'--' if f is None else f'{f:.2f}'} |")
        lines.append("")
    lines.append("CPU s per simulated s; chain: (max link-end error at T against "
                 + (d["chain_reference"][0]["code"] if d.get("chain_reference") else "?") + ").")
    for code in ("chain-phmech-default", "chain-phmech-klu", "chain-phmech-tree"):
        m = chain_matched(d, code)
        if m:
            lines += ["", f"{code} over the cheapest MuJoCo run at or below its error: "
                      + ", ".join(f"n = {n}: {r:.2f} (error {e:.0e} m, {c})" for n, r, e, c in m) + "."]
    lv = chain_levels(d)
    if lv:
        groups = list(CHAIN_GROUPS)
        lines += ["", "Chain at matched error: CPU s per simulated s of each ladder (the codes' settings) "
                  "interpolated in log-log at the level (-- outside a ladder's measured errors), and the "
                  "ratios to MuJoCo RK4:", "",
                  "| n | error [m] | " + " | ".join(groups) + " | " + " | ".join(f"{g} / {groups[-1]}" for g in groups[:-1]) + " |",
                  "|---" * (2 + 2 * len(groups) - 1) + "|"]
        for n, lev, row in lv:
            rk = row.get(groups[-1])
            lines.append(f"| {n} | {lev:.0e} | " + " | ".join(f"{row[g]:.3g}" if row.get(g) else "--" for g in groups)
                         + " | " + " | ".join(f"{row[g] / rk:.2f}" if row.get(g) and rk else "--" for g in groups[:-1]) + " |")
    return lines


#: the chain's ladders (benchmarks/bench_scaling.py) and the levels they are compared at [m]
CHAIN_GROUPS = {"phmech default": lambda c: c.startswith("chain-phmech-default"),
                "phmech IDA (KLU)": lambda c: c.startswith("chain-phmech-klu"),
                "phmech tree": lambda c: c.startswith("chain-phmech-tree"),
                "MuJoCo RK4": lambda c: c == "chain-mujoco" or c.startswith("chain-mujoco-rk4")}
#: the group of CHAIN_GROUPS the others' ratios are to
CHAIN_PEER = "MuJoCo RK4"
CHAIN_LEVELS = (1e-6, 3e-7, 1e-7, 3e-8)


def rate_at_error(runs: list, pred, n: int, level: float):
    """CPU per simulated second of the runs of size n whose code satisfies pred, at link-end error
    ``level`` [m]: log-log interpolation between the two neighbouring measured errors that bracket
    it (None outside them: no extrapolation)."""
    import math
    pts = sorted((r["error_m"], r["cpu_per_sim_s"]) for r in runs
                 if pred(r["code"]) and r["size"] == n and r.get("error_m", 0) > 0)
    for (e0, c0), (e1, c1) in zip(pts, pts[1:]):
        if e0 <= level <= e1:
            w = math.log(level / e0) / math.log(e1 / e0) if e1 > e0 else 0.0
            return math.exp(math.log(c0) + w * (math.log(c1) - math.log(c0)))
    return next((c for e, c in pts if e == level), None)


def chain_levels(sc: dict) -> list:
    """(n, level, {group: CPU s/s at that error}) for every chain size and CHAIN_LEVELS level
    where MuJoCo RK4's ladder and at least one of phmech's bracket the level."""
    out = []
    for n in sorted({r["size"] for r in sc["runs"] if r["code"].startswith("chain-")}):
        for lev in CHAIN_LEVELS:
            row = {g: rate_at_error(sc["runs"], p, n, lev) for g, p in CHAIN_GROUPS.items()}
            if row[CHAIN_PEER] and any(v for g, v in row.items() if g != CHAIN_PEER):
                out.append((n, lev, row))
    return out


def chain_matched(sc: dict, code: str = "chain-phmech-default") -> list:
    """Per chain size: (n, rate(code) / rate(cheapest MuJoCo run with error_m <= code's), code's
    error, that MuJoCo run's code)."""
    out = []
    for n in sorted({r["size"] for r in sc["runs"] if r["code"] == code}):
        ph = next(r for r in sc["runs"] if r["code"] == code and r["size"] == n)
        if "error_m" not in ph:
            continue
        mj = [r for r in sc["runs"] if r["code"].startswith("chain-mujoco") and r["size"] == n
              and r.get("error_m", 1e9) <= ph["error_m"]]
        if mj:
            b = min(mj, key=lambda r: r["cpu_per_sim_s"])
            out.append((n, ph["cpu_per_sim_s"] / b["cpu_per_sim_s"], ph["error_m"], b["code"]))
    return out


def leaf(results: str) -> list:
    d, path = load(results, "bench_leaf_spring.json")
    if d is None:
        return ["(no bench_leaf_spring.json)"]
    lines = ["### Leaf spring, first frequency", "", header(d, path, "bench_leaf_spring.py"), "",
             f"f_ref = {d['reference']['f_ref']:.7f} Hz (+- {d['reference']['f_ref_rel_uncertainty']:.1e} rel). "
             "Cheapest point reaching each level (CPU = build + simulate + FFT; modal: build + modes(1)):", "",
             "| error | " + " | ".join(f"FFT {r}" for r in d["fft_routes"]) + " | modal |",
             "|---" * (2 + len(d["fft_routes"])) + "|"]
    for lev in ("1e-02", "1e-03", "1e-04"):
        def c(x):
            x = (x or {}).get("cheapest")
            return "not reached" if not x else f"{ms(x['cpu_s'])} (N {x['N']}, {x['rel_error']:.1e})"
        lines.append(f"| {lev} | " + " | ".join(c(r["cheapest"].get(lev)) for r in d["fft_routes"].values())
                     + f" | {c(d['modal_route']['cheapest'].get(lev))} |")
    return lines


def modal(results: str) -> list:
    d, path = load(results, "bench_modal.json")
    if d is None:
        return ["(no bench_modal.json)"]
    lines = ["### Leaf spring with modal leaves", "", header(d, path, "bench_modal.py"), "",
             "| leaves | N | band [Hz] | CPU | error | steps |", "|---|---|---|---|---|---|"]
    for r in d["runs"]:
        lines.append(f"| {r['fidelity']} | {r['elements']} | {r['band_hz']} | {ms(r['cpu_s'])} | {r['error']:.1e} | {r['steps']} |")
    dw = d["done_when"]
    lines += ["", f"Modal leaves ({dw['elements']} elements, modes {dw['modes_per_leaf']}), simulate(10, 1e-2, "
              f"band=10): thread CPU {ms(dw['thread_cpu_s'])} (median), error {dw['error']:.1e}."]
    return lines


def newer_run(results: str, stem: str):
    """(data, path, command) of the newer of ``stem``.json and ``stem``_quick.json, by the date
    each stores (a run without one: before issue 31, counts as oldest); data None if neither."""
    d, path = load(results, f"{stem}.json")
    name = f"{stem}.py"
    dq, pq = load(results, f"{stem}_quick.json")
    date = lambda x: (x or {}).get("machine", {}).get("date_utc", "")  # noqa: E731
    if dq is not None and (d is None or date(dq) > date(d)):
        d, path, name = dq, pq, f"{stem}.py --quick"
    return d, path, name


def scenes(results: str) -> list:
    d, path, name = newer_run(results, "scenes")
    if d is None:
        return ["(no scenes.json)"]
    lines = ["### Scenes (default integrator)", "", header(d, path, name), "",
             "| scene | t [s] | CPU | CPU/s | steps | error/scale | error/(rtol scale + atol) |",
             "|---|---|---|---|---|---|---|"]
    for r in d["scenes"]:
        et = r.get("error_vs_tolerance")
        lines.append(f"| {r['scene']} | {r['t_end']:g} | {ms(r['cpu_s'])} | {r['cpu_per_s']:.3g} | {r['steps']} | "
                     f"{r['error']:.1e} | {'-' if et is None else f'{et:.2f}'} |")
    return lines


def headline(results: str) -> list:
    """README's summary: the released cantilever's and the whip's ratios, modes, chain n = 30/100."""
    d, path = load(results, "bench_transient.json")
    w, _ = load(results, "bench_whip.json")
    sc, _ = load(results, "bench_scaling.json")
    if d is None:
        return ["(no bench_transient.json: run `make bench`)"]
    m = d["machine"]
    def rr(doc, a, b, key, lev):
        return ratio(doc["cheapest_at_level"].get(lev), a, b, key)
    parts = [f"Measured by `python benchmarks/{m.get('command', 'run.py')}` on {m.get('date_utc', '?')} UTC "
             f"(a shared {m.get('cpus', '?')}-CPU machine; tables, commands and dates: `docs/performance.md`). "
             "CPU(phmech) / CPU(peer) at matched error, the cheapest measured point of each reaching the level: "
             "released cantilever against Exudyn's 2-D beam (its best of dense and sparse solvers, "
             "generalized-alpha rho 1 and 0.9) "
             + " / ".join(rr(d, "phmech", "exudyn-ge2d", "cpu_s", lev) for lev in LEVELS)
             + " at " + " / ".join(LEVELS) + " L (build, statics and integration; the 3-D DAE "
             + " / ".join(rr(d, "phmech-3d", "exudyn-ge2d", "cpu_s", lev) for lev in LEVELS) + ")"]
    el = [r for r in d["runs"] if r["code"] == "pyelastica" and "error" in r]
    if el:
        import math
        el = sorted(el, key=lambda r: r["N"])
        b = min(el, key=lambda r: r["error"])
        order = (math.log(el[-2]["error"] / el[-1]["error"]) / math.log(el[-1]["N"] / el[-2]["N"])
                 if len(el) > 1 else float("nan"))
        lev = [lv for lv in LEVELS if float(lv) >= b["error"]]
        parts.append(f"PyElastica's explicit Cosserat rod (position Verlet) reaches {b['error']:.1e} L at best "
                     f"(N = {b['N']}; observed order {order:.2f} in N between N = {el[-2]['N']} and {el[-1]['N']})"
                     + (", integration CPU ratio " + " / ".join(rr(d, "phmech", "pyelastica", "sim_cpu_s", lv) for lv in lev)
                        + " at " + " / ".join(lev) + " L" if lev else ", so no ratio at 1e-2 L or below"))
    if w is not None:
        parts.append("a rod whipped by its driven base, integration CPU against Exudyn's 2-D beam "
                     + " / ".join(rr(w, "phmech", "exudyn-ge2d", "sim_cpu_s", lev) for lev in LEVELS[:2])
                     + " at " + " / ".join(LEVELS[:2]) + " L")
    if sc is not None:
        bits = [f"n = {n}: {r:.2f} ({ph:.0e} m)" for n, r, ph, _ in chain_matched(sc)]
        if bits:
            parts.append(f"(`python benchmarks/{sc['machine'].get('command', 'bench_scaling.py')}`, "
                         f"{sc['machine'].get('date_utc', '?')} UTC) a rigid chain's CPU per simulated second, phmech's default integrator over the cheapest "
                         "MuJoCo run (RK4, Euler, implicitfast at the steps of `docs/perf_scaling.md`) whose link-end "
                         "error is at or below phmech's (phmech's error in brackets): " + ", ".join(bits))
        # the issue's sizes (below n = 10 a tree run's CPU is under the clock's resolution)
        tree: dict = {}
        for n, lev, row in chain_levels(sc):
            if n >= 10 and row["phmech tree"] and row[CHAIN_PEER]:
                tree.setdefault(n, []).append(row["phmech tree"] / row[CHAIN_PEER])
        if tree:
            parts.append("with `simulate(integrator=\"tree\", error_check=False)` (rigid trees in joint "
                         "coordinates, `docs/integrators.md`; its error check, on by default, costs 2-7x the run), "
                         "CPU over MuJoCo RK4's interpolated at the same link-end "
                         f"error ({' / '.join(f'{v:.0e}' for v in CHAIN_LEVELS)} m): "
                         + ", ".join(f"n = {n}: {min(r):.2f}-{max(r):.2f}" for n, r in tree.items()))
    return ["; ".join(parts) + "."]


def large(results: str) -> list:
    """bench_large.py: the newer of its full and quick runs."""
    d, path, name = newer_run(results, "bench_large")
    if d is None:
        return ["(no bench_large.json)"]
    e = lambda x: "--" if x is None else f"{x:.1e}"  # noqa: E731
    lines = ["### Large models: hanging riser, top driven", "", header(d, path, name), "",
             f"Problem: {d['problem']}. phmech: {d['phmech_call']}. Exudyn: {d.get('exudyn_setting') or 'not run'}.", "",
             f"error: {d['error']}; time error: {d.get('time_error', '--')}; mesh error: {d['mesh_error']}. "
             f"{d['rate']}. Last column: phmech's CPU/s over Exudyn's at phmech's error (log-log interpolation "
             "between Exudyn's points; -- where phmech's error is below all of Exudyn's).", "",
             "| N | phmech CPU/s | static CPU [s] | peak RSS [MB] | steps | Newton | error / L | time error / L "
             "| mesh error / L | Exudyn CPU/s | Exudyn peak RSS [MB] | Exudyn error / L | phmech / Exudyn at phmech's error |",
             "|---" * 13 + "|"]
    ex = {r["N"]: r for r in d["runs"] if r["code"] == "exudyn"}
    for r in sorted((r for r in d["runs"] if r["code"] == "phmech"), key=lambda r: r["N"]):
        x = ex.get(r["N"]) or {}
        rat = r.get("ratio_to_exudyn")
        xc = f"{x['cpu_per_sim_s']:.3g} (h {x['h']:g})" if x else "--"
        xm = f"{x['maxrss_MB']:.0f}" if x else "--"
        lines.append(f"| {r['N']} | {r['cpu_per_sim_s']:.3g} | {r['static_cpu_s']:.3g} | {r['maxrss_MB']:.0f} | {r['steps']} "
                     f"| {r['newton_iterations']} | {e(r.get('error'))} | {e(r.get('time_error'))} | {e(r.get('mesh_error'))} "
                     f"| {xc} | {xm} | {e(x.get('error'))} | {'--' if rat is None else f'{rat:.2f}'} |")
    for code in ("phmech", "exudyn"):
        f = d["fits"].get(code)
        if f:
            ranges = "".join(f"; over N = {k.replace('-', ' ... ')}: N^{v['exponent']:.2f}"
                             for k, v in (f.get("cpu_exponents") or {}).items()
                             if v["exponent"] is not None and v["fitted_on"] != f["fitted_on"])
            lines += ["", f"{code}: CPU/s ~ N^{f['cpu_exponent']:.2f} over N = {f['fitted_on']}{ranges} (local slopes "
                      + ", ".join(f"{v:.2f}" for v in f["local_slopes"]) + "); peak RSS above the baseline "
                      f"({d['baseline_rss_MB'][code]:.0f} MB) ~ N^{f['memory_exponent_above_baseline']:.2f}."]
    added = [f"N = {r['N']} ({r['code']}): {r['added_by']}" for r in d["runs"] if r.get("added_by")]
    if added:
        lines += ["", "Added later, without errors: " + "; ".join(added) + "."]
    if d.get("skipped"):
        lines += ["", "Skipped: " + "; ".join(f"{s['code']} N = {s['N']}: {s['reason']}" for s in d["skipped"]) + "."]
    if d.get("reference_check"):
        c = d["reference_check"]
        lines += ["", f"Reference check: at N = {c['N']}, rtol 1e-6 against {c['rtol']:g}: {c['reference_vs_tighter']:.1e} L."]
    return lines


def overhead(results: str) -> list:
    """Per-call CPU of modes(), static(), simulate() against the core's own (bench_overhead.py)."""
    d, path, cmd = newer_run(results, "bench_overhead")
    if d is None:
        return ["(no bench_overhead.json)"]
    lines = ["### Per-call overhead (small models)", "", header(d, path, cmd), "",
             "| model | analysis | CPU per call | core (model_* calls) | total / core |", "|---|---|---|---|---|"]
    for r in d["runs"]:
        lines.append(f"| {r['model']} | {r['analysis']} | {ms(r['cpu_s'])} | {ms(r['core_cpu_s'])} | "
                     f"{r['ratio']:.2f} |")
    if d.get("exudyn"):
        lines += ["", "| N | modes(5) per call | Exudyn GE2D eigenvalues | ratio | phmech build + modes | "
                  "Exudyn build + eigenvalues | ratio |", "|---|---|---|---|---|---|---|"]
        for r in d["exudyn"]:
            lines.append(f"| {r['N']} | {ms(r['phmech_call_cpu_s'])} | {ms(r['exudyn_call_cpu_s'])} | "
                         f"{r['call_ratio']:.2f} | {ms(r['phmech_build_solve_cpu_s'])} | "
                         f"{ms(r['exudyn_build_solve_cpu_s'])} | {r['build_solve_ratio']:.2f} |")
    return lines


PARTS = dict(headline=headline, transient=transient, whip=whip, modes=modes, scaling=scaling, leaf=leaf,
             modal=modal, scenes=scenes, large=large, overhead=overhead)


def write_docs(results: str) -> None:
    """Replace every marked block of README.md and docs/performance.md, docs/perf_*.md."""
    import glob
    import re
    root = os.path.dirname(HERE)
    files = [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "perf*.md")))
    for path in files:
        with open(path) as f:
            text = f.read()
        def sub(mo):
            name = mo.group(1)
            if name not in PARTS:
                return mo.group(0)
            return f"<!-- report:{name} -->\n" + "\n".join(PARTS[name](results)) + f"\n<!-- /report:{name} -->"
        new = re.sub(r"<!-- report:(\w+) -->.*?<!-- /report:\1 -->", sub, text, flags=re.S)
        if new != text:
            with open(path, "w") as f:
                f.write(new)
            print(f"updated {os.path.relpath(path, root)}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--results", default=os.environ.get("BENCH_RESULTS") or os.path.join(HERE, "results"))
    ap.add_argument("--only", nargs="+", choices=list(PARTS), default=None)
    ap.add_argument("--write-docs", action="store_true", help="rewrite the marked blocks of README.md and docs/perf*.md")
    a = ap.parse_args()
    if a.write_docs:
        write_docs(a.results)
        return
    for name, fn in PARTS.items():
        if a.only and name not in a.only:
            continue
        print("\n".join(fn(a.results)))
        print()


if __name__ == "__main__":
    main()
