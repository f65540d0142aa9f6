"""texbake: bake 2D images onto 3D meshes through analytic proxy shapes.

A proxy (sphere, cylinder, cone, disk, convex quad, plane) carries every mesh
point P to texture coordinates (u, v) by its inverse mapping; the image is
sampled there (bilinear) and the colour stored per vertex or in a UV-atlas
texture, with Embree ray-traced occlusion. This module wraps the C++ API
(texbake/texbake.h) with numpy arrays in and out; the command line `texbake`
is another client of the same calls, and both give the same bytes.

    import texbake
    mesh = texbake.read_mesh("data/bunny00.off")
    image = texbake.read_image("data/earth.jpg")          # (h, w, 4) float32
    proxy = texbake.fit(mesh, "sphere", up="y")            # or Proxy.sphere(...)
    colors, stats = texbake.bake_vertex(mesh, image, proxy)
    texbake.write_vertex_colors("bunny.ply", mesh, colors)

Conventions (SPEC section 1): (u, v) in [0, 1], v = 0 the image's bottom row;
colours RGBA in [0, 1] in the image's stored (sRGB) encoding; options are
spelled as the command line spells them ("area", "first", "fill", ...).

Meshes are texbake.Mesh objects (read_mesh, or Mesh(vertices, faces, ...));
every function that takes a mesh also takes the two arrays `vertices` (n, 3)
and `faces` (m, 3) in its place: bake_vertex(vertices, faces, image, proxy).

Errors raise ValueError (a bad argument or option: the command line's exit
2), OSError (a file, or a mesh the job cannot work on: exit 1), RuntimeError
(an internal failure) or texbake.Cancelled (the progress callback returned
False), with the command line's messages. Options are checked by the same
library checks as the command line's flags, so a bad value raises
ValueError with the message the CLI prints for that flag (e.g. samples=0:
"--samples 0 is out of range (1 .. 65536)"), whatever its type (1.5 where
a count is due, None where a proxy is).

Non-finite numbers: arrays of geometry (vertices, uvs, normals, colors)
must be finite and within float32's range (ValueError naming the array and
the first bad row); NaN or infinite values of an image (an array or a
file) are read as 0 with a RuntimeWarning naming it and the count, as the
command line warns for a texture.

Every default of a bake's option is the command line's and a batch line's,
read from the library's one table of job options (texbake.JOB_OPTIONS,
viewed by call group as texbake.DEFAULTS); render's and compare's are
their commands' (the library's option structs).

Long calls release the GIL. `progress(stage, fraction)`, when given, is
called with the GIL held, never concurrently with itself; returning False
cancels the call (texbake.Cancelled); an exception it raises cancels the call
and propagates. `threads=0` uses all cores; results never depend on it.
"""

import json as _json

import numpy as _np

from . import _texbake
from ._texbake import Atlas, Cancelled, Mesh  # noqa: F401

__version__ = _texbake.version()

__all__ = [
    "ImageArray",
    "image",
    "Atlas", "Cancelled", "DEFAULTS", "Mesh", "Proxy", "STATUS", "atlas_files", "bake_atlas",
    "bake_atlas_from_camera", "bake_atlas_from_layers", "bake_atlas_from_photos",
    "bake_vertex", "bake_vertex_from_camera", "bake_vertex_from_layers",
    "bake_vertex_from_photos", "CameraChecks", "check_cameras", "compare", "refine_cameras", "fit", "map", "read_image",
    "read_mesh", "render",
    "write_atlas", "write_image", "write_vertex_colors",
    "JOB_OPTIONS", "run_batch", "run_job",
]

#: The options of a whole job (run_job, run_batch, `texbake bake`'s flags and
#: a batch line's keys): one table in the library, each a dict with "key"
#: (the keyword), "flag" (the command line's), "type", "value_name",
#: "default", "range", "bakes" (where it applies: "proxy vertex", "photos
#: atlas", ...) and "help".
JOB_OPTIONS = tuple(_texbake.job_options())

_OPTIONS = {o["key"]: o for o in JOB_OPTIONS}


def _option_value(option, text):
    """A job option's value as the command line takes it ("16", "1,0,0",
    "false") as the Python value a call takes (16, (1.0, 0.0, 0.0), False);
    None stays None."""
    if text is None:
        return None
    kind = option["type"]
    if kind == "flag":
        return text == "true"
    if kind == "integer" or (kind == "text" and text.isdigit()):
        return int(text)
    if kind == "number":
        return float(text)
    if kind in ("vec3", "text") and "," in text:
        return tuple(float(x) for x in text.split(","))
    return text


def _default(key, target="vertex"):
    """The table's default of job option `key` for a bake of `target`, as a
    Python value; None when the job works it out (padding: 8 at 2048,
    scaled with size)."""
    option = _OPTIONS[key]
    return _option_value(option, option["defaults"][target])


