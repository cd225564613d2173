"""Graphs and incidence matrices: the paper's Fig. 3 mechanism must give its (25) exactly."""
import numpy as np
import pytest

import phmech
from phmech.graphs import MechanismGraph


def fig3_graph() -> MechanismGraph:
    g = MechanismGraph(rigid=["1", "2", "3"], flexible=["1", "2", "3"])
    for n, (a, b) in enumerate([("1L", "0"), ("1", "1R"), ("2L", "1"), ("3L", "1"),
                                ("2", "2R"), ("2", "3R"), ("3", "2")], start=1):
        g.add_pair(f"k{n}", a, b)
    g.add_interaction("i1", "3", "0")
    return g


# The paper's (25), written out by hand from the edge list of docs/method.md section 8.3 and the
# rule -1 at l(e), +1 at r(e); rows 1, 2, 3 and 1L, 1R, 2L, 2R, 3L, 3R.
B_K_r = [[0, -1, 1, 1, 0, 0, 0],
         [0, 0, 0, 0, -1, -1, 1],
         [0, 0, 0, 0, 0, 0, -1]]
B_K_f = [[-1, 0, 0, 0, 0, 0, 0],
         [0, 1, 0, 0, 0, 0, 0],
         [0, 0, -1, 0, 0, 0, 0],
         [0, 0, 0, 0, 1, 0, 0],
         [0, 0, 0, -1, 0, 0, 0],
         [0, 0, 0, 0, 0, 1, 0]]


def test_fig3_incidence_matches_paper_eq25():
    g = fig3_graph()
    bk = g.incidence_pairs()
    np.testing.assert_array_equal(bk.rigid, B_K_r)
    np.testing.assert_array_equal(bk.flexible, B_K_f)
    assert bk.rigid_rows == ("1", "2", "3")
    assert bk.flexible_rows == ("1L", "1R", "2L", "2R", "3L", "3R")
    bi = g.incidence_interactions()
    np.testing.assert_array_equal(bi.rigid, [[0], [0], [-1]])
    np.testing.assert_array_equal(bi.flexible, np.zeros((6, 1)))


def test_every_column_sums_to_zero_or_touches_ground():
    bk = fig3_graph().incidence_pairs().full
    # an edge between two non-ground vertices has one -1 and one +1
    touches_ground = [0]  # k(1) = (1L, 0)
    for j in range(bk.shape[1]):
        assert abs(bk[:, j].sum()) == (1 if j in touches_ground else 0)


def test_fig3_spanning_tree_and_loop():
    g = fig3_graph()
    tree, closing = g.spanning_tree()
    # 9 non-ground vertices need 9 tree edges; 7 pairs + 3 links = 10 edges -> 1 loop.
    assert len(tree) == 9 and len(closing) == 1
    loops = g.loops()
    assert len(loops) == 1
    # Breadth-first from the ground closes the loop with k(6) = (2, 3R): the chain
    # R1 -k3- F2 -k5- R2 -k6- F3 -k4- R1 of rigid and flexible links.
    assert closing[0][0] == "k6"
    assert sorted(loops[0]) == sorted(["k3", "2", "k5", "k6", "3", "k4"])
    # every vertex on the loop has even degree within the loop's edges
    edges = {name: (l, r) for name, l, r in g.pairs + g.flexible_edges()}
    degree: dict[str, int] = {}
    for e in loops[0]:
        for v in edges[e]:
            degree[v] = degree.get(v, 0) + 1
    assert all(d == 2 for d in degree.values()), degree


def test_bad_edges_raise():
    g = MechanismGraph(rigid=["a"], flexible=["f"])
    with pytest.raises(phmech.ModelError, match="unknown vertex"):
        g.add_pair("p", "a", "nope")
    with pytest.raises(phmech.ModelError, match="itself"):
        g.add_pair("p", "a", "a")
    with pytest.raises(ValueError, match="not connected"):
        g.spanning_tree()
