"""sdftrace: signed distances of triangle meshes, and the sphere tracer that renders them.

The converter of ``mesh2sdf`` and the tracer of ``sdftrace``, on numpy arrays,
with no subprocess and no files between them. Every call releases the GIL
while the library works (on all cores), and errors raise ``ValueError`` (bad
arguments, malformed files), ``OSError`` (files that cannot be read or
written), ``MemoryError`` or ``RuntimeError`` with the library's message.
Conversions and samples take a ``progress`` callable that can stop them, and
Ctrl-C stops them, and queries of many points, at their next progress step
(``KeyboardInterrupt``).

Meshes
    Every function that takes ``mesh`` takes any of: a file path (.obj .ply
    .off .stl .om, and the scenes .gltf .glb .fbx .dae .3mf, each flattened:
    every mesh of every node, moved by the node's transform), a pair ``(vertices, faces)`` of arrays (vertices (n, 3)
    float32 or float64, faces (m, 3) integers, any memory order), an object
    with ``.vertices`` and ``.faces`` (a trimesh mesh, say), or a
    :class:`Mesh`, which reads and orients the mesh once for many calls.

    Each mesh is oriented first, as ``mesh2sdf`` orients it (each
    edge-connected patch made consistent and turned outward), and signed by
    its winding number (inside where it exceeds 1/2), so open and
    inside-out meshes get the right sign too. Distances are exact to the
    triangles, float32, negative inside.

Training data (DeepSDF's sampling)::

    import sdftrace
    mesh = sdftrace.Mesh("bunny.obj", normalize=True)    # into the unit sphere
    points, sdf = mesh.sample_near_surface(250_000, seed=0)
    query = points[:10]
    assert abs(mesh.signed_distance(query) - sdf[:10]).max() < 1e-6

Grids::

    grid = sdftrace.mesh_to_grid("bunny.obj", res=256, band=3)
    volume = grid.to_numpy()            # (nx, ny, nz) float32, z fastest
    grid.save("bunny.vdb")              # .vdb, .nvdb or .npy (+ .json), as mesh2sdf writes them
    values = grid.sample(points)        # trilinear, the tracer's sampler
    image = sdftrace.render(grid, width=640, height=480)
    image["depth"], image["normal"], image["steps"]
"""

from __future__ import annotations

import inspect
import os
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

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
]