def _defaults(target, *keys, **renamed):
    d = {k: _default(k, target) for k in keys}
    d.update({name: _default(key, target) for name, key in renamed.items()})
    return d


_SHADING = ("filter", "samples", "visibility", "occluded", "outside", "linear", "wrap",
            "cache_mb")

#: The defaults of every call's options, by group: vertex (bake_vertex),
#: atlas (bake_atlas and every atlas bake), photos (the photo and camera
#: bakes; colorspace is the table's texture_colorspace), layers: a view of
#: JOB_OPTIONS' defaults (the command line's and a batch line's); render and
#: compare: those commands' defaults (the library's option structs).
DEFAULTS = {
    "vertex": _defaults("vertex", *_SHADING),
    "atlas": _defaults("atlas", "uv", "size", "samples", "padding", *_SHADING),
    "photos": _defaults("vertex", "blend", "exposure", "occluded",
                        colorspace="texture_colorspace"),
    "layers": _defaults("vertex", "occluded", "cache_mb"),
    **_texbake.render_defaults(),
}
_R = DEFAULTS["render"]


def _v(key):
    """The table's default of `key` for a vertex bake."""
    return _default(key, "vertex")


def _a(key):
    """The table's default of `key` for an atlas bake."""
    return _default(key, "atlas")

#: Names of the codes in map()'s `status` array: 0 ok, 1 outside (beyond the
#: proxy's (u, v) domain; uv unclamped), 2 undefined (no mapping).
STATUS = ("ok", "outside", "undefined")

_UP = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1),
       "-x": (-1, 0, 0), "-y": (0, -1, 0), "-z": (0, 0, -1)}


def _up(up):
    """An up direction: 'x'|'y'|'z'|'-x'|'-y'|'-z' or 3 numbers; None stays None."""
    if up is None or not isinstance(up, str):
        return up
    if up not in _UP:
        raise ValueError(f"up: unknown value '{up}' (expected x, y, z, -x, -y or -z)")
    return _UP[up]


def _mesh(args, rest, name):
    """Splits (mesh, *rest) or (vertices, faces, *rest) into a Mesh and rest."""
    if args and isinstance(args[0], Mesh):
        mesh, tail = args[0], args[1:]
    elif len(args) >= 2:
        mesh, tail = Mesh(args[0], args[1]), args[2:]
    else:
        raise TypeError(f"{name}() takes a Mesh or vertices, faces first")
    if len(tail) != rest:
        raise TypeError(f"{name}() takes (mesh, {rest} more) or (vertices, faces, {rest} more) "
                        f"positional arguments")
    return (mesh,) + tuple(tail)


# ---- Reading ---------------------------------------------------------------

def read_mesh(path):
    """Read a mesh (.obj, .ply, .off, .stl, .glb, .gltf) into a texbake.Mesh.

    The Mesh has `vertices` (n, 3) float64, `faces` (m, k) int64 (None when
    the polygons have different corner counts: see face_offsets and
    face_vertices), `triangles` (t, 3) int64 (the triangulation without
    degenerate triangles), and when present `uvs` (a table, (u, 2)) with
    `corner_uvs` (an index per corner of face_vertices), `normals` with
    `corner_normals`, `colors` (n, 4) float32, `texture_path` (OBJ map_Kd),
    and `issues` (degenerate triangles, unreferenced vertices, non-manifold
    edges). Errors: OSError naming the file (and line).
    """
    return _texbake.read_mesh(path)


class ImageArray(_np.ndarray):
    """An image array that knows the encoding of its values: `colorspace` is
    'srgb' (sRGB-encoded, as 8/16-bit files are) or 'linear' (linear light,
    as float files are). The bakes and the render sample it accordingly, as
    the CLI does (README, Colour spaces). A plain numpy array is taken as
    sRGB; wrap it with texbake.image(array, 'linear') otherwise."""

    colorspace = "srgb"

    def __array_finalize__(self, obj):
        self.colorspace = getattr(obj, "colorspace", "srgb")


def image(array, colorspace="srgb"):
    """The array viewed as an ImageArray with that colour space ('srgb' or
    'linear'); no copy. Errors: ValueError for another colour space."""
    if colorspace not in ("srgb", "linear"):
        raise ValueError("colorspace must be 'srgb' or 'linear', not %r" % (colorspace,))
    out = _np.asarray(array).view(ImageArray)
    out.colorspace = colorspace
    return out


def read_image(path, colorspace="auto"):
    """Read an image (anything OpenImageIO reads) as an (h, w, 4) float32
    RGBA ImageArray.

    Top row first; integer formats scaled to [0, 1]; 1 and 2 channel images
    become grey RGB(A); no colour-space conversion of the values. Its
    `colorspace` is what the file says (oiio:ColorSpace; float data linear,
    integer data sRGB), or `colorspace` ('srgb' or 'linear') when given, as
    --texture-colorspace. Errors: OSError, ValueError.
    """
    values, space = _texbake.read_image(path, colorspace)
    return image(values, space)


