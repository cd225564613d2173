"""Mechanisms as FMUs (phmech.export_fmu, python/phmech/fmu.py; csrc/fmi/): FMPy, an
independent FMI client, simulates the FMU with a held torque step, and its motion equals
simulate() with the same torque given as a Step law; FMPy's model-description validation reports
nothing; every library the wrapper loads beyond glibc is inside the FMU; the FMU runs in a fresh
venv with only FMPy installed; bad arguments get a ModelError naming them."""
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

import phmech as ph
from phmech import se3

fmpy = pytest.importorskip("fmpy")   # tools/requirements-dev.txt installs it
from fmpy.validation import validate_fmu  # noqa: E402

T_STEP, TAU = 0.2, -1.5      # the torque step: -1.5 N m on the shoulder motor from t = 0.2 s
SYSTEM_OK = re.compile(r"^(linux-vdso|ld-linux|libc|libm|libpthread|libdl|librt|libgcc_s)\b")


def rigid_arm(law=None):
    """Two rigid links in a vertical plane (revolutes about y, gravity -z), a motor on the
    shoulder: an Effort with ``law`` (None: a 1 N m constant, replaced by the FMU's input)."""
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    a = m.add_rigid_body("upper", 1.0, np.diag([1e-3, 0.02, 0.02]), com=(0.25, 0, 0))
    b = m.add_rigid_body("fore", 0.5, np.diag([1e-3, 0.01, 0.01]), com=(0.2, 0, 0),
                         pose=se3.translation([0.5, 0, 0]))
    m.add_pair("shoulder", ph.Revolute("y"), m.ground, a)
    m.add_pair("elbow", ph.Revolute("y"), ph.Frame(a.carrier, se3.translation([0.5, 0, 0])), b)
    m.add_actuator("motor", "shoulder", ph.Effort(law=law))
    return m


def flexible_arm(law=None):
    """A 0.5 m aluminium strip (3 elements, material damping 2e-3 s K) on a hub revolute, a
    0.2 kg tip mass welded to its end, gravity across it; a motor on the hub."""
    al = ph.BeamProperties.from_material(ph.Section.rectangle(0.02, 0.004),
                                         ph.Material(E=70e9, nu=0.33, density=2700.0))
    props = ph.BeamProperties(al.stiffness, al.inertia, 2e-3 * al.stiffness)
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    f = m.add_flexible_link("arm", 0.5, props, elements=3)
    tip = m.add_rigid_body("tip", 0.2, 1e-4 * np.eye(3), pose=se3.translation([0.5, 0, 0]))
    m.add_pair("hub", ph.Revolute("y"), m.ground, f.start)
    m.add_actuator("motor", "hub", ph.Effort(law=law))
    m.add_pair("weld", ph.Fixed(), f.end, tip)
    return m


def step_input(t_end):
    """FMPy's input table: 0 before T_STEP, TAU from it on (held over each communication step)."""
    return np.array([(0.0, 0.0), (T_STEP, 0.0), (T_STEP, TAU), (t_end, TAU)],
                    dtype=[("time", float), ("motor", float)])


@pytest.fixture(scope="module")
def rigid_fmu(tmp_path_factory):
    path = tmp_path_factory.mktemp("fmu") / "rigid_arm.fmu"
    return ph.export_fmu(rigid_arm(), path, inputs=["motor"],
                         outputs=["shoulder", "elbow", "fore", "energy"],
                         integrator="ida", rtol=1e-10, stop_time=1.0, step_size=0.01)


def test_rigid_arm_through_fmpy_equals_simulate(rigid_fmu):
    """IDA at rtol 1e-10 (atol 1e-12) in both; the FMU restarts it at every 0.01 s communication
    point from the state reached, simulate() runs through (stopping at the Step's breakpoint)."""
    r = fmpy.simulate_fmu(str(rigid_fmu), start_time=0.0, stop_time=1.0, output_interval=0.01,
                          input=step_input(1.0))
    s = rigid_arm(ph.Step(T_STEP, TAU)).simulate(1.0, 0.01, integrator="ida", rtol=1e-10)
    assert np.allclose(r["time"], s.t, rtol=0, atol=1e-12)
    for pair in ("shoulder", "elbow"):
        j = s.joint(pair)
        assert np.ptp(j["x"][:, 0]) > 0.5                     # the arm swings (rad)
        assert np.max(np.abs(r[f"{pair}.x"] - j["x"][:, 0])) < 1e-6
        assert np.max(np.abs(r[f"{pair}.xdot"] - j["xdot"][:, 0])) < 1e-5
    p = s.position("fore")
    for c in range(3):
        assert np.max(np.abs(r[f"fore.p[{c + 1}]"] - p[:, c])) < 1e-6
    e = s.energy
    for k in ("kinetic", "gravity"):
        assert np.max(np.abs(r[f"energy.{k}"] - e[k])) < 1e-5
    total = e["kinetic"] + e["elastic"] + e["gravity"]
    assert np.max(np.abs(r["energy.total"] - total)) < 1e-5
    # the motor's work shows: before the step gravity alone (total constant), after it not
    before = s.t < T_STEP
    assert np.ptp(r["energy.total"][before]) < 1e-6 < np.ptp(r["energy.total"])


