"""The whole configuration's error of benchmarks/scenes.py's default runs, in the accuracy
contract's own norm (docs/user_guide.md, "Accuracy contract").

scenes.py compares a few band quantities per scene (a tip, a joint angle); the error estimate
controls every carrier's position and quaternion and every joint coordinate, each weighed by
rtol |y| + atol, in the root-mean-square norm over them. This script measures that norm of the
run's error: each scene's default run (its default band at the default rtol, passed explicitly, with outputs every
``--dt`` so that the band can be separated) against a reference of the same model and mesh, the
largest over the outputs of

    sqrt(mean over coordinates of ((y - y_ref) / (rtol |y_ref| + atol))^2)

raw, and in-band: the error low-passed at the band (4th-order Butterworth, forward and backward),
since what lies above the band is damped, not controlled. Quaternions are compared as unit
quaternions with the reference's sign. The reference: the fixed-step generalized-alpha at
``--ref-step`` (5 us; self-convergence), or IDA (``--reference ida``, the scene's reference
route of scenes.py). ``error_sum`` is the run's summed estimate (what the contract bounds).
``rot_raw``/``rot_in_band``: the same in a rotation-aware norm (each carrier's orientation error
as the rotation vector of R_ref^T R [rad], weighed by rtol x 1 rad + atol; positions and joints
as above); ``rotj_*``: that with the joint coordinates' scale at least 1 (rad or m)
(benchmarks/results/history.md, 2026-12-07, a prototype; not the contract's norm).

    python benchmarks/configuration_error.py [--only NAME ...] [--t-end T] [--options 'rtol=1e-5']
                                             [--reference ida] [--smoke]      (make validate)

writes benchmarks/results/configuration_error.json (configuration_error_ida.json with IDA, a
``_smoke`` file with --smoke;
docs/integrators.md, "Limits").
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
import warnings

import numpy as np
from scipy.signal import butter, filtfilt
from scipy.spatial.transform import Rotation

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import scenes as S  # noqa: E402

FLEXIBLE = ["double pendulum", "cantilever + tip mass, impulse", "slider-crank, flexible rod",
            "flexible arm, torque profile"]


def _quaternions(poses: np.ndarray) -> np.ndarray:
    """(nt, nc, 4, 4) poses -> (nt, nc, 4) unit quaternions (x, y, z, w)."""
    R = poses[..., :3, :3]
    return Rotation.from_matrix(R.reshape(-1, 3, 3)).as_quat().reshape(R.shape[:-2] + (4,))


def configuration(res) -> np.ndarray:
    """Every carrier's position [m] and quaternion, and every joint coordinate [m or rad]:
    (nt, k)."""
    nt = len(res.t)
    parts = [res.poses[..., :3, 3].reshape(nt, -1), _quaternions(res.poses).reshape(nt, -1)]
    if res.joints is not None and res.joints.size:
        parts.append(res.joints)
    return np.concatenate(parts, axis=1)


def contract_terms(y: np.ndarray, yr: np.ndarray, nc: int, rtol: float, atol: float) -> tuple:
    """(e, w): the error y - yr with y's quaternions (columns 3 nc .. 7 nc) given yr's sign, and
    the contract's weights rtol |yr| + atol."""
    y = y.copy()
    q, qr = y[:, 3 * nc:7 * nc].reshape(-1, nc, 4), yr[:, 3 * nc:7 * nc].reshape(-1, nc, 4)
    y[:, 3 * nc:7 * nc] = (q * np.sign(np.sum(q * qr, axis=-1, keepdims=True))).reshape(-1, 4 * nc)
    return y - yr, rtol * np.abs(yr) + atol


def contract_error(y: np.ndarray, yr: np.ndarray, nc: int, rtol: float, atol: float,
                   band: float, dt: float) -> dict:
    """The largest over the outputs of the RMS of (y - yr) / (rtol |yr| + atol), raw and
    low-passed at ``band`` [Hz]; the quaternions (columns 3 nc .. 7 nc) take yr's sign."""
    e, w = contract_terms(y, yr, nc, rtol, atol)
    b, a = butter(4, band, fs=1.0 / dt)
    out = {}
    for name, d in (("raw", e), ("in_band", filtfilt(b, a, e, axis=0))):
        rms = np.sqrt(np.mean((d / w) ** 2, axis=1))
        out[name] = float(rms.max())
        out[name + "_time"] = float(np.argmax(rms) * dt)
    return out