# ---- Proxies ---------------------------------------------------------------

class Proxy:
    """A validated proxy shape (SPEC section 2). Build one with a constructor
    per kind (Proxy.sphere, .cylinder, .cone, .disk, .quad, .plane),
    Proxy.from_json(path or dict) or texbake.fit(). Vectors need not be
    unit; an equator not given is the first of +X, +Y, +Z not parallel to the
    pole/axis/normal. Invalid geometry raises ValueError naming the key.
    """

    def __init__(self, native):
        self._native = native

    @property
    def kind(self):
        """'sphere', 'cylinder', 'cone', 'disk', 'quad' or 'plane'."""
        return self._native.kind

    @property
    def fitted(self):
        """Keys fitted to the mesh by texbake.fit (empty otherwise)."""
        return list(self._native.fitted)

    def to_dict(self):
        """The proxy as its JSON object (vectors unit, equator filled in)."""
        return _json.loads(self._native.to_json())

    def to_json(self):
        """The proxy as one line of JSON (what `texbake fit` writes)."""
        return self._native.to_json()

    def write(self, path):
        """Write the proxy as a JSON file for --proxy-file (atomically)."""
        self._native.write(path)

    def __repr__(self):
        return f"texbake.Proxy({self.to_json()})"

    def __eq__(self, other):
        return isinstance(other, Proxy) and self.to_dict() == other.to_dict()

    @staticmethod
    def _make(kind, up=None, **values):
        return Proxy(_texbake.make_proxy(kind, values, _up(up)))

    @staticmethod
    def sphere(center=(0, 0, 0), radius=1.0, pole=None, equator=None, up=None):
        """Sphere: u the azimuth around `pole` from `equator`, v = phi / pi
        (0 at -pole, 1 at +pole). pole defaults to `up` (default +Z)."""
        return Proxy._make("sphere", up, center=center, radius=radius, pole=pole, equator=equator)

    @staticmethod
    def cylinder(base, radius, height, axis=None, equator=None, up=None):
        """Cylinder from `base` (v = 0) along `axis` (v = 1 at base + height*axis)."""
        return Proxy._make("cylinder", up, base=base, axis=axis, equator=equator,
                           radius=radius, height=height)

    @staticmethod
    def cone(apex, height, radius, axis=None, equator=None, up=None):
        """Cone: `axis` points from the base centre to `apex` (v = 1 there, 0 on the rim)."""
        return Proxy._make("cone", up, apex=apex, axis=axis, equator=equator,
                           height=height, radius=radius)

    @staticmethod
    def disk(center, radius, normal=None, equator=None, up=None):
        """Disk: u the azimuth around `normal`, v = r / radius."""
        return Proxy._make("disk", up, center=center, normal=normal, equator=equator,
                           radius=radius)

    @staticmethod
    def quad(corners):
        """Convex planar quad, corners p00, p10, p11, p01 (u: p00->p10, v: p00->p01)."""
        return Proxy._make("quad", corners=corners)

    @staticmethod
    def plane(origin, u_axis, v_axis):
        """Plane: P = origin + u u_axis + v v_axis (the axes' lengths are the image's extent)."""
        return Proxy._make("plane", origin=origin, u_axis=u_axis, v_axis=v_axis)

    @staticmethod
    def from_json(source):
        """A proxy from a JSON file path or a dict such as
        {"kind": "sphere", "center": [0, 0, 0], "radius": 1, "pole": [0, 0, 1]}.
        Errors name the file (or "proxy JSON") and key: OSError for a file
        that cannot be read or whose content is wrong, as --proxy-file."""
        if isinstance(source, dict):
            return Proxy(_texbake.proxy_from_json(_json.dumps(source), "proxy JSON"))
        return Proxy(_texbake.read_proxy_file(source))


def fit(*mesh_kind, up="z", threads=0, **given):
    """fit(mesh, kind, up='z', **given) or fit(vertices, faces, kind, ...):
    the proxy of `kind` ('sphere', 'cylinder', ...) fitted to the mesh (SPEC
    section 6, as `texbake fit` and `bake` without every geometry flag):
    given values (by JSON key, e.g. center=(0, 0, 0)) are kept and the rest
    is fitted around them; `up` is the pole / the axis line hint. Errors:
    ValueError (a bad given value), OSError (the mesh cannot be fitted)."""
    mesh, kind = _mesh(mesh_kind, 1, "fit")
    return Proxy(_texbake.fit(mesh, kind, given, _up(up), threads))


