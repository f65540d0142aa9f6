"""Open3D's colour-map optimisation on a COLMAP model, for bench/photos/open3d_refine.sh.

Open3D (0.16) refines the camera poses of RGB-D frames against a mesh with
o3d.pipelines.color_map.run_rigid_optimizer (Zhou and Koltun 2014, rigid
part); this puts the project's photos and COLMAP models through it and writes
its poses back as a COLMAP model that texbake can bake with. Not texbake's
code: numpy and open3d only (texbake's Python module only to read meshes
for the comparisons).

    open3d_refine.py depth MESH MODEL DEPTH_DIR
        The z-depth of MESH from every photo of MODEL (its cameras.txt and
        images.txt; the true model), as a depth camera registered with the
        colour camera would record it: 16-bit PNGs DEPTH_DIR/NAME.png in
        millimetres (0 where no surface is hit), with the scene in metres
        of Open3D's example: its units divided by a power of two (exact in
        floating point) that puts the farthest surface between 1.2 and 2.4
        m, inside the example's maximum_allowable_depth (2.5 m) and
        depth_trunc (3 m). DEPTH_DIR/depth.json holds that "units_per_metre"
        and the largest depth. The depth is a z-buffer in numpy: Debian's
        Open3D 0.16.1 RaycastingScene.cast_rays hits nothing on the
        project's machine (a unit box included).

    open3d_refine.py refine MESH MODEL IMAGES DEPTH_DIR ITERATIONS OUT_MODEL OUT_MESH
        run_rigid_optimizer with maximum_iteration=ITERATIONS from the poses
        of MODEL (the disturbed ones), the photos IMAGES/NAME and the depth
        maps DEPTH_DIR/NAME.png, the scene in metres as above and
        everything else as in Open3D's example; writes the optimised poses
        as OUT_MODEL (images.txt; cameras.txt and points3D.txt copied from
        MODEL), Open3D's coloured mesh as OUT_MESH (PLY, the input's vertex
        order) and Open3D's debug log as OUT_MESH.log.
        Prints "seconds peak_MB load_seconds residual_first residual_last":
        the optimiser's own wall time, the process's peak resident memory,
        the time to read the photos and depth maps, and Open3D's average
        residual at the first and last iteration.

    open3d_refine.py same A.ply B.ply
        The largest difference of the two meshes' vertex colours, in 8-bit
        levels (0 when identical).

    open3d_refine.py poses TRUE MODEL MESH
        How far MODEL's poses are from TRUE's, photo by photo: the median
        and largest rotation error in degrees, then the median and largest
        camera centre error in % of the mesh's size (its bounding box
        diagonal).

Conventions: COLMAP's images.txt holds the world-to-camera rotation (as
QW QX QY QZ) and translation, camera looking down +z with y down, the same
as Open3D's PinholeCameraParameters.extrinsic (world-to-camera 4x4). COLMAP
puts pixel centres at half-integers (the image's centre at width / 2),
Open3D at integers (its bilinear lookups and rounding treat pixel (i, j)'s
centre as (i, j)), so Open3D's principal point is COLMAP's less half a pixel.
"""

import json
import os
import resource
import shutil
import sys
import tempfile
import time

import numpy as np
import open3d as o3d


