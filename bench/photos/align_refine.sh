#!/usr/bin/env bash
# cameras align and cameras refine at scale: the photos of run.sh (the bunny
# and the armadillo subdivided to 832k triangles, 24 views of 1920 x 1080
# each, known cameras), their models disturbed by hand, then put right. A
# benchmark run by hand, not part of the ctest suite.
#
#   bench/photos/align_refine.sh [-n N] [-w WORKDIR]
#
#   -n N     repetitions of every command (default 1; the table shows medians)
#   -w DIR   work folder, shared with run.sh (default
#            ${TMPDIR:-/tmp}/texbake_photos)
#
# align: the true model with 20,000 of the mesh's vertices as its sparse
# points, moved away by a similarity (scale 0.4, 120 degrees about
# (1, 1, 1), a shift), then aligned back: time, peak memory, and how far
# the recovered camera centres are from the true ones (relative to the
# mesh's size). refine: every pose turned by 0.25-0.5 degree and its centre
# moved by 0.5 % of its distance ("half"), or 0.5-1 degree and 1 % ("full",
# the issue's perturbation), then refined: time, peak memory, steps, and the
# photo bake's agreement with the direct bake (the share of vertices within
# 8 levels of the Earth map's colour from the sphere the photos were
# rendered with) for the true, disturbed and refined cameras, and the photo
# bake's own time beside it. Prints Markdown tables.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source-path=SCRIPTDIR source=../../scripts/setup.sh
source "$here/../../scripts/setup.sh"
# shellcheck source=../common.sh
source "$here/../common.sh"
bench_options 1 "${TMPDIR:-/tmp}/texbake_photos" "$@"
bench_start

# Photos: 24 views around each mesh's up axis, 1920 x 1080, unlit.
bench_photo_meshes

# model.py MODE ARGS: the models' arithmetic, with numpy (not texbake's code).
cat >model.py <<'PY'
import sys
import numpy as np

def rot(axis, deg):
    a = np.asarray(axis, float); a /= np.linalg.norm(a)
    t = np.radians(deg); k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(t) * k + (1 - np.cos(t)) * k @ k

def quat_to_r(w, x, y, z):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])

def r_to_quat(r):
    w = np.sqrt(max(0.0, 1 + np.trace(r))) / 2
    if w > 1e-6:
        return [w, (r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w), (r[1, 0] - r[0, 1]) / (4 * w)]
    i = int(np.argmax(np.diag(r))); j, k = (i + 1) % 3, (i + 2) % 3
    s = np.sqrt(1 + r[i, i] - r[j, j] - r[k, k]) * 2
    q = [0.0] * 4; q[0] = (r[k, j] - r[j, k]) / s; q[i + 1] = s / 4
    q[j + 1] = (r[j, i] + r[i, j]) / s; q[k + 1] = (r[k, i] + r[i, k]) / s
    return q

def read_images(folder):
    lines = [l for l in open(f"{folder}/images.txt").read().splitlines() if l and l[0] != "#"]
    out = []
    for l in lines:
        f = l.split()
        if len(f) == 10:
            out.append((f, quat_to_r(*map(float, f[1:5])), np.array(list(map(float, f[5:8])))))
    return out

def write_images(folder, images):
    with open(f"{folder}/images.txt", "w") as o:
        for f, r, t in images:
            q = r_to_quat(r)
            o.write(" ".join([f[0], *(repr(float(v)) for v in q), *(repr(float(v)) for v in t), f[8], f[9]]) + "\n\n")

def centres(folder):
    return {f[9]: -r.T @ t for f, r, t in read_images(folder)}

mode = sys.argv[1]
if mode == "perturb":  # src dst scale
    src, dst, scale = sys.argv[2], sys.argv[3], float(sys.argv[4])
    axes = [(1, 2, 3), (-2, 1, 1), (3, -1, 2), (1, 1, -3), (-1, -3, 1), (2, 2, 1)]
    out = []
    for k, (f, r, t) in enumerate(read_images(src)):
        c = -r.T @ t
        r2 = rot(axes[k % 6], scale * (0.5 + 0.1 * (k % 6))) @ r
        move = np.cross(axes[(k + 1) % 6], c); move /= np.linalg.norm(move)
        c2 = c + move * 0.01 * scale * np.linalg.norm(c)
        out.append((f, r2, -r2 @ c2))
    write_images(dst, out)
