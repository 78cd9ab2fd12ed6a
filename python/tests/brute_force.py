"""Truth the Python tests hold sdftrace to, computed here with numpy over
every triangle."""

import numpy as np


def brute_winding(vertices, faces, points):
    """The winding number: the triangles' solid angles (Van Oosterom and
    Strackee) summed, over 4 pi."""
    out = np.empty(len(points))
    for i, p in enumerate(points):
        a, b, c = (vertices[faces[:, k]] - p for k in range(3))
        la, lb, lc = (np.linalg.norm(x, axis=1) for x in (a, b, c))
        det = np.einsum("ij,ij->i", a, np.cross(b, c))
        den = la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", b, c) * la
        den += np.einsum("ij,ij->i", c, a) * lb
        out[i] = np.sum(2 * np.arctan2(det, den)) / (4 * np.pi)
    return out
