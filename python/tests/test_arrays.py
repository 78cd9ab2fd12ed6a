"""What ML code hands sdftrace, held to analytic truth: the signed distance
of the cube [-1, 1]^3 is known in closed form at every point, and the
winding number of an open box is summed here over its triangles. Points of
any shape (..., 3), float32, float64 and integers, results in the points'
precision or `dtype=`, `threads=` on every call, mesh objects of trimesh and
Open3D (stand-ins, and the real packages where installed), PyTorch tensors
read in place (a stand-in, and torch where installed), contiguous samples,
n=0, no hidden cache, and a module that lists only its API."""

import threading

import numpy as np
import pytest

import sdftrace
from brute_force import brute_winding


def cube(open_top=False):
    """The cube [-1, 1]^3 as 12 triangles (10 without its top face, z = 1),
    each turned to face outward; vertices float64, faces int64."""
    corners = np.array([[x, y, z] for z in (-1.0, 1.0) for y in (-1.0, 1.0) for x in (-1.0, 1.0)])
    index = {tuple(c): i for i, c in enumerate(corners)}
    faces = []
    for axis in range(3):
        u, v = [k for k in range(3) if k != axis]
        for side in (-1.0, 1.0):
            if open_top and axis == 2 and side == 1.0:
                continue
            quad = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = side, a, b
                quad.append(index[tuple(p)])
            for tri in ((quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])):
                a, b, c = corners[list(tri)]
                if np.dot(np.cross(b - a, c - a), a + b + c) < 0:
                    tri = (tri[0], tri[2], tri[1])
                faces.append(tri)
    return corners, np.array(faces, dtype=np.int64)


def box_sdf(p):
    """The exact signed distance of the cube [-1, 1]^3 (negative inside)."""
    q = np.abs(np.asarray(p, dtype=np.float64)) - 1.0
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=-1)
    return outside + np.minimum(q.max(axis=-1), 0.0)


def close(values, truth):
    """Float32's precision on distances of order 1."""
    np.testing.assert_allclose(values, truth, rtol=1e-6, atol=2e-7)


@pytest.fixture(scope="module")
def mesh():
    return sdftrace.Mesh(cube())


@pytest.fixture(scope="module")
def grid_points():
    """A (4, 5, 6, 3) block of points around and inside the cube."""
    rng = np.random.default_rng(7)
    return rng.uniform(-2.0, 2.0, size=(4, 5, 6, 3))


# ---- shapes ------------------------------------------------------------------


def test_points_of_any_shape_answer_in_that_shape(mesh, grid_points):
    d = mesh.signed_distance(grid_points)
    assert d.shape == (4, 5, 6) and d.dtype == np.float64
    close(d, box_sdf(grid_points))
    flat = mesh.signed_distance(grid_points.reshape(-1, 3))
    assert flat.shape == (120,) and np.array_equal(flat, d.reshape(-1))
    # A view that cannot be flattened in place (every other point of a grid).
    strided = grid_points[:, ::2]
    close(mesh.signed_distance(strided), box_sdf(strided))
    d2, w2 = mesh.signed_distance(grid_points, return_winding=True)
    assert d2.shape == w2.shape == (4, 5, 6) and np.array_equal(d2, d)
    inside = np.all(np.abs(grid_points) < 0.99, axis=-1)
    outside = np.any(np.abs(grid_points) > 1.01, axis=-1)
    assert inside.any() and outside.any()
    np.testing.assert_allclose(w2[inside], 1.0, atol=1e-3)
    np.testing.assert_allclose(w2[outside], 0.0, atol=1e-3)
    w = sdftrace.winding_number(mesh, grid_points)
    assert w.shape == (4, 5, 6) and np.array_equal(w, w2)


