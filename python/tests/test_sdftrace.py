"""The Python module sdftrace, held to brute force computed here (numpy over
every triangle), to mesh2sdf's own files, and to its promises: every accepted
form and dtype of arrays, errors as exceptions, the GIL released."""

import os
import subprocess
import threading
import time

import numpy as np
import pytest

import sdftrace

DATA = os.environ.get("SDFT_TEST_DATA", os.path.join(os.path.dirname(__file__), "..", "..", "tests", "data"))
SUZANNE = os.path.join(DATA, "meshes", "suzanne.obj")
BUNNY = os.path.join(DATA, "meshes", "stanford-bunny.obj")
MESH2SDF = os.environ.get("MESH2SDF")
ROOT = os.path.abspath(os.path.join(DATA, "..", ".."))


def read_obj(path):
    """Vertices (float64) and triangles (fans of the polygons), read here."""
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "v":
                vertices.append([float(x) for x in words[1:4]])
            elif words[0] == "f":
                corners = [int(w.split("/")[0]) for w in words[1:]]
                corners = [c - 1 if c > 0 else len(vertices) + c for c in corners]
                for k in range(1, len(corners) - 1):
                    faces.append([corners[0], corners[k], corners[k + 1]])
    return np.array(vertices), np.array(faces, dtype=np.int64)


