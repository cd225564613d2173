"""The default integrator's cost against an older build's, at matched error (issue 27).

"Within 1.5x of the older build's cost at the same tolerance" compares unlike runs when the older
build did not keep its tolerance (before the accuracy contract, the default generalized-alpha
accepted steps above tolerance at the band's floor step). This script compares cost at matched
error. For each scene of benchmarks/scenes.py (the same models, horizons and outputs):

1. each build integrates the scene's reference (scenes.py's route, IDA, 10x tighter than
   scenes.py's options) and a check (scenes.py's own options; the slider-crank and the flexible
   arm, where IDA does not resolve the errors compared: the fixed-step generalized-alpha at 5 us,
   checked at 10 us; the leaf spring: the reference is scenes.py's, the check the fixed-step
   generalized-alpha at 20 us): the check against the
   reference bounds the reference's own error; the two builds' references are compared with
   each other (they differ where the model changed between the builds, e.g. a flexible link's
   mass matrix);
2. each build runs ``simulate(t_end, dt_out)`` with nothing else; its error against its own
   build's reference is measured (a) in the scene's band quantities, the largest over the outputs
   and quantities of |q - q_ref| / scale, and (b) in the accuracy contract's norm of
   benchmarks/configuration_error.py (every carrier's position and unit quaternion and every
   joint coordinate, weighed by rtol |y_ref| + atol with the default rtol 1e-4, atol 1e-6, the
   root-mean-square over them, the largest over the outputs; raw, at the scene's outputs, whose
   Nyquist frequency is the default band);
3. this build runs an rtol ladder (loose to tight, until its errors are below the baseline's in
   both measures), and the CPU at the baseline's default error is interpolated in log-log
   between the two rungs that bracket it: ratio = CPU(this build at the baseline's error) /
   CPU(baseline's default run);
4. CPU: ``time.process_time()`` around ``simulate`` in a worker process per build, the median of
   ``--repeats`` runs interleaved (baseline default, this build's default, its bracketing rungs,
   scene after scene, round after round).

The baseline build is another installation of phmech (a worktree's .venv built from an older
commit); its worker runs this file with that interpreter and this tree's scene definitions.

    python benchmarks/cost_matched_error.py --baseline-python /path/to/old/.venv/bin/python
                                            [--only NAME ...] [--repeats 3] [--mass lumped] [--smoke]

writes benchmarks/results/cost_matched_error.json (``_smoke`` with --smoke: the double pendulum
over 0.3 s, one repeat; without a baseline interpreter (``--baseline-python`` or the environment
variable PHMECH_BASELINE_PYTHON) the smoke compares this build with itself). docs/integrators.md,
"Cost".
"""
from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from types import SimpleNamespace
from typing import Optional

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

#: main's rtol ladder, loose to tight (1e-4 is the default: that rung is the default run)
LADDER = [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7]
DEFAULT_RTOL, DEFAULT_ATOL = 1e-4, 1e-6
SMOKE_SCENE, SMOKE_T_END = "double pendulum", 0.3


# ------------------------------------------------------------------------------------------------
# the worker: runs in either build's interpreter; needs numpy, phmech and scenes.py only