def test_one_point_gives_a_scalar(mesh):
    d = mesh.signed_distance([2.0, 0.0, 0.0])
    assert np.ndim(d) == 0 and d.shape == () and d.dtype == np.float64 and float(d) == 1.0
    assert float(mesh.signed_distance(np.array([0.0, 0.5, 0.0]))) == -0.5
    d, w = mesh.signed_distance(np.float32([0.0, 0.0, 3.0]), return_winding=True)
    assert d.shape == w.shape == () and d.dtype == np.float32 and float(d) == 2.0 and abs(float(w)) < 1e-3
    w = sdftrace.winding_number(mesh, (0.1, 0.2, 0.3))
    assert w.shape == () and abs(float(w) - 1.0) < 1e-3


def test_no_points_give_empty_answers(mesh):
    for shape in ((0, 3), (2, 0, 3)):
        d = mesh.signed_distance(np.empty(shape, np.float32))
        assert d.shape == shape[:-1] and d.dtype == np.float32
        assert mesh.winding_number(np.empty(shape)).shape == shape[:-1]
    d, w = mesh.signed_distance(np.empty((0, 3)), return_winding=True)
    assert d.shape == w.shape == (0,) and d.dtype == w.dtype == np.float64


def test_rows_of_four_and_other_shapes_are_refused(mesh):
    rows = np.zeros((10, 4))
    with pytest.raises(ValueError, match=r"\(10, 4\).*rows\[\.\.\., :3\]"):
        mesh.signed_distance(rows)
    close(mesh.signed_distance(rows[:, :3]), box_sdf(rows[:, :3]))  # what the message says works
    for bad in (np.zeros((10, 2)), np.zeros(4), np.float64(1.0), np.zeros((3, 3, 0))):
        with pytest.raises(ValueError, match=r"shape \(\.\.\., 3\)"):
            mesh.winding_number(bad)
    with pytest.raises(TypeError, match="real"):
        mesh.signed_distance(np.zeros((2, 3), np.complex128))


# ---- dtypes --------------------------------------------------------------------


def test_answers_in_the_points_precision_or_dtype(mesh, grid_points):
    p64 = grid_points.reshape(-1, 3)
    p32 = p64.astype(np.float32)
    truth32 = box_sdf(p32)
    for call in (mesh.signed_distance, mesh.winding_number):
        assert call(p64).dtype == np.float64 and call(p32).dtype == np.float32
        assert call(p64, dtype=np.float32).dtype == np.float32
        assert call(p32, dtype="float64").dtype == np.float64
        with pytest.raises(ValueError, match="dtype"):
            call(p64, dtype=np.float16)
    close(mesh.signed_distance(p32), truth32)
    close(mesh.signed_distance(p32, dtype=np.float64), truth32)
    # float64 answers are the library's float32 values, widened: the same numbers.
    widened = mesh.signed_distance(p32).astype(np.float64)
    assert np.array_equal(mesh.signed_distance(p32, dtype=np.float64), widened)
    # Integer points (a voxel grid's indices, say) answer in float64.
    ijk = np.stack(np.meshgrid(*[np.arange(-3, 4)] * 3, indexing="ij"), axis=-1)
    d = mesh.signed_distance(ijk)
    assert d.dtype == np.float64 and d.shape == (7, 7, 7)
    close(d, box_sdf(ijk))


# ---- threads -------------------------------------------------------------------