def map(proxy, points):  # noqa: A001 (the command's name)
    """The inverse mapping of `proxy` at `points` (n, 3), vectorised (`texbake map`).

    Returns (uv (n, 2) float64, status (n,) int8, direction (n, 3) float64):
    status codes index texbake.STATUS (0 ok, 1 outside, 2 undefined);
    direction is d(P), the unit vector from P towards the projector.
    """
    return _texbake.map(proxy, points)


# ---- Bakes -----------------------------------------------------------------

def bake_vertex(*mesh_image_proxy, filter=_v("filter"), samples=_v("samples"),
                visibility=_v("visibility"), occluded=_v("occluded"), outside=_v("outside"),
                linear=_v("linear"), wrap=_v("wrap"), cache_mb=_v("cache_mb"), threads=0,
                progress=None):
    """bake_vertex(mesh, image, proxy, ...) or bake_vertex(vertices, faces, image, proxy, ...):
    one colour per vertex (`texbake bake ... --target vertex`).

    image: (h, w, c) array (float32 RGBA C-contiguous is used without a
    copy; uint8/uint16 are scaled to [0, 1]), or an image file's path, read
    as `--texture` is: with the memory budget cache_mb (MiB, --cache-mb), past
    which (or past 16384 x 16384 pixels) its texels are read in tiles through
    OpenImageIO's ImageCache, with the same results. Options as the command line's:
    filter 'area' | 'bilinear' | 'ewa', samples (1..65536, area only), visibility
    'first' | 'all', occluded 'fill' | 'project' | (r, g, b[, a]), outside
    'clamp' | (r, g, b[, a]), linear, wrap 'clamp' | 'repeat' (plane only),
    cache_mb 1..16777216. Bad values raise ValueError with the CLI's message.
    Returns (colors (n, 4) float32 in the input's vertex order, stats dict:
    counts, timings in seconds, warnings, notes: a photo or layers bake's
    camera file reader's, e.g. a nerfstudio applied_transform undone). The
    counts are the CLI's --report "counts" for the same job, by the same
    names (vertices, triangles, degenerate_skipped, ..., occluded, filled,
    unfilled), the timings its
    stages' (scene_build, bake, fill) and the call's total; so are every
    bake's, and an atlas's stats["atlas"] is the report's "atlas" object
    (uv, size, samples_per_texel, padding, counts, ...) less its timings.
    Progress stages: 'bake', 'fill'.
    """
    mesh, image, proxy = _mesh(mesh_image_proxy, 2, "bake_vertex")
    return _texbake.bake_vertex(mesh, image, proxy, filter, samples, visibility,
                                occluded, outside, linear, wrap, cache_mb, threads, progress)


def bake_vertex_from_photos(*mesh, cameras, images=None, masks=None, blend=_v("blend"),
                            exposure=_v("exposure"), occluded=_v("occluded"),
                            colorspace=_v("texture_colorspace"),
                            strict_photos=_v("strict_photos"), threads=0, progress=None):
    """bake_vertex_from_photos(mesh, cameras=PATH, ...) or (vertices, faces, cameras=PATH, ...):
    one colour per vertex from calibrated photographs (`texbake bake MESH --cameras PATH`).

    cameras: a COLMAP sparse model folder (cameras + images, .txt or .bin) or
    a JSON camera list; images: the photos' folder (default: a COLMAP
    workspace's images/ beside sparse/, or the list's folder); masks: the
    photos' masks in COLMAP's convention (--masks: DIR/<image name>.png, 0 =
    masked out; a photo without one is used whole, named in
    stats['warnings']; a photo's own alpha always weighs its samples). blend
    'soft' | 'best' | 'mean'; exposure 'gain' | 'none'; occluded 'fill' | (r, g, b[, a]);
    colorspace 'auto' | 'srgb' | 'linear' (the photos'). A photo that cannot
    be read is left out, named in stats['warnings'] and listed in
    stats['photos_skipped'] (dicts with image, path, reason); strict_photos=True
    makes it an error (OSError), as --strict-photos; no readable photo is an
    error. Returns (colors (n, 4) float32, stats dict (counts as the report's:
    camera_samples, unseen, ...), cameras: a list of dicts per photo used
    with image, photo (w, h), masked (the share of its pixels masked out),
    in_view, visible, weight_share, gain (r, g, b), shared, deviation).
    Progress stage: 'photos'.
    """
    mesh = _mesh(mesh, 0, "bake_vertex_from_photos")[0]
    return _texbake.bake_vertex_from_photos(mesh, cameras, images, masks, blend, exposure, occluded,
                                            colorspace, bool(strict_photos), threads, progress)