def worker() -> None:
    """Reads one JSON job a line from stdin: {"scene", "t_end", "options", "out"}; simulates,
    saves t, poses, joints and the band quantities to ``out`` (.npz); answers one JSON line."""
    import warnings
    answer = sys.stdout
    sys.stdout = sys.stderr   # nothing the library prints can break the answers
    import phmech as ph
    import scenes as S
    by_name = {sc.name: sc for sc in S.SCENES}
    add_link = ph.Mechanism.add_flexible_link
    for line in sys.stdin:
        job = json.loads(line)
        sc = by_name[job["scene"]]
        mass = job.get("mass")
        # --mass: every flexible link of the scene with that mass matrix ("lumped": the same in
        # both builds, to every digit at a fixed step; the consistent mass changed since ac73c91)
        ph.Mechanism.add_flexible_link = add_link if mass is None else \
            (lambda self, *a, **k: add_link(self, *a, **dict(k, mass=mass)))
        m, measure = sc.build()
        caught = []
        try:
            with warnings.catch_warnings(record=True) as w:
                warnings.simplefilter("always")
                c0 = time.process_time()
                res = m.simulate(job["t_end"], sc.dt_out, **job["options"])
                cpu = time.process_time() - c0
            caught = sorted({x.category.__name__ for x in w} - {"RedundantConstraintWarning"})
        except Exception as e:  # noqa: BLE001 -- reported, the parent goes on
            answer.write(json.dumps(dict(failed=f"{type(e).__name__}: {e}")) + "\n")
            answer.flush()
            continue
        q = measure(res)
        np.savez(job["out"], t=res.t, poses=res.poses,
                 joints=res.joints if res.joints is not None else np.zeros((len(res.t), 0)),
                 **{"q_" + k: v for k, v in q.items()})
        st = res.stats
        keep = ("steps", "floor_steps", "error_test_fails", "nonlinear_iters", "jacobian_evals",
                "residual_evals", "error_estimate", "error_sum", "min_step", "last_step", "rtol",
                "atol", "band", "noise_steps", "ledger_relative")
        stats = {k: (float(st[k]) if isinstance(st[k], (int, float, np.floating, np.integer)) else st[k])
                 for k in keep if k in st}
        answer.write(json.dumps(dict(cpu_s=cpu, stats=stats, warnings=caught,
                                     phmech=os.path.dirname(ph.__file__))) + "\n")
        answer.flush()


class Worker:
    """One build's worker process."""

    def __init__(self, python: str, tmp: str, name: str, mass: Optional[str] = None):
        self.name, self.tmp, self.n, self.mass = name, tmp, 0, mass
        self.log = open(os.path.join(tmp, f"{name}.log"), "w")
        self.proc = subprocess.Popen([python, os.path.abspath(__file__), "--worker"], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=self.log, text=True, cwd=HERE)

    def run(self, scene: str, t_end: float, options: dict) -> dict:
        self.n += 1
        out = os.path.join(self.tmp, f"{self.name}_{self.n}.npz")
        job = dict(scene=scene, t_end=t_end, options=options, out=out, mass=self.mass)
        self.proc.stdin.write(json.dumps(job) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"the {self.name} worker died (log: {self.log.name})")
        r = json.loads(line)
        if "failed" not in r:
            z = np.load(out)
            r["arrays"] = {k: z[k] for k in z.files}
            os.remove(out)
        return r

    def close(self):
        self.proc.stdin.close()
        self.proc.wait(timeout=60)
        self.log.close()


# ------------------------------------------------------------------------------------------------
# the errors


def band_error(a: dict, ref: dict, scale: dict) -> float:
    """The largest over the band quantities and outputs of |q - q_ref| / scale."""
    return max(float(np.max(np.abs(a["q_" + k] - ref["q_" + k]))) / s for k, s in scale.items())


def band_vs_tolerance(a: dict, ref: dict, scale: dict, rtol: float, atol: float) -> float:
    """scenes.py's error_vs_tolerance: the largest of |q - q_ref| / (rtol scale + atol)."""
    return max(float(np.max(np.abs(a["q_" + k] - ref["q_" + k]))) / (rtol * s + atol)
               for k, s in scale.items())


def contract_norm(a: dict, ref: dict, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL) -> float:
    """configuration_error.py's norm, raw: the largest over the outputs of the RMS over the
    configuration of (y - y_ref) / (rtol |y_ref| + atol), quaternions with the reference's sign."""
    from configuration_error import configuration, contract_terms
    y = configuration(SimpleNamespace(t=a["t"], poses=a["poses"], joints=a["joints"]))
    yr = configuration(SimpleNamespace(t=ref["t"], poses=ref["poses"], joints=ref["joints"]))
    e, w = contract_terms(y, yr, a["poses"].shape[1], rtol, atol)
    rms = np.sqrt(np.mean((e / w) ** 2, axis=1))
    return float(rms.max())


