"""Skeleton-graph coarsening and the normalised hop kernels of ActFormer's critic (Xu et al., "ActFormer";
the authors' ``utils/skeleton/graph/coarsening.py`` and ``utils/skeleton/nn/graph_conv.py``), in numpy.

The critic (:mod:`jaxmotion.models.actformer_critic`) halves the skeleton graph twice. One coarsening step
keeps a *maximal independent set* of the graph's nodes, chosen among **all** maximal independent sets (not
greedily) by this lexicographic order, each criterion deciding only among the sets tied on the previous ones:

1. largest sum of node degrees;
2. largest mean betweenness (unnormalised, each unordered pair of end nodes counted once);
3. largest mean closeness (``(V - 1) / Σ_u d(v, u)``, the inverse mean distance to the other nodes);
4. smallest mean eccentricity (largest distance to another node);
5. fewest nodes;
6. smallest sum of node indices;
7. (not reached on the skeletons used) the lexicographically smallest sorted index list.

Measures are those of the finer graph the set is chosen from (python-igraph's ``degree``, ``betweenness``,
``closeness`` and ``eccentricity`` in the authors' code). Kept nodes keep their original order; two of them
are linked in the coarse graph when they are at most 3 hops apart in the finer one.

Where this differs from the authors' code:

* **Exact means.** The authors compare float means accumulated as running means, so two sets whose means are
  equal can be told apart by rounding error (e.g. betweenness means 8/3 from ``[8, 0, 0]`` and ``[0, 4, 4]``);
  here means are compared as rationals. On NTU-25, SMPL-24/25 and GTA-22 both give the same sets.
* **Last resort.** Sets still tied after the index sum are resolved by igraph's enumeration order there;
  on the skeletons used this happens once (SMPL's second step: ``[0, 4, 5, 9, 10]`` against
  ``[1, 3, 5, 9, 10]`` of its 12 nodes), where igraph's first is also the lexicographically smaller.
* **Hop kernels** mark ``d(w, v) == k`` directly; the authors index igraph's list of all shortest paths by
  position, which equals this only while no node has two shortest paths to a node listed before a neighbour
  (true of every graph the critic builds on the skeletons used).

A graph layer from ``V`` nodes to the ``W`` nodes ``rows`` uses one kernel per hop ``k`` (0: the node itself,
1: its neighbours): ``mask[k, w, v] = [d(rows[w], v) == k]``, then every entry is divided by
``√(Σ_v' mask[k, w, v'] · Σ_w' mask[k, w', v])``, the row count and the column count of that kernel, the
column count taken over the kept rows only (the authors' "group" normalisation).

Recomputed sets (the tests pin them): NTU-25: 25 -> 11 ``[0, 3, 5, 7, 9, 11, 13, 15, 17, 19, 20]`` -> 5
``[7, 11, 13, 17, 20]`` (-> ``[20]``); SMPL-25 (SMPL-24 plus the translation node 24 under joint 0): 25 -> 12
``[1, 2, 3, 7, 8, 9, 15, 16, 17, 20, 21, 24]`` -> 5 ``[1, 8, 9, 20, 21]``; GTA-22: 22 -> 10 -> 4.

Use: ``CriticGraphs(*critic_adjacency(parents))``. Enumerating every maximal independent set is exponential
in the worst case; like the authors' code it is meant for skeleton-sized graphs (at most 50 nodes).

Axes: V input nodes, W output (kept) nodes, K hop kernels.
"""

from __future__ import annotations

from fractions import Fraction
from typing import NamedTuple

import numpy as np

from jaxmotion.geometry.skeletons import bones

MAX_NODES = 50  # the enumeration of maximal independent sets is exponential; skeletons are far below this
COARSE_HOPS = 3  # kept nodes at most this many hops apart are linked in the coarse graph
CRITIC_KERNELS = 2  # hop kernels of the critic's graph layers: the node itself and its neighbours


class GraphPyramid(NamedTuple):
    """``adjacency[0]`` is the skeleton's ``[V, V]``; ``kept[i]`` indexes the nodes of ``adjacency[i]`` that
    survive coarsening ``i``, and ``adjacency[i + 1]`` ``[W_i, W_i]`` links them."""

    kept: tuple[np.ndarray, ...]
    adjacency: tuple[np.ndarray, ...]


# ------------------------------------------------------------------------------------------------ graphs


def skeleton_adjacency(parents: tuple[int, ...]) -> np.ndarray:
    """``[V, V]`` 0/1 adjacency of a kinematic tree (one edge per bone, no self-loops)."""
    adjacency = np.zeros((len(parents), len(parents)), dtype=np.int64)
    for parent, child in bones(tuple(parents)):  # validates the tree
        adjacency[parent, child] = adjacency[child, parent] = 1
    return adjacency


