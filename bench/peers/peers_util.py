#!/usr/bin/python3
"""Helpers of bench/peers/run.sh (Debian /usr/bin/python3 with numpy).

  peers_util.py mesh IN.off OUT.ply [ROUNDS]
                                         midpoint-subdivide 1-to-4 ROUNDS
                                         times (default 2, as
                                         bench/bench_meshes.cpp does), write a
                                         binary PLY without colours
  peers_util.py center MESH.ply          print the bounding-box centre X,Y,Z
  peers_util.py check-vertex OUT.ply EARTH.ppm X,Y,Z
                                         exit 1 unless most vertices carry the
                                         Earth map's colour at their sphere
                                         (u, v) (pole +z, u = 0 towards +x)
  peers_util.py check-image IMAGE.ppm    exit 1 unless the image is mostly
                                         covered with varied colours
  peers_util.py summary TIMES.tsv        print the medians and ratios of the
                                         runs (lines: job, tool, repetition,
                                         seconds, ok|FAILED) as a Markdown table

Each check prints one line: what fraction matched. It exists so that a peer
that fails silently (no colours, grey, a mirrored map) cannot pass as a fast
time. Images are read as binary PPM (run.sh converts them with oiiotool): no
imaging module is installed for /usr/bin/python3.
"""
import sys

import numpy as np

PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "<i2", "int16": "<i2", "ushort": "<u2", "uint16": "<u2",
    "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
    "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8",
}


def read_off(path):
    """Vertices (n, 3) float64 and triangles (m, 3) int64 of an OFF file."""
    with open(path) as f:
        tokens = f.read().split()
    assert tokens[0] == "OFF", path
    nv, nf = int(tokens[1]), int(tokens[2])
    pos = 4
    v = np.array(tokens[pos:pos + 3 * nv], dtype=np.float64).reshape(nv, 3)
    pos += 3 * nv
    f = np.array(tokens[pos:pos + 4 * nf], dtype=np.int64).reshape(nf, 4)
    assert (f[:, 0] == 3).all(), "triangles only"
    return v, f[:, 1:]


def subdivide(v, t):
    """1-to-4 midpoint subdivision: one new vertex per edge, four triangles per
    triangle (t0 ab ca, ab t1 bc, ca bc t2, ab bc ca)."""
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    e.sort(axis=1)
    uniq, inv = np.unique(e, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    mid = len(v) + inv.reshape(3, -1)
    ab, bc, ca = mid[0], mid[1], mid[2]
    nv = np.concatenate([v, (v[uniq[:, 0]] + v[uniq[:, 1]]) / 2])
    nt = np.stack([
        np.stack([t[:, 0], ab, ca], 1), np.stack([ab, t[:, 1], bc], 1),
        np.stack([ca, bc, t[:, 2]], 1), np.stack([ab, bc, ca], 1)
    ], 1).reshape(-1, 3)
    return nv, nt


def write_ply(path, v, t, rgb=None):
    """Binary little-endian PLY: float x y z (+ uchar red green blue when
    `rgb`, (n, 3) uint8, is given), uchar-count int vertex_indices."""
    fields = [("p", "<f4", 3)] + ([("c", "u1", 3)] if rgb is not None else [])
    vert = np.empty(len(v), dtype=fields)
    vert["p"] = v
    colour = ""
    if rgb is not None:
        vert["c"] = rgb
        colour = "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    faces = np.empty(len(t), dtype=[("n", "u1"), ("i", "<i4", 3)])
    faces["n"] = 3
    faces["i"] = t
    with open(path, "wb") as f:
        f.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {len(v)}\n"
                 f"property float x\nproperty float y\nproperty float z\n{colour}"
                 f"element face {len(t)}\nproperty list uchar int vertex_indices\n"
                 "end_header\n").encode())
        f.write(vert.tobytes())
        f.write(faces.tobytes())


def read_ply(path):
    """(vertices, faces) of a binary little-endian PLY: the vertex element as a
    structured array, then the face element as an (m, 3) int32 array if every
    face is a 'list uchar int' triangle, else None. The vertex element must
    come first, as every writer here puts it."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        sys.exit(f"{path}: FAILED, {e.strerror}")
    end = data.index(b"end_header\n") + len(b"end_header\n")
    lines = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in lines:
        sys.exit(f"{path}: not a binary little-endian PLY")
    count, faces, fields, face_fields, element = 0, 0, [], [], None
    for line in lines:
        words = line.split()
        if words[:1] == ["element"]:
            element = words[1]
            if element == "vertex":
                count = int(words[2])
            elif element == "face":
                faces = int(words[2])
        elif words[:1] == ["property"] and element == "vertex":
            if words[1] == "list":
                sys.exit(f"{path}: list property in the vertex element")
            fields.append((words[2], PLY_TYPES[words[1]]))
        elif words[:1] == ["property"] and element == "face":
            face_fields.append(words[1:])
    vert = np.frombuffer(data, dtype=np.dtype(fields), count=count, offset=end)
    tri = None
    if face_fields == [["list", "uchar", "int", "vertex_indices"]]:
        f = np.frombuffer(data, dtype=[("n", "u1"), ("i", "<i4", 3)], count=faces,
                          offset=end + vert.nbytes)
        if (f["n"] == 3).all():
            tri = f["i"]
    return vert, tri


def read_ply_vertices(path):
    """The vertex element of a binary little-endian PLY (read_ply)."""
    return read_ply(path)[0]


def read_ppm(path):
    """(h, w, 3) uint8 of a binary PPM (P6, maxval 255)."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        sys.exit(f"{path}: FAILED, {e.strerror}")
    header = []
    pos = 0
    while len(header) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos)
            continue
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        header.append(data[start:pos])
    pos += 1
    assert header[0] == b"P6" and header[3] == b"255", path
    w, h = int(header[1]), int(header[2])
    return np.frombuffer(data, dtype=np.uint8, count=w * h * 3, offset=pos).reshape(h, w, 3)