def errors(a: dict, ref: dict, scale: dict) -> dict:
    return dict(band=band_error(a, ref, scale), contract=contract_norm(a, ref))


def interpolate(ladder: list, target: float, key: str) -> dict:
    """CPU at error ``target`` in log-log between the first two consecutive rungs (loose to
    tight) whose errors bracket it, or the loosest rung's if it is already as accurate (a bound);
    the rungs' "cpu_s" are their medians."""
    rungs = [r for r in ladder if "errors" in r]
    if rungs and rungs[0]["errors"][key] <= target:
        return dict(cpu_s=rungs[0]["cpu_s"], rtol=rungs[0]["rtol"], between=[rungs[0]["rtol"]],
                    bound="at most")
    for lo, hi in zip(rungs, rungs[1:]):
        e0, e1 = lo["errors"][key], hi["errors"][key]
        if e0 >= target >= e1 and e0 > e1:
            w = math.log(e0 / target) / math.log(e0 / e1)
            cpu = math.exp((1 - w) * math.log(lo["cpu_s"]) + w * math.log(hi["cpu_s"]))
            rt = math.exp((1 - w) * math.log(lo["rtol"]) + w * math.log(hi["rtol"]))
            return dict(cpu_s=cpu, rtol=rt, between=[lo["rtol"], hi["rtol"]], bound=None)
    return dict(cpu_s=None, rtol=None, between=[], bound="not reached")


def bracketing(ladder: list, target: float, key: str) -> list:
    """The rtols of the rungs interpolate() would use."""
    return interpolate([dict(r, cpu_s=1.0) for r in ladder], target, key)["between"]


# ------------------------------------------------------------------------------------------------


def reference_options(sc) -> tuple:
    """(the reference's simulate options, the check's): scenes.py's reference route 10x
    tighter, checked by scenes.py's own; FIXED_STEP_REFERENCE's scenes: the fixed step, checked
    at twice it; the leaf spring: scenes.py's (IDA with every state in its error test at rtol
    1e-8; 10x tighter it crawls, 151 s of CPU and 691 200 steps for 0.3 s on ac73c91), checked
    by the fixed-step generalized-alpha at 20 us."""
    import scenes as S
    ropt = sc.reference or S.REFERENCE
    if sc.name == "leaf spring":
        return ropt, dict(integrator="generalized-alpha", step=2e-5)
    if sc.name in FIXED_STEP_REFERENCE:
        return (dict(integrator="generalized-alpha", step=FIXED_STEP_REFERENCE[sc.name]),
                dict(integrator="generalized-alpha", step=2 * FIXED_STEP_REFERENCE[sc.name]))
    return dict(ropt, rtol=ropt["rtol"] / 10, atol=ropt["atol"] / 10), ropt


#: scenes whose IDA reference (configuration test) does not resolve the default runs' errors:
#: IDA at rtol 1e-9 against 1e-10 differed by 6.0e-7 of scale on the slider-crank (the default
#: runs' error: 4.9e-7) and by 1.5e-5 on the flexible arm (6.8e-5); their reference is the
#: fixed-step generalized-alpha [s], checked at twice the step (as benchmarks/configuration_error.py)
FIXED_STEP_REFERENCE = {"slider-crank, flexible rod": 5e-6, "flexible arm, torque profile": 5e-6}