def brute_distance(vertices, faces, points):
    """Unsigned distance from each point to the nearest triangle (Ericson's
    closest point on a triangle, vectorized over the triangles)."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    out = np.empty(len(points))
    for i, p in enumerate(points):
        out[i] = np.sqrt(np.min(closest_dist2(p, a, b, c)))
    return out


def closest_dist2(p, a, b, c):
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = p - b
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp = p - c
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v, w = vb / denom, vc / denom
        q = a + ab * v[:, None] + ac * w[:, None]
        # Regions: the vertices, the edges, else the face.
        conds = [
            (d1 <= 0) & (d2 <= 0),
            (d3 >= 0) & (d4 <= d3),
            (d6 >= 0) & (d5 <= d6),
            (vc <= 0) & (d1 >= 0) & (d3 <= 0),
            (vb <= 0) & (d2 >= 0) & (d6 <= 0),
            (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0),
        ]
        vals = [
            a,
            b,
            c,
            a + ab * (d1 / (d1 - d3))[:, None],
            a + ac * (d2 / (d2 - d6))[:, None],
            b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))[:, None],
        ]
    for cond, val in zip(reversed(conds), reversed(vals)):
        q = np.where(cond[:, None], val, q)
    return np.einsum("ij,ij->i", p - q, p - q)


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


@pytest.fixture(scope="module")
def suzanne():
    return read_obj(SUZANNE)


@pytest.fixture(scope="module")
def points(suzanne):
    vertices = suzanne[0]
    lo, hi = vertices.min(0), vertices.max(0)
    rng = np.random.default_rng(5)
    return lo - 0.25 * (hi - lo) + rng.random((300, 3)) * 1.5 * (hi - lo)


def test_signed_distance_and_winding_against_brute_force(suzanne, points):
    vertices, faces = suzanne
    mesh = sdftrace.Mesh(SUZANNE)
    d = mesh.signed_distance(points)
    assert d.dtype == np.float32 and d.shape == (len(points),)
    truth = brute_distance(vertices, faces, points)
    np.testing.assert_allclose(np.abs(d), truth, rtol=2e-5, atol=1e-6)
    w = sdftrace.winding_number(mesh, points)
    wt = brute_winding(vertices, faces, points)
    np.testing.assert_allclose(w, wt, atol=0.02)
    clear = np.abs(wt - 0.5) > 0.1
    assert clear.sum() > len(points) // 2
    assert np.array_equal(d[clear] < 0, wt[clear] > 0.5)
    d2, w2 = mesh.signed_distance(points, return_winding=True)
    assert np.array_equal(d2, d) and np.array_equal(w2, w)


class Trimeshlike:
    def __init__(self, vertices, faces):
        self.vertices, self.faces = vertices, faces


def test_every_form_of_mesh_and_points_alike(suzanne, points):
    vertices, faces = suzanne
    reference = sdftrace.signed_distance(SUZANNE, points)
    forms = [
        (vertices, faces),
        (vertices.astype(np.float32), faces.astype(np.int32)),
        (np.asfortranarray(vertices), np.asfortranarray(faces)),
        (vertices.astype(np.float32), faces.astype(np.uint32)),
        [vertices.tolist(), faces.tolist()],
        Trimeshlike(vertices, faces),
        sdftrace.Mesh((vertices, faces)),
    ]
    for form in forms:
        assert np.array_equal(sdftrace.signed_distance(form, points), reference), type(form)
    p32 = points.astype(np.float32)
    mesh = sdftrace.Mesh(SUZANNE)
    from32 = mesh.signed_distance(p32)
    for p in (np.asfortranarray(p32), p32.copy(), np.asfortranarray(p32)[::1]):
        assert np.array_equal(mesh.signed_distance(p), from32)
    assert np.array_equal(mesh.signed_distance(np.asfortranarray(points)), reference)
    # Every other row of a bigger array, read in place through its strides.
    doubled = np.repeat(points, 2, axis=0)
    assert np.array_equal(mesh.signed_distance(doubled[::2]), reference)


def test_samples_against_brute_force_and_the_cli(suzanne, tmp_path):
    vertices, faces = suzanne
    points, sdf = sdftrace.sample_near_surface(SUZANNE, 4000, seed=3)
    assert points.shape == (4000, 3) and sdf.shape == (4000,) and points.dtype == np.float32
    assert points.base is not None and points.base is sdf.base  # views of one array, no copy
    again, _ = sdftrace.sample_near_surface(SUZANNE, 4000, seed=3)
    assert np.array_equal(points, again)
    sub = slice(0, 4000, 40)
    truth = brute_distance(vertices, faces, points[sub].astype(np.float64))
    np.testing.assert_allclose(np.abs(sdf[sub]), truth, rtol=2e-5, atol=1e-6)
    near = np.abs(sdf) < 0.1 * np.ptp(vertices, axis=0).max()
    assert near.mean() > 0.8  # most points near the surface
    if MESH2SDF:
        out = tmp_path / "s.npy"
        subprocess.run([MESH2SDF, SUZANNE, "--samples", "4000", str(out), "--seed", "3", "--quiet"], check=True)
        assert np.array_equal(np.load(out), np.column_stack([points, sdf]))
    unit = sdftrace.Mesh(SUZANNE, normalize=True)
    p, _ = unit.sample_near_surface(1000)
    assert np.abs(p).max() <= 1.0 + 1e-6


def test_grid_against_the_cli_and_the_sampler(tmp_path):
    grid = sdftrace.mesh_to_grid(SUZANNE, res=40, band=2)
    dense = grid.to_numpy()
    info = grid.info()
    assert dense.shape == tuple(info["dims"]) and dense.dtype == np.float32
    if MESH2SDF:
        cli = tmp_path / "cli.npy"
        subprocess.run(
            [MESH2SDF, SUZANNE, "-o", str(tmp_path / "cli.vdb"), "--npy", str(cli), "--res", "40", "--band", "2",
             "--quiet"],
            check=True,
        )
        assert np.array_equal(np.load(cli), dense)
        grid.save(tmp_path / "lib.npy")
        assert (tmp_path / "lib.npy").read_bytes() == cli.read_bytes()
    # The tracer's sampler at voxel centres gives the voxels' values.
    idx = np.argwhere(np.abs(dense) < info["background"])[::7]
    centres = np.array(info["origin"]) + idx * info["voxel_size"]
    np.testing.assert_allclose(grid.sample(centres), dense[tuple(idx.T)], atol=1e-5 * info["voxel_size"])
    grid.save(tmp_path / "g.nvdb")
    grid.save(tmp_path / "g.vdb")
    for path in ("g.nvdb", "g.vdb"):
        loaded = sdftrace.Grid.load(tmp_path / path)
        np.testing.assert_allclose(loaded.sample(centres), dense[tuple(idx.T)], atol=1e-5 * info["voxel_size"])
    assert sdftrace.Grid.load(tmp_path / "g.nvdb").to_numpy().size > 0
    with pytest.raises(ValueError):
        sdftrace.Grid.load(tmp_path / "g.nvdb").save(tmp_path / "again.nvdb")
    broken = tmp_path / "broken.nvdb"
    broken.write_bytes(b"NanoVDB0" + bytes(100))
    with pytest.raises(ValueError):
        sdftrace.Grid.load(broken)


def test_render_planes():
    grid = sdftrace.mesh_to_grid(SUZANNE, res=48)
    image = sdftrace.render(grid, width=64, height=48)
    assert image["depth"].shape == (48, 64) and image["normal"].shape == (48, 64, 3)
    hit = np.isfinite(image["depth"])
    assert 0 < hit.sum() < hit.size
    np.testing.assert_allclose(np.linalg.norm(image["normal"][hit], axis=1), 1, atol=1e-3)
    assert image["steps"].dtype == np.uint32 and image["steps"][hit].min() > 0
    assert np.all(image["primary_steps"] <= image["steps"])
    scene = sdftrace.render("temple", width=32, height=24, method="sphere")
    assert np.isfinite(scene["depth"]).any()
    # A camera given as lists, looking at the grid's centre from farther
    # away: the mesh covers fewer pixels.
    info = grid.info()
    centre = (np.array(info["lo"]) + np.array(info["hi"])) / 2
    size = np.ptp(np.array([info["lo"], info["hi"]]), axis=0).max()
    far = sdftrace.render(
        grid, width=64, height=48,
        camera={"eye": list(centre + [0, 0, 6 * size]), "target": list(centre), "up": [0, 1, 0], "fov": 40},
    )
    assert 0 < np.isfinite(far["depth"]).sum() < hit.sum()
    with pytest.raises(ValueError):
        sdftrace.render("no such scene")
    assert "temple" in sdftrace.scenes()


def test_progress_reports_and_stops():
    mesh = sdftrace.Mesh(SUZANNE)
    seen = []
    mesh.to_grid(res=64, progress=seen.append)
    assert len(seen) >= 3 and seen == sorted(seen) and seen[-1] == 1.0
    calls = []
    with pytest.raises(sdftrace.Canceled, match="canceled"):
        mesh.to_grid(res=64, progress=lambda done: calls.append(done) or len(calls) >= 2)
    assert len(calls) == 2

    def broken(done):
        raise ZeroDivisionError("from the callable")

    with pytest.raises(ZeroDivisionError, match="from the callable"):
        mesh.sample_near_surface(1000, progress=broken)
    with pytest.raises(sdftrace.Canceled):
        sdftrace.sample_near_surface(mesh, 1000, progress=lambda done: True)


def test_ctrl_c_stops_a_conversion():
    """SIGINT during a long conversion raises KeyboardInterrupt at its next
    progress report, not once the grid is done (on one thread, the caller's,
    where Python runs its signal handlers)."""
    import signal

    mesh = sdftrace.Mesh(BUNNY)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            mesh.to_grid(res=1600, threads=1)
    finally:
        timer.cancel()
    # The whole conversion takes about 12 s on one core of the machine the
    # tests were written on (and more under the sanitizers); stopping it
    # takes one report's share of that after the signal.
    assert time.perf_counter() - start < 3


def test_readme_example_runs(tmp_path, monkeypatch):
    """The README's Python example, as printed there, from a folder with the
    repository's tests/ in it."""
    with open(os.path.join(ROOT, "README.md")) as f:
        code = f.read().split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(tmp_path)
    os.symlink(os.path.join(ROOT, "tests"), tmp_path / "tests")
    exec(compile(code, "README.md", "exec"), {})
    saved = np.load(tmp_path / "spot-samples.npz")
    assert saved["points"].shape == (250_000, 3)