def test_threads_bound_every_call(mesh, grid_points):
    """threads=1 keeps a call on the caller's thread: every progress report
    comes from it, though the mesh's own setting (0) is all cores; the
    answers do not depend on the count."""
    rng = np.random.default_rng(3)
    points = rng.uniform(-2, 2, size=(200_000, 3))
    caller = threading.get_ident()

    def reporters(call, **kw):
        seen = set()
        result = call(progress=lambda done: seen.add(threading.get_ident()), **kw)
        return result, seen

    one, seen = reporters(lambda **kw: mesh.signed_distance(points, threads=1, **kw))
    assert seen == {caller}
    two, _ = reporters(lambda **kw: mesh.signed_distance(points, threads=2, **kw))
    assert np.array_equal(one, two)
    close(one, box_sdf(points))
    w, seen = reporters(lambda **kw: sdftrace.winding_number(mesh, points, threads=1, **kw))
    assert seen == {caller} and np.array_equal(w, mesh.winding_number(points, threads=2))
    (p1, s1), seen = reporters(lambda **kw: mesh.sample_near_surface(20_000, seed=4, threads=1, **kw))
    assert seen == {caller}
    p2, s2 = sdftrace.sample_near_surface(mesh, 20_000, seed=4, threads=2)
    assert np.array_equal(p1, p2) and np.array_equal(s1, s2)
    grid = sdftrace.mesh_to_grid(mesh, res=24, threads=1)
    assert np.array_equal(grid.sample(grid_points, threads=1), grid.sample(grid_points, threads=2))
    for bad in (-1, 1025):
        for call in (mesh.signed_distance, mesh.winding_number, grid.sample):
            with pytest.raises(ValueError, match="threads"):
                call(grid_points, threads=bad)
        with pytest.raises(ValueError, match="threads"):
            mesh.sample_near_surface(10, threads=bad)
    # A path is read on the call's threads too: a mesh setting, in range.
    with pytest.raises(ValueError, match="threads"):
        sdftrace.signed_distance(cube(), grid_points, threads=5000)


# ---- meshes as ML code holds them -------------------------------------------------


class Trimeshlike:
    """trimesh.Trimesh's names: .faces, and .triangles the corners' coordinates (m, 3, 3)."""

    def __init__(self, vertices, faces):
        self.vertices, self.faces = vertices, faces
        self.triangles = vertices[faces]


class Vector:
    """Open3D's legacy Vector3dVector / Vector3iVector: numpy reads it through __array__."""

    def __init__(self, a):
        self._a = a

    def __array__(self, dtype=None):
        return self._a if dtype is None else self._a.astype(dtype)


class Open3DLegacylike:
    def __init__(self, vertices, faces):
        self.vertices, self.triangles = Vector(vertices), Vector(faces.astype(np.int32))


class Tensor:
    """An Open3D core Tensor: .numpy(), and no __array__."""

    def __init__(self, a):
        self._a = a

    def numpy(self):
        return self._a


class Open3DTensorlike:
    """open3d.t.geometry.TriangleMesh: .vertex.positions and .triangle.indices."""

    class Attributes:
        pass

    def __init__(self, vertices, faces):
        self.vertex, self.triangle = self.Attributes(), self.Attributes()
        self.vertex.positions = Tensor(vertices.astype(np.float32))
        self.triangle.indices = Tensor(faces.astype(np.int64))


def test_meshes_as_ml_code_holds_them(grid_points):
    vertices, faces = cube()
    truth = box_sdf(grid_points)
    forms = [
        (vertices, faces),
        [vertices, faces],
        Trimeshlike(vertices, faces),
        Open3DLegacylike(vertices, faces),
        Open3DTensorlike(vertices, faces),
        (DLPackStandIn(vertices), DLPackStandIn(faces)),
    ]
    for form in forms:
        close(sdftrace.signed_distance(form, grid_points), truth)
        assert sdftrace.Mesh(form).info()["triangles"] == 12, type(form)

    class VerticesOnly:
        def __init__(self, vertices):
            self.vertices = vertices

    for bad in (VerticesOnly(vertices), 42, (vertices,)):
        with pytest.raises(TypeError, match="triangles"):
            sdftrace.Mesh(bad)


def test_real_trimesh_and_open3d_where_installed(grid_points):
    vertices, faces = cube()
    truth = box_sdf(grid_points)
    tried = 0
    try:
        import trimesh

        close(sdftrace.signed_distance(trimesh.Trimesh(vertices, faces, process=False), grid_points), truth)
        tried += 1
    except ImportError:
        pass
    try:
        import open3d as o3d

        legacy = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(vertices), o3d.utility.Vector3iVector(faces))
        close(sdftrace.signed_distance(legacy, grid_points), truth)
        close(sdftrace.signed_distance(o3d.t.geometry.TriangleMesh.from_legacy(legacy), grid_points), truth)
        tried += 1
    except ImportError:
        pass
    if not tried:
        pytest.skip("neither trimesh nor open3d is installed")