def scene_row(sc, t_end: float, base: Worker, main: Worker, rtols: list) -> dict:
    """References, default runs and main's ladder (one run each): everything but the timing."""
    ropt, copt = reference_options(sc)
    refs = {}
    for who, w in (("baseline", base), ("main", main)):
        for name, opts in (("reference", ropt), ("check", copt)):
            r = w.run(sc.name, t_end, opts)
            if "failed" in r:
                raise RuntimeError(f"{sc.name}: {who}'s {name} ({opts}) failed: {r['failed']}")
            refs[who, name] = r
    # each build's errors are against its own reference; the check (another tolerance or route)
    # against it bounds the reference's own error; the two builds' references against each other:
    # equal where the builds integrate the same model
    ref_b, ref_m = refs["baseline", "reference"]["arrays"], refs["main", "reference"]["arrays"]
    row = dict(scene=sc.name, t_end=t_end, dt_out=sc.dt_out, scale=sc.scale, reference_options=ropt,
               check_options=copt,
               reference=dict(baseline_cpu_s=refs["baseline", "reference"]["cpu_s"],
                              main_cpu_s=refs["main", "reference"]["cpu_s"],
                              baseline_check=errors(refs["baseline", "check"]["arrays"], ref_b, sc.scale),
                              main_check=errors(refs["main", "check"]["arrays"], ref_m, sc.scale),
                              agreement=errors(ref_b, ref_m, sc.scale)))
    b = base.run(sc.name, t_end, {})
    if "failed" in b:
        raise RuntimeError(f"{sc.name}: baseline default failed: {b['failed']}")
    row["baseline"] = dict(stats=b["stats"], warnings=b["warnings"], cpu_first_s=b["cpu_s"],
                           errors=errors(b["arrays"], ref_b, sc.scale),
                           vs_tolerance=dict(band=band_vs_tolerance(b["arrays"], ref_b, sc.scale,
                                                                    b["stats"]["rtol"], b["stats"]["atol"]),
                                             contract=contract_norm(b["arrays"], ref_b, b["stats"]["rtol"],
                                                                    b["stats"]["atol"])))
    # the same uniform step on both builds (the baseline's band floor 1/(20 band), what its
    # default run took nearly everywhere): separates the builds' models and schemes from the
    # step-size controller
    h = 1.0 / (20 * max(0.5 / sc.dt_out, 50.0 / t_end))
    row["fixed_step"] = dict(step=h)
    for who, w, ref in (("baseline", base, ref_b), ("main", main, ref_m)):
        r = w.run(sc.name, t_end, dict(integrator="generalized-alpha", step=h))
        row["fixed_step"][who] = r.get("failed") or dict(cpu_s=r["cpu_s"], steps=r["stats"]["steps"],
                                                         errors=errors(r["arrays"], ref, sc.scale))
    target = row["baseline"]["errors"]
    ladder = []
    for rt in rtols:
        opts = {} if rt == DEFAULT_RTOL else dict(rtol=rt)   # the default run is the 1e-4 rung
        r = main.run(sc.name, t_end, opts)
        rung = dict(rtol=rt, options=opts, cpu_first_s=r.get("cpu_s"))
        if "failed" in r:
            rung["failed"] = r["failed"]
        else:
            rung.update(stats=r["stats"], warnings=r["warnings"], errors=errors(r["arrays"], ref_m, sc.scale),
                        vs_tolerance=dict(band=band_vs_tolerance(r["arrays"], ref_m, sc.scale,
                                                                 r["stats"]["rtol"], r["stats"]["atol"]),
                                          contract=contract_norm(r["arrays"], ref_m, r["stats"]["rtol"],
                                                                 r["stats"]["atol"])))
        ladder.append(rung)
        print(f"  {sc.name:32s} main rtol {rt:.0e}: steps {rung.get('stats', {}).get('steps', 0):7.0f} "
              f"CPU {rung['cpu_first_s'] or 0:6.2f} s  err band {rung.get('errors', {}).get('band', math.nan):.2e} "
              f"contract {rung.get('errors', {}).get('contract', math.nan):.2e}", flush=True)
        if rt <= DEFAULT_RTOL and "errors" in rung and \
                all(rung["errors"][k] <= target[k] for k in target):
            break
    row["ladder"] = ladder
    row["main"] = next(dict(r) for r in ladder if r["rtol"] == DEFAULT_RTOL)
    return row