__version__ = "%d.%d.%d" % (_sdftrace.version // 10000, _sdftrace.version // 100 % 100, _sdftrace.version % 100)

MeshLike = Union["Mesh", str, os.PathLike, Tuple[Any, Any], Any]

#: Raised when a ``progress`` callable returns true: the call stopped.
Canceled = _sdftrace.Canceled

#: A long call's ``progress``: called with the fraction done (0 to 1, rising) about once a
#: percent, from the library's worker threads, with the GIL held; return a true value to stop
#: the call (it raises :class:`Canceled`); an exception it raises stops the call and propagates.
Progress = Optional[Callable[[float], Optional[bool]]]

# The settings of the library's params structs (sdftrace/mesh.h): their
# names, defaults, ranges and meanings are the library's, read here once, so
# that every keyword below, its default and its line in the docstrings come
# from the one table in C; a setting added there is a keyword here.
_SETTINGS = {of: _sdftrace.settings(i) for i, of in enumerate(("mesh", "grid", "samples"))}


def _default(row: Dict[str, Any]) -> Any:
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


def _range(row: Dict[str, Any]) -> str:
    """'[1, 4096]', '(0, 1]', '> 0' or '' (a choice names its values in its text)."""
    if row["kind"] not in ("int", "count", "real"):
        return ""
    lo, hi = ("%g" % row["lo"]), ("%g" % row["hi"])
    if row["hi"] == float("inf"):
        return ("> " if row["open_lo"] else ">= ") + lo
    return "%s%s, %s%s" % ("(" if row["open_lo"] else "[", lo, hi, ")" if row["open_hi"] else "]")


def _setting_lines(rows: List[Dict[str, Any]]) -> str:
    """One docstring paragraph a setting: name, default, range and meaning."""
    lines = []
    for row in rows:
        default = row["automatic"] if row["automatic"] else repr(_default(row))
        extent = _range(row)
        lines.append("    ``%s`` (default %s%s): %s." % (row["name"], default, "; " + extent if extent else "", row["doc"]))
    return "\n".join(lines)


def _takes_settings(of: str, before: Sequence[str] = (), after: Sequence[Tuple[str, Any]] = (), skip=()):
    """Gives the function the settings of `of` as keywords (in the table's
    order, so also positionally after `before`), then `after`: its signature
    and docstring are made from the table, and it is called with the given
    settings in a dict, `settings` (only those given: the rest keep the
    library's defaults)."""
    rows = [r for r in _SETTINGS[of] if r["name"] not in skip]
    kind = inspect.Parameter.POSITIONAL_OR_KEYWORD
    params = [inspect.Parameter(name, kind) for name in before]
    params += [inspect.Parameter(r["name"], kind, default=_default(r)) for r in rows]
    params += [inspect.Parameter(name, kind, default=value) for name, value in after]
    signature = inspect.Signature(params)
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


def settings(of: str) -> List[Dict[str, Any]]:
    """The settings of ``of`` ('mesh', 'grid' or 'samples'), as the library
    lists them: a dict each of name, kind, default, range (lo, hi, open_lo,
    open_hi), choices, value and doc."""
    return [dict(r) for r in _SETTINGS[of]]


#: DeepSDF's two standard deviations, in units of the mesh sphere's radius (the library's default).
DEEPSDF_NEAR_SIGMA = _default(next(r for r in _SETTINGS["samples"] if r["name"] == "near_sigma"))
#: DeepSDF's share of uniform points (the library's default).
DEEPSDF_UNIFORM_SHARE = _default(next(r for r in _SETTINGS["samples"] if r["name"] == "uniform_share"))


class Mesh:
    """A triangle mesh, read (or copied from arrays) and oriented once.

    ``Mesh(source, orient=..., normalize=..., ...)``: ``source`` is a path, a
    ``(vertices, faces)`` pair or an object with ``.vertices`` and ``.faces``;
    the keywords are the library's settings below (``orient`` also takes
    True and False). Safe to share between threads.
    """

    @_takes_settings("mesh", before=("self", "source"))
    def __init__(self, source: MeshLike, settings: Dict[str, Any]):
        if isinstance(source, Mesh):
            self._mesh = source._mesh
            return
        if isinstance(source, (str, bytes, os.PathLike)):
            self._mesh = _sdftrace.load_mesh(source, **settings)
            return
        if hasattr(source, "vertices") and hasattr(source, "faces"):
            vertices, faces = source.vertices, source.faces
        elif isinstance(source, (tuple, list)) and len(source) == 2:
            vertices, faces = source
        else:
            raise TypeError("a mesh is a path, a (vertices, faces) pair or an object with .vertices and .faces")
        self._mesh = _sdftrace.mesh_from_arrays(vertices, faces, **settings)

    def info(self) -> Dict[str, Any]:
        """Health and orientation counts: vertices, faces, triangles, degenerate_faces,
        welded_vertices, boundary_edges, non_manifold_edges, closed, oriented, patches,
        reoriented_faces, outward_patches, cavity_patches, ambiguous_patches, ...,
        skipped_faces (faces of the file its reader could not take) and warnings (what
        reading and orienting took with a doubt, a line each); the box (lo, hi) in the
        mesh's frame and the sphere (centre, radius) in the input's units."""
        return self._mesh.info()

    def signed_distance(self, points: Any, return_winding: bool = False):
        """The signed distance at each point of an (n, 3) array (float32 or float64, any
        order): float32 (n,), exact to the triangles, negative inside. With
        ``return_winding``, a pair (distance, winding number)."""
        return self._mesh.signed_distance(points, return_winding)

    def winding_number(self, points: Any) -> np.ndarray:
        """The generalized winding number at each point: float32 (n,); 1 inside a closed
        mesh, 0 outside, fractional near holes."""
        return self._mesh.winding_number(points)

    @_takes_settings("samples", before=("self", "n"), after=(("progress", None),), skip=("count",))
    def sample_near_surface(self, n: int, settings: Dict[str, Any], progress: Progress = None) -> Tuple[np.ndarray, np.ndarray]:
        """``n`` training samples as DeepSDF draws them: a share ``uniform_share`` uniform in
        the cube around the mesh's sphere, the rest on the surface (area-weighted random
        triangles) moved by a Gaussian of either sigma of ``near_sigma`` (in units of the
        sphere's radius), half each. Returns (points (n, 3), sdf (n,)), float32 views of one
        (n, 4) array, the rows ``mesh2sdf --samples`` writes for the same settings. The same
        seed gives the same samples on any number of cores. ``progress``: see :data:`Progress`."""
        rows = self._mesh.samples(n, progress, **settings)
        return rows[:, :3], rows[:, 3]

    @_takes_settings("grid", before=("self",), after=(("progress", None),))
    def to_grid(self, settings: Dict[str, Any], progress: Progress = None) -> "Grid":
        """The signed distance grid ``mesh2sdf`` makes with the same options; ``progress``: see
        :data:`Progress`."""
        return Grid(self._mesh.to_grid(progress, **settings))


def _mesh(mesh: MeshLike) -> Mesh:
    return mesh if isinstance(mesh, Mesh) else Mesh(mesh)


class Grid:
    """A signed distance grid: converted from a mesh (:func:`mesh_to_grid`) or loaded
    (:meth:`Grid.load`). The tracer renders it (:func:`render`)."""

    def __init__(self, source: Any):
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
    def load(path: Union[str, os.PathLike], name: Optional[str] = None) -> "Grid":
        """A grid from a ``.vdb`` or ``.nvdb`` file: the grid called ``name``, or the first
        scalar level set."""
        return Grid(_sdftrace.open_grid(path, name))

    def info(self) -> Dict[str, Any]:
        """name, type, class, voxel_size, background, active_voxels and the world box of the
        active voxels (lo, hi); for a converted grid also its box (dims, origin)."""
        info = self._nano.info()
        if self._converted is not None:
            info.update(self._converted.box())
        return info

    def to_numpy(self) -> np.ndarray:
        """The grid densely, float32 (nx, ny, nz), z fastest: for a converted grid the whole
        padded box (voxel (i, j, k) centred at origin + (i, j, k) * voxel_size; the array of
        ``mesh2sdf --npy``), for a loaded one the box of its active voxels."""
        if self._converted is not None:
            return self._converted.dense()
        return self._nano.dense()[0]

    def save(self, path: Union[str, os.PathLike], fp16: bool = False) -> None:
        """Writes ``.vdb``, ``.nvdb`` (``fp16``: half-float leaves) or ``.npy`` (with its
        sidecar ``.json``), the bytes ``mesh2sdf`` writes, whole or not at all. For grids
        from :func:`mesh_to_grid`."""
        if self._converted is None:
            raise ValueError("a loaded grid is saved by the file it came from; save converts grids")
        self._converted.write(os.fspath(path), fp16)

    def sample(self, points: Any) -> np.ndarray:
        """Trilinear values at world points (n, 3), float32 (n,): the tracer's sampler;
        the background beyond the band."""
        return self._nano.sample(points)


def signed_distance(mesh: MeshLike, points: Any) -> np.ndarray:
    """The signed distance from ``mesh`` at each point (n, 3): float32 (n,), negative inside."""
    return _mesh(mesh).signed_distance(points)


def winding_number(mesh: MeshLike, points: Any) -> np.ndarray:
    """The generalized winding number of ``mesh`` at each point (n, 3): float32 (n,)."""
    return _mesh(mesh).winding_number(points)


@_takes_settings("samples", before=("mesh", "n"), after=(("progress", None),), skip=("count",))
def sample_near_surface(mesh: MeshLike, n: int, settings: Dict[str, Any], progress: Progress = None):
    """``n`` training samples of ``mesh`` as DeepSDF draws them: (points (n, 3), sdf (n,)).
    See :meth:`Mesh.sample_near_surface`; for unit-sphere samples, pass
    ``Mesh(path, normalize=True)``."""
    return _mesh(mesh).sample_near_surface(n, progress=progress, **settings)


@_takes_settings("grid", before=("mesh",), after=(("progress", None),))
def mesh_to_grid(mesh: MeshLike, settings: Dict[str, Any], progress: Progress = None) -> "Grid":
    """The signed distance grid of ``mesh``, as ``mesh2sdf`` converts it (see :meth:`Mesh.to_grid`)."""
    return _mesh(mesh).to_grid(progress=progress, **settings)


def render(
    source: Union[Grid, str],
    width: int = 640,
    height: int = 480,
    camera: Optional[Dict[str, Any]] = None,
    method: str = "auto",
    light: Optional[Sequence[float]] = None,
    shadows: bool = True,
    threads: int = 0,
) -> Dict[str, np.ndarray]:
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