def test_a_mesh_given_is_used_and_nothing_is_cached(tmp_path, grid_points):
    """A Mesh is used as it is (its settings stand: normalized, the cube's
    distances shrink by its sphere's radius); anything else is read on each
    call, so a file changed between calls gives the new answers."""
    vertices, faces = cube()
    unit = sdftrace.Mesh((vertices, faces), normalize=True)
    radius = unit.info()["radius"]
    close(sdftrace.signed_distance(unit, grid_points / radius), box_sdf(grid_points) / radius)
    assert sdftrace.Mesh(unit)._mesh is unit._mesh
    with pytest.raises(ValueError, match="normalize"):
        sdftrace.Mesh(unit, normalize=False)
    path = tmp_path / "cube.obj"

    def write(scale):
        lines = ["v %.17g %.17g %.17g" % tuple(scale * v) for v in vertices]
        lines += ["f %d %d %d" % tuple(f + 1) for f in faces]
        path.write_text("\n".join(lines) + "\n")

    write(1.0)
    close(sdftrace.signed_distance(path, grid_points), box_sdf(grid_points))
    write(2.0)
    close(sdftrace.signed_distance(path, grid_points), 2.0 * box_sdf(grid_points / 2.0))


# ---- samples -------------------------------------------------------------------------


def test_samples_are_contiguous_arrays_of_their_own(mesh):
    points, sdf = mesh.sample_near_surface(5000, seed=2)
    assert points.shape == (5000, 3) and sdf.shape == (5000,)
    assert points.dtype == sdf.dtype == np.float32
    assert points.flags.c_contiguous and sdf.flags.c_contiguous and not np.shares_memory(points, sdf)
    close(sdf, box_sdf(points))
    p64, s64 = sdftrace.sample_near_surface(mesh, 5000, seed=2, dtype=np.float64)
    assert p64.dtype == s64.dtype == np.float64 and p64.flags.c_contiguous and s64.flags.c_contiguous
    assert np.array_equal(p64, points.astype(np.float64)) and np.array_equal(s64, sdf.astype(np.float64))
    with pytest.raises(ValueError, match="dtype"):
        mesh.sample_near_surface(10, dtype=np.int32)


def test_zero_samples_are_empty_arrays(mesh):
    points, sdf = mesh.sample_near_surface(0)
    assert points.shape == (0, 3) and sdf.shape == (0,) and points.dtype == np.float32
    points, sdf = sdftrace.sample_near_surface(mesh, 0, dtype=np.float64)
    assert points.shape == (0, 3) and sdf.dtype == np.float64
    with pytest.raises(ValueError, match="n must be"):
        mesh.sample_near_surface(-1)
    with pytest.raises(TypeError):
        mesh.sample_near_surface(2.5)
    # The settings are checked as for any n.
    with pytest.raises(ValueError, match="uniform_share"):
        mesh.sample_near_surface(0, uniform_share=2)
    with pytest.raises(ValueError, match="near_sigma"):
        mesh.sample_near_surface(0, near_sigma=(0.1, 0.0))


# ---- tensors, read in place ------------------------------------------------------


class DLPackStandIn:
    """A tensor on the CPU as PyTorch's shows itself to numpy: DLPack only."""

    def __init__(self, a, device=(1, 0)):
        self._a, self._device = a, device

    def __dlpack__(self, stream=None):
        return self._a.__dlpack__()

    def __dlpack_device__(self):
        return self._device