def time_rows(rows: list, todo: dict, base: Worker, main: Worker, repeats: int) -> None:
    """``repeats`` interleaved rounds: in each, scene after scene, the baseline's default run,
    then this build's default and bracketing rungs; CPU medians into the rows."""
    samples = {(r["scene"], who, rt): [] for r in rows for who, rt in todo[r["scene"]]}
    for k in range(repeats):
        for r in rows:
            for who, rt in todo[r["scene"]]:
                w = base if who == "baseline" else main
                opts = {} if rt == DEFAULT_RTOL else dict(rtol=rt)
                a = w.run(r["scene"], r["t_end"], opts)
                if "failed" in a:
                    raise RuntimeError(f"{r['scene']} {who} rtol {rt}: {a['failed']}")
                samples[(r["scene"], who, rt)].append((a["cpu_s"], a["stats"]["steps"]))
        print(f"  timing round {k + 1}/{repeats} done", flush=True)
    for r in rows:
        for who, rt in todo[r["scene"]]:
            s = samples[(r["scene"], who, rt)]
            target = r["baseline"] if who == "baseline" else next(x for x in r["ladder"] if x["rtol"] == rt)
            target["cpu_s"] = float(np.median([c for c, _ in s]))
            target["cpu_runs_s"] = [c for c, _ in s]
            target["steps_each_run"] = sorted({int(n) for _, n in s})
        r["main"].update(next(x for x in r["ladder"] if x["rtol"] == DEFAULT_RTOL))