def bake_vertex_from_layers(*mesh, layers, occluded=_v("occluded"), cache_mb=_v("cache_mb"),
                            threads=0, progress=None):
    """bake_vertex_from_layers(mesh, layers=PATH, ...) or (vertices, faces, layers=PATH, ...):
    one colour per vertex composited from a layers file (`texbake bake MESH
    --layers PATH`, SPEC section 10: its base, then every layer bottom first,
    in linear light; "cameras" layers included).

    occluded 'fill' | (r, g, b[, a]): vertices no layer and no base colour
    cover (their alpha stays 0); cache_mb: the memory budget for each layer's
    texture and mask (--cache-mb). Returns (colors (n, 4) float32, sRGB-encoded,
    alpha = coverage; stats dict (counts as the report's: uncovered, ...);
    layers: a list of dicts per layer with texture (or cameras), in_domain,
    visible, blended, mean_alpha, seconds, and for a cameras layer
    photos_skipped, as bake_vertex_from_photos'). Progress stage: 'layers'.
    """
    mesh = _mesh(mesh, 0, "bake_vertex_from_layers")[0]
    return _texbake.bake_vertex_from_layers(mesh, layers, occluded, cache_mb, threads, progress)


def bake_atlas(*mesh_image_proxy, uv=_a("uv"), size=_a("size"), samples=_a("samples"),
               padding=_a("padding"), filter=_a("filter"), visibility=_a("visibility"),
               occluded=_a("occluded"), outside=_a("outside"), linear=_a("linear"),
               wrap=_a("wrap"), cache_mb=_a("cache_mb"), threads=0, progress=None):
    """bake_atlas(mesh, image, proxy, ...) or bake_atlas(vertices, faces, image, proxy, ...):
    a texture atlas (`texbake bake ... --target atlas`).

    uv 'auto' | 'mesh' | 'generate' | 'proxy'; size N (1..16384); samples
    per texel (1..256); padding None (8 at 2048, scaled), a count, or 'inf';
    filter 'bilinear' | 'ewa' (each supersample filtered by its footprint;
    'area' is the vertex bake's); the image (an array or a path, with
    cache_mb) and the other shading options as bake_vertex's (an atlas's
    defaults: DEFAULTS["atlas"]). Returns a texbake.Atlas: `image`
    (N, N, 4) float32, `mesh` (the mesh with the per-corner UVs baked
    against: its `uvs` and `corner_uvs`), `uvs`/`face_uvs` of that mesh,
    `stats`, `uv_layout`, `repeat_u`; it unpacks as
    image, uvs, face_uvs, stats. write_atlas() writes it.
    Progress stages: 'uv_layout', 'sample'.
    """
    mesh, image, proxy = _mesh(mesh_image_proxy, 2, "bake_atlas")
    return _texbake.bake_atlas(mesh, image, proxy, uv, size, samples, padding, filter,
                               visibility, occluded, outside, linear, wrap, cache_mb, threads,
                               progress)


def bake_atlas_from_photos(*mesh, cameras, images=None, masks=None, blend=_a("blend"),
                           exposure=_a("exposure"), occluded=_a("occluded"),
                           colorspace=_a("texture_colorspace"), uv=_a("uv"), size=_a("size"),
                           samples=_a("samples"), padding=_a("padding"),
                           strict_photos=_a("strict_photos"), threads=0, progress=None):
    """bake_atlas_from_photos(mesh, cameras=PATH, ...) or (vertices, faces, cameras=PATH, ...):
    a texture atlas from calibrated photographs (`texbake bake MESH --cameras
    PATH -o OUT.obj|.glb`).

    cameras, images, masks, blend, exposure, occluded, colorspace, strict_photos as
    bake_vertex_from_photos; uv 'auto' | 'mesh' | 'generate' (no proxy here),
    size, samples, padding as bake_atlas. Every atlas supersample is blended
    from the photos that see it; unseen samples as `occluded` says. Returns
    (atlas, cameras): a texbake.Atlas (write_atlas writes the CLI's bytes)
    and a list of dicts per photo (image, photo (w, h), in_view and visible
    counting atlas samples, weight_share, gain). atlas.stats has the
    report's counts and photos_skipped (the photos left out, as
    bake_vertex_from_photos' stats). Errors: ValueError (bad
    options, uv='proxy', uv='mesh' on a mesh without UVs), OSError (the
    model, a photo, the mesh). Progress stages: 'uv_layout', 'photos'.
    """
    mesh = _mesh(mesh, 0, "bake_atlas_from_photos")[0]
    return _texbake.bake_atlas_from_photos(mesh, cameras, images, masks, blend, exposure, occluded,
                                           colorspace, bool(strict_photos), uv, size, samples,
                                           padding, threads, progress)


