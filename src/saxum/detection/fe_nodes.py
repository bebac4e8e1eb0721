"""Narrow phase of deformable blocks (design-deformable-and-joints.md section 3): points
against edges, where a point is a boundary node of a deformable block or a vertex of a rigid
polygon, and an edge is a rigid polygon's edge or a boundary facet (two nodes) of a
deformable block.

    deformable - rigid:       the block's boundary nodes against the polygon's edges, and the
                              polygon's vertices against the block's facets;
    deformable - deformable:  the boundary nodes of the block of lower index against the
                              other's facets (one pass: conforming meshes of blocks built
                              touching need no more).

For a point x and a convex block (a deformable block is taken as convex, as its undeformed
shape is), d_e = n_e . (x - a_e) is the signed distance to edge e's line, and outside = max_e
d_e how far outside the block x is (the distance to the nearest edge where x projects onto it).
A point with outside within `alert` becomes a contact on one edge, chosen among the edges
within alert of outside (d_e >= outside - alert) onto which x projects (within tie = 1e-3
alert): the edge whose normal is most opposed to the point's outward direction m (a node's: the
sum of its half edges' outward normals; a rigid vertex's: from its polygon's centre of mass),
then the nearest, then the first (prefer). Not the nearest alone: a node at the end of a joint,
on the other block's corner, lies on that block's side line as well, so once the joint closes
by more than tie (a compliant joint's sigma / k_n), the side (d = 0) is nearer than the bed (d
= -closure), and a contact keyed to the side would start anew, cracked under a cohesive law; by
m the node stays on the bed until the closure reaches the alert distance. The contact: frame
(t, n) with n the edge's outward normal and t = (n_y, -n_x) as in saxum.detection.polygons,
point = x, gap d_e. A point that projects onto no such edge is left to the corner there. Sides:
a node is side_node with weight 1; a facet is its two nodes with the linear shape functions (1
- xi, xi) at the projection of x. A node's contact on a deformable block is keyed by the
straight side its facet lies on (flat_sides), not by the facet, so that it keeps its key, and
its joint law's state, when it strains or slips onto the next facet of that side.

Area: a node stands for the part of its tributary boundary (half of each adjacent boundary
edge) that faces the edge, sum max(0, -n . s) over its two half edges s (outward normal times
half the length, turned by the block's frame); a rigid vertex for nothing (0), as a vertex
against a face in saxum.detection.polygons stands for a small area only.
"""

import math

import numba as nb
import numpy as np

from .polygons import _write as _polygon_row
from .polygons import alert_of_pair

__all__ = ["candidate_node", "facet_side", "flat_sides", "key_layout", "node_contacts",
           "pair_sides", "prefer", "rigid_side", "unit"]