def test_keywords_are_the_library_settings(tmp_path):
    """Every setting of the library's tables is a keyword of the call that
    takes it, with the library's default, and reaches the library: a value
    past its range is refused there (ValueError), and the default works."""
    import inspect

    calls = {
        "mesh": inspect.signature(sdftrace.Mesh),
        "grid": inspect.signature(sdftrace.Mesh.to_grid),
        "samples": inspect.signature(sdftrace.Mesh.sample_near_surface),
    }
    for of, signature in calls.items():
        for row in sdftrace.settings(of):
            if of == "samples" and row["name"] == "count":
                assert "n" in signature.parameters  # Python's name for it
                continue
            param = signature.parameters[row["name"]]
            default = param.default
            if row["kind"] == "choice":
                assert row["choices"].split()[int(row["default"][0])] == default
            elif row["kind"] == "text":
                assert default is None
            else:
                assert tuple(np.atleast_1d(default).astype(float)) == row["default"], row["name"]
    mesh = sdftrace.Mesh(SUZANNE, threads=1, simd="none")
    with pytest.raises(ValueError, match="threads"):
        sdftrace.Mesh(SUZANNE, threads=100000)
    with pytest.raises(ValueError, match="band"):
        mesh.to_grid(res=16, band=0)
    with pytest.raises(ValueError, match="uniform_share"):
        mesh.sample_near_surface(10, uniform_share=2)
    with pytest.raises(ValueError, match="sign"):
        mesh.to_grid(res=16, sign="sideways")
    with pytest.raises(TypeError):
        mesh.to_grid(res=16, no_such_setting=1)
    # orient takes its names and, as before, True and False.
    assert sdftrace.Mesh(SUZANNE, orient="none").info()["oriented"] is False
    assert sdftrace.Mesh(SUZANNE, orient=False).info()["oriented"] is False
    assert sdftrace.Mesh(SUZANNE, orient=True).info()["oriented"] is True
    # Positional, in the order the keywords always had.
    a = mesh.to_grid(24, 2.0, False).to_numpy()
    b = mesh.to_grid(res=24, band=2.0).to_numpy()
    assert np.array_equal(a, b)