def bake_vertex_from_camera(*mesh, camera, photo, occluded=_v("occluded"),
                            colorspace=_v("texture_colorspace"), threads=0, progress=None):
    """bake_vertex_from_camera(mesh, camera=PATH, photo=PATH, ...) or (vertices, faces, ...):
    one colour per vertex from one photo through one calibrated camera given
    as a proxy file (`texbake bake MESH --texture PHOTO --proxy-file CAMERA`,
    SPEC section 9: a JSON proxy of "kind": "camera").

    The photo is sampled through the camera's lens model, in linear light;
    a vertex is seen unless it faces away (90 degrees) or is hidden along the
    segment to the camera; no exposure balance (one photo). occluded 'fill' |
    (r, g, b[, a]); colorspace 'auto' | 'srgb' | 'linear' (the photo's).
    Returns (colors (n, 4) float32, stats dict, cameras: one dict, as
    bake_vertex_from_photos). Errors: ValueError (bad options, a proxy file
    that is not a camera), OSError (the files). Progress stage: 'photos'.
    """
    mesh = _mesh(mesh, 0, "bake_vertex_from_camera")[0]
    return _texbake.bake_vertex_from_camera(mesh, camera, photo, occluded, colorspace, threads,
                                            progress)


def bake_atlas_from_camera(*mesh, camera, photo, occluded=_a("occluded"),
                           colorspace=_a("texture_colorspace"), uv=_a("uv"), size=_a("size"),
                           samples=_a("samples"), padding=_a("padding"), threads=0,
                           progress=None):
    """bake_atlas_from_camera(mesh, camera=PATH, photo=PATH, ...) or (vertices, faces, ...):
    a texture atlas from one photo through a camera proxy file (`texbake bake
    MESH --texture PHOTO --proxy-file CAMERA -o OUT.obj|.glb`); the camera
    rules of bake_vertex_from_camera, the atlas options of
    bake_atlas_from_photos. Returns (atlas, cameras) as bake_atlas_from_photos.
    """
    mesh = _mesh(mesh, 0, "bake_atlas_from_camera")[0]
    return _texbake.bake_atlas_from_camera(mesh, camera, photo, occluded, colorspace, uv, size,
                                           samples, padding, threads, progress)


def bake_atlas_from_layers(*mesh, layers, occluded=_a("occluded"), uv=_a("uv"), size=None,
                           samples=_a("samples"), padding=_a("padding"),
                           cache_mb=_a("cache_mb"), threads=0, progress=None):
    """bake_atlas_from_layers(mesh, layers=PATH, ...) or (vertices, faces, layers=PATH, ...):
    a texture atlas composited from a layers file (`texbake bake MESH
    --layers PATH -o OUT.obj|.glb`, SPEC section 10).

    uv 'auto' | 'mesh' | 'generate'; size None: the base texture's size
    (base "mesh" on a textured mesh), else DEFAULTS["atlas"]["size"], as the
    CLI without --size; samples, padding as bake_atlas; occluded and
    cache_mb as bake_vertex_from_layers. The atlas has straight alpha =
    coverage (Atlas.blend when a covered texel is not opaque). Returns
    (atlas, layers): a texbake.Atlas and a list of dicts per layer (texture
    or cameras, in_domain, visible, blended counting atlas samples,
    mean_alpha, seconds; photos_skipped for a cameras layer). Errors: ValueError (bad options, uv='proxy', base
    "mesh" with another layout), OSError (the layers file, an image, the
    mesh). Progress stages: 'layers', 'uv_layout', 'sample'.
    """
    mesh = _mesh(mesh, 0, "bake_atlas_from_layers")[0]
    return _texbake.bake_atlas_from_layers(mesh, layers, occluded, uv, size, samples, padding,
                                           cache_mb, threads, progress)


class CameraChecks(list):
    """What check_cameras returns: a list, per camera of the model, of dicts
    (see check_cameras), with the model's figures as attributes:
    alignment (dict: verdict, points, measured, in_box, near, share_near,
    median_distance; None when the model has no sparse points),
    photo_agreement (dict: vertices, agreeing, median_deviation, gain_ratio,
    as a photo bake's stats; None when not measured), agreement_note (why
    it was not measured, or ''), warnings (list of str) and notes (list of
    str: what the camera file's reader did, as the CLI prints, e.g. a
    nerfstudio applied_transform undone)."""

    alignment = None
    photo_agreement = None
    agreement_note = ""
    warnings = ()
    notes = ()


def check_cameras(*mesh, cameras, images=None, masks=None, photos=True, threads=0):
    """check_cameras(mesh, cameras=PATH, images=None, masks=None, photos=True) or
    (vertices, faces, ...): `texbake cameras check`. Returns a CameraChecks:
    per photo a dict with image, in_front, inside, masked, visible (shares of
    the mesh's vertices in front of the camera, inside its photo, inside but
    masked out by its mask file, inside, unmasked and visible from it, in
    [0, 1]), has_mask (its mask file was found in masks) and warnings (poses
    that look like convention errors); with photos=True (the CLI's default;
    False is --no-photos) and two photos or more, also shared (vertices it
    sees with another photo), deviation (its mean relative deviation from
    their consensus) and gain (its exposure gain per channel), None for a
    photo left out. The geometric figures read no photo (only mask files
    mask); the agreement is a photo bake's, and is not measured (the
    result's agreement_note says why) when no photo can be read. cameras,
    images and masks as bake_vertex_from_photos. Errors: ValueError, OSError
    (the model, the masks folder or a mask file, the mesh)."""
    mesh = _mesh(mesh, 0, "check_cameras")[0]
    checks, alignment, agreement, note, warnings, notes = _texbake.check_cameras(
        mesh, cameras, images, masks, bool(photos), threads)
    out = CameraChecks(checks)
    out.alignment, out.photo_agreement = alignment, agreement
    out.agreement_note, out.warnings, out.notes = note, warnings, notes
    return out