def quat_to_r(w, x, y, z):
    n = np.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def r_to_quat(r):
    # Shepperd's method: the largest of w, x, y, z first.
    t = np.trace(r)
    d = [t, r[0, 0], r[1, 1], r[2, 2]]
    i = int(np.argmax(d))
    if i == 0:
        s = np.sqrt(1 + t) * 2
        q = [s / 4, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    else:
        a = i - 1
        b, c = (a + 1) % 3, (a + 2) % 3
        s = np.sqrt(1 + r[a, a] - r[b, b] - r[c, c]) * 2
        q = [0.0] * 4
        q[0] = (r[c, b] - r[b, c]) / s
        q[a + 1] = s / 4
        q[b + 1] = (r[a, b] + r[b, a]) / s
        q[c + 1] = (r[a, c] + r[c, a]) / s
    if q[0] < 0:
        q = [-v for v in q]
    return q


def data_lines(path):
    return [l for l in open(path).read().splitlines() if l.strip() and l[0] != "#"]


def read_cameras(folder):
    """camera id -> (width, height, fx, fy, cx, cy) in COLMAP's pixel convention."""
    out = {}
    for l in data_lines(f"{folder}/cameras.txt"):
        f = l.split()
        cid, model, w, h, p = f[0], f[1], int(f[2]), int(f[3]), list(map(float, f[4:]))
        if model == "PINHOLE":
            fx, fy, cx, cy = p[:4]
        elif model == "SIMPLE_PINHOLE":
            fx, cx, cy = p[:3]
            fy = fx
        elif model in ("SIMPLE_RADIAL", "RADIAL") and not any(p[3:]):
            fx, cx, cy = p[:3]
            fy = fx
        elif model in ("OPENCV", "FULL_OPENCV") and not any(p[4:]):
            fx, fy, cx, cy = p[:4]
        else:
            sys.exit(f"open3d_refine.py: camera {cid}: {model} with distortion; Open3D "
                     "takes pinhole cameras only")
        out[cid] = (w, h, fx, fy, cx, cy)
    return out


def read_images(folder):
    """[(fields, R, t)] in the file's order: world-to-camera x_cam = R x + t."""
    out = []
    lines = open(f"{folder}/images.txt").read().splitlines()
    body = [l for l in lines if not l.startswith("#")]
    # Two lines per image; the second (its 2D points) may be empty.
    i = 0
    while i < len(body):
        f = body[i].split()
        i += 1
        if len(f) < 10:
            continue
        out.append((f[:10], quat_to_r(*map(float, f[1:5])), np.array(list(map(float, f[5:8])))))
        i += 1  # the points line
    return out


def write_model(src, dst, images):
    os.makedirs(dst, exist_ok=True)
    for n in ("cameras.txt", "points3D.txt"):
        if os.path.exists(f"{src}/{n}"):
            shutil.copy(f"{src}/{n}", f"{dst}/{n}")
    with open(f"{dst}/images.txt", "w") as o:
        o.write("# Image list with two lines of data per image:\n"
                "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
                "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
                "# Number of images: %d\n" % len(images))
        for f, r, t in images:
            q = r_to_quat(r)
            o.write(" ".join([f[0], *(repr(float(v)) for v in q), *(repr(float(v)) for v in t),
                              f[8], f[9]]) + "\n\n")


def zbuffer(vertices, triangles, r, t, w, h, fx, fy, cx, cy):
    """The z-depth at every pixel's centre (COLMAP: (i + 0.5, j + 0.5)), 0 where
    no triangle covers it: a z-buffer in numpy, depth interpolated as 1 / z
    (exact for planar triangles under perspective)."""
    x = vertices @ r.T + t
    z = x[:, 2]
    depth = np.full(w * h, np.inf)
    front = (z[triangles] > 1e-9).all(1)
    tri = triangles[front]
    u = (fx * x[:, 0] / np.where(z > 1e-9, z, 1) + cx)[tri]
    v = (fy * x[:, 1] / np.where(z > 1e-9, z, 1) + cy)[tri]
    iz = (1 / np.where(z > 1e-9, z, 1))[tri]
    # The pixels whose centres may lie in each triangle: its bounding box.
    i0 = np.clip(np.ceil(u.min(1) - 0.5), 0, w).astype(np.int64)
    i1 = np.clip(np.floor(u.max(1) - 0.5), -1, w - 1).astype(np.int64)
    j0 = np.clip(np.ceil(v.min(1) - 0.5), 0, h).astype(np.int64)
    j1 = np.clip(np.floor(v.max(1) - 0.5), -1, h - 1).astype(np.int64)
    nx, ny = i1 - i0 + 1, j1 - j0 + 1
    area = (u[:, 1] - u[:, 0]) * (v[:, 2] - v[:, 0]) - (u[:, 2] - u[:, 0]) * (v[:, 1] - v[:, 0])
    keep = np.flatnonzero((nx > 0) & (ny > 0) & (np.abs(area) > 1e-12))
    count = (nx * ny)[keep]
    ends = np.cumsum(count)
    # In chunks of about 4 million pixel candidates.
    start = 0
    while start < len(keep):
        stop = int(np.searchsorted(ends, (ends[start - 1] if start else 0) + 4_000_000, "right"))
        stop = max(stop, start + 1)
        k = keep[start:stop]
        c = count[start:stop]
        which = np.repeat(np.arange(len(k)), c)
        off = np.arange(int(c.sum())) - np.repeat(np.cumsum(c) - c, c)
        tk = k[which]
        pi = i0[tk] + off % nx[tk]
        pj = j0[tk] + off // nx[tk]
        px, py = pi + 0.5, pj + 0.5
        uu, vv, a = u[tk], v[tk], area[tk]
        b0 = ((uu[:, 1] - px) * (vv[:, 2] - py) - (uu[:, 2] - px) * (vv[:, 1] - py)) / a
        b1 = ((uu[:, 2] - px) * (vv[:, 0] - py) - (uu[:, 0] - px) * (vv[:, 2] - py)) / a
        b2 = 1 - b0 - b1
        inside = (b0 >= -1e-9) & (b1 >= -1e-9) & (b2 >= -1e-9)
        zz = 1 / (b0 * iz[tk, 0] + b1 * iz[tk, 1] + b2 * iz[tk, 2])
        np.minimum.at(depth, (pj * w + pi)[inside], zz[inside])
        start = stop
    depth[~np.isfinite(depth)] = 0
    return depth.reshape(h, w)


def depth_maps(mesh_path, model, out_dir):
    cams = read_cameras(model)
    mesh = o3d.io.read_triangle_mesh(mesh_path)
    vertices = np.asarray(mesh.vertices, float)
    triangles = np.asarray(mesh.triangles, np.int64)
    os.makedirs(out_dir, exist_ok=True)
    depths = []
    for f, r, t in read_images(model):
        w, h, fx, fy, cx, cy = cams[f[8]]
        depths.append((f[9], zbuffer(vertices, triangles, r, t, w, h, fx, fy, cx, cy)))
    top = max(float(z.max()) for _, z in depths)
    unit = 2.0 ** np.ceil(np.log2(top / 2.4))
    for name, z in depths:
        png = np.round(z / unit * 1000).astype(np.uint16)
        o3d.io.write_image(f"{out_dir}/{os.path.splitext(name)[0]}.png", o3d.geometry.Image(png))
    json.dump({"units_per_metre": unit, "max_depth": top, "photos": len(depths)},
              open(f"{out_dir}/depth.json", "w"))
    print(f"{len(depths)} depth maps, largest depth {top:.4f} units = {top / unit:.3f} m")


class Stdout:
    """Captures what the C++ side prints to file descriptor 1 (Open3D's log)."""

    def __enter__(self):
        sys.stdout.flush()
        self.file = tempfile.TemporaryFile(mode="w+")
        self.saved = os.dup(1)
        os.dup2(self.file.fileno(), 1)
        return self

    def __exit__(self, *exc):
        sys.stdout.flush()
        os.dup2(self.saved, 1)
        os.close(self.saved)
        self.file.seek(0)
        self.text = self.file.read()
        self.file.close()


def refine(mesh_path, model, images_dir, depth_dir, iterations, out_model, out_mesh):
    import texbake

    cams = read_cameras(model)
    images = read_images(model)
    unit = json.load(open(f"{depth_dir}/depth.json"))["units_per_metre"]
    mesh = o3d.io.read_triangle_mesh(mesh_path)
    ours = np.asarray(texbake.read_mesh(mesh_path).vertices, float)
    theirs = np.array(mesh.vertices)  # a copy: the mesh is scaled below
    if ours.shape != theirs.shape or np.abs(ours - theirs).max() > 1e-6 * np.abs(ours).max():
        sys.exit("open3d_refine.py: Open3D reads the mesh's vertices in another order or number "
                 "than texbake; its colours could not be compared vertex by vertex")
    mesh.vertices = o3d.utility.Vector3dVector(theirs / unit)

    start = time.perf_counter()
    rgbd = []
    trajectory = o3d.camera.PinholeCameraTrajectory()
    params = []
    for f, r, t in images:
        w, h, fx, fy, cx, cy = cams[f[8]]
        colour = np.asarray(o3d.io.read_image(f"{images_dir}/{f[9]}"))
        if colour.ndim == 2:
            colour = np.stack([colour] * 3, -1)
        colour = o3d.geometry.Image(np.ascontiguousarray(colour[:, :, :3]))
        depth = o3d.io.read_image(f"{depth_dir}/{os.path.splitext(f[9])[0]}.png")
        # As the example: depth_scale 1000 (millimetres), depth_trunc 3 m.
        rgbd.append(o3d.geometry.RGBDImage.create_from_color_and_depth(
            colour, depth, convert_rgb_to_intensity=False))
        p = o3d.camera.PinholeCameraParameters()
        p.intrinsic = o3d.camera.PinholeCameraIntrinsic(w, h, fx, fy, cx - 0.5, cy - 0.5)
        e = np.eye(4)
        e[:3, :3], e[:3, 3] = r, t / unit
        p.extrinsic = e
        params.append(p)
    trajectory.parameters = params
    load = time.perf_counter() - start

    # Open3D's example (examples/python/pipelines/color_map_optimization.py):
    # RigidOptimizerOption(maximum_iteration=300), the rest its defaults
    # (lengths in metres: maximum_allowable_depth 2.5, visibility 0.03,
    # discontinuity 0.1).
    option = o3d.pipelines.color_map.RigidOptimizerOption(maximum_iteration=iterations)
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Debug)
    with Stdout() as log:
        start = time.perf_counter()
        coloured, optimised = o3d.pipelines.color_map.run_rigid_optimizer(
            mesh, rgbd, trajectory, option)
        seconds = time.perf_counter() - start
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Warning)
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    with open(f"{out_mesh}.log", "w") as o:
        o.write(log.text)
    residuals = [float(l.split("avg : ")[1].rstrip(")\n ")) for l in log.text.splitlines()
                 if "avg : " in l]
    out = []
    for (f, _, _), p in zip(images, optimised.parameters):
        e = np.asarray(p.extrinsic)
        out.append((f, e[:3, :3], e[:3, 3] * unit))
    write_model(model, out_model, out)
    if not np.array_equal(np.asarray(coloured.vertices), theirs / unit):
        sys.exit("open3d_refine.py: Open3D's coloured mesh has other vertices than its input")
    coloured.vertices = o3d.utility.Vector3dVector(theirs)
    o3d.io.write_triangle_mesh(out_mesh, coloured, write_ascii=False)
    first = f"{residuals[0]:.5f}" if residuals else "-"
    last = f"{residuals[-1]:.5f}" if residuals else "-"
    print(f"{seconds:.3f} {peak_mb:.0f} {load:.3f} {first} {last}")


