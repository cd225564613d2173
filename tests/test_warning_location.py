"""A warning phmech issues points at the user's line, not inside phmech, however deep it was
found (mechanism._outside_stacklevel): Python shows that line with the message."""
import os
import sys
import warnings

import phmech as ph

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_closed_chains import fourbar  # noqa: E402


def horizontal_pendulum() -> ph.Mechanism:
    """A flexible pendulum released horizontal under gravity: not a static equilibrium."""
    m = ph.Mechanism(gravity=(0.0, 0.0, -9.81))
    arm = m.add_flexible_link("arm", 1.0, ph.table1_properties(), elements=4)
    m.add_pair("pivot", ph.Revolute("y"), m.ground, arm.start)
    return m


def test_modes_and_sized_warn_at_the_callers_line():
    m = horizontal_pendulum()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m.modes(2); line_modes = _line()                                        # noqa: E702
        m.sized(band=47.7, tolerance=1e-2); line_sized = _line()                # noqa: E702
    said = [(w.filename, w.lineno) for w in caught if issubclass(w.category, ph.EquilibriumWarning)]
    assert said == [(__file__, line_modes), (__file__, line_sized)]


def test_a_warning_found_while_building_the_model_points_at_the_call():
    """The redundant constraints of a four-bar of 3-D revolutes are found when the core model is
    built, three calls deep in phmech: the warning names the user's modes() line (it named a line
    of mechanism.py before)."""
    m = fourbar()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m.modes(1); line = _line()                                              # noqa: E702
    said = [(w.filename, w.lineno) for w in caught
            if issubclass(w.category, ph.RedundantConstraintWarning)]
    assert said == [(__file__, line)]


def _line() -> int:
    """The caller's line number."""
    return sys._getframe(1).f_lineno
