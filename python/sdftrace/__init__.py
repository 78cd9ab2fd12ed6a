"""sdftrace: signed distances of triangle meshes, and the sphere tracer that renders them.

The converter of ``mesh2sdf`` and the tracer of ``sdftrace``, on numpy arrays,
with no subprocess and no files between them. Every call releases the GIL
while the library works (on all cores), and errors raise ``ValueError`` (bad
arguments, malformed files), ``OSError`` (files that cannot be read or
written), ``MemoryError`` or ``RuntimeError`` with the library's message.
Queries, conversions and samples take a ``progress`` callable that can stop
them, and Ctrl-C stops them at their next progress step
(``KeyboardInterrupt``).

Meshes
    Every function that takes ``mesh`` takes any of: a file path (.obj .ply
    .off .stl .om, and the scenes .gltf .glb .fbx .dae .3mf, each flattened:
    every mesh of every node, moved by the node's transform), a pair ``(vertices, faces)`` of arrays (vertices (n, 3)
    float32 or float64, faces (m, 3) integers, any memory order), an object
    with ``.vertices`` and ``.faces`` (a trimesh mesh) or ``.vertices`` and
    ``.triangles`` (Open3D's ``TriangleMesh``), an Open3D tensor mesh
    (``.vertex.positions``, ``.triangle.indices``), or a :class:`Mesh`, which
    reads and orients the mesh once for many calls. A module-level function
    given a :class:`Mesh` uses it as it is; given anything else it reads and
    orients it anew on every call (nothing is cached behind your back): make
    a :class:`Mesh` once for many calls.

    Each mesh is oriented first, as ``mesh2sdf`` orients it (each
    edge-connected patch made consistent and turned outward), and signed by
    its winding number (inside where it exceeds 1/2), so open and
    inside-out meshes get the right sign too. Distances are exact to the
    triangles, negative inside.

Points
    Queries take points of shape (..., 3) and answer in shape (...): an
    (n, 3) array gives (n,), a (h, w, 3) grid of points (h, w), a single
    point (3,) a scalar, and (0, 3) an empty array. Rows of four, such as
    ``mesh2sdf --samples`` rows (x, y, z, sdf), are refused: pass
    ``rows[:, :3]``. Points may be float32, float64 (or integers), in any
    memory order, and anything numpy can view: a PyTorch tensor on the CPU
    is read in place through DLPack (or ``__array__``), with no copy. The
    answers are float32 for float32 points and float64 otherwise, or
    ``dtype=``: either way the library's values, computed in double from the
    mesh's vertices (held as float32) and rounded to float32 (a relative
    6e-8), float64 ones widened from those. Every call
    takes ``threads=``: at most that many threads, the caller's included
    (0: the mesh's ``threads``, whose 0 is all cores).

Training data (DeepSDF's sampling)::

    import sdftrace
    mesh = sdftrace.Mesh("bunny.obj", normalize=True)    # into the unit sphere
    points, sdf = mesh.sample_near_surface(250_000, seed=0)
    assert abs(mesh.signed_distance(points[:10]) - sdf[:10]).max() < 1e-6
    inside = mesh.winding_number(points, threads=2) > 0.5

Grids::

    grid = sdftrace.mesh_to_grid("bunny.obj", res=256, band=3)
    volume = grid.to_numpy()            # (nx, ny, nz) float32, z fastest
    grid.save("bunny.vdb")              # .vdb, .nvdb or .npy (+ .json), as mesh2sdf writes them
    values = grid.sample(points)        # trilinear, the tracer's sampler
    image = sdftrace.render(grid, width=640, height=480)
    image["depth"], image["normal"], image["steps"]
"""

from __future__ import annotations

import inspect as _inspect
import operator as _operator
import os as _os
import typing as _t

import numpy as _np

from . import _sdftrace

__all__ = [
    "Canceled",
    "Mesh",
    "Grid",
    "sample_near_surface",
    "signed_distance",
    "winding_number",
    "mesh_to_grid",
    "render",
    "scenes",
    "settings",
    "MeshLike",
    "Progress",
    "DEEPSDF_NEAR_SIGMA",
    "DEEPSDF_UNIFORM_SHARE",
]

