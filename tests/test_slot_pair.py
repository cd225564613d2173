"""The slot pair (csrc/model/pair_types.c): a body on a slot slides along F_a's x axis and turns
about z. References: free fall along the slot, x = -g t^2 / 2, and a spin kept constant, both
exact for this pair; a model file round trip."""
import numpy as np
import pytest

import phmech as ph


def test_a_body_falls_along_the_slot_and_keeps_its_spin(tmp_path):
    """Measured at the defaults: 3.1e-5 m on the slide (scale 4.9 m, rtol 1e-4) and 1.6e-6 rad
    on the angle after 1 s."""
    m = ph.Mechanism(gravity=(-9.81, 0, 0))
    b = m.add_rigid_body("b", 2.0, np.diag([0.01, 0.01, 0.02]))
    m.add_pair("s", ph.Slot(), m.ground, b, xdot0=(3.0, 0.0))
    r = m.simulate(1.0, 0.1)
    x, t = r.joint("s")["x"], r.t
    assert np.abs(x[:, 1] + 9.81 * t**2 / 2).max() <= 1e-4 * 9.81 / 2 + 1e-6
    assert np.abs(x[:, 0] - 3.0 * t).max() <= 1e-4 * 3.0 + 1e-6
    m.save(tmp_path / "slot.json")
    assert type(ph.load(tmp_path / "slot.json")._desc.pairs[0]["pair"]).__name__ == "Slot"


def test_the_slot_holds_the_other_four_directions():
    """Gravity across the slot and a centre of mass off it, so that the weight pulls the origin
    off the axis and twists the body about x and y: the body stays on the slot's axis, turned
    about z only (the constraint wrench's f_y_a, f_z_a, tau_x, tau_y hold it)."""
    m = ph.Mechanism(gravity=(0, -9.81, -9.81))
    b = m.add_rigid_body("b", 1.0, np.diag([0.01, 0.01, 0.02]), com=(0.1, 0.1, 0.05))
    m.add_pair("s", ph.Slot(), m.ground, b)
    r = m.simulate(0.5, 0.05)
    H = r.poses[:, b.carrier]
    assert np.abs(H[:, 1:3, 3]).max() < 1e-9                       # on F_a's x axis
    assert np.abs(H[:, 2, 2] - 1.0).max() < 1e-9                    # z stays z: no tilt
    assert np.abs(r.joint("s")["x"][:, 0]).max() > 1e-3             # it does turn about z