def refine_cameras(*mesh, cameras, images=None, masks=None, intrinsics=False, max_rotation=2.0,
                   max_translation=0.05, iterations=200, colorspace="auto", strict_photos=False,
                   threads=0, progress=None):
    """refine_cameras(mesh, cameras=PATH, ...) or (vertices, faces, cameras=PATH, ...):
    `texbake cameras refine`: every photo's pose (with intrinsics=True also its
    focal length and principal point) refined so that the photos agree on the
    mesh (photometric, linear light, exposure gains solved jointly), each change
    bounded by max_rotation (degrees) and max_translation (a fraction of the
    mesh's bounding-box diagonal). cameras, images and masks as
    bake_vertex_from_photos (a masked-out pixel is never sampled).

    Returns (photos, stats): photos a list, in the model's order, of dicts with
    image, skipped (its photo cannot be read: unchanged), model, width, height,
    params (COLMAP's order), R (3 rows) and t (world-to-camera, OpenCV axes:
    what the CLI writes to images.txt), rotation_change_deg, translation_change,
    focal_change, residual_before, residual_after (RMS per channel, linear
    light), samples_before, samples_after, iterations, clamped, gain; stats a
    dict with counts, timings, warnings, points, levels, mesh_size and
    photos_skipped. Errors: ValueError (options, fewer than two photos),
    OSError (the model, the photos, the mesh). Progress stages: 'photos',
    'refine'.
    """
    mesh = _mesh(mesh, 0, "refine_cameras")[0]
    return _texbake.refine_cameras(mesh, cameras, images, masks, bool(intrinsics), max_rotation,
                                   max_translation, iterations, colorspace, bool(strict_photos),
                                   threads, progress)


def _atlas_face_uvs(atlas):
    m = atlas.mesh
    return m.corner_uvs.reshape(-1, 3) if m.faces is not None else m.corner_uvs


def _atlas_iter(atlas):
    return iter((atlas.image, atlas.mesh.uvs, _atlas_face_uvs(atlas), atlas.stats))


Atlas.uvs = property(lambda a: a.mesh.uvs, doc="The UV table (u, 2) of the atlas' mesh.")
Atlas.face_uvs = property(_atlas_face_uvs,
                          doc="Per face corner, indices into uvs ((m, 3) for triangles).")
Atlas.__iter__ = _atlas_iter


def render(*mesh, colors="auto", texture=None, proxy=None, atlas_image=None,
           outside=_v("outside"), wrap=_v("wrap"), linear=_v("linear"), size=_R["size"],
           view=_R["view"], views=_R["views"], shadows=_R["shadows"], samples=_R["samples"],
           up="z", flat=_R["flat"], background=None, threads=0, progress=None):
    """render(mesh, ...) or render(vertices, faces, ...): a Phong-shaded,
    ray-traced preview (`texbake render`). Colours: with texture and proxy,
    the direct projection at every hit (the ground truth); else colors
    'auto' (atlas_image through the mesh's UVs if given, else vertex
    colours, else grey), 'vertex', 'atlas', 'none'. size (w, h), view
    (azimuth, elevation) degrees (elevation in [-90, 90]), views (a contact
    sheet, 1..64), samples per pixel (1..1024), background (r, g, b) in
    [0, 1] (default DEFAULTS["render"]["background"]). Sizes up to 32768 per
    side. Returns (image (h, w, 4) float32, stats)."""
    (m,) = _mesh(mesh, 0, "render")
    return _texbake.render(m, colors, texture, proxy, atlas_image, outside, wrap, linear, size,
                           view, views, shadows, samples, _up(up), flat, background, threads,
                           progress)


def compare(a, b, mask_background=False, background=None):
    """PSNR and largest difference of two images (`texbake compare`): file
    paths or (h, w, c) arrays (both of one kind: ValueError otherwise);
    background (r, g, b) in [0, 1] for images without alpha. Returns a dict:
    width, height, channels, compared_pixels, rms, psnr (dB, inf when equal),
    max_difference, max_x, max_y, max_channel."""
    return _texbake.compare(a, b, mask_background, background)


# ---- Writing ---------------------------------------------------------------