def rotation_error(y: np.ndarray, yr: np.ndarray, res_poses: np.ndarray, ref_poses: np.ndarray,
                   nc: int, rtol: float, atol: float, band: float, dt: float) -> dict:
    """The same in the rotation-aware norm: every carrier's position (rtol |p_ref| + atol), its
    orientation error as the rotation vector of R_ref^T R [rad] (3 entries weighed by
    rtol * 1 rad + atol), and the joint coordinates (rtol |y_ref| + atol)."""
    nt = len(y)
    R = res_poses[..., :3, :3].reshape(-1, 3, 3)
    Rr = ref_poses[..., :3, :3].reshape(-1, 3, 3)
    rv = Rotation.from_matrix(np.einsum("nji,njk->nik", Rr, R)).as_rotvec().reshape(nt, 3 * nc)
    pe = y[:, :3 * nc] - yr[:, :3 * nc]
    je = y[:, 7 * nc:] - yr[:, 7 * nc:]
    e = np.concatenate([pe, rv, je], axis=1)
    w = np.concatenate([rtol * np.abs(yr[:, :3 * nc]) + atol, np.full((nt, 3 * nc), rtol + atol),
                        rtol * np.abs(yr[:, 7 * nc:]) + atol], axis=1)
    wj = w.copy()  # the joint coordinates' scale at least 1 (rad or m): "rotj"
    wj[:, 6 * nc:] = rtol * np.maximum(np.abs(yr[:, 7 * nc:]), 1.0) + atol
    b, a = butter(4, band, fs=1.0 / dt)
    out = {}
    for name, d in (("rotj_raw", e / wj * w), ("rotj_in_band", filtfilt(b, a, e / wj * w, axis=0)),
                    ("rot_raw", e), ("rot_in_band", filtfilt(b, a, e, axis=0))):
        rms = np.sqrt(np.mean((d / w) ** 2, axis=1))
        out[name] = float(rms.max())
        out[name + "_time"] = float(np.argmax(rms) * dt)
    return out


def run(sc: S.Scene, dt: float, reference: str, ref_step: float, options: dict,
        t_end: float = 0.0) -> dict:
    """One scene: its default run and the reference at outputs every ``dt`` [s] over ``t_end``
    [s] (0: the scene's); the errors."""
    t_end = t_end or sc.t_end
    warnings.simplefilter("ignore")
    options = dict(options)
    # the scene's default band at the default rtol (python/phmech/_simulate.py), unless given
    band = options.pop("band", max(0.5 / sc.dt_out, 50.0 / t_end))  # _run.BAND_PER_SPAN
    m, measure = sc.build()
    c0 = time.process_time()
    res = m.simulate(t_end, dt, band=band, **options)
    cpu = time.process_time() - c0
    m2, _ = sc.build()
    c0 = time.process_time()
    if reference == "ida":
        ref = m2.simulate(t_end, dt, **(sc.reference or S.REFERENCE))
    else:
        ref = m2.simulate(t_end, dt, step=ref_step)
    ref_cpu = time.process_time() - c0
    st = res.stats
    rtol, atol = st.get("rtol", 1e-4), st.get("atol", 1e-6)  # (older versions: the defaults)
    nc = res.poses.shape[1]
    out = dict(scene=sc.name, t_end=t_end, band=band, dt_out=dt, options=options, steps=int(st["steps"]),
               cpu_s=cpu, error_sum=st.get("error_sum"), reference=reference,
               reference_step=ref_step if reference != "ida" else None, reference_cpu_s=ref_cpu)
    y, yr = configuration(res), configuration(ref)
    out.update(contract_error(y, yr, nc, rtol, atol, band, dt))
    out.update(rotation_error(y, yr, res.poses, ref.poses, nc, rtol, atol, band, dt))
    q, qr = measure(res), measure(ref)
    out["band_quantities_vs_tolerance"] = max(float(np.max(np.abs(q[k] - qr[k]))) / (rtol * sc.scale[k] + atol)
                                              for k in q)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", default=FLEXIBLE, help="scene names (default: the flexible ones)")
    ap.add_argument("--dt", type=float, default=1e-4, help="output interval [s] (the band is the scene's own)")
    ap.add_argument("--reference", choices=["fixed", "ida"], default="fixed")
    ap.add_argument("--ref-step", type=float, default=5e-6, help="the fixed-step reference's step [s]")
    ap.add_argument("--t-end", type=float, default=0.0, help="horizon [s] (default: the scene's)")
    ap.add_argument("--smoke", action="store_true",
                    help="the cantilever over 0.05 s, reference step 20 us (tests/test_benchmarks_smoke.py)")
    ap.add_argument("--options", default="", help="simulate options of the run, e.g. 'rtol=1e-5'")
    a = ap.parse_args(argv)
    options = eval(f"dict({a.options})")
    rows = []
    if a.smoke:
        a.only, a.t_end, a.ref_step = ["cantilever + tip mass, impulse"], 0.05, 2e-5
    for sc in S.SCENES:
        if sc.name not in a.only:
            continue
        r = run(sc, a.dt, a.reference, a.ref_step, options, a.t_end)
        rows.append(r)
        print(f"{sc.name:32s} steps {r['steps']:6d} CPU {r['cpu_s']:5.2f} s  error_sum {r['error_sum'] or 0:.2f}  "
              f"configuration vs tolerance: in-band {r['in_band']:.3f} (t {r['in_band_time']:.3f} s), "
              f"raw {r['raw']:.3f}; rotation norm: in-band {r['rot_in_band']:.3f}, raw {r['rot_raw']:.3f}; band quantities {r['band_quantities_vs_tolerance']:.3f}", flush=True)
    res = os.environ.get("BENCH_RESULTS") or os.path.join(HERE, "results")
    os.makedirs(res, exist_ok=True)
    # a smoke run writes its own file: never the committed full run's
    stem = "configuration_error" + ("" if a.reference == "fixed" else "_ida") + ("_smoke" if a.smoke else "")
    path = os.path.join(res, stem + ".json")
    if not options and (a.smoke or not a.t_end):
        with open(path, "w") as f:
            from run import machine
            json.dump(dict(scenes=rows, machine=machine()), f, indent=1)
        print(f"results: {path}")
    return rows


if __name__ == "__main__":
    main()
