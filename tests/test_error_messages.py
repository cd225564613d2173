"""Bad input gets a ModelError that says what was wrong
(python/phmech/mechanism.py: FlexibleLink.node, _frame_of; python/phmech/laws.py: checked_law)."""
import numpy as np
import pytest

import phmech as ph

PROPS = type("P", (), dict(stiffness=np.diag([1e2, 1e2, 1e2, 1e5, 1e4, 1e4]),
                           inertia=np.diag([1e-3, 1e-3, 1e-3, 1.0, 1.0, 1.0])))


def model():
    m = ph.Mechanism()
    link = m.add_flexible_link("beam", 1.0, PROPS, elements=4)
    m.add_pair("clamp", ph.Fixed(), m.ground, link.start)
    return m, link


def test_node_index_out_of_range_names_link_and_range():
    _, link = model()
    with pytest.raises(ph.ModelError, match=r"link 'beam' has nodes 0\.\.4 \(4 elements; negative "
                                            r"indices -5\.\.-1 count from the end\); got node\(99\)"):
        link.node(99)
    with pytest.raises(ph.ModelError, match=r"got node\(-6\)"):
        link.node(-6)
    with pytest.raises(ph.ModelError, match="node index must be an integer"):
        link.node(1.5)


def test_negative_node_index_counts_from_the_end():
    _, link = model()
    # documented Python-style: -1 is the end node (x = L), -5 the start, -2 the node at 0.75 L
    assert link.node(-1).carrier == link.end.carrier == link.nodes[4]
    assert link.node(-5).carrier == link.start.carrier
    assert link.node(-2).carrier == link.node(3).carrier and link.node(-2).name == "beam.node3"
    m, link = model()
    H = m.initial_configuration().poses
    np.testing.assert_allclose(H[link.node(-2).carrier][:3, 3], [0.75, 0, 0], atol=1e-15)


def test_python_function_as_time_law_is_accepted_and_a_bad_one_refused_clearly():
    """A Python function of t is a law (phmech.Function, called back from the core); one that
    raises or returns something else than a finite real number is refused at add_* time with
    its name, the time and what it did (the original exception as the cause)."""
    m, link = model()
    body = m.add_rigid_body("b", 1.0, np.eye(3))

    def ramp(t):
        return 2.0 * t

    def broken(t):
        return 1.0 / 0.0

    m.add_pair("drive", ph.Fixed(), link.end, body, driven=ph.Motion((0, 0, 1, 0, 0, 0), ramp))
    m.add_wrench("w", link.end, (0, 0, 0, 0, 0, 1.0), law=ramp)
    with pytest.raises(ph.ModelError, match=r"wrench 'w1': law: time law: the function 'broken' raised "
                                            r"ZeroDivisionError at t = 0 s") as e:
        m.add_wrench("w1", link.end, (0, 0, 0, 0, 0, 1.0), law=broken)
    assert isinstance(e.value.__cause__, ZeroDivisionError)
    with pytest.raises(ph.ModelError, match=r"Effort law: time law: the function '<lambda>' returned "
                                            r"str 'x' at t = 0 s, not a real number"):
        m.add_pair("hinge", ph.Revolute("z"), m.ground, body, actuator=ph.Effort(lambda t: "x"))
    with pytest.raises(ph.ModelError, match=r"PD target: time law: the function '<lambda>' returned nan"):
        m.add_pair("hinge2", ph.Revolute("z"), m.ground, body,
                   actuator=ph.PD(1.0, 0.1, target=lambda t: float("nan")))
    with pytest.raises(ph.ModelError, match=r"wrench 'w2': law: expected a time law .* \(got str\)"):
        m.add_wrench("w2", link.end, (0, 0, 0, 0, 0, 1.0), law="step")
    # none of the refused names was taken
    m.add_wrench("w1", link.end, (0, 0, 0, 0, 0, 1.0), law=ph.Table([0.0, 1.0], [0.0, 2.0]))


def test_frame_on_unknown_carrier_says_which_argument_and_what_was_given():
    m, link = model()
    other = ph.Mechanism()
    stray = other.add_flexible_link("long", 1.0, PROPS, elements=20)   # carriers 0..20 there
    with pytest.raises(ph.ModelError, match=r"wrench 'tap', argument target: the frame 'long.end' is on "
                                            r"carrier 20, which this mechanism does not have \(carriers "
                                            r"-1 = the ground, 0\.\.4\)"):
        m.add_wrench("tap", stray.end, (0, 0, 0, 0, 0, 1.0))
    with pytest.raises(ph.ModelError, match=r"pair 'p', argument b: the frame \(unnamed\) is on carrier 7"):
        m.add_pair("p", ph.Revolute(), m.ground, ph.Frame(7, np.eye(4)))
    with pytest.raises(ph.ModelError, match=r"pair 'p', argument b: unknown body 'nobody', neither "
                                            r"'ground' nor a body of this mechanism \(bodies: none\)"):
        m.add_pair("p", ph.Revolute(), "ground", "nobody")
    with pytest.raises(ph.ModelError, match=r"static load 0, target: 'beam' is a flexible link"):
        m.static(loads=[("beam", (0, 0, 0, 0, 0, 1.0), "world")])