def write_vertex_colors(path, mesh, colors, ascii=False, up="z"):
    """Write `mesh` with per-vertex `colors` (n, 3|4) by extension: .ply
    (binary, or ascii=True), .obj (v x y z r g b), .glb (COLOR_0, linear;
    its node matrix turns `up` to glTF's +Y, as `bake --up`). Atomic. The
    same bytes as `texbake bake -o path`. `mesh` may be (vertices, faces)."""
    if not isinstance(mesh, Mesh):
        mesh = Mesh(*mesh)
    _texbake.write_vertex_colors(path, mesh, colors, ascii, _up(up))


def write_atlas(path, atlas, format="png8", up="z"):
    """Write an Atlas: .obj (+ .mtl + the atlas image beside it; format
    'png8' | 'png16' | 'exr') or .glb (embedded PNG; `up` as in
    write_vertex_colors). The set is replaced all together or not at all.
    atlas_files(path, format) names the files."""
    _texbake.write_atlas(path, atlas, format, _up(up))


def atlas_files(path, format="png8"):
    """The files write_atlas(path, ...) writes, the mesh file first."""
    return _texbake.atlas_files(path, format)


def write_image(path, image, bits=8, compression=6):
    """Write an (h, w, c) image atomically, the format by extension: PNG
    8-bit (bits=8) or 16-bit (bits=16), EXR float (bits=32); values clamped
    to [0, 1] for integer formats; `compression` is PNG's zlib level 0..9."""
    _texbake.write_image(path, image, bits, compression)


def _job_value(key, value):
    """A keyword argument as its JSON value in a job object."""
    import os
    if isinstance(value, (str, bool, int, float)) or value is None:
        return value
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, _np.generic):
        return value.item()
    if isinstance(value, _np.ndarray):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [_job_value(key, v) for v in value]
    raise ValueError(f"{key}: {value!r} is not a value of a job option (a str, path, number, "
                     "bool or sequence of numbers)")


def _job_json(settings):
    """The JSON object of a job's keyword arguments (None: not given)."""
    return _json.dumps({k: _job_value(k, v) for k, v in settings.items() if v is not None})


def run_job(mesh, output, progress=None, **options):
    """Runs one whole job as `texbake bake MESH -o OUTPUT ...` and a batch line do:
    reads the files, fits what is not given, bakes, writes the outputs
    atomically (and the report when `report` is given) and returns what it
    did: a dict with "outputs" (the files written), "warnings", "notes"
    (what the command line prints as "texbake: ..." lines: the fit, a camera
    file reader's notes, the model's alignment), "fitted" (the
    proxy's flags filled by the fit), "report" (the report as a dict),
    "summary" (the command line's last line) and "seconds".

    `options` are the job options by their keys (texbake.JOB_OPTIONS; the
    command line's long flags with "_" for "-"), with the same defaults,
    ranges and messages: texture="earth.jpg", proxy="sphere",
    center=(0, 0, 0), samples=8, linear=True, cameras="sparse/0",
    layers="layers.json", target="atlas", report="r.json", threads=2, ...
    A flag is True or False, a vector a sequence of 3 numbers, corners 4 of
    them; None is "not given". The outputs equal the command line's bytes.

        texbake.run_job("bunny.ply", "bunny.glb", texture="earth.jpg",
                        proxy="sphere", up="y", target="atlas", size=1024)
    """
    result = _texbake.run_job(_job_json({"mesh": mesh, "output": output, **options}), progress)
    result["report"] = _json.loads(result["report"]) if result["report"] else None
    return result


def run_batch(jobs, results=None, fail_fast=False, skip_existing=False, threads=0):
    """Runs many jobs as `texbake batch` does: `jobs` is a sequence of dicts of
    run_job's keywords ("mesh" and "output" among them). Jobs run in order;
    a failing job is recorded and the others run (fail_fast: stop at the
    first failure); skip_existing skips a job whose outputs exist and are
    not older than its inputs; `threads` is the thread count of a job
    without "threads". `results`, when given, is a file that gets each job's
    line as soon as the job ends (as `texbake batch --results`).

    Returns a dict: "jobs" (per job: "line" (its index + 1), "status" ("ok",
    "failed", "skipped"), "exit", "error", "warnings", "outputs", "target",
    "counts", "timings", "seconds"), "ok", "failed", "skipped", "not_run",
    "seconds". A job's bad option is that job's error, never an exception;
    ValueError only for a bad argument of run_batch itself, OSError when
    `results` cannot be written.
    """
    texts = [_job_json(dict(job)) for job in jobs]
    batch = _texbake.run_batch(texts, results=None if results is None else str(results),
                               fail_fast=fail_fast, skip_existing=skip_existing,
                               threads=threads)
    batch["jobs"] = [_json.loads(line) for line in batch["jobs"]]
    return batch
