"""Narrow phase of deformable blocks (design-deformable-and-joints.md section 3): the boundary
nodes of a deformable block (candidates) against the edges of a rigid convex polygon
(antagonist).

For a node x outside a convex polygon, the largest signed distance to its edges' lines,
g = max_e n_e . (x - a_e), is the distance to the nearest edge when the node projects onto
that edge; a node within `alert` of it becomes a contact on that edge: frame (t, n) with n the
edge's outward normal and t = (n_y, -n_x) as in saxum.detection.polygons, point = the node,
area = the part of the node's tributary boundary (half of each adjacent boundary edge) that
faces the edge: sum max(0, -n . s) over its two half edges s (outward normal times half the
length, turned by the block's frame). A node beyond an edge's ends is left to the
polygon's corner, which would be a rigid candidate against an FE edge (not yet detected).
"""

import math

import numba as nb

__all__ = ["node_contacts"]


@nb.njit(cache=True)
def node_contacts(pairs, pair_count, fe_index, q, node_x, boundary_start, boundary_node,
                  node_side, wv, wn, edge_length, body_vertex_start, body_group, group_law, alert,
                  key_base, vertex_count, count, candidate, antagonist, key, law, point, frame,
                  gap, area, side_kind, side_node, side_weight):
    """Append the node contacts of the pairs (body i, body j) in which exactly one body is
    deformable, from row `count` on; returns the new count. Keys: key_base + node *
    vertex_count + edge's first vertex (above every polygon contact's key), increasing within
    a pair. The arrays must have room for every boundary node of every pair."""
    tie = 1e-9 * alert
    for pr in range(pair_count):
        i = pairs[pr, 0]
        j = pairs[pr, 1]
        if (fe_index[i] >= 0) == (fe_index[j] >= 0):
            continue
        fb, rb = (i, j) if fe_index[i] >= 0 else (j, i)
        law_index = group_law[body_group[fb], body_group[rb]]
        if law_index < 0:
            continue
        f = fe_index[fb]
        cf = math.cos(q[fb, 2])
        sf = math.sin(q[fb, 2])
        v0 = body_vertex_start[rb]
        v1 = body_vertex_start[rb + 1]
        for m in range(boundary_start[f], boundary_start[f + 1]):
            p = boundary_node[m]
            x = node_x[p, 0]
            y = node_x[p, 1]
            best = -1
            g = -1e300
            for k in range(v0, v1):
                d = wn[k, 0] * (x - wv[k, 0]) + wn[k, 1] * (y - wv[k, 1])
                if d > g:
                    g = d
                    best = k
            if g > alert:
                continue
            nx = wn[best, 0]
            ny = wn[best, 1]
            s = -ny * (x - wv[best, 0]) + nx * (y - wv[best, 1])  # along the edge, from a_e
            if s < -tie or s > edge_length[best] + tie:
                continue
            candidate[count] = fb
            antagonist[count] = rb
            key[count] = key_base + p * vertex_count + best
            law[count] = law_index
            point[count, 0] = x
            point[count, 1] = y
            frame[count, 0, 0] = ny
            frame[count, 0, 1] = -nx
            frame[count, 1, 0] = nx
            frame[count, 1, 1] = ny
            gap[count] = g
            a = 0.0
            for k in range(2):
                sx = cf * node_side[p, k, 0] - sf * node_side[p, k, 1]
                sy = sf * node_side[p, k, 0] + cf * node_side[p, k, 1]
                a += max(0.0, -(nx * sx + ny * sy))
            area[count] = a
            side_kind[count, 0] = 1
            side_kind[count, 1] = 0
            side_node[count, 0, 0] = p
            side_weight[count, 0, 0] = 1.0
            count += 1
    return count
