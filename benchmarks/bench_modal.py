"""Modal leaves against nonlinear leaves on the leaf spring (issue 13): work-precision.

    python benchmarks/bench_modal.py [--quick]

The model is ``examples/leaf_spring.py``'s :func:`build` (beta = 1e-5 s, a 0.05 N s pulse of
10 ms at t = 0.1 s on the stage R1). Each route simulates the pulse response for T_END seconds
with the default integrator (outputs every 2 ms) and takes the dominant frequency of R1's x
after 2 s (``phmech.analysis.dominant_frequency``); its error is against the converged
f_ref = 3.3645021 Hz (docs/perf_leaf_spring.md). Routes: nonlinear leaves of N elements, and
modal leaves (``fidelity="modal"``: each leaf statically reduced from N elements onto its
ends), and modal leaves with the fixed-interface modes a 50 Hz band chooses (``modal+modes``),
all with the integrator's band at 10 Hz (three times the mode) and at the output's (250 Hz, no
``band=``). CPU = build + simulate (``time.process_time``), median of REPEAT runs.

Issue 13's case on its own (``done_when`` in the JSON): modal leaves reduced from 64 elements
with the modes a 50 Hz band chooses, ``simulate(10, 1e-2, band=10)``: thread CPU of the
simulation alone (``time.thread_time``, after a warm-up run), median of 5, and its FFT error.

Writes benchmarks/results/bench_modal.{json,png}.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "examples"))
sys.path.insert(0, HERE)

import phmech as ph  # noqa: E402
import leaf_spring as LS  # noqa: E402
from run import RESULTS, machine, write_json  # noqa: E402

F_REF = 3.3645021
T_END, T_FFT, DT_OUT = 10.0, 2.0, 2e-3


#: the band [Hz] that chooses the modal leaves' fixed-interface modes (route "modal+modes")
MODES_BAND = 50.0


def build(fidelity: str, N: int):
    """The leaf spring with leaves of this fidelity ("modal+modes": modal, modes from MODES_BAND)."""
    modal = fidelity.startswith("modal")
    return LS.build(LS.default_params(), elements=N, beta=1e-5,
                    fidelity="modal" if modal else fidelity,
                    band=MODES_BAND if fidelity == "modal+modes" else None,
                    pulse=ph.Pulse(t0=0.1, duration=0.01, value=5.0))


def fft_error(r, h) -> tuple:
    """The dominant frequency of R1's x after T_FFT and its error against f_ref."""
    x = r.poses[:, h["R1"].carrier, 0, 3]
    sel = r.t >= T_FFT
    f = ph.analysis.dominant_frequency(r.t[sel], x[sel] - x[0], fmin=1.0, fmax=10.0)
    return f, abs(f / F_REF - 1)


def route(fidelity: str, N: int, band, t_end: float) -> dict:
    """One simulated pulse response: CPU and the FFT frequency's error against f_ref."""
    t0 = time.process_time()
    m, h = build(fidelity, N)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.CostWarning)
        r = m.simulate(t_end, DT_OUT, **({} if band is None else dict(band=band)))
    cpu = time.process_time() - t0
    f, err = fft_error(r, h)
    return dict(fidelity=fidelity, elements=N, band_hz=band, cpu_s=cpu, f_fft_hz=f,
                error=err, steps=int(r.stats["steps"]),
                ledger_relative=float(r.stats["ledger_relative"]))


def done_when(repeat: int = 5, N: int = 64) -> dict:
    """Issue 13's leaf-spring case (module doc): thread CPU of simulate alone, median."""
    m, h = build("modal+modes", N)
    modes = [lk.modal_choice.modes for lk in m._desc.links.values()]
    m.simulate(T_END, 1e-2, band=10.0)                       # warm-up (build, reduction)
    cpu = []
    for _ in range(repeat):
        t0 = time.thread_time()
        r = m.simulate(T_END, 1e-2, band=10.0)
        cpu.append(time.thread_time() - t0)
    f, err = fft_error(r, h)
    return dict(elements=N, modes_band_hz=MODES_BAND, modes_per_leaf=modes, dt_out_s=1e-2,
                band_hz=10.0, thread_cpu_s=float(np.median(cpu)), thread_cpu_runs=cpu,
                f_fft_hz=f, error=err, ledger_relative=float(r.stats["ledger_relative"]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer meshes, one repetition")
    ap.add_argument("--smoke", action="store_true",
                    help="seconds: one coarse mesh per route, 4 s simulated (tests/test_benchmarks_smoke.py)")
    a = ap.parse_args(argv)
    global T_END
    repeat = 1 if a.quick or a.smoke else 3
    if a.smoke:
        T_END = 4.0
    meshes = {"nonlinear": [4], "modal": [8], "modal+modes": [8]} if a.smoke else {"nonlinear": [10, 20, 40] if a.quick else [10, 20, 40, 64],
              "modal": [16, 64] if a.quick else [8, 16, 32, 64],
              "modal+modes": [16, 64] if a.quick else [8, 16, 32, 64]}
    runs = []
    for band in ((10.0,) if a.smoke else (10.0, None)):
        for fid, Ns in meshes.items():
            for N in Ns:
                rs = [route(fid, N, band, T_END) for _ in range(repeat)]
                best = dict(rs[0], cpu_s=float(np.median([r["cpu_s"] for r in rs])))
                runs.append(best)
                print(f"{fid:9s} N={N:3d} band={band}: CPU {best['cpu_s']:.3f} s, "
                      f"f {best['f_fft_hz']:.7f} Hz, error {best['error']:.2e}, "
                      f"{best['steps']} steps", flush=True)
    dw = done_when(1, 8) if a.smoke else done_when()
    print(f"done-when case: modal leaves (64 elements, modes from {MODES_BAND:g} Hz: "
          f"{dw['modes_per_leaf']}), simulate(10, 1e-2, band=10): thread CPU "
          f"{dw['thread_cpu_s'] * 1e3:.1f} ms (median of 5), error {dw['error']:.2e}", flush=True)
    write_json("bench_modal", dict(
        problem="leaf spring pulse response, 10 s: nonlinear against modal leaves",
        f_ref_hz=F_REF, t_end_s=T_END, dt_out_s=DT_OUT, repeat=repeat, runs=runs, machine=machine(),
        done_when=dw))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker  # noqa: F401
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for fid, mk in (("nonlinear", "o"), ("modal", "s"), ("modal+modes", "^")):
        for band, ls in ((10.0, "-"), (None, "--")):
            sel = [r for r in runs if r["fidelity"] == fid and r["band_hz"] == band]
            ax.loglog([r["cpu_s"] for r in sel], [max(r["error"], 1e-7) for r in sel], mk + ls,
                      label=f"{fid}, band {'10 Hz' if band else '250 Hz (output)'}")
            for r in sel:
                ax.annotate(str(r["elements"]), (r["cpu_s"], max(r["error"], 1e-7)), fontsize=7)
    ax.axhline(1e-3, color="grey", lw=0.8)
    ax.set(xlabel="CPU [s] (build + 10 s simulation)", ylabel="|f_fft / f_ref - 1|",
           title="leaf spring: modal vs nonlinear leaves (labels: elements per leaf)")
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())   # overlapping labels
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, "bench_modal.png"), dpi=120)
    print("wrote", os.path.join(RESULTS, "bench_modal.png"))


if __name__ == "__main__":
    main()