__version__ = "%d.%d.%d" % (_sdftrace.version // 10000, _sdftrace.version // 100 % 100, _sdftrace.version % 100)


def __dir__() -> _t.List[str]:
    """The API: what ``__all__`` names, and the version."""
    return sorted(__all__ + ["__version__"])


#: What a ``mesh`` argument takes: a path, a (vertices, faces) pair, a mesh object of trimesh
#: or Open3D (legacy or tensor), or a :class:`Mesh`.
MeshLike = _t.Union["Mesh", str, _os.PathLike, _t.Tuple[_t.Any, _t.Any], _t.Any]

#: Raised when a ``progress`` callable returns true: the call stopped.
Canceled = _sdftrace.Canceled

#: A long call's ``progress``: called with the fraction done (0 to 1, rising) about once a
#: percent, from the library's worker threads, with the GIL held; return a true value to stop
#: the call (it raises :class:`Canceled`); an exception it raises stops the call and propagates.
Progress = _t.Optional[_t.Callable[[float], _t.Optional[bool]]]

# The settings of the library's params structs (sdftrace/mesh.h): their
# names, defaults, ranges and meanings are the library's, read here once, so
# that every keyword below, its default and its line in the docstrings come
# from the one table in C; a setting added there is a keyword here.
_SETTINGS = {of: _sdftrace.settings(i) for i, of in enumerate(("mesh", "grid", "samples"))}


def _default(row: _t.Dict[str, _t.Any]) -> _t.Any:
    """A setting's default as Python passes it."""
    value = row["default"]
    if row["kind"] == "choice":
        return row["choices"].split()[int(value[0])]
    if row["kind"] == "flag":
        return bool(value[0])
    if row["kind"] in ("int", "count"):
        return int(value[0])
    if row["kind"] == "text":
        return None
    return float(value[0]) if row["count"] == 1 else tuple(value)


def _range(row: _t.Dict[str, _t.Any]) -> str:
    """'[1, 4096]', '(0, 1]', '> 0' or '' (a choice names its values in its text)."""
    if row["kind"] not in ("int", "count", "real"):
        return ""
    lo, hi = ("%g" % row["lo"]), ("%g" % row["hi"])
    if row["hi"] == float("inf"):
        return ("> " if row["open_lo"] else ">= ") + lo
    return "%s%s, %s%s" % ("(" if row["open_lo"] else "[", lo, hi, ")" if row["open_hi"] else "]")


def _setting_lines(rows: _t.List[_t.Dict[str, _t.Any]]) -> str:
    """One docstring paragraph a setting: name, default, range and meaning."""
    lines = []
    for row in rows:
        default = row["automatic"] if row["automatic"] else repr(_default(row))
        extent = _range(row)
        lines.append("    ``%s`` (default %s%s): %s." % (row["name"], default, "; " + extent if extent else "", row["doc"]))
    return "\n".join(lines)


def _takes_settings(of: str, before: _t.Sequence[str] = (), after: _t.Sequence[_t.Tuple[str, _t.Any]] = (), skip=()):
    """Gives the function the settings of `of` as keywords (in the table's
    order, so also positionally after `before`), then `after`: its signature
    and docstring are made from the table, and it is called with the given
    settings in a dict, `settings` (only those given: the rest keep the
    library's defaults)."""
    rows = [r for r in _SETTINGS[of] if r["name"] not in skip]
    kind = _inspect.Parameter.POSITIONAL_OR_KEYWORD
    params = [_inspect.Parameter(name, kind) for name in before]
    params += [_inspect.Parameter(r["name"], kind, default=_default(r)) for r in rows]
    params += [_inspect.Parameter(name, kind, default=value) for name, value in after]
    signature = _inspect.Signature(params)
    names = {r["name"] for r in rows}

    def wrap(fn):
        def call(*args, **kwargs):
            given = signature.bind(*args, **kwargs).arguments
            settings = {k: v for k, v in given.items() if k in names}
            rest = {k: v for k, v in given.items() if k not in names}
            return fn(settings=settings, **rest)

        call.__name__, call.__qualname__, call.__module__ = fn.__name__, fn.__qualname__, fn.__module__
        call.__signature__ = signature
        call.__doc__ = (fn.__doc__ or "") + "\n\n    Settings (the library's, sdftrace/mesh.h):\n\n" + _setting_lines(rows)
        return call

    return wrap


def settings(of: str) -> _t.List[_t.Dict[str, _t.Any]]:
    """The settings of ``of`` ('mesh', 'grid' or 'samples'), as the library
    lists them: a dict each of name, kind, default, range (lo, hi, open_lo,
    open_hi), choices, value and doc."""
    return [dict(r) for r in _SETTINGS[of]]


#: DeepSDF's two standard deviations, in units of the mesh sphere's radius (the library's default).
DEEPSDF_NEAR_SIGMA = _default(next(r for r in _SETTINGS["samples"] if r["name"] == "near_sigma"))
#: DeepSDF's share of uniform points (the library's default).
DEEPSDF_UNIFORM_SHARE = _default(next(r for r in _SETTINGS["samples"] if r["name"] == "uniform_share"))


# ---- arrays in: what ML code has ------------------------------------------

# DLPack's device type of the CPU's memory (dlpack.h: kDLCPU).
_DLPACK_CPU = 1


def _as_array(obj: _t.Any, what: str) -> _np.ndarray:
    """obj as a numpy array, sharing its memory where it can: an ndarray as it is; an object
    with ``__dlpack__`` (a PyTorch, JAX or CuPy array, ...) viewed in place when its memory is
    the CPU's, refused with a clear message when it is not; one with ``.numpy()`` (an Open3D
    tensor) through it; anything else as numpy takes it (``__array__``, the buffer protocol,
    nested sequences)."""
    if isinstance(obj, _np.ndarray):
        return obj
    if hasattr(obj, "__dlpack__") and hasattr(obj, "__dlpack_device__"):
        device = tuple(int(x) for x in obj.__dlpack_device__())
        if device[0] != _DLPACK_CPU:
            raise ValueError(
                "%s are not in the CPU's memory (DLPack device %s): move them there first, as "
                "with tensor.cpu()" % (what, device)
            )
        try:
            return _np.from_dlpack(obj)
        except BufferError:  # a type numpy has no dtype for, such as bfloat16
            pass
    elif not hasattr(obj, "__array__") and callable(getattr(obj, "numpy", None)):
        return _np.asarray(obj.numpy())
    return _np.asarray(obj)


def _result_type(points: _np.ndarray, dtype: _t.Any) -> _np.dtype:
    """The answers' dtype: ``dtype`` when given (float32 or float64), else float32 for float32
    points and float64 for any other (as numpy's own functions answer)."""
    if dtype is None:
        return _np.dtype(_np.float32 if points.dtype == _np.float32 else _np.float64)
    out = _np.dtype(dtype)
    if out not in (_np.dtype(_np.float32), _np.dtype(_np.float64)):
        raise ValueError("dtype must be float32 or float64, not %s" % out)
    return out


def _points(points: _t.Any) -> _t.Tuple[_np.ndarray, _t.Tuple[int, ...]]:
    """Points of shape (..., 3) as (n, 3), a view where their strides allow it, and the
    shape (...) of the answers."""
    a = _as_array(points, "points")
    if a.dtype.kind not in "fiu":
        raise TypeError("points must be real numbers, not %s" % a.dtype)
    if a.ndim == 0 or a.shape[-1] != 3:
        hint = ""
        if a.ndim >= 1 and a.shape[-1] == 4:
            hint = ": rows of four (x, y, z, sdf) are samples, pass rows[..., :3]"
        raise ValueError("points must have shape (..., 3), not %s%s" % (a.shape, hint))
    return a.reshape(-1, 3), a.shape[:-1]


def _answer(values: _np.ndarray, shape: _t.Tuple[int, ...], dtype: _np.dtype):
    """The library's float32 answers (n,) in `dtype` and `shape`: a numpy scalar for one point
    given as (3,), as numpy's own functions answer."""
    values = values.astype(dtype, copy=False).reshape(shape)
    return values[()] if shape == () else values


def _mesh_arrays(source: _t.Any) -> _t.Tuple[_t.Any, _t.Any]:
    """The (vertices, faces) of a mesh object or pair, or a TypeError."""
    if isinstance(source, (tuple, list)) and len(source) == 2:
        return source[0], source[1]
    vertices = getattr(source, "vertices", None)
    if vertices is not None:
        # trimesh's .faces before .triangles, which trimesh has too (the corners' coordinates)
        faces = getattr(source, "faces", None)
        if faces is None:
            faces = getattr(source, "triangles", None)  # Open3D's legacy TriangleMesh
        if faces is not None:
            return vertices, faces
    vertex, triangle = getattr(source, "vertex", None), getattr(source, "triangle", None)
    if vertex is not None and triangle is not None:  # Open3D's tensor TriangleMesh
        try:
            return vertex.positions, triangle.indices
        except (AttributeError, KeyError):
            pass
    raise TypeError(
        "a mesh is a path, a (vertices, faces) pair, an object with .vertices and .faces or "
        ".triangles (trimesh, Open3D), an Open3D tensor mesh or an sdftrace.Mesh; not %s" % type(source).__name__
    )


def _check_ranges(of: str, settings: _t.Dict[str, _t.Any]) -> None:
    """The library's ranges on the numbers among `settings`, for a call that does no work
    (n=0) and so does not reach the library's own check."""
    for row in _SETTINGS[of]:
        if row["name"] not in settings or row["kind"] not in ("int", "count", "real"):
            continue
        for x in _np.atleast_1d(_np.asarray(settings[row["name"]], dtype=float)):
            low = x > row["lo"] if row["open_lo"] else x >= row["lo"]
            high = x < row["hi"] if row["open_hi"] else x <= row["hi"]
            if not (low and high):
                extent = _range(row)
                extent = "in " + extent if extent[0] in "[(" else extent
                raise ValueError("%s must be %s, not %g" % (row["name"], extent, x))


def _samples(rows_of: _t.Callable[[], _np.ndarray], n: int, dtype: _t.Any, settings: _t.Dict[str, _t.Any]):
    """Points (n, 3) and distances (n,), contiguous arrays of their own, in `dtype`, from the
    library's rows (n, 4); n=0 gives empty ones."""
    n = _operator.index(n)
    if n < 0:
        raise ValueError("n must be 0 or more, not %d" % n)
    out = _np.dtype(dtype)
    if out not in (_np.dtype(_np.float32), _np.dtype(_np.float64)):
        raise ValueError("dtype must be float32 or float64, not %s" % out)
    if n == 0:
        _check_ranges("samples", settings)
        return _np.empty((0, 3), out), _np.empty((0,), out)
    rows = rows_of()
    return _np.array(rows[:, :3], dtype=out, order="C"), _np.array(rows[:, 3], dtype=out, order="C")


# The keywords of the samples' calls after the library's settings.
_SAMPLES_AFTER = (("progress", None), ("dtype", _np.float32))


class Mesh:
    """A triangle mesh, read (or copied from arrays) and oriented once.

    ``Mesh(source, orient=..., normalize=..., ...)``: ``source`` is any :data:`MeshLike` (a
    path, a ``(vertices, faces)`` pair, a trimesh or Open3D mesh); the keywords are the
    library's settings below (``orient`` also takes True and False). ``Mesh(mesh)`` of a
    :class:`Mesh` is the same mesh, and takes no settings. Safe to share between threads.
    """

    @_takes_settings("mesh", before=("self", "source"))
    def __init__(self, source: MeshLike, settings: _t.Dict[str, _t.Any]):
        if isinstance(source, Mesh):
            if settings:
                raise ValueError(
                    "an sdftrace.Mesh is read and oriented already: its settings (%s) cannot change; "
                    "make a Mesh of the source again" % ", ".join(sorted(settings))
                )
            self._mesh = source._mesh
            return
        if isinstance(source, (str, bytes, _os.PathLike)):
            self._mesh = _sdftrace.load_mesh(source, **settings)
            return
        vertices, faces = _mesh_arrays(source)
        self._mesh = _sdftrace.mesh_from_arrays(_as_array(vertices, "vertices"), _as_array(faces, "faces"), **settings)

    def info(self) -> _t.Dict[str, _t.Any]:
        """Health and orientation counts: vertices, faces, triangles, degenerate_faces,
        welded_vertices, boundary_edges, non_manifold_edges, closed, oriented, patches,
        reoriented_faces, outward_patches, cavity_patches, ambiguous_patches, ...,
        skipped_faces (faces of the file its reader could not take) and warnings (what
        reading and orienting took with a doubt, a line each); the box (lo, hi) in the
        mesh's frame and the sphere (centre, radius) in the input's units."""
        return self._mesh.info()

    def signed_distance(
        self,
        points: _t.Any,
        return_winding: bool = False,
        *,
        threads: int = 0,
        dtype: _t.Any = None,
        progress: Progress = None,
    ):
        """The signed distance at each point of ``points`` (..., 3): shape (...), exact to the
        triangles, negative inside; float32 for float32 points, else float64 (or ``dtype``).
        With ``return_winding``, a pair (distance, winding number). ``threads``: at most this
        many (0: the mesh's). ``progress``: see :data:`Progress`."""
        flat, shape = _points(points)
        out = _result_type(flat, dtype)
        if return_winding:
            d, w = self._mesh.signed_distance(flat, True, threads, progress)
            return _answer(d, shape, out), _answer(w, shape, out)
        return _answer(self._mesh.signed_distance(flat, False, threads, progress), shape, out)

    def winding_number(self, points: _t.Any, *, threads: int = 0, dtype: _t.Any = None, progress: Progress = None):
        """The generalized winding number at each point of ``points`` (..., 3): shape (...); 1
        inside a closed mesh, 0 outside, fractional near holes; dtype, ``threads`` and
        ``progress`` as :meth:`signed_distance`'s."""
        flat, shape = _points(points)
        return _answer(self._mesh.winding_number(flat, threads, progress), shape, _result_type(flat, dtype))

    @_takes_settings("samples", before=("self", "n"), after=_SAMPLES_AFTER, skip=("count",))
    def sample_near_surface(
        self, n: int, settings: _t.Dict[str, _t.Any], progress: Progress = None, dtype: _t.Any = _np.float32
    ) -> _t.Tuple[_np.ndarray, _np.ndarray]:
        """``n`` training samples as DeepSDF draws them: a share ``uniform_share`` uniform in
        the cube around the mesh's sphere, the rest on the surface (area-weighted random
        triangles) moved by a Gaussian of either sigma of ``near_sigma`` (in units of the
        sphere's radius), half each. Returns (points (n, 3), sdf (n,)), two C-contiguous
        arrays of ``dtype`` (float32 or float64; the values are the library's float32), the
        rows ``mesh2sdf --samples`` writes for the same settings; n=0 gives empty arrays. The
        same seed gives the same samples on any number of cores. ``progress``: see
        :data:`Progress`."""
        return _samples(lambda: self._mesh.samples(n, progress, **settings), n, dtype, settings)

    @_takes_settings("grid", before=("self",), after=(("progress", None),))
    def to_grid(self, settings: _t.Dict[str, _t.Any], progress: Progress = None) -> "Grid":
        """The signed distance grid ``mesh2sdf`` makes with the same options; ``progress``: see
        :data:`Progress`."""
        return Grid(self._mesh.to_grid(progress, **settings))


def _mesh(mesh: MeshLike, threads: int = 0) -> Mesh:
    """A :class:`Mesh` as it is; anything else read and oriented now, with `threads`."""
    return mesh if isinstance(mesh, Mesh) else Mesh(mesh, threads=threads)


class Grid:
    """A signed distance grid: converted from a mesh (:func:`mesh_to_grid`) or loaded
    (:meth:`Grid.load`). The tracer renders it (:func:`render`)."""

    def __init__(self, source: _t.Any):
        if isinstance(source, _sdftrace.MeshGrid):
            self._converted, self._nano_grid = source, None
        elif isinstance(source, _sdftrace.NanoGrid):
            self._converted, self._nano_grid = None, source
        else:
            raise TypeError("make a Grid with mesh_to_grid or Grid.load")

    @property
    def _nano(self):
        """The tracer's NanoVDB copy, made on first use (sampling, rendering)."""
        if self._nano_grid is None:
            self._nano_grid = self._converted.nano()
        return self._nano_grid

    @staticmethod
    def load(path: _t.Union[str, _os.PathLike], name: _t.Optional[str] = None) -> "Grid":
        """A grid from a ``.vdb`` or ``.nvdb`` file: the grid called ``name``, or the first
        scalar level set."""
        return Grid(_sdftrace.open_grid(path, name))

    def info(self) -> _t.Dict[str, _t.Any]:
        """name, type, class, voxel_size, background, active_voxels and the world box of the
        active voxels (lo, hi); for a converted grid also its box (dims, origin)."""
        info = self._nano.info()
        if self._converted is not None:
            info.update(self._converted.box())
        return info

    def to_numpy(self) -> _np.ndarray:
        """The grid densely, float32 (nx, ny, nz), z fastest: for a converted grid the whole
        padded box (voxel (i, j, k) centred at origin + (i, j, k) * voxel_size; the array of
        ``mesh2sdf --npy``), for a loaded one the box of its active voxels."""
        if self._converted is not None:
            return self._converted.dense()
        return self._nano.dense()[0]

    def save(self, path: _t.Union[str, _os.PathLike], fp16: bool = False) -> None:
        """Writes ``.vdb``, ``.nvdb`` (``fp16``: half-float leaves) or ``.npy`` (with its
        sidecar ``.json``), the bytes ``mesh2sdf`` writes, whole or not at all. For grids
        from :func:`mesh_to_grid`."""
        if self._converted is None:
            raise ValueError("a loaded grid is saved by the file it came from; save converts grids")
        self._converted.write(_os.fspath(path), fp16)

    def sample(self, points: _t.Any, *, threads: int = 0, dtype: _t.Any = None):
        """Trilinear values at world points (..., 3), shape (...): the tracer's sampler; the
        background beyond the band. float32 for float32 points, else float64 (or ``dtype``);
        on at most ``threads`` threads (0: all cores)."""
        flat, shape = _points(points)
        return _answer(self._nano.sample(flat, threads), shape, _result_type(flat, dtype))


def signed_distance(
    mesh: MeshLike,
    points: _t.Any,
    return_winding: bool = False,
    *,
    threads: int = 0,
    dtype: _t.Any = None,
    progress: Progress = None,
):
    """The signed distance from ``mesh`` at each point of ``points`` (..., 3): shape (...),
    negative inside. See :meth:`Mesh.signed_distance`; a ``mesh`` that is not a :class:`Mesh`
    is read and oriented for this call alone (on ``threads`` threads too)."""
    return _mesh(mesh, threads).signed_distance(points, return_winding, threads=threads, dtype=dtype, progress=progress)


def winding_number(
    mesh: MeshLike, points: _t.Any, *, threads: int = 0, dtype: _t.Any = None, progress: Progress = None
):
    """The generalized winding number of ``mesh`` at each point of ``points`` (..., 3): shape
    (...). See :meth:`Mesh.winding_number` and :func:`signed_distance`."""
    return _mesh(mesh, threads).winding_number(points, threads=threads, dtype=dtype, progress=progress)


@_takes_settings("samples", before=("mesh", "n"), after=_SAMPLES_AFTER, skip=("count",))
def sample_near_surface(
    mesh: MeshLike, n: int, settings: _t.Dict[str, _t.Any], progress: Progress = None, dtype: _t.Any = _np.float32
):
    """``n`` training samples of ``mesh`` as DeepSDF draws them: (points (n, 3), sdf (n,)).
    See :meth:`Mesh.sample_near_surface`; for unit-sphere samples, pass
    ``Mesh(path, normalize=True)``."""
    return _mesh(mesh, settings.get("threads", 0)).sample_near_surface(n, progress=progress, dtype=dtype, **settings)


@_takes_settings("grid", before=("mesh",), after=(("progress", None),))
def mesh_to_grid(mesh: MeshLike, settings: _t.Dict[str, _t.Any], progress: Progress = None) -> "Grid":
    """The signed distance grid of ``mesh``, as ``mesh2sdf`` converts it (see :meth:`Mesh.to_grid`)."""
    return _mesh(mesh, settings.get("threads", 0)).to_grid(progress=progress, **settings)


def render(
    source: _t.Union[Grid, str],
    width: int = 640,
    height: int = 480,
    camera: _t.Optional[_t.Dict[str, _t.Any]] = None,
    method: str = "auto",
    light: _t.Optional[_t.Sequence[float]] = None,
    shadows: bool = True,
    threads: int = 0,
) -> _t.Dict[str, _np.ndarray]:
    """Sphere-traces a grid or a procedural scene (by name, :func:`scenes`) into image
    planes, row-major, y down, filled in place by the tracer: depth (h, w) float32 (inf
    where nothing is hit), normal (h, w, 3), rgb (h, w, 3) linear, steps, primary_steps and
    fallbacks (h, w) uint32 (evaluations per pixel, all rays and the primary ray's), status
    (h, w) uint8 (sdftrace/trace.h's sdft_status). ``camera``: a dict of eye, target, up (3 floats each) and fov (degrees);
    by default the scene's camera, or for a grid one in front of it. ``method``: sphere,
    relaxed (Keinert et al.'s Listing 2), relaxed-bv (Bán–Valasek's Algorithm 2), enhanced or auto."""
    camera = camera or {}
    target = source._nano if isinstance(source, Grid) else source

    def vec(name):
        value = camera.get(name)
        return None if value is None else tuple(float(x) for x in value)

    return _sdftrace.render(
        target,
        width,
        height,
        vec("eye"),
        vec("target"),
        vec("up"),
        float(camera.get("fov", 0.0)),
        tuple(light) if light is not None else None,
        method,
        shadows,
        threads,
    )


def scenes() -> list:
    """The names of the procedural scenes :func:`render` takes."""
    return _sdftrace.scenes()
