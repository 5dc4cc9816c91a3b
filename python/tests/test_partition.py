"""rbpart.partition on graphs given as CSR arrays, checked against the properties every partitioner
and refiner promises (docs/design.md#partition, #refine): the parts cover every node, hold at most
nmax nodes, are connected, and refinement never raises the edge cut. The cut and interface are
recomputed here from the arrays."""
import itertools
from collections import deque

import numpy as np
import pytest

import rbpart

PARTITIONERS = ["bfs", "mindp", "maxdp", "mr", "mix", "metis"]
REFINERS = ["none", "kl", "fm", "fm-rollback"]


def csr(n, edges, weights=None):
    """CSR arrays of an undirected graph on n nodes, each edge listed from both ends."""
    weights = [1] * len(edges) if weights is None else weights
    lists = [[] for _ in range(n)]
    for (a, b), w in zip(edges, weights):
        lists[a].append((b, w))
        lists[b].append((a, w))
    xadj = np.cumsum([0] + [len(l) for l in lists])
    adjncy = np.array([v for l in lists for v, _ in l], dtype=np.int64)
    adjwgt = np.array([w for l in lists for _, w in l], dtype=np.int64)
    return xadj, adjncy, adjwgt


def grid_graph(rows, cols, rng):
    node = lambda r, c: r * cols + c
    edges = [(node(r, c), node(r, c + 1)) for r in range(rows) for c in range(cols - 1)]
    edges += [(node(r, c), node(r + 1, c)) for r in range(rows - 1) for c in range(cols)]
    return rows * cols, edges, list(rng.integers(1, 5, len(edges)))


def geometric_graph(n, radius, rng):
    """Random points in the unit square joined when closer than radius: clustered, often several
    components (islands), like a pile's contact graph."""
    p = rng.random((n, 2))
    edges = [(a, b) for a, b in itertools.combinations(range(n), 2) if np.linalg.norm(p[a] - p[b]) < radius]
    return n, edges, list(rng.integers(1, 4, len(edges)))


def components(n, xadj, adjncy, keep):
    """Connected components of the nodes with keep[v], as a list of node lists."""
    seen, out = np.zeros(n, bool), []
    for s in range(n):
        if seen[s] or not keep[s]:
            continue
        seen[s], queue, comp = True, deque([s]), []
        while queue:
            v = queue.popleft()
            comp.append(v)
            for u in adjncy[xadj[v]:xadj[v + 1]]:
                if keep[u] and not seen[u]:
                    seen[u] = True
                    queue.append(u)
        out.append(comp)
    return out


def check_partition(n, xadj, adjncy, adjwgt, parts, quality, nmax):
    assert parts.shape == (n,)
    count = quality["parts"]
    assert set(parts.tolist()) == set(range(count))  # every node has a part, no part is empty
    sizes = np.bincount(parts, minlength=count)
    assert sizes.max() <= nmax
    assert quality["max_bodies"] == sizes.max() and quality["min_bodies"] == sizes.min()
    for p in range(count):
        assert len(components(n, xadj, adjncy, parts == p)) == 1, f"part {p} is not connected"
    # Every island (component) is split apart from the others.
    for island in components(n, xadj, adjncy, np.ones(n, bool)):
        others = np.ones(n, bool)
        others[island] = False
        assert not set(parts[island]) & set(parts[others])
    src = np.repeat(np.arange(n), np.diff(xadj))
    cut_edges = parts[src] != parts[adjncy]
    assert quality["edge_cut"] == adjwgt[cut_edges].sum() // 2
    assert quality["interface_bodies"] == len(set(src[cut_edges]))


GRAPHS = {
    "grid 12x9": lambda rng: grid_graph(12, 9, rng),
    "geometric 150": lambda rng: geometric_graph(150, 0.12, rng),
}


@pytest.mark.parametrize("graph", list(GRAPHS))
@pytest.mark.parametrize("partitioner", PARTITIONERS)
def test_every_partitioner_and_refiner_keeps_the_partition_properties(graph, partitioner):
    rng = np.random.default_rng(7)
    n, edges, weights = GRAPHS[graph](rng)
    xadj, adjncy, adjwgt = csr(n, edges, weights)
    masses = rng.choice([10.0, 100.0, 1000.0], n)
    nmax = 10
    cuts = {}
    for refiner in REFINERS:
        parts, quality = rbpart.partition(xadj, adjncy, partitioner, refiner, edge_weights=adjwgt, masses=masses,
                                          nmax=nmax)
        assert parts.dtype == np.int32
        check_partition(n, xadj, adjncy, adjwgt, parts, quality, nmax)
        cuts[refiner] = quality["edge_cut"]
    assert all(cuts[r] <= cuts["none"] for r in REFINERS), cuts