def _check_adjacency(adjacency: np.ndarray, name: str = "adjacency") -> np.ndarray:
    """Validated ``[V, V]`` boolean copy: square, 0/1, symmetric, no self-loops, connected."""
    adjacency = np.asarray(adjacency)
    if adjacency.ndim != 2 or adjacency.shape[0] != adjacency.shape[1] or adjacency.shape[0] == 0:
        raise ValueError(f"{name}: expected a square [V, V] matrix with V >= 1, got shape {adjacency.shape}")
    if not np.isin(adjacency, (0, 1)).all():
        raise ValueError(f"{name}: expected 0/1 entries, got values {np.unique(adjacency).tolist()}")
    linked = adjacency.astype(bool)
    if (linked != linked.T).any():
        raise ValueError(f"{name}: expected a symmetric matrix (an undirected graph)")
    if linked.diagonal().any():
        raise ValueError(f"{name}: expected a zero diagonal (no self-loops), got self-loops at "
                         f"{np.flatnonzero(linked.diagonal()).tolist()}")
    if np.isinf(_distances(linked)).any():
        raise ValueError(f"{name}: expected a connected graph")
    return linked


def _distances(linked: np.ndarray) -> np.ndarray:
    """``[V, V]`` hop counts (``inf`` between components) by repeated one-hop expansion."""
    nodes = linked.shape[0]
    reached = np.eye(nodes, dtype=bool)
    distance = np.where(reached, 0.0, np.inf)
    for hop in range(1, nodes):
        grown = reached | ((reached.astype(np.int64) @ linked.astype(np.int64)) > 0)
        if (grown == reached).all():
            break
        distance[grown & ~reached] = hop
        reached = grown
    return distance


def hop_distances(adjacency: np.ndarray) -> np.ndarray:
    """``[V, V]`` integer hop counts between the nodes of a connected graph ``adjacency [V, V]``."""
    return _distances(_check_adjacency(adjacency)).astype(np.int64)


# ---------------------------------------------------------------------------------------------- measures


def _betweenness(linked: np.ndarray, distance: np.ndarray) -> list[Fraction]:
    """Exact betweenness per node: Σ over unordered pairs {s, t} not containing v of σ_st(v) / σ_st.

    Brute force over pairs, fine at skeleton size: σ_st counts shortest paths (``σ[s, t]`` by dynamic
    programming over distance), and v lies on σ[s, v]·σ[v, t] of them when d(s, v) + d(v, t) = d(s, t).
    """
    nodes = linked.shape[0]
    sigma = np.zeros((nodes, nodes), dtype=object)
    for s in range(nodes):
        sigma[s, s] = 1
        for hop in range(1, int(distance[s].max()) + 1):
            for t in np.flatnonzero(distance[s] == hop):
                sigma[s, t] = sum(sigma[s, u] for u in np.flatnonzero(linked[t] & (distance[s] == hop - 1)))
    scores = [Fraction(0)] * nodes
    for s in range(nodes):
        for t in range(s + 1, nodes):
            for v in range(nodes):
                if v not in (s, t) and distance[s, v] + distance[v, t] == distance[s, t]:
                    scores[v] += Fraction(int(sigma[s, v] * sigma[v, t]), int(sigma[s, t]))
    return scores


def _closeness(distance: np.ndarray) -> list[Fraction]:
    """Exact closeness per node, ``(V - 1) / Σ_u d(v, u)`` (1 for a single node)."""
    nodes = distance.shape[0]
    return [Fraction(nodes - 1, int(row.sum())) if nodes > 1 else Fraction(1) for row in distance]


def maximal_independent_sets(adjacency: np.ndarray) -> list[tuple[int, ...]]:
    """Every maximal independent set of ``adjacency [V, V]`` (sorted index tuples, in sorted order): the
    maximal cliques of the complement graph, by Bron–Kerbosch with pivoting over bit masks."""
    linked = _check_adjacency(adjacency)
    nodes = linked.shape[0]
    if nodes > MAX_NODES:
        raise ValueError(f"adjacency: expected at most {MAX_NODES} nodes (the enumeration is exponential), "
                         f"got {nodes}")
    everyone = (1 << nodes) - 1
    # compatible[v]: the nodes that may join a set holding v (neither v nor its neighbours)
    compatible = [everyone & ~(1 << v) & ~sum(1 << u for u in np.flatnonzero(linked[v])) for v in range(nodes)]
    found: list[int] = []

    def members(mask: int) -> list[int]:
        return [v for v in range(nodes) if mask >> v & 1]

    def expand(chosen: int, candidates: int, excluded: int) -> None:
        if not candidates and not excluded:
            found.append(chosen)
            return
        pivot = max(members(candidates | excluded), key=lambda u: bin(candidates & compatible[u]).count("1"))
        for v in members(candidates & ~compatible[pivot]):
            expand(chosen | 1 << v, candidates & compatible[v], excluded & compatible[v])
            candidates &= ~(1 << v)
            excluded |= 1 << v

    expand(0, everyone, 0)
    return sorted(tuple(members(mask)) for mask in found)