def sphere_uv(p, c):
    """SPEC section 2's sphere, pole +z, equator +x: u = atan2(y, x) / 2 pi in
    [0, 1), v = acos(-z / |d|) / pi."""
    d = p - c
    u = np.mod(np.arctan2(d[:, 1], d[:, 0]) / (2 * np.pi), 1.0)
    v = np.arccos(np.clip(-d[:, 2] / np.linalg.norm(d, axis=1), -1, 1)) / np.pi
    return u, v


def check_vertex(path, earth_path, center):
    vert = read_ply_vertices(path)
    names = vert.dtype.names
    for key in ("red", "green", "blue"):
        if key not in names:
            sys.exit(f"{path}: no vertex {key}")
    p = np.stack([vert["x"], vert["y"], vert["z"]], 1).astype(np.float64)
    rgb = np.stack([vert["red"], vert["green"], vert["blue"]], 1).astype(np.float64)
    if vert.dtype["red"].kind == "f":
        rgb *= 255
    earth = read_ppm(earth_path).astype(np.float64)
    h, w, _ = earth.shape
    u, v = sphere_uv(p, np.array(center))
    # Nearest texel (SPEC section 1: x = u W - 0.5, y = (1 - v) H - 0.5).
    x = np.clip(np.floor(u * w).astype(int), 0, w - 1)
    y = np.clip(np.floor((1 - v) * h).astype(int), 0, h - 1)
    want = earth[y, x]
    # Bilinear, linear-light and nearest sampling differ by a few levels
    # except across the coastlines; 40 levels lets those through and still
    # rejects a constant, a shifted or a mirrored map.
    match = np.abs(rgb - want).max(axis=1) <= 40
    # The dark ocean is about three quarters of the vertices: a constant dark
    # blue would match 70 % of them, a mirrored or quarter-turned map 50 %,
    # but none of the land (texels far from the median colour; 90 % of them
    # match in a correct bake, 20 % mirrored, 0 % constant).
    land = np.abs(want - np.median(want, axis=0)).max(axis=1) > 60
    frac, frac_land = match.mean(), match[land].mean() if land.any() else 0.0
    ok = frac >= 0.8 and frac_land >= 0.7
    print(f"{path}: {len(p)} vertices, {frac:.3f} within 40/255 of the map's "
          f"nearest texel, {frac_land:.3f} of the {land.mean():.3f} on land: "
          f"{'ok' if ok else 'FAILED'}")
    return 0 if ok else 1


def check_image(path):
    img = read_ppm(path).astype(np.int32)
    # Covered: not the black or white background a bake starts from.
    lum = img.sum(axis=2)
    covered = (lum > 0) & (lum < 765)
    frac = covered.mean()
    distinct = len(np.unique(img[covered].reshape(-1, 3) // 16, axis=0)) if covered.any() else 0
    ok = frac >= 0.3 and distinct >= 50
    print(f"{path}: {img.shape[1]}x{img.shape[0]}, {frac:.3f} covered, {distinct} "
          f"distinct colours (16-level bins): {'ok' if ok else 'FAILED'}")
    return 0 if ok else 1


def summary(path):
    """Median per (job, tool) and each peer's median over each texbake
    variant's of the same job (tools named texbake* are the baselines)."""
    runs = {}
    failed = 0
    with open(path) as f:
        for line in f:
            job, tool, _, seconds, status = line.rstrip("\n").split("\t")
            runs.setdefault((job, tool), []).append((float(seconds), status))
    print("| job | tool | median s | runs (s) | peer / texbake |")
    print("|---|---|---|---|---|")
    medians = {k: float(np.median([t for t, _ in v])) for k, v in runs.items()}
    for (job, tool), v in runs.items():
        bad = sum(s != "ok" for _, s in v)
        failed += bad
        times = " ".join(f"{t:.2f}" + ("" if s == "ok" else "!") for t, s in v)
        ratio = ""
        if not tool.startswith("texbake"):
            ratio = ", ".join(f"{medians[(job, tool)] / m:.2f}x {b}"
                              for (j, b), m in medians.items()
                              if j == job and b.startswith("texbake"))
        status = f" ({bad} FAILED)" if bad else ""
        print(f"| {job} | {tool} | {medians[(job, tool)]:.2f}{status} | {times} | {ratio} |")
    if failed:
        print(f"{failed} run(s) FAILED their output check (marked !): see the logs")
    return 1 if failed else 0


def main(argv):
    if len(argv) in (3, 4) and argv[0] == "mesh":
        v, t = read_off(argv[1])
        for _ in range(int(argv[3]) if len(argv) == 4 else 2):
            v, t = subdivide(v, t)
        write_ply(argv[2], v, t)
        print(f"{argv[2]}: {len(v)} vertices, {len(t)} triangles")
        return 0
    if len(argv) == 2 and argv[0] == "center":
        v = read_ply_vertices(argv[1])
        p = np.stack([v["x"], v["y"], v["z"]], 1).astype(np.float64)
        c = (p.min(axis=0) + p.max(axis=0)) / 2
        print(",".join(f"{x:.9g}" for x in c))
        return 0
    if len(argv) == 4 and argv[0] == "check-vertex":
        return check_vertex(argv[1], argv[2], [float(x) for x in argv[3].split(",")])
    if len(argv) == 2 and argv[0] == "check-image":
        return check_image(argv[1])
    if len(argv) == 2 and argv[0] == "summary":
        return summary(argv[1])
    sys.exit(__doc__)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
