"""The mechanism's oriented graphs and incidence matrices (paper Sec. IV).

Vertices: the ground ``0``; rigid bodies ``1..n_r``; the two ends ``nL``, ``nR`` of each flexible
link. Edges: kinematic pairs (graph G_K), flexible links (G_F, the edge (nL, nR)) and interactions
(G_I). An edge (a, b) has l(e) = a and r(e) = b. An incidence matrix has a row per vertex (ground
left out; rigid rows first, then 1L, 1R, 2L, ...) and a column per edge, with -1 at l(e) and +1
at r(e); it is split into the rigid rows (B_r) and the flexible rows (B_f), as in the paper's (24).
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

import numpy as np

from ._errors import ModelError

GROUND = "0"


@dataclass(frozen=True)
class Incidence:
    """An incidence matrix split as in the paper's (24), with its row and column labels.

    ``rigid`` has shape (n_r, n_edges), ``flexible`` (2 n_f, n_edges); entries are -1, 0, +1.
    """

    rigid: np.ndarray
    flexible: np.ndarray
    rigid_rows: tuple[str, ...]
    flexible_rows: tuple[str, ...]
    columns: tuple[str, ...]

    @property
    def full(self) -> np.ndarray:
        """The whole matrix: rigid rows stacked over flexible rows."""
        return np.vstack([self.rigid, self.flexible])


@dataclass
class MechanismGraph:
    """Vertices and edges of a mechanism; derives G_K, G_F, G_I, incidence matrices and trees.

    ``rigid`` lists the rigid-body vertex names in order; ``flexible`` the flexible-link names (each
    contributes the vertices ``name + 'L'`` and ``name + 'R'`` unless ``ends`` are given).
    Edges are (name, l, r) triples in the order they were added.
    """

    rigid: list[str] = field(default_factory=list)
    flexible: list[str] = field(default_factory=list)
    pairs: list[tuple[str, str, str]] = field(default_factory=list)
    interactions: list[tuple[str, str, str]] = field(default_factory=list)
    #: interior beam nodes used as pair or interaction vertices: link name -> [(node k, label)]
    inner: dict = field(default_factory=dict)

    # ---- vertices -------------------------------------------------------------------------
    def flexible_vertices(self) -> list[str]:
        """Vertex labels of the flexible-link ends: 1L, 1R, 2L, 2R, ... (by link name)."""
        ends = [f"{name}{side}" for name in self.flexible for side in ("L", "R")]
        return ends + [lab for name in self.flexible for _, lab in sorted(self.inner.get(name, []))]

    def vertices(self) -> list[str]:
        """All vertices except the ground, in incidence-matrix row order."""
        return list(self.rigid) + self.flexible_vertices()

    def _check_vertex(self, v: str, what: str) -> None:
        if v != GROUND and v not in set(self.vertices()):
            raise ModelError(f"{what}: unknown vertex {v!r}; known: {['0'] + self.vertices()}")

    def add_pair(self, name: str, a: str, b: str) -> None:
        """Add the kinematic pair edge (a, b) of G_K."""
        self._add_edge(self.pairs, "pair", name, a, b)

    def add_interaction(self, name: str, a: str, b: str) -> None:
        """Add the interaction edge (a, b) of G_I."""
        self._add_edge(self.interactions, "interaction", name, a, b)

    def _add_edge(self, edges: list, kind: str, name: str, a: str, b: str) -> None:
        self._check_vertex(a, f"{kind} {name!r}")
        self._check_vertex(b, f"{kind} {name!r}")
        if a == b:
            raise ModelError(f"{kind} {name!r} connects vertex {a!r} with itself")
        edges.append((name, a, b))

    # ---- incidence matrices ---------------------------------------------------------------
    def _incidence(self, edges: list[tuple[str, str, str]]) -> Incidence:
        rows = self.vertices()
        index = {v: i for i, v in enumerate(rows)}
        B = np.zeros((len(rows), len(edges)), dtype=np.int64)
        for j, (_, l, r) in enumerate(edges):
            if l != GROUND:
                B[index[l], j] -= 1
            if r != GROUND:
                B[index[r], j] += 1
        nr = len(self.rigid)
        return Incidence(B[:nr], B[nr:], tuple(rows[:nr]), tuple(rows[nr:]),
                         tuple(e[0] for e in edges))

    def incidence_pairs(self) -> Incidence:
        """B_K = (B_K,r ; B_K,f): the incidence matrix of the kinematic-pair graph G_K."""
        return self._incidence(self.pairs)

    def incidence_interactions(self) -> Incidence:
        """B_I = (B_I,r ; B_I,f): the incidence matrix of the interaction graph G_I."""
        return self._incidence(self.interactions)

    def flexible_edges(self) -> list[tuple[str, str, str]]:
        """The edges f(n) = (nL, nR) of G_F (split through interior nodes used as vertices)."""
        out = []
        for name in self.flexible:
            chain = [f"{name}L"] + [lab for _, lab in sorted(self.inner.get(name, []))] + [f"{name}R"]
            out += [(name, chain[i], chain[i + 1]) for i in range(len(chain) - 1)]
        return out

    # ---- spanning tree of G_K ∪ G_F (paper Sec. V) ----------------------------------------
    def spanning_tree(self, require_connected: bool = True
                      ) -> tuple[list[tuple[str, str, str, bool]], list[tuple[str, str, str]]]:
        """Breadth-first spanning tree of the kinematic graph G_K ∪ G_F from the ground.

        Returns ``(tree, closing)``: ``tree`` lists (edge name, from vertex, to vertex, forward)
        in the order a walk from the ground meets them (``forward`` is True when the edge is
        traversed from l(e) to r(e)); ``closing`` lists the loop-closing edges (name, l, r).
        Raises ModelError naming the vertices that no path joins to the ground.
        """
        tree, closing, seen = self._walk([GROUND])
        unreachable = [v for v in self.vertices() if v not in seen]
        if unreachable and require_connected:
            raise ModelError(
                f"vertices {unreachable} are not connected to the ground by any pair or link; "
                "add a pair (e.g. ph.Free()) to give them a path")
        return tree, closing

    def loops(self) -> list[list[str]]:
        """One independent loop per loop-closing edge, as the list of edge names around it.
        Vertices unreachable from the ground are rooted at the first vertex of their component."""
        tree, closing = self._forest()
        parent: dict[str, tuple[str, str]] = {}
        for name, frm, to, _ in tree:
            parent[to] = (frm, name)

        def path_to_ground(v: str) -> list[tuple[str, str]]:
            out = []
            while v in parent:
                frm, name = parent[v]
                out.append((v, name))
                v = frm
            return out

        result = []
        for name, l, r in closing:
            pl, pr = path_to_ground(l), path_to_ground(r)
            common = {v for v, _ in pl} & {v for v, _ in pr}
            left = [e for v, e in pl if v not in common]
            right = [e for v, e in pr if v not in common]
            result.append(left + [name] + right[::-1])
        return result

    def _forest(self):
        """Breadth-first spanning forest: the tree from the ground, then one tree per component
        not connected to it (free bodies or links); returns (tree edges, closing edges)."""
        tree, closing, _ = self._walk([GROUND] + self.vertices())
        return tree, closing

    def _walk(self, roots: list[str]):
        """Breadth-first walk of G_K ∪ G_F starting a new tree at each root not yet reached.
        Returns (tree edges (name, from, to, forward), unused (closing) edges, reached vertices)."""
        edges = list(self.pairs) + self.flexible_edges()
        adjacent: dict[str, list[tuple[int, str, bool]]] = {v: [] for v in [GROUND] + self.vertices()}
        for k, (_, l, r) in enumerate(edges):
            adjacent[l].append((k, r, True))
            adjacent[r].append((k, l, False))
        seen: set = set()
        used = [False] * len(edges)
        tree = []
        for root in roots:
            if root in seen:
                continue
            seen.add(root)
            queue = deque([root])
            while queue:
                v = queue.popleft()
                for k, w, forward in adjacent[v]:
                    if used[k] or w in seen:
                        continue
                    used[k] = True
                    seen.add(w)
                    tree.append((edges[k][0], v, w, forward))
                    queue.append(w)
        closing = [edges[k] for k in range(len(edges)) if not used[k]]
        return tree, closing, seen


# ---- the graphs of a mechanism ------------------------------------------------------------
@dataclass(frozen=True)
class Graphs:
    """The mechanism's graphs (paper Sec. IV). Vertices ``G_B``: "0" (ground), the
    rigid bodies and rigid-fidelity links by name in the order added, then "<link>L", "<link>R" per flexible link (and
    "<link>[k]" for interior nodes used by a pair). Edges (name, l, r): ``G_K`` pairs, ``G_F``
    links, ``G_I`` interactions (add_interaction, whose reaction defaults to the ground, and
    spring-dampers). ``B_K``/``B_I``: incidence matrices with labels (-1 at l(e), +1 at r(e));
    ``B_K_r`` etc. are their rigid and flexible row blocks, as in the paper's (24)-(25)."""
    graph: MechanismGraph
    B_K: Incidence
    B_I: Incidence

    G_B = property(lambda self: ["0"] + self.graph.vertices())
    G_K = property(lambda self: list(self.graph.pairs))
    G_F = property(lambda self: self.graph.flexible_edges())
    G_I = property(lambda self: list(self.graph.interactions))
    B_K_r = property(lambda self: self.B_K.rigid)
    B_K_f = property(lambda self: self.B_K.flexible)
    B_I_r = property(lambda self: self.B_I.rigid)
    B_I_f = property(lambda self: self.B_I.flexible)

    def loops(self) -> list:
        """One independent loop per loop-closing edge (lists of pair and link names)."""
        return self.graph.loops()