def summarize(r: dict) -> None:
    b, m = r["baseline"], r["main"]
    r["same_settings"] = dict(cpu_ratio=m["cpu_s"] / b["cpu_s"], steps_ratio=m["stats"]["steps"] / b["stats"]["steps"])
    r["matched"] = {}
    for key in ("band", "contract"):
        ip = interpolate(r["ladder"], b["errors"][key], key)
        ip["ratio"] = None if ip["cpu_s"] is None else ip["cpu_s"] / b["cpu_s"]
        # the references' own error (each build's check against its reference) well below the
        # error matched: else the matched point is within the references' uncertainty
        ref_err = max(r["reference"]["baseline_check"][key], r["reference"]["main_check"][key])
        ip["reference_error_over_target"] = ref_err / b["errors"][key]
        r["matched"][key] = ip


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--baseline-python", default=os.environ.get("PHMECH_BASELINE_PYTHON"),
                    help="the older build's interpreter (default: $PHMECH_BASELINE_PYTHON)")
    ap.add_argument("--only", nargs="*", default=None, help="scene names (default: all of scenes.py)")
    ap.add_argument("--repeats", type=int, default=3, help="interleaved timing rounds (median)")
    ap.add_argument("--mass", choices=["lumped", "consistent"], default=None,
                    help="every flexible link with this mass matrix (default: the scenes' own, "
                         "consistent); writes cost_matched_error_<mass>.json")
    ap.add_argument("--smoke", action="store_true",
                    help=f"the {SMOKE_SCENE} over {SMOKE_T_END} s, one round (tests/test_benchmarks_smoke.py)")
    a = ap.parse_args(argv)
    if a.worker:
        return worker()
    import scenes as S
    if a.smoke:
        a.only, a.repeats = [SMOKE_SCENE], 1
    if not a.baseline_python and not a.smoke:
        ap.error("--baseline-python (or PHMECH_BASELINE_PYTHON) is needed: the older build's interpreter")
    baseline = a.baseline_python or sys.executable
    scenes = [sc for sc in S.SCENES if a.only is None or sc.name in a.only]
    rows, todo = [], {}
    with tempfile.TemporaryDirectory() as tmp:
        base = Worker(baseline, tmp, "baseline", a.mass)
        main_w = Worker(sys.executable, tmp, "main", a.mass)
        try:
            for sc in scenes:
                t_end = SMOKE_T_END if a.smoke else sc.t_end
                r = scene_row(sc, t_end, base, main_w, LADDER)
                rows.append(r)
                need = {DEFAULT_RTOL}
                for key in ("band", "contract"):
                    need |= set(bracketing(r["ladder"], r["baseline"]["errors"][key], key))
                todo[sc.name] = [("baseline", DEFAULT_RTOL)] + [("main", rt) for rt in sorted(need, reverse=True)]
                ag, rf, be = r["reference"]["agreement"], r["reference"], r["baseline"]["errors"]
                print(f"{sc.name:32s} references: builds agree to {ag['band']:.1e} of scale (contract "
                      f"norm {ag['contract']:.1e}); check: baseline {rf['baseline_check']['band']:.1e}"
                      f"/{rf['baseline_check']['contract']:.1e}, main {rf['main_check']['band']:.1e}"
                      f"/{rf['main_check']['contract']:.1e}; baseline error band {be['band']:.2e} "
                      f"contract {be['contract']:.2e}", flush=True)
                fx = r["fixed_step"]
                if all(isinstance(fx[w], dict) for w in ("baseline", "main")):
                    print(f"{'':32s} fixed step {fx['step']:.2e} s: error band {fx['baseline']['errors']['band']:.2e}"
                          f" / {fx['main']['errors']['band']:.2e}, contract {fx['baseline']['errors']['contract']:.2e}"
                          f" / {fx['main']['errors']['contract']:.2e} (baseline / main)", flush=True)
            time_rows(rows, todo, base, main_w, a.repeats)
        finally:
            base.close()
            main_w.close()
    for r in rows:
        summarize(r)
    print(f"\n{'scene':32s} {'error band (base/main)':>22s} {'contract (base/main)':>22s} {'CPU base/main':>15s} "
          f"{'matched band':>12s} {'matched contract':>16s} {'same settings':>13s}")
    for r in rows:
        b, m, mt = r["baseline"], r["main"], r["matched"]

        def fmt(ip):   # "?": the references' own error is more than 0.3 of the error matched
            return "n/a" if ip["ratio"] is None else ("<=" if ip["bound"] else "") + f"{ip['ratio']:.2f}" + \
                ("?" if ip["reference_error_over_target"] > 0.3 else "")
        print(f"{r['scene']:32s} {b['errors']['band']:10.2e}/{m['errors']['band']:9.2e}  "
              f"{b['errors']['contract']:10.2e}/{m['errors']['contract']:9.2e}  {b['cpu_s']:6.3f}/{m['cpu_s']:6.3f}  "
              f"{fmt(mt['band']):>12s} {fmt(mt['contract']):>16s} {r['same_settings']['cpu_ratio']:13.2f}")
    print("(?: the references' own error is above 0.3 of the error matched: not resolved)")
    out_dir = os.environ.get("BENCH_RESULTS") or os.path.join(HERE, "results")
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, "cost_matched_error" + (f"_{a.mass}" if a.mass else "") +
                        ("_smoke" if a.smoke else "") + ".json")
    from run import machine
    base_info = subprocess.run([baseline, "-c", "import phmech, os; print(os.path.dirname(phmech.__file__))"],
                               capture_output=True, text=True).stdout.strip()
    with open(path, "w") as f:
        json.dump(dict(baseline_python=baseline, baseline_phmech=base_info,
                       baseline_is_self=os.path.realpath(baseline) == os.path.realpath(sys.executable),
                       ladder=LADDER, repeats=a.repeats, smoke=a.smoke, mass=a.mass,
                       norm_weights=dict(rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL), scenes=rows,
                       machine=machine()), f, indent=1, default=float)
    print(f"results: {path}")
    return rows


if __name__ == "__main__":
    main()