def flat_sides(node_x0: np.ndarray, facet_node: np.ndarray,
               facet_start: np.ndarray) -> np.ndarray:
    """Per boundary facet (2D a segment, 3D a triangle), the first facet of its block on the
    same line (plane) in the reference configuration node_x0 [m] (unit normals within 1e-6,
    offsets within 1e-9 of the block's size): the straight (flat) side of the block it lies
    on, by which a node's contact on it is keyed (node_contacts, node_contacts_3d), int64
    [facets]."""
    x = [node_x0[facet_node[:, k]] for k in range(facet_node.shape[1])]
    if len(x) == 2:
        normal = (x[1] - x[0])[:, ::-1] * np.array([1.0, -1.0])
    else:
        normal = np.cross(x[1] - x[0], x[2] - x[0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    offset = np.einsum("fd,fd->f", normal, x[0])
    side = np.arange(len(facet_node), dtype=np.int64)
    for f0, f1 in zip(facet_start[:-1], facet_start[1:], strict=True):
        n, d = normal[f0:f1], offset[f0:f1]
        size = float(np.ptp(node_x0[facet_node[f0:f1]].reshape(-1, node_x0.shape[1]),
                            axis=0).max())
        same = ((np.abs(n[:, None] - n[None]).max(axis=2) < 1e-6)
                & (np.abs(d[:, None] - d[None]) < 1e-9 * size))
        side[f0:f1] = f0 + same.argmax(axis=1)  # the first True: the row's own at the latest
    return side


@nb.njit(inline="always")
def prefer(dot, d, facing, g, tie):
    """Whether a face at signed distance d [m] whose normal n has dot = n . m with the point's
    outward unit direction m (unit) beats the best so far (facing, g): the face most opposed
    to m (by more than 1e-3: two sides at a corner differ by ~1, the facets of one straight
    side, turned against each other by the strain, by ~1e-4), then the nearest (by more than
    tie), then the first (module doc)."""
    return dot < facing - 1e-3 or (dot <= facing + 1e-3 and d > g + tie)


@nb.njit(inline="always")
def unit(mx, my, mz):
    """The direction (mx, my, mz) made unit (prefer's margin is on cosines); (0, 0, 0), no
    direction, as it is."""
    norm = math.sqrt(mx * mx + my * my + mz * mz)
    if norm == 0.0:
        return mx, my, mz
    return mx / norm, my / norm, mz / norm


@nb.njit(inline="always")
def _nearest_edge(x, y, mx, my, v0, v1, wv, wn, edge_length, tie, window):
    """(outside [m], g [m], edge k) of point (x, y) against the edges v0..v1 of a rigid
    polygon (world vertices wv, outward normals wn, lengths edge_length [m]), as
    _nearest_facet: outside the largest signed distance, g and k those of the edge chosen
    (prefer) among the edges within `window` of it onto which the point projects (within
    tie). Edge -1: none."""
    mx, my = unit(mx, my, 0.0)[:2]
    outside = -1e300
    for k in range(v0, v1):
        outside = max(outside, wn[k, 0] * (x - wv[k, 0]) + wn[k, 1] * (y - wv[k, 1]))
    best = -1
    g = -1e300
    facing = 1e300
    for k in range(v0, v1):
        d = wn[k, 0] * (x - wv[k, 0]) + wn[k, 1] * (y - wv[k, 1])
        s = -wn[k, 1] * (x - wv[k, 0]) + wn[k, 0] * (y - wv[k, 1])  # along the edge, from a_k
        if d < outside - window or not -tie <= s <= edge_length[k] + tie:
            continue
        dot = wn[k, 0] * mx + wn[k, 1] * my
        if prefer(dot, d, facing, g, tie):
            g = d
            best = k
            facing = dot
    return outside, g, best


@nb.njit(inline="always")
def _facet(node_x, facet_node, f):
    """(a_x, a_y, outward unit normal n, length) of boundary facet f on positions node_x."""
    a = facet_node[f, 0]
    b = facet_node[f, 1]
    dx = node_x[b, 0] - node_x[a, 0]
    dy = node_x[b, 1] - node_x[a, 1]
    length = math.sqrt(dx * dx + dy * dy)
    return node_x[a, 0], node_x[a, 1], dy / length, -dx / length, length


@nb.njit(inline="always")
def _nearest_facet(x, y, mx, my, f0, f1, node_x, facet_node, tie, window):
    """(outside [m], g [m], facet, xi) of point (x, y) against the boundary facets f0..f1 of a
    deformable block: outside the largest signed distance over all facets, how far outside
    the block the point is; g and the facet those of the facet chosen (prefer: by the point's
    own outward direction (mx, my), (0, 0) for none, then by distance) among the facets
    within `window` [m] of outside onto which the point projects (xi in [0, 1] along it,
    within tie). Facet -1: none."""
    mx, my = unit(mx, my, 0.0)[:2]
    outside = -1e300
    for f in range(f0, f1):
        ax, ay, nx, ny = _facet(node_x, facet_node, f)[:4]
        outside = max(outside, nx * (x - ax) + ny * (y - ay))
    best = -1
    g = -1e300
    facing = 1e300
    xi = 0.0
    for f in range(f0, f1):
        ax, ay, nx, ny, length = _facet(node_x, facet_node, f)
        d = nx * (x - ax) + ny * (y - ay)
        s = -ny * (x - ax) + nx * (y - ay)
        if d < outside - window or not -tie <= s <= length + tie:
            continue
        dot = nx * mx + ny * my
        if prefer(dot, d, facing, g, tie):
            g = d
            best = f
            facing = dot
            xi = min(max(s / length, 0.0), 1.0)
    return outside, g, best, xi


@nb.njit(inline="always")
def _write(count, cand, ant, key_value, law_index, x, y, nx, ny, g, area_value, candidate,
           antagonist, key, law, point, frame, gap, area):
    """Row count of the contact arrays (detection.polygons' row, frame t = (n_y, -n_x), n) and
    its area [m^2/m]."""
    _polygon_row(candidate, antagonist, key, law, point, frame, gap, count, cand, ant, key_value,
                 law_index, x, y, nx, ny, g)
    area[count] = area_value


@nb.njit(inline="always")
def _node_area(node_side, p, c, s, nx, ny):
    """The part of node p's tributary boundary facing the normal (nx, ny) [m] (module doc)."""
    a = 0.0
    for k in range(2):
        sx = c * node_side[p, k, 0] - s * node_side[p, k, 1]
        sy = s * node_side[p, k, 0] + c * node_side[p, k, 1]
        a += max(0.0, -(nx * sx + ny * sy))
    return a


@nb.njit(inline="always")
def candidate_node(count, p, side_kind, side_node, side_weight):
    """Row count's candidate side is node p alone (weight 1 in the first of its slots)."""
    side_kind[count, 0] = 1
    for k in range(side_node.shape[2]):
        side_node[count, 0, k] = p
        side_weight[count, 0, k] = 1.0 if k == 0 else 0.0


@nb.njit(inline="always")
def rigid_side(count, side, side_kind, side_node, side_weight):
    """Row count's side `side` (0 candidate, 1 antagonist) is a rigid body's: no nodes."""
    side_kind[count, side] = 0
    for k in range(side_node.shape[2]):
        side_node[count, side, k] = 0
        side_weight[count, side, k] = 0.0


@nb.njit(inline="always")
def facet_side(count, facet_node, e, weight, side_kind, side_node, side_weight):
    """Row count's antagonist side is facet e's nodes (2D two, 3D three) with the weights
    [-], the shape functions at the point's projection on it."""
    side_kind[count, 1] = 1
    for k in range(facet_node.shape[1]):
        side_node[count, 1, k] = facet_node[e, k]
        side_weight[count, 1, k] = weight[k]


@nb.njit(inline="always")
def key_layout(alert, rigid_features, node_count, facets, key_base):
    """(tie [m], features E, first key of the rigid corners) of node_contacts' keys (its doc)
    over rigid_features edges (3D: faces) and `facets` boundary facets; tie = 1e-3 alert,
    since nodes built coincident drift apart by round-off and strain."""
    features = rigid_features + facets
    return 1e-3 * alert, features, key_base + node_count * features


@nb.njit(inline="always")
def pair_sides(pairs, pr, fe_index, body_group, group_law, law_alert, body_alert, alert):
    """(fb, ob, f, o, law, alert [m]) of pair pr: the block whose boundary nodes are the
    candidates (of two deformable blocks, the one of lower index), the other body, their
    deformable block indices (o = -1: ob is rigid), the pair's law index (-1 when the pair
    has no deformable block or no law: no contacts) and its alert (alert_of_pair)."""
    i = pairs[pr, 0]
    j = pairs[pr, 1]
    fb, ob = (i, j) if fe_index[i] >= 0 else (j, i)
    f = fe_index[fb]
    o = fe_index[ob]
    law = group_law[body_group[fb], body_group[ob]] if f >= 0 else -1
    if law < 0:
        return fb, ob, f, o, -1, alert
    return fb, ob, f, o, law, alert_of_pair(law_alert, body_alert, law, fb, ob, alert)


@nb.njit(cache=True)
def node_contacts(pairs, pair_count, fe_index, q, node_x, boundary_start, boundary_node,
                  node_side, facet_start, facet_node, flat_side, wv, wn, edge_length,
                  body_vertex_start, body_group, group_law, alert, law_alert, body_alert,
                  key_base, count, candidate, antagonist, key, law, point, frame, gap, area,
                  side_kind, side_node, side_weight):
    """Append the contacts of the pairs (body i, body j) with a deformable block (module doc)
    from row `count` on; returns the new count. Keys are above key_base (every polygon
    contact's key is below it), distinct per (point, side): a node p against edge or facet e,
    key_base + p * E + e' with e' = e for a rigid edge and V + flat_side[e] for a facet (V
    vertices, E = V + facets; flat_sides: a node that strains or slips onto the next facet of
    the same straight side keeps its contact, with its warm start and a joint law's state); a
    rigid vertex k against facet e, key_base + N E + k F + e (N nodes, F facets). The arrays
    must have room for every boundary node and vertex of every pair. alert [m]: the
    detector's, and the window of the choice of a point's edge (module doc); law_alert,
    body_alert [m]: per law and body (Detector), which a pair uses (alert_of_pair)."""
    vertices = wv.shape[0]
    facets = facet_node.shape[0]
    tie, edges, vertex_base = key_layout(alert, vertices, node_x.shape[0], facets, key_base)
    weight = np.empty(2)
    for pr in range(pair_count):
        fb, ob, f, o, law_index, pair_alert = pair_sides(pairs, pr, fe_index, body_group,
                                                         group_law, law_alert, body_alert, alert)
        if law_index < 0:
            continue
        cf = math.cos(q[fb, 2])
        sf = math.sin(q[fb, 2])
        rigid = o < 0
        for m in range(boundary_start[f], boundary_start[f + 1]):
            p = boundary_node[m]
            x = node_x[p, 0]
            y = node_x[p, 1]
            mx = node_side[p, 0, 0] + node_side[p, 1, 0]
            my = node_side[p, 0, 1] + node_side[p, 1, 1]
            if rigid:
                outside, g, e = _nearest_edge(x, y, cf * mx - sf * my, sf * mx + cf * my,
                                              body_vertex_start[ob], body_vertex_start[ob + 1],
                                              wv, wn, edge_length, tie, pair_alert)
                if e < 0 or outside > pair_alert:
                    continue
                nx = wn[e, 0]
                ny = wn[e, 1]
                edge_key = e
            else:
                outside, g, e, xi = _nearest_facet(x, y, cf * mx - sf * my, sf * mx + cf * my,
                                                   facet_start[o], facet_start[o + 1], node_x,
                                                   facet_node, tie, pair_alert)
                if e < 0 or outside > pair_alert:
                    continue
                nx, ny = _facet(node_x, facet_node, e)[2:4]
                weight[0] = 1.0 - xi
                weight[1] = xi
                facet_side(count, facet_node, e, weight, side_kind, side_node, side_weight)
                edge_key = vertices + flat_side[e]
            if rigid:
                rigid_side(count, 1, side_kind, side_node, side_weight)
            candidate_node(count, p, side_kind, side_node, side_weight)
            _write(count, fb, ob, key_base + p * edges + edge_key, law_index, x, y, nx, ny, g,
                   _node_area(node_side, p, cf, sf, nx, ny), candidate, antagonist, key, law,
                   point, frame, gap, area)
            count += 1
        if not rigid:
            continue
        # the rigid polygon's corners against the deformable block's facets
        for k in range(body_vertex_start[ob], body_vertex_start[ob + 1]):
            x = wv[k, 0]
            y = wv[k, 1]
            # the corner's outward direction: from the polygon's centre of mass
            outside, g, e, xi = _nearest_facet(x, y, x - q[ob, 0], y - q[ob, 1], facet_start[f],
                                               facet_start[f + 1], node_x, facet_node, tie,
                                               pair_alert)
            if e < 0 or outside > pair_alert:
                continue
            nx, ny, length = _facet(node_x, facet_node, e)[2:5]
            if min(xi, 1.0 - xi) * length <= tie:
                continue  # on a node: the node's own contact on the polygon's edge holds it
            rigid_side(count, 0, side_kind, side_node, side_weight)
            weight[0] = 1.0 - xi
            weight[1] = xi
            facet_side(count, facet_node, e, weight, side_kind, side_node, side_weight)
            _write(count, ob, fb, vertex_base + k * facets + e, law_index, x, y, nx, ny, g,
                   0.0, candidate, antagonist, key, law, point, frame, gap, area)
            count += 1
    return count