# ------------------------------------------------------------------------------------------- coarsening


def coarsen(adjacency: np.ndarray) -> np.ndarray:
    """Sorted indices ``[W]`` of the nodes of ``adjacency [V, V]`` that one coarsening step keeps: the best
    maximal independent set by the module docstring's criteria."""
    linked = _check_adjacency(adjacency)
    candidates = maximal_independent_sets(linked)  # checks the size before the measures' work
    distance = _distances(linked).astype(np.int64)
    degree = linked.sum(axis=1)
    betweenness = _betweenness(linked, distance)
    closeness = _closeness(distance)
    eccentricity = distance.max(axis=1)

    def rank(nodes: tuple[int, ...]) -> tuple:
        size = len(nodes)
        return (-int(degree[list(nodes)].sum()),
                -sum(betweenness[v] for v in nodes) / size,
                -sum(closeness[v] for v in nodes) / size,
                Fraction(int(eccentricity[list(nodes)].sum()), size),
                size,
                sum(nodes),
                nodes)

    return np.array(min(candidates, key=rank), dtype=np.int64)


def _check_kept(kept: np.ndarray, nodes: int, name: str = "kept") -> np.ndarray:
    kept = np.asarray(kept)
    if kept.ndim != 1 or kept.size == 0 or not np.issubdtype(kept.dtype, np.integer):
        raise ValueError(f"{name}: expected a non-empty [W] integer index array, got shape {kept.shape} "
                         f"and dtype {kept.dtype}")
    if kept.min() < 0 or kept.max() >= nodes or np.unique(kept).size != kept.size:
        raise ValueError(f"{name}: expected distinct node indices in [0, {nodes}), got {kept.tolist()}")
    return kept


def coarse_adjacency(adjacency: np.ndarray, kept: np.ndarray, hops: int = COARSE_HOPS) -> np.ndarray:
    """``[W, W]`` 0/1 adjacency of the coarse graph on ``kept [W]`` (indices into ``adjacency [V, V]``): two
    kept nodes are linked when at most ``hops`` hops apart in ``adjacency``."""
    linked = _check_adjacency(adjacency)
    kept = _check_kept(kept, linked.shape[0])
    if hops < 1:
        raise ValueError(f"hops: expected at least 1, got {hops}")
    near = _distances(linked)[np.ix_(kept, kept)] <= hops
    np.fill_diagonal(near, False)
    return near.astype(np.int64)


def graph_pyramid(parents: tuple[int, ...], levels: int = 2) -> GraphPyramid:
    """The skeleton graph of ``parents`` and ``levels`` successive coarsenings of it (:class:`GraphPyramid`)."""
    if levels < 0:
        raise ValueError(f"levels: expected at least 0, got {levels}")
    adjacency = [skeleton_adjacency(parents)]
    kept = []
    for _ in range(levels):
        kept.append(coarsen(adjacency[-1]))
        adjacency.append(coarse_adjacency(adjacency[-1], kept[-1]))
    return GraphPyramid(tuple(kept), tuple(adjacency))


# -------------------------------------------------------------------------------------------- hop kernels


def hop_kernels(adjacency: np.ndarray, rows: np.ndarray | None = None,
                kernels: int = CRITIC_KERNELS) -> np.ndarray:
    """Normalised ``[K, W, V]`` graph-layer weights from the ``V`` nodes of ``adjacency [V, V]`` to the nodes
    ``rows [W]`` (all nodes when ``None``): hop masks ``d(rows[w], v) == k`` for ``k < kernels``, each entry
    divided by √(its row count · its column count) within its kernel, columns counted over ``rows``."""
    linked = _check_adjacency(adjacency)
    rows = np.arange(linked.shape[0]) if rows is None else _check_kept(rows, linked.shape[0], "rows")
    if kernels < 1:
        raise ValueError(f"kernels: expected at least 1, got {kernels}")
    distance = _distances(linked)[rows]  # [W, V]
    mask = (distance[None] == np.arange(kernels)[:, None, None]).astype(np.float64)  # [K, W, V]
    counts = mask.sum(axis=2, keepdims=True) * mask.sum(axis=1, keepdims=True)
    return (mask / np.sqrt(np.maximum(counts, 1.0))).astype(np.float32)


def critic_adjacency(parents: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The critic's four graph layers for the skeleton ``parents``, in
    :class:`~jaxmotion.models.actformer_critic.CriticGraphs` order, each ``[2, W, V]``:
    conv0 ``[2, V, V]``, down1 ``[2, L1, V]``, down2 ``[2, L2, L1]``, down3 ``[2, L2, L2]``."""
    pyramid = graph_pyramid(parents, levels=2)
    fine, middle, coarse = pyramid.adjacency
    return (hop_kernels(fine),
            hop_kernels(fine, pyramid.kept[0]),
            hop_kernels(middle, pyramid.kept[1]),
            hop_kernels(coarse))