elif mode == "points":  # mesh.ply|off folder count
    import texbake
    v = np.asarray(texbake.read_mesh(sys.argv[2]).vertices, float)
    v = v[:: max(1, len(v) // int(sys.argv[4]))]
    with open(f"{sys.argv[3]}/points3D.txt", "w") as o:
        for i, p in enumerate(v):
            o.write(f"{i + 1} {p[0]!r} {p[1]!r} {p[2]!r} 128 128 128 0.1\n")
elif mode == "similarity":  # the 4x4 moving the model away, as --transform takes it
    m = np.eye(4); m[:3, :3] = 0.4 * rot((1, 1, 1), 120); m[:3, 3] = (3, -2, 5)
    print(",".join(repr(float(x)) for x in m.ravel()))
elif mode == "centres":  # truth aligned mesh: the largest centre error / mesh size
    import texbake
    v = np.asarray(texbake.read_mesh(sys.argv[4]).vertices, float)
    size = np.linalg.norm(v.max(0) - v.min(0))
    a, b = centres(sys.argv[2]), centres(sys.argv[3])
    print(f"{max(np.linalg.norm(a[n] - b[n]) for n in a) / size:.2e}")
elif mode == "steps":  # a refine report: steps per photo, clamped, levels
    import json
    r = json.load(open(sys.argv[2]))
    n = [p["iterations"] for p in r["photos"]]
    clamped = sum(p["clamped"] for p in r["photos"])
    print(f"{min(n)}-{max(n)}, {clamped} clamped, {r['levels']} levels")
elif mode == "agree":  # direct.ply baked.ply: share of vertices within 8 levels
    import texbake
    a = np.asarray(texbake.read_mesh(sys.argv[2]).colors, float)[:, :3]
    b = np.asarray(texbake.read_mesh(sys.argv[3]).colors, float)[:, :3]
    print(f"{100 * np.mean(np.abs(a - b).max(1) <= 8 / 255 + 1e-9):.1f}")
PY
export PYTHONPATH="$TEXBAKE_BUILD/python${PYTHONPATH:+:$PYTHONPATH}"

# The median of $reps runs of texbake ARGS: "seconds peak_MB" (texbake's
# own stdout dropped).
median_of() {
  local i
  for ((i = 0; i < reps; i++)); do timed "$@" | tail -n 1; done | sort -n |
    sed -n "$(((reps + 1) / 2))p"
}

align_rows=()
refine_rows=()
for mesh in bunny.off armadillo_832k.ply; do
  name=${mesh%.*}
  model=$name/ws/sparse/0
  # align: the true model with points, moved away, brought back.
  rm -rf "$name/with_points" "$name/away" "$name/aligned"
  mkdir -p "$name/with_points"
  cp "$model/cameras.txt" "$model/images.txt" "$name/with_points/"
  "$py" model.py points "$mesh" "$name/with_points" 20000
  "$texbake" cameras align "$mesh" --cameras "$name/with_points" \
    --transform "$("$py" model.py similarity)" -o "$name/away" >/dev/null
  read -r s p < <(median_of cameras align "$mesh" --cameras "$name/away" -o "$name/aligned")
  err=$("$py" model.py centres "$model" "$name/aligned" "$mesh")
  align_rows+=("| $mesh | $s | $p | $err |")

  # The direct bake and the photo bake with the true cameras.
  "$texbake" bake "$mesh" --texture "$TEXBAKE_ROOT/data/earth.jpg" --proxy-file "$name/sphere.json" \
    -q -o "$name/direct.ply"
  read -r bake_s _ < <(median_of bake "$mesh" --cameras "$model" -q -o "$name/true.ply")
  true_agree=$("$py" model.py agree "$name/direct.ply" "$name/true.ply")
  for scale in half full; do
    f=0.5
    [ "$scale" = full ] && f=1
    rm -rf "$name/moved_$scale" "$name/refined_$scale"
    mkdir -p "$name/moved_$scale"
    cp "$model/cameras.txt" "$model/points3D.txt" "$name/moved_$scale/"
    "$py" model.py perturb "$model" "$name/moved_$scale" "$f"
    "$texbake" bake "$mesh" --cameras "$name/moved_$scale" --images "$name/ws/images" -q \
      -o "$name/moved_$scale.ply"
    read -r s p < <(median_of cameras refine "$mesh" --cameras "$name/moved_$scale" \
      --images "$name/ws/images" -q --report "$name/refine_$scale.json" -o "$name/refined_$scale")
    "$texbake" bake "$mesh" --cameras "$name/refined_$scale" --images "$name/ws/images" -q \
      -o "$name/refined_$scale.ply"
    steps=$("$py" model.py steps "$name/refine_$scale.json")
    moved_agree=$("$py" model.py agree "$name/direct.ply" "$name/moved_$scale.ply")
    refined_agree=$("$py" model.py agree "$name/direct.ply" "$name/refined_$scale.ply")
    refine_rows+=("| $mesh | $scale | $s | $p | $steps | $true_agree / $moved_agree / $refined_agree | $bake_s |")
  done
done

echo
echo "| mesh | cameras align s | peak MB | largest centre error / mesh size |"
echo "|---|---|---|---|"
printf '%s\n' "${align_rows[@]}"
echo
echo "| mesh | perturbation | cameras refine s | peak MB | steps per photo | % of vertices within 8 levels: true / disturbed / refined | photo bake s |"
echo "|---|---|---|---|---|---|---|"
printf '%s\n' "${refine_rows[@]}"