def test_parts_k_caps_the_parts_at_n_over_k():
    rng = np.random.default_rng(3)
    n, edges, weights = grid_graph(10, 10, rng)
    xadj, adjncy, adjwgt = csr(n, edges, weights)
    for k in (1, 3, 7):
        parts, quality = rbpart.partition(xadj, adjncy, "metis", "fm", edge_weights=adjwgt, parts=k)
        assert quality["nmax"] == -(-n // k)
        check_partition(n, xadj, adjncy, adjwgt, parts, quality, quality["nmax"])
    parts, quality = rbpart.partition(xadj, adjncy, "bfs", parts=1)
    assert quality["parts"] == 1 and quality["edge_cut"] == 0


def test_neighbour_order_does_not_change_the_partition():
    rng = np.random.default_rng(5)
    n, edges, weights = geometric_graph(80, 0.18, rng)
    xadj, adjncy, adjwgt = csr(n, edges, weights)
    shuffled, shuffled_w = adjncy.copy(), adjwgt.copy()
    for v in range(n):
        order = xadj[v] + rng.permutation(xadj[v + 1] - xadj[v])
        shuffled[xadj[v]:xadj[v + 1]], shuffled_w[xadj[v]:xadj[v + 1]] = adjncy[order], adjwgt[order]
    a, qa = rbpart.partition(xadj, adjncy, "mix", "fm", edge_weights=adjwgt, nmax=6)
    b, qb = rbpart.partition(xadj, shuffled, "mix", "fm", edge_weights=shuffled_w, nmax=6)
    np.testing.assert_array_equal(a, b)
    assert qa["edge_cut"] == qb["edge_cut"]


def test_a_simulated_scene_graph_partitions_like_any_other():
    world = rbpart.World("box_stack", {"boxes": 10})
    world.step(5)
    g = world.constraint_graph()
    n = len(g["masses"])
    assert n == 10 and sorted(g["bodies"]) == list(range(1, 11))
    np.testing.assert_allclose(g["masses"], world.masses[g["bodies"]])
    parts, quality = rbpart.partition(g["xadj"], g["adjncy"], "mr", "kl", edge_weights=g["edge_weights"],
                                      masses=g["masses"], nmax=3)
    check_partition(n, g["xadj"], g["adjncy"], g["edge_weights"], parts, quality, 3)
    # Without a partitioner the world's parts are its islands: one stack, one part.
    assert set(world.parts().tolist()) == {0}


@pytest.mark.parametrize("xadj,adjncy,kwargs", [
    ([0, 1, 1], [1], {}),                       # 0 lists 1, 1 does not list 0
    ([0, 1, 2], [0, 0], {}),                    # self loop
    ([0, 1, 2], [1, 5], {}),                    # neighbour out of range
    ([0, 2, 3], [1, 1, 0], {}),                 # 1 listed twice
    ([0, 1, 2], [1, 0], {"edge_weights": [1, 2]}),  # the two directions disagree
    ([0, 1, 2], [1, 0], {"masses": [1.0, -1.0]}),
    ([0, 1, 2], [1.5, 0], {}),                  # not integers
    ([0, 1, 2], [1, 0], {"nmax": 0}),
    ([0, 1, 2], [1, 0], {"nmax": 2, "parts": 1}),
])
def test_malformed_graphs_and_options_raise_value_error(xadj, adjncy, kwargs):
    with pytest.raises(ValueError):
        rbpart.partition(np.array(xadj), np.array(adjncy), "bfs", **kwargs)


def test_unknown_partitioner_or_refiner_raises_value_error():
    xadj, adjncy, _ = csr(3, [(0, 1), (1, 2)])
    for partitioner, refiner in [("kahip", "none"), ("none", "none"), ("bfs", "sa")]:
        with pytest.raises(ValueError):
            rbpart.partition(xadj, adjncy, partitioner, refiner)