def test_errors_raise(tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(ValueError, match="non-finite"):
        sdftrace.Mesh(bad)
    with pytest.raises(OSError, match="missing.obj"):
        sdftrace.Mesh(tmp_path / "missing.obj")
    tri = np.eye(3)
    with pytest.raises(ValueError, match="vertex index 5"):
        sdftrace.Mesh((tri, np.array([[0, 1, 5]])))
    with pytest.raises(ValueError, match="non-finite"):
        sdftrace.Mesh((np.array([[0, 0, 0], [1, 0, 0], [0, np.nan, 0]]), np.array([[0, 1, 2]])))
    with pytest.raises(ValueError, match="shape"):
        sdftrace.signed_distance((tri, np.array([[0, 1, 2]])), np.zeros((4, 2)))
    with pytest.raises(ValueError):
        sdftrace.mesh_to_grid(SUZANNE, res=0)
    with pytest.raises(TypeError):
        sdftrace.Mesh(42)


def test_the_gil_is_released_while_converting():
    """A Python thread goes on running while another converts: if the
    conversion held the GIL, the counter would stand still for its whole
    second."""
    mesh = sdftrace.Mesh(BUNNY)
    count, stop = [0], [False]

    def spin():
        while not stop[0]:
            count[0] += 1

    spinner = threading.Thread(target=spin)
    spinner.start()
    time.sleep(0.2)
    start, before = time.perf_counter(), count[0]
    mesh.to_grid(res=160, threads=1)
    during = (count[0] - before) / (time.perf_counter() - start)
    stop[0] = True
    spinner.join()
    count[0], stop[0] = 0, False
    spinner = threading.Thread(target=spin)
    spinner.start()
    time.sleep(0.5)
    stop[0] = True
    spinner.join()
    alone = count[0] / 0.5
    assert during > 0.1 * alone, (during, alone)


def test_two_threads_convert_in_the_time_of_one():
    """Two threads converting at once, each on one worker thread, finish in
    about the time of one on two cores. Timing needs idle cores: on a
    machine busier than that, the test is skipped."""
    cores = os.cpu_count() or 1
    if cores < 2 or os.getloadavg()[0] > cores - 1.5:
        pytest.skip("needs two idle cores")
    mesh = sdftrace.Mesh(BUNNY)

    def convert():
        mesh.to_grid(res=160, threads=1)

    def timed(threads):
        start = time.perf_counter()
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        return time.perf_counter() - start

    convert()  # warm
    best = min(
        timed([threading.Thread(target=convert), threading.Thread(target=convert)])
        / timed([threading.Thread(target=convert)])
        for _ in range(3)
    )
    assert best < 1.6, best


def test_faces_left_out_and_strict():
    """A file with faces its reader cannot take: the cube's twelve kept, the
    five others counted and said; refused with strict=True."""
    path = os.path.join(DATA, "real", "bad_indices.obj")
    info = sdftrace.Mesh(path).info()
    assert info["faces"] == 12 and info["skipped_faces"] == 5
    assert "5 faces of the file were left out" in info["warnings"]
    assert sdftrace.Mesh(os.path.join(DATA, "real", "cup_lid.off")).info()["skipped_faces"] == 0
    with pytest.raises(ValueError, match="refused as strict"):
        sdftrace.Mesh(path, strict=True)
