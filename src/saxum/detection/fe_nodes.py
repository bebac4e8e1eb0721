"""Narrow phase of deformable blocks (design-deformable-and-joints.md section 3): points
against edges, where a point is a boundary node of a deformable block or a vertex of a rigid
polygon, and an edge is a rigid polygon's edge or a boundary facet (two nodes) of a
deformable block.

    deformable - rigid:       the block's boundary nodes against the polygon's edges, and the
                              polygon's vertices against the block's facets;
    deformable - deformable:  the boundary nodes of the block of lower index against the
                              other's facets (one pass: conforming meshes of blocks built
                              touching need no more).

For a point x outside a convex polygon, the largest signed distance to its edges' lines,
g = max_e n_e . (x - a_e), is the distance to the nearest edge when x projects onto that
edge (a deformable block is taken as convex, as its undeformed shape is; among its collinear
facets, the one x projects onto); a point within
`alert` of it becomes a contact on that edge: frame (t, n) with n the edge's outward normal
and t = (n_y, -n_x) as in saxum.detection.polygons, point = x. A point beyond the edge's ends
is left to the corner there. Sides: a node is side_node with weight 1; a facet is its two
nodes with the linear shape functions (1 - xi, xi) at the projection of x.

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

__all__ = ["candidate_node", "facet_side", "key_layout", "node_contacts", "pair_sides",
           "rigid_side"]


@nb.njit(inline="always")
def _nearest_edge(x, y, mx, my, v0, v1, wv, wn, tie):
    """(largest signed distance g [m], its edge k) of point (x, y) over edges v0..v1 of a
    rigid polygon (world vertices wv, outward normals wn); between edges at equal distances
    (within tie: a node on the polygon's corner), the one whose normal is most opposed to
    the node's outward direction (mx, my), as in _nearest_facet, so that the choice, and the
    contact's key, do not follow round-off from step to step."""
    best = -1
    g = -1e300
    facing = 0.0
    for k in range(v0, v1):
        d = wn[k, 0] * (x - wv[k, 0]) + wn[k, 1] * (y - wv[k, 1])
        dot = wn[k, 0] * mx + wn[k, 1] * my
        if d > g + tie or (d >= g - tie and dot < facing - 1e-3):
            g = d
            best = k
            facing = dot
    return g, best


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
def _nearest_facet(x, y, mx, my, f0, f1, node_x, facet_node, tie):
    """(outside [m], g [m], facet, xi) of point (x, y) against the boundary facets f0..f1 of a
    deformable block, as _nearest_edge: outside the largest signed distance over all facets,
    how far outside the block the point is; g and the facet the largest over those onto which
    the point projects (xi in [0, 1] along it), since a block's boundary has runs of collinear
    facets whose equal distances leave the choice to the projection. Between facets at equal
    distances (within tie: a point at a corner), the one whose normal is most opposed to the
    point's own outward direction (mx, my) (0, 0 for none), and between facets equally
    opposed (within 1e-3: the facets of a straight side, turned against each other by the
    strain, ~1e-4, where two sides at a corner differ by ~1), the first: a node built on the
    common end of two collinear facets then keeps its facet, and its contact its key, from
    step to step (the warm start goes by key). Facet -1: none."""
    best = -1
    g = -1e300
    g_onto = -1e300
    facing = 0.0
    xi = 0.0
    for f in range(f0, f1):
        ax, ay, nx, ny, length = _facet(node_x, facet_node, f)
        d = nx * (x - ax) + ny * (y - ay)
        g = max(g, d)
        s = -ny * (x - ax) + nx * (y - ay)
        if not -tie <= s <= length + tie:
            continue
        dot = nx * mx + ny * my
        if d > g_onto + tie or (d >= g_onto - tie and dot < facing - 1e-3):
            g_onto = d
            best = f
            facing = dot
            xi = min(max(s / length, 0.0), 1.0)
    return g, g_onto, best, xi


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
                  node_side, facet_start, facet_node, wv, wn, edge_length, body_vertex_start,
                  body_group, group_law, alert, law_alert, body_alert, key_base, count, candidate,
                  antagonist, key, law, point, frame, gap, area, side_kind, side_node,
                  side_weight):
    """Append the contacts of the pairs (body i, body j) with a deformable block (module doc)
    from row `count` on; returns the new count. Keys are above key_base (every polygon
    contact's key is below it), distinct per (point, edge): a node p against edge or facet e,
    key_base + p * E + e' with e' = e for a rigid edge and V + e for a facet (V vertices, E =
    V + facets); a rigid vertex k against facet e, key_base + N E + k F + e (N nodes, F
    facets). The arrays must have room for every boundary node and vertex of every pair.
    alert [m]: the detector's; law_alert, body_alert [m]: per law and body (Detector), which
    a pair uses (alert_of_pair)."""
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
                g, e = _nearest_edge(x, y, cf * mx - sf * my, sf * mx + cf * my,
                                     body_vertex_start[ob], body_vertex_start[ob + 1], wv, wn,
                                     tie)
                if g > pair_alert:
                    continue
                nx = wn[e, 0]
                ny = wn[e, 1]
                s = -ny * (x - wv[e, 0]) + nx * (y - wv[e, 1])  # along the edge, from a_e
                if s < -tie or s > edge_length[e] + tie:
                    continue
                edge_key = e
            else:
                outside, g, e, xi = _nearest_facet(x, y, cf * mx - sf * my, sf * mx + cf * my,
                                                   facet_start[o], facet_start[o + 1], node_x,
                                                   facet_node, tie)
                if e < 0 or outside > pair_alert:
                    continue
                nx, ny = _facet(node_x, facet_node, e)[2:4]
                weight[0] = 1.0 - xi
                weight[1] = xi
                facet_side(count, facet_node, e, weight, side_kind, side_node, side_weight)
                edge_key = vertices + e
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
            outside, g, e, xi = _nearest_facet(x, y, 0.0, 0.0, facet_start[f],
                                               facet_start[f + 1], node_x, facet_node, tie)
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