def _vertex(desc: "ModelDescription", carrier: int, inner: dict) -> str:
    """The vertex label of a carrier: "0", a body's name, "<link>L", "<link>R", or "<link>[k]"
    for an interior node k (recorded in ``inner``)."""
    if carrier < 0:
        return GROUND
    rigid = desc.rigid_carriers()
    if carrier in rigid:
        return rigid[carrier]
    for lk in desc.links.values():
        if carrier in lk.nodes:
            k = lk.nodes.index(carrier)
            if k == 0:
                return lk.name + "L"
            if k == lk.elements:
                return lk.name + "R"
            lab = f"{lk.name}[{k}]"
            if (k, lab) not in inner.setdefault(lk.name, []):
                inner[lk.name].append((k, lab))
            return lab
    raise ModelError(f"carrier {carrier} belongs to no body or link")


def mechanism_graphs(desc: "ModelDescription") -> Graphs:
    """The graphs of the mechanism ``desc`` describes: a pair or interaction added between a
    and b, in that order, is the edge (a, b): -1 at row a, +1 at row b."""
    inner: dict = {}
    g = MechanismGraph(rigid=list(desc.rigid_carriers().values()),
                       flexible=[nm for nm, lk in desc.links.items() if not lk.rigid], inner=inner)
    # a modal link's sliders (its modes' pairs and springs) are inside its G_F edge
    inside = {c for lk in desc.links.values() for c in lk.sliders}
    for e in desc.pairs:
        if e["b"] not in inside:
            g.pairs.append((e["name"], _vertex(desc, e["a"], inner), _vertex(desc, e["b"], inner)))
    for ld in desc.loads:
        if ld.get("interaction"):
            g.interactions.append((ld["name"], _vertex(desc, ld["carrier"], inner),
                                   _vertex(desc, ld["reaction"], inner)))
    for q in desc.springs:
        if q["b"] in inside:
            continue
        g.interactions.append((q["name"], _vertex(desc, q["a"], inner), _vertex(desc, q["b"], inner)))
    return Graphs(g, g.incidence_pairs(), g.incidence_interactions())
