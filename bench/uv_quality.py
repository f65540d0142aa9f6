#!/usr/bin/env python3
"""Chart count, UV area used and L2 stretch of an OBJ's texture layout,
computed here with numpy (independently of texbake's own figures), so that
the layouts of texbake and of other tools (xatlas, Blender) are measured
alike. Used by bench/uv/xatlas.sh for bench/RESULTS.md's "UV layout against xatlas".

    bench/uv_quality.py MESH.obj [...]

Prints one JSON line per file: triangles, charts (groups of triangles
connected through shared UV vertices, i.e. across edges whose two corners
have the same vt indices), uv_area (the triangles' UV area over the unit
square's bounding box of all UVs) and stretch_l2: Sander, Snyder, Gortler
and Hoppe 2001's L2 stretch, area-weighted over the mesh and normalised by
sqrt(UV area / 3D area) so that an isometry up to scale gives 1.
"""
import json
import sys

import numpy as np


def read_obj(path):
    v, vt, tris = [], [], []
    with open(path) as f:
        for line in f:
            p = line.split()
            if not p:
                continue
            if p[0] == "v":
                v.append([float(x) for x in p[1:4]])
            elif p[0] == "vt":
                vt.append([float(x) for x in p[1:3]])
            elif p[0] == "f":
                corners = [c.split("/") for c in p[1:]]
                for k in range(1, len(corners) - 1):
                    tri = [corners[0], corners[k], corners[k + 1]]
                    tris.append([[int(c[0]), int(c[1])] for c in tri])
    v, vt, t = np.array(v), np.array(vt), np.array(tris)
    # OBJ indices are 1-based; negative ones count from the end.
    pos = np.where(t[..., 0] > 0, t[..., 0] - 1, len(v) + t[..., 0])
    uv = np.where(t[..., 1] > 0, t[..., 1] - 1, len(vt) + t[..., 1])
    return v, vt, pos, uv


def charts(uv_index, n_uv):
    parent = np.arange(n_uv)

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for tri in uv_index:
        r0 = find(tri[0])
        for c in tri[1:]:
            r = find(c)
            if r != r0:
                parent[r] = r0
    return len({find(i) for i in np.unique(uv_index)})


def quality(path):
    v, vt, pos, uv = read_obj(path)
    q = v[pos]  # (n, 3, 3)
    s = vt[uv]  # (n, 3, 2)
    a3 = 0.5 * np.linalg.norm(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), axis=1)
    ds1, ds2 = s[:, 1] - s[:, 0], s[:, 2] - s[:, 0]
    a2 = 0.5 * (ds1[:, 0] * ds2[:, 1] - ds1[:, 1] * ds2[:, 0])
    ok = (np.abs(a2) > 0) & (a3 > 0)
    # Sander et al.: S_s, S_t, the partial derivatives of the 3D position in u and v.
    q1, q2, q3 = q[ok, 0], q[ok, 1], q[ok, 2]
    s1, s2, s3 = s[ok, 0, 0], s[ok, 1, 0], s[ok, 2, 0]
    t1, t2, t3 = s[ok, 0, 1], s[ok, 1, 1], s[ok, 2, 1]
    area = a2[ok][:, None]
    ss = (q1 * (t2 - t3)[:, None] + q2 * (t3 - t1)[:, None] + q3 * (t1 - t2)[:, None]) / (2 * area)
    st = (q1 * (s3 - s2)[:, None] + q2 * (s1 - s3)[:, None] + q3 * (s2 - s1)[:, None]) / (2 * area)
    a, c = (ss * ss).sum(1), (st * st).sum(1)
    l2 = np.sqrt((a + c) / 2)
    w = a3[ok]
    total3, total2 = w.sum(), np.abs(a2[ok]).sum()
    stretch = np.sqrt((l2 * l2 * w).sum() / total3) * np.sqrt(total2 / total3)
    lo, hi = vt.min(0), vt.max(0)
    box = float(np.prod(np.maximum(hi - lo, 1e-300)))
    return {"file": str(path), "triangles": int(len(pos)), "charts": charts(uv, len(vt)),
            "uv_area": float(np.abs(a2).sum() / box), "stretch_l2": float(stretch),
            "degenerate_in_uv": int((~ok).sum())}


if __name__ == "__main__":
    for p in sys.argv[1:]:
        print(json.dumps(quality(p)))