def test_flexible_arm_through_fmpy_equals_simulate(tmp_path):
    """The generalized-alpha at a fixed 1e-4 s step (rho_inf 0.9, Newton rtol 1e-10) in both:
    the FMU restarts it at each 0.01 s communication point."""
    path = ph.export_fmu(flexible_arm(), tmp_path / "flexible_arm.fmu", inputs=["motor"],
                         outputs=["hub", "tip"], integrator="generalized-alpha", step=1e-4,
                         rtol=1e-10)
    r = fmpy.simulate_fmu(str(path), start_time=0.0, stop_time=0.5, output_interval=0.01,
                          input=step_input(0.5))
    s = flexible_arm(ph.Step(T_STEP, TAU)).simulate(0.5, 0.01, integrator="generalized-alpha",
                                                     step=1e-4, rtol=1e-10)
    x = s.joint("hub")["x"][:, 0]
    assert np.ptp(x) > 0.3
    assert np.max(np.abs(r["hub.x"] - x)) < 1e-6
    assert np.max(np.abs(r["tip.p[3]"] - s.position("tip")[:, 2])) < 1e-6


def test_fig3_manipulator_through_fmpy_equals_simulate(tmp_path):
    """The paper's Fig. 3 manipulator (examples/manipulator.py: 4 elements per flexible link,
    PD-controlled, the flexible parallelogram loop) with an extra Effort "dist" on the shoulder
    k1 as the input: a 2 N m step at 0.1 s. The generalized-alpha at a fixed 1e-4 s (Newton rtol
    1e-10) in both; simulate() runs the planar DAE (its default here), the FMU the 3-D one
    (2.3e-9 .. 3.9e-9 rad apart themselves). Measured: 2.9e-8 rad at most over the seven
    joints (at step 2e-4 s: 1.4e-6, the restarts' share)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
    import manipulator as M

    def arm(law):
        m, _ = M.build(M.ManipulatorParams(), elements=4)
        m.add_actuator("dist", "k1", ph.Effort(law=law))
        return m
    kw = dict(integrator="generalized-alpha", step=1e-4, rtol=1e-10)
    path = ph.export_fmu(arm(None), tmp_path / "manipulator.fmu", inputs=["dist"],
                         outputs=list(M.PAIRS), **kw)
    assert validate_fmu(str(path)) == []
    u = np.array([(0.0, 0.0), (0.1, 0.0), (0.1, 2.0), (0.5, 2.0)],
                 dtype=[("time", float), ("dist", float)])
    r = fmpy.simulate_fmu(str(path), stop_time=0.5, output_interval=0.01, input=u)
    s = arm(ph.Step(0.1, 2.0)).simulate(0.5, 0.01, **kw)
    for k in M.PAIRS:
        x = s.joint(k)["x"][:, 0]
        assert np.ptp(x) > 0.3
        assert np.max(np.abs(r[f"{k}.x"] - x)) < 1e-6, k


def test_wrench_amplitude_input_equals_simulate(tmp_path):
    """A wrench's amplitude as the input: a world force (0, 0, 2 N) times the input on the
    forearm's centre of mass, from 0 to 1 at T_STEP; the motor's own law (zero torque) stays."""
    def arm(law):
        m = rigid_arm(ph.Constant(0.0))
        m.add_wrench("push", "fore", (0, 0, 0, 0, 0, 2.0), law=law, point=(0.2, 0, 0))
        return m
    path = ph.export_fmu(arm(ph.Constant(1.0)), tmp_path / "push.fmu", inputs=["push"],
                         outputs=["elbow"], rtol=1e-10)
    u = np.array([(0.0, 0.0), (T_STEP, 0.0), (T_STEP, 1.0), (0.5, 1.0)],
                 dtype=[("time", float), ("push", float)])
    r = fmpy.simulate_fmu(str(path), stop_time=0.5, output_interval=0.01, input=u)
    s = arm(ph.Step(T_STEP, 1.0)).simulate(0.5, 0.01, integrator="ida", rtol=1e-10)
    free = rigid_arm(ph.Constant(0.0)).simulate(0.5, 0.01, integrator="ida", rtol=1e-10)
    x = s.joint("elbow")["x"][:, 0]
    assert np.max(np.abs(x - free.joint("elbow")["x"][:, 0])) > 1e-3   # the push shows
    assert np.max(np.abs(r["elbow.x"] - x)) < 1e-6


def test_model_description_validates(rigid_fmu):
    assert validate_fmu(str(rigid_fmu)) == []
    md = fmpy.read_model_description(str(rigid_fmu))
    assert md.fmiVersion == "2.0" and md.coSimulation.modelIdentifier == "rigid_arm"
    names = [v.name for v in md.modelVariables]
    assert names[0] == "motor" and "shoulder.x" in names and "energy.total" in names
    assert {v.name: v.unit for v in md.modelVariables}["shoulder.x"] == "rad"


def test_every_library_beyond_glibc_is_inside_the_fmu(rigid_fmu, tmp_path):
    with zipfile.ZipFile(rigid_fmu) as z:
        z.extractall(tmp_path)
    so = tmp_path / "binaries" / "linux64" / "rigid_arm.so"
    env = {k: v for k, v in os.environ.items() if k != "LD_LIBRARY_PATH"}
    ldd = subprocess.run(["ldd", str(so)], capture_output=True, text=True, check=True, env=env).stdout
    rows = [ln.split() for ln in ldd.splitlines() if "=>" in ln]
    outside = [r for r in rows if not SYSTEM_OK.match(r[0]) and
               not Path(r[2]).resolve().is_relative_to(so.parent.resolve())]
    assert not outside, ldd
    assert any("sundials" in r[0] for r in rows), ldd     # the core's libraries are there


def test_fmu_runs_in_a_fresh_venv_with_only_fmpy(rigid_fmu, tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    py = venv / "bin" / "python"
    r = subprocess.run([str(py), "-m", "pip", "install", "-q", "fmpy"], capture_output=True, text=True)
    if r.returncode:
        pytest.skip(f"pip could not install fmpy here: {r.stderr[-500:]}")
    script = ("import sys, fmpy; r = fmpy.simulate_fmu(sys.argv[1], stop_time=0.3, output_interval=0.01, "
              "output=['shoulder.x']); print('X', repr(float(r['shoulder.x'][-1])))\n"
              "import importlib.util; print('PHMECH', importlib.util.find_spec('phmech'))")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "LD_LIBRARY_PATH")}
    out = subprocess.run([str(py), "-c", script, str(rigid_fmu)], capture_output=True, text=True,
                         cwd=tmp_path, env=env)
    assert out.returncode == 0, out.stderr
    assert "PHMECH None" in out.stdout                      # phmech is not there
    # the motor's input stays 0: gravity alone, as simulate() with a zero torque
    s = rigid_arm(ph.Constant(0.0)).simulate(0.3, 0.01, integrator="ida", rtol=1e-10)
    x = float(out.stdout.split("X", 1)[1].split()[0])
    assert abs(x - s.joint("shoulder")["x"][-1, 0]) < 1e-6


def test_bad_arguments_are_named(tmp_path):
    m = rigid_arm()
    with pytest.raises(ph.ModelError, match="unknown input 'torque'.*'motor'"):
        ph.export_fmu(m, tmp_path / "a.fmu", inputs=["torque"])
    with pytest.raises(ph.ModelError, match="unknown output 'wrist'.*'shoulder'"):
        ph.export_fmu(m, tmp_path / "a.fmu", inputs=["motor"], outputs=["wrist"])
    with pytest.raises(ph.ModelError, match="input 'shoulder' is a pair"):
        ph.export_fmu(m, tmp_path / "a.fmu", inputs=["shoulder"])
    with pytest.raises(ph.ModelError, match=r"\.fmu"):
        ph.export_fmu(m, tmp_path / "a.zip")
    m.add_actuator("servo", "elbow", ph.PD(kp=10.0, kd=1.0))
    with pytest.raises(ph.ModelError, match="input 'servo' is a 'pd' actuator"):
        ph.export_fmu(m, tmp_path / "a.fmu", inputs=["servo"])
    # a Python-function law cannot go into an FMU, unless an input replaces it
    m2 = rigid_arm(ph.Function(lambda t: np.sin(t)))
    with pytest.raises(ph.ModelError, match="actuator 'motor': its time law is a Python function"):
        ph.export_fmu(m2, tmp_path / "b.fmu")
    assert ph.export_fmu(m2, tmp_path / "b.fmu", inputs=["motor"]).is_file()
    assert not (tmp_path / "a.fmu").exists()


def test_ida_on_flexible_links_warns_of_its_cost(tmp_path):
    with pytest.warns(ph.CostWarning, match="restarts IDA.*3 elements.*generalized-alpha") as w:
        ph.export_fmu(flexible_arm(), tmp_path / "f.fmu", inputs=["motor"])
    assert w[0].filename == __file__                       # the user's line
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ph.export_fmu(flexible_arm(), tmp_path / "f.fmu", inputs=["motor"],
                      integrator="generalized-alpha", step=1e-4)
        ph.export_fmu(rigid_arm(), tmp_path / "r.fmu", inputs=["motor"])


def test_example_runs_quick():
    examples = Path(__file__).resolve().parents[1] / "examples"
    out = subprocess.run([sys.executable, str(examples / "fmu_export.py"), "--quick", "--json"],
                         capture_output=True, text=True, check=True, cwd=examples).stdout
    import json
    d = json.loads(out)
    assert d["validation_problems"] == []
    assert d["max_diff_hub_rad"] < 1e-6 and d["max_diff_tip_z_m"] < 1e-6
    assert abs(d["hub_final_rad"]) > 0.1


def test_outputs_in_initialization_mode_and_reset(rigid_fmu, tmp_path):
    """The outputs are those of the initial state from fmi2EnterInitializationMode on; after
    fmi2Reset the FMU starts again from it (FMPy's low-level FMU2Slave)."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave
    md = read_model_description(str(rigid_fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    f = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(rigid_fmu), str(tmp_path / "x")),
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName="arm")
    f.instantiate()
    f.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    ask = [vr["fore.p[1]"], vr["fore.p[3]"], vr["energy.gravity"], vr["shoulder.x"]]
    assert np.allclose(f.getReal(ask), [0.5, 0.0, 0.0, 0.0], atol=1e-12)   # the given pose
    f.exitInitializationMode()
    f.doStep(0.0, 0.1)
    moved = f.getReal(ask)
    s = rigid_arm(ph.Constant(0.0)).simulate(0.1, 0.1, integrator="ida", rtol=1e-10)
    assert abs(moved[3] - s.joint("shoulder")["x"][-1, 0]) < 1e-6 and moved[2] < -0.01
    f.reset()
    f.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    f.exitInitializationMode()
    assert np.allclose(f.getReal(ask), [0.5, 0.0, 0.0, 0.0], atol=1e-12)
    f.doStep(0.0, 0.1)
    assert np.allclose(f.getReal(ask), moved, rtol=0, atol=1e-12)       # the same run again
    f.terminate()
    f.freeInstance()


def test_a_column_the_wrapper_does_not_read_is_refused(tmp_path, monkeypatch):
    """If phmech's model gains a column (python/phmech/_marshal.py), export_fmu refuses to write
    an FMU whose wrapper would silently leave it out."""
    from phmech import _marshal
    real = _marshal.components

    def more(*a, **k):
        c = real(*a, **k)
        c["elements"]["new_field"] = np.zeros(len(c["elements"]["h"]))
        return c
    import types
    monkeypatch.setattr(ph.fmu, "_marshal", types.SimpleNamespace(components=more))
    with pytest.raises(ph.ModelError, match=r"elements columns \['new_field'\].*csrc/fmi/fmu.c"):
        ph.export_fmu(flexible_arm(), tmp_path / "n.fmu", inputs=["motor"],
                      integrator="generalized-alpha", step=1e-4)


def test_fmi3_rigid_arm_through_fmpy_equals_simulate(tmp_path):
    """fmi_version="3.0": the same wrapper's fmi3* functions (co-simulation, no event mode),
    binaries in binaries/x86_64-linux/; FMPy validates and runs it; as the FMI 2.0 test."""
    path = ph.export_fmu(rigid_arm(), tmp_path / "arm3.fmu", inputs=["motor"],
                         outputs=["shoulder", "elbow"], integrator="ida", rtol=1e-10,
                         fmi_version="3.0")
    assert validate_fmu(str(path)) == []
    md = fmpy.read_model_description(str(path))
    assert md.fmiVersion == "3.0"
    assert "binaries/x86_64-linux/arm3.so" in zipfile.ZipFile(path).namelist()
    r = fmpy.simulate_fmu(str(path), stop_time=1.0, output_interval=0.01, input=step_input(1.0))
    s = rigid_arm(ph.Step(T_STEP, TAU)).simulate(1.0, 0.01, integrator="ida", rtol=1e-10)
    for pair in ("shoulder", "elbow"):
        assert np.max(np.abs(r[f"{pair}.x"] - s.joint(pair)["x"][:, 0])) < 1e-6
    with pytest.raises(ph.ModelError, match="fmi_version must be '2.0' or '3.0'"):
        ph.export_fmu(rigid_arm(), tmp_path / "x.fmu", fmi_version="1.0")