def same(a, b):
    import texbake

    ca = np.asarray(texbake.read_mesh(a).colors, float)
    cb = np.asarray(texbake.read_mesh(b).colors, float)
    print(f"{255 * np.abs(ca - cb).max():.3f}" if ca.shape == cb.shape else "different sizes")


def poses(true_model, model, mesh_path):
    v = np.asarray(o3d.io.read_triangle_mesh(mesh_path).vertices)
    size = np.linalg.norm(v.max(0) - v.min(0))
    truth = {f[9]: (r, t) for f, r, t in read_images(true_model)}
    rot, centre = [], []
    for f, r, t in read_images(model):
        r0, t0 = truth[f[9]]
        c = np.clip((np.trace(r @ r0.T) - 1) / 2, -1, 1)
        rot.append(np.degrees(np.arccos(c)))
        centre.append(100 * np.linalg.norm(r.T @ t - r0.T @ t0) / size)
    print(f"{np.median(rot):.2f} / {max(rot):.2f} deg, "
          f"{np.median(centre):.2f} / {max(centre):.2f} %")


if __name__ == "__main__":
    mode = sys.argv[1] if len(sys.argv) > 1 else ""
    if mode == "depth" and len(sys.argv) == 5:
        depth_maps(*sys.argv[2:5])
    elif mode == "refine" and len(sys.argv) == 9:
        a = sys.argv[2:9]
        refine(a[0], a[1], a[2], a[3], int(a[4]), a[5], a[6])
    elif mode == "same" and len(sys.argv) == 4:
        same(sys.argv[2], sys.argv[3])
    elif mode == "poses" and len(sys.argv) == 5:
        poses(*sys.argv[2:5])
    else:
        sys.exit(__doc__.split("\n\n", 2)[2].split("Conventions")[0].rstrip())