def test_tensors_are_read_in_place(mesh, grid_points):
    base = np.ascontiguousarray(grid_points.reshape(-1, 3))
    for tensor in (DLPackStandIn(base), Vector(base)):
        flat, shape = sdftrace._points(tensor)
        assert np.shares_memory(flat, base) and shape == (120,), type(tensor)
        close(mesh.signed_distance(tensor), box_sdf(base))
    # A (..., 3) tensor is viewed as (n, 3) in place too.
    flat, shape = sdftrace._points(DLPackStandIn(grid_points))
    assert shape == (4, 5, 6) and np.shares_memory(flat, grid_points)
    with pytest.raises(ValueError, match="CPU"):
        mesh.signed_distance(DLPackStandIn(base, device=(2, 0)))


def test_torch_where_installed(mesh, grid_points):
    torch = pytest.importorskip("torch")
    t = torch.from_numpy(grid_points.astype(np.float32))
    d = mesh.signed_distance(t)
    assert d.dtype == np.float32 and d.shape == (4, 5, 6)
    close(d, box_sdf(t.numpy()))
    flat, _ = sdftrace._points(t)
    assert np.shares_memory(flat, t.numpy())
    close(mesh.signed_distance(t.double()), box_sdf(grid_points))


# ---- the grid's sampler ---------------------------------------------------------------


def test_grid_sample_takes_the_same_points(mesh):
    grid = mesh.to_grid(res=32, band=3)
    dense, info = grid.to_numpy(), grid.info()
    idx = np.argwhere(np.abs(dense) < 0.5 * info["background"])[::5]
    centres = np.array(info["origin"]) + idx * info["voxel_size"]
    block = centres[: 6 * (len(centres) // 6)].reshape(2, 3, -1, 3)
    values = grid.sample(block)
    assert values.shape == block.shape[:-1] and values.dtype == np.float64
    np.testing.assert_allclose(values.reshape(-1), dense[tuple(idx[: block.size // 3].T)], atol=1e-5)
    # The grid's values are the exact distances at the voxel centres (to float32).
    np.testing.assert_allclose(values, box_sdf(block), atol=1e-5)
    assert grid.sample(centres[0].astype(np.float32)).shape == ()
    assert grid.sample(np.empty((0, 3))).shape == (0,)
    with pytest.raises(ValueError, match="rows"):
        grid.sample(np.zeros((3, 4)))


# ---- the module's names ---------------------------------------------------------------


def test_the_module_lists_only_its_api():
    names = set(dir(sdftrace))
    assert names == set(sdftrace.__all__) | {"__version__"}
    assert not names & {"np", "os", "Any", "Callable", "inspect", "_sdftrace"}
    for name in sdftrace.__all__:
        assert getattr(sdftrace, name) is not None, name
    star = {}
    exec("from sdftrace import *", star)
    assert set(star) - {"__builtins__"} == set(sdftrace.__all__)
    assert {"Mesh", "Grid", "signed_distance", "winding_number", "sample_near_surface", "mesh_to_grid"} <= names


def test_open_box_winding_against_brute_force():
    """An open mesh (the box without its top): the winding number against the
    triangles' solid angles, and the distance's sign its side of 1/2."""
    vertices, faces = cube(open_top=True)
    rng = np.random.default_rng(11)
    points = rng.uniform(-1.5, 1.5, size=(400, 3))
    truth = brute_winding(vertices, faces, points)
    mesh = sdftrace.Mesh((vertices, faces))
    d, w = mesh.signed_distance(points.reshape(20, 20, 3), return_winding=True)
    np.testing.assert_allclose(w.reshape(-1), truth, atol=0.02)
    clear = np.abs(truth - 0.5) > 0.05
    assert clear.sum() > 300
    assert np.array_equal(d.reshape(-1)[clear] < 0, truth[clear] > 0.5)
    # Unsigned, the distance is the box's surface but its top.
    top_free = np.where(np.abs(points[:, 2]) <= 0.5, np.abs(box_sdf(points)), np.nan)
    near_sides = np.isfinite(top_free) & np.all(np.abs(points[:, :2]) > 1.0, axis=1)
    close(np.abs(d.reshape(-1)[near_sides]), top_free[near_sides])

