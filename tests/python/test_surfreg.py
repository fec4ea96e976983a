"""The Python module surfreg (tools/python): its typed results (Surface,
Measure, Alignment, TerrainChange, Series) against known answers, against the CLI's
--json output on the same inputs, bad input, and the GIL.

Run by ctest (tests/CMakeLists.txt) with PYTHONPATH holding the built module
and SURFREG_CLI naming the built `surfreg` program.
"""
import json
import os
import pathlib
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import surfreg



def field(x, y):
    """A smooth height field with structure in every direction (no symmetry
    that would leave a motion unobservable)."""
    return 2.0 * np.sin(x / 9.0) * np.cos(y / 7.0) + 0.5 * np.sin((x + y) / 5.0) + 0.01 * x


def sample(n, lo, hi, seed):
    rng = np.random.default_rng(seed)
    xy = rng.uniform(lo, hi, (n, 2))
    return np.column_stack([xy, field(xy[:, 0], xy[:, 1])])


def rotation(axis, degrees):
    """Rodrigues: the rotation by `degrees` about `axis`."""
    a = np.radians(degrees)
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K


def known_pair(n=3000, seed=7):
    """A reference and a moving surface with the moving -> reference motion
    `truth`: the moving samples are other points of the same field, carried
    by the inverse motion (1.5 degrees about a tilted axis, and a shift)."""
    reference = sample(n, 0.0, 60.0, seed)
    on_field = sample(n, 6.0, 54.0, seed + 1)
    R = rotation([0.3, 0.2, 1.0], 1.5)
    t = np.array([0.8, -0.5, 0.3])
    truth = np.eye(4)
    truth[:3, :3], truth[:3, 3] = R, t
    moving = (on_field - t) @ R  # R^T (p - t), row by row
    return reference, moving, truth


def write_xyz(path, points):
    # %.17g reads back as the same double: the file holds exactly the array.
    np.savetxt(path, points, fmt="%.17g")
    return str(path)


MEASURE_FIELDS = ("rho_d", "rho_d_axial", "rho_s", "overlap_area", "weight_integral", "mean_abs_dz",
                  "signed_volume", "volume_above", "volume_below", "domain_area_a", "domain_area_b",
                  "n_points_a", "n_points_b", "n_overlap_nodes", "n_cells")


def same_measure(m, expected):
    """A Measure equal, to the bit, to another Measure or to a measure JSON."""
    keys = [k for k in MEASURE_FIELDS if not isinstance(expected, dict) or k in expected]
    assert len(keys) >= 5
    for key in keys:
        want = expected[key] if isinstance(expected, dict) else getattr(expected, key)
        assert getattr(m, key) == want, key


def cli():
    program = os.environ.get("SURFREG_CLI")
    if not program:
        pytest.skip("SURFREG_CLI (the surfreg program) not set; ctest sets it")
    return program


def run_cli(*args):
    done = subprocess.run([cli(), *args], capture_output=True, text=True)
    return done.returncode, done.stdout, done.stderr


def cli_json(*args):
    code, out, err = run_cli(*args, "--json")
    assert code == 0, err
    return json.loads(out)


def cli_error(*args):
    """The CLI's one-line message for bad input, without 'surfreg: error: '."""
    code, _, err = run_cli(*args)
    assert code == 2, err
    prefix = "surfreg: error: "
    assert err.startswith(prefix), err
    return err[len(prefix):].strip()


# --- surfaces ---------------------------------------------------------------


def test_surface_from_an_array_and_from_a_file_holds_the_samples(tmp_path):
    a = sample(500, 0.0, 20.0, seed=9)
    s = surfreg.Surface(a, name="mine")
    assert len(s) == 500 and s.name == "mine" and not s.is_raster and s.weights is None
    np.testing.assert_allclose(s.points, a, rtol=0, atol=1e-12)
    f = surfreg.read_surface(write_xyz(tmp_path / "a.xyz", np.column_stack([a, np.ones(500)])))
    np.testing.assert_allclose(f.points, a, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(f.weights, np.ones(500))


def test_a_raster_reads_as_a_raster_surface():
    data = pathlib.Path(__file__).resolve().parents[2] / "configs" / "data"
    try:
        s = surfreg.read_surface(data / "volcano_dem.tif")
    except ValueError as e:  # surfreg.InputError
        if "built without GDAL" in str(e):
            pytest.skip("this surfreg was built without GDAL")
        raise
    assert s.is_raster and len(s) > 1000


# --- measure --------------------------------------------------------------


def test_measure_of_a_surface_and_itself_shifted_gives_the_shift():
    a = sample(2000, 0.0, 50.0, seed=1)
    dz = 0.37
    b = a + [0.0, 0.0, dz]
    r = surfreg.measure(a, b)
    assert isinstance(r, surfreg.Measure)
    assert r.rho_d_axial == pytest.approx(dz, abs=1e-9)
    assert r.mean_abs_dz == pytest.approx(dz, abs=1e-9)
    assert r.signed_volume / r.overlap_area == pytest.approx(dz, abs=1e-9)
    assert r.rho_d == pytest.approx(dz * r.overlap_area, rel=1e-12)
    assert r.volume_below == 0.0
    assert r.n_points_a == r.n_points_b == 2000


def test_measure_options_are_the_config_keys():
    a = sample(1500, 0.0, 50.0, seed=2)
    b = a + [0.0, 0.0, -0.2]
    r = surfreg.measure(a, b, volume="union", domain="hull")
    assert r.volume_mode == "union" and r.domain == "hull"
    assert r.rho_d_axial == pytest.approx(0.2, abs=1e-9)
    # lod: cut beyond it, none below it (every gap is 0.2).
    beyond = surfreg.measure(a, b, lod=0.1)
    assert beyond.cut_detected == pytest.approx(0.2 * beyond.overlap_area, rel=1e-9)
    assert surfreg.measure(a, b, lod=0.3).cut_detected == 0.0
    # threads: the same bits on one thread and on eight.
    one, eight = surfreg.measure(a, b, threads=1), surfreg.measure(a, b, threads=8)
    assert one.rho_d == eight.rho_d and one.rho_d_axial == eight.rho_d_axial


def test_per_point_weights_from_a_fourth_column(tmp_path):
    a = sample(1500, 0.0, 50.0, seed=3)
    weights = np.where(a[:, 0] < 25.0, 1.0, 0.0)
    a4 = np.column_stack([a, weights])
    b = a + [0.0, 0.0, 0.5]
    r = surfreg.measure(a4, b, weights="per_point")
    assert r.weight_integral < 0.6 * r.overlap_area
    same_measure(surfreg.measure(write_xyz(tmp_path / "a4.xyz", a4), b, weights="per_point"), r)


# --- align ----------------------------------------------------------------


def motion_errors(matrix, truth, points):
    """Rotation error (degrees) and the displacement error at the moving
    points' centroid (data units) of `matrix` against `truth`."""
    d = matrix[:3, :3] @ truth[:3, :3].T
    angle = np.degrees(np.arccos(np.clip((np.trace(d) - 1) / 2, -1, 1)))
    c = points[:, :3].mean(axis=0)
    shift = np.linalg.norm(matrix[:3, :3] @ c + matrix[:3, 3] - (truth[:3, :3] @ c + truth[:3, 3]))
    return angle, shift


@pytest.mark.parametrize("cost", ["volume", "axial"])
def test_align_recovers_a_known_motion(cost):
    reference, moving, truth = known_pair()
    r = surfreg.align(reference, moving, cost=cost)
    assert isinstance(r, surfreg.Alignment)
    assert r.matrix.shape == (4, 4) and r.matrix.dtype == np.float64
    assert r.verdict == "converged_improved" and r.solve_cost == cost
    angle, shift = motion_errors(r.matrix, truth, moving)
    # Measured: 0.002-0.004 degrees and 0.0005-0.003 units (the two
    # samplings' linear interpolation error; spacing about 1.1 units). The
    # bounds leave 5-10x for that, and are 1% of the motion's 1.5 degrees
    # and 1% of the spacing.
    assert angle < 0.02, angle
    assert shift < 0.02, shift
    assert r.after.rho_d_axial < 0.05 * r.before.rho_d_axial
    assert set(r.stddev) == {"rx", "ry", "rz", "tx", "ty", "tz"} and 0 < r.stddev["tz"] < 0.01
    assert r.covariance.shape == (6, 6)
    np.testing.assert_allclose(np.sqrt(np.diag(r.covariance)), list(r.stddev.values()), rtol=1e-9)


def test_align_with_locked_parameters_keeps_them():
    reference, moving, truth = known_pair()
    r = surfreg.align(reference, moving, cost="axial", free=["tx", "ty", "tz"], max_iterations=50)
    np.testing.assert_allclose(r.matrix[:3, :3], np.eye(3), atol=1e-12)


def test_initial_matrix_starts_where_an_alignment_ended():
    reference, moving, _ = known_pair(n=1500)
    first = surfreg.align(reference, moving)
    second = surfreg.align(reference, moving, initial_matrix=first.matrix)
    np.testing.assert_allclose(second.matrix, first.matrix, atol=1e-6)
    assert second.before.mean_abs_dz == pytest.approx(first.after.mean_abs_dz, rel=1e-9)


# --- arrays, files and the CLI agree -----------------------------------------


def test_array_file_and_surface_inputs_give_the_same_result(tmp_path):
    reference, moving, _ = known_pair(n=1500)
    files = (write_xyz(tmp_path / "ref.xyz", reference), write_xyz(tmp_path / "mov.xyz", moving))
    from_arrays = surfreg.measure(reference, moving)
    same_measure(surfreg.measure(*files), from_arrays)
    same_measure(surfreg.measure(*(pathlib.Path(f) for f in files)), from_arrays)  # os.PathLike
    same_measure(surfreg.measure(*(surfreg.read_surface(f) for f in files)), from_arrays)
    from_arrays = surfreg.align(reference, moving, cost="axial")
    from_files = surfreg.align(*files, cost="axial")
    np.testing.assert_array_equal(from_arrays.matrix, from_files.matrix)


def test_measure_equals_the_cli_json(tmp_path):
    a = write_xyz(tmp_path / "a.xyz", sample(1500, 0.0, 50.0, seed=4))
    b = write_xyz(tmp_path / "b.xyz", sample(1200, 3.0, 47.0, seed=5) + [0.0, 0.0, 0.1])
    for flags, options in [([], {}),
                           (["--volume=union", "--domain=hull"], {"volume": "union", "domain": "hull"}),
                           (["--lod=0.05"], {"lod": 0.05})]:
        expected = cli_json("measure", a, b, *flags)
        got = surfreg.measure(a, b, **options)
        same_measure(got, expected)
        if "lod" in options:
            assert got.fill_detected == expected["change"]["fill"]
            assert got.cut_detected == expected["change"]["cut"]


def test_align_equals_the_cli_json(tmp_path):
    reference, moving, _ = known_pair(n=1500)
    ref = write_xyz(tmp_path / "ref.xyz", reference)
    mov = write_xyz(tmp_path / "mov.xyz", moving)
    for flags, options in [
        ([], {}),
        (["--cost=axial", "--max_iterations=50", "--free=rx,ry,rz,tz", "--loss=huber"],
         {"cost": "axial", "max_iterations": 50, "free": ["rx", "ry", "rz", "tz"], "loss": "huber"}),
        (["--initial_rotation_deg=0,0,1.5", "--initial_translation=0.5,-0.5,0.25"],
         {"initial_rotation_deg": np.array([0.0, 0.0, 1.5]), "initial_translation": (0.5, -0.5, 0.25)}),
    ]:
        expected = cli_json("align", ref, mov, *flags)
        got = surfreg.align(ref, mov, **options)
        np.testing.assert_array_equal(got.matrix, np.array(expected["matrix"]))
        assert got.verdict == expected["verdict"] and got.iterations == expected["iterations"]
        assert got.stddev == expected["stddev"]
        same_measure(got.after, expected["after"])


def test_series_recovers_each_epochs_motion_and_equals_the_cli_json(tmp_path):
    """Three epochs of one field, each moved by its own motion: the joint
    matrices are the truth relative to the reference; the same numbers as
    `surfreg series --json` on the same files."""
    rng = np.random.default_rng(11)
    world = [np.eye(4)]
    epochs = []
    for k in range(3):
        points = sample(1500, 0.0 + 12 * k, 40.0 + 12 * k, 20 + k)
        if k:
            w = np.eye(4)
            w[:3, :3] = rotation(rng.normal(size=3), 0.5 + 0.3 * k)
            w[:3, 3] = rng.normal(0, 0.3, 3)
            world.append(w)
        epochs.append((points - world[k][:3, 3]) @ world[k][:3, :3])  # W^-1 p
    files = [write_xyz(tmp_path / ("e%d.xyz" % k), e) for k, e in enumerate(epochs)]
    got = surfreg.series(files, reference=1)
    assert len(got.epochs) == 3 and got.reference == 1
    np.testing.assert_array_equal(got.epochs[1].matrix, np.eye(4))
    for k, epoch in enumerate(got.epochs):
        truth = np.linalg.inv(world[1]) @ world[k]
        delta = epoch.matrix[:3, :3] @ truth[:3, :3].T
        assert np.degrees(np.arccos(min(1.0, (np.trace(delta) - 1) / 2))) < 0.02
        centre = np.append(epoch.centre, 1.0)
        assert np.linalg.norm((epoch.matrix @ centre - truth @ centre)[:3]) < 0.01
    expected = cli_json("series", *files, "--reference=1")
    for epoch, want in zip(got.epochs, expected["epochs"]):
        np.testing.assert_array_equal(epoch.matrix, np.array(want["matrix"]))
        assert epoch.stddev == want["stddev"] and epoch.verdict == want["verdict"]
    assert [(p.reference, p.moving) for p in got.pairs] == [(p["reference"], p["moving"]) for p in expected["pairs"]]
    # Arrays work as files do; a series that falls apart is refused in one line.
    np.testing.assert_array_equal(surfreg.series(epochs, reference=1).epochs[2].matrix, got.epochs[2].matrix)
    far = epochs[2] + np.array([1000.0, 0.0, 0.0])
    with pytest.raises(surfreg.InputError, match="overlaps no other"):
        surfreg.series([epochs[0], epochs[1], far])


def test_series_of_lonlat_files_is_solved_in_utm_as_the_cli_solves_it(tmp_path):
    """Two epochs written in degrees (a small patch near 40.6 N, 15 E):
    read as files with crs=, both are solved in UTM zone 33N, as `surfreg
    series --crs` does, to the same numbers; crs= is refused beside arrays."""
    epochs = []
    for k in range(2):
        points = sample(1500, 0.0, 60.0, 30 + k)
        if k:
            points = points @ rotation([0.2, 0.1, 1.0], 0.4).T + np.array([0.5, -0.3, 0.1])
        # ~1 m per 1e-5 degree: a patch about 50 m across
        epochs.append(np.column_stack([15.0 + points[:, 0] * 1.2e-5, 40.6 + points[:, 1] * 0.9e-5, points[:, 2]]))
    files = [write_xyz(tmp_path / ("g%d.xyz" % k), e) for k, e in enumerate(epochs)]
    try:
        got = surfreg.series(files, crs="EPSG:4326")
    except ValueError as e:  # surfreg.InputError
        if "built without GDAL" in str(e):
            pytest.skip("this surfreg was built without GDAL")
        raise
    expected = cli_json("series", *files, "--crs=EPSG:4326")
    assert got.frame.startswith("UTM zone 33N") and expected["frame"] == got.frame
    for epoch, want in zip(got.epochs, expected["epochs"]):
        np.testing.assert_array_equal(epoch.matrix, np.array(want["matrix"]))
    with pytest.raises(surfreg.InputError, match="every surface is a file"):
        surfreg.series([files[0], epochs[1]], crs="EPSG:4326")


def test_terrain_change_equals_the_cli_measure_json(tmp_path):
    data = pathlib.Path(__file__).resolve().parents[2] / "configs" / "data"
    a, b = str(data / "volcano_dem.tif"), str(data / "volcano_dem_moved.tif")
    dod = tmp_path / "dod.tif"
    try:
        t = surfreg.terrain_change(a, b, lod=0.5, sigma_reference=0.3, dod=dod)
    except ValueError as e:  # surfreg.InputError
        if "built without GDAL" in str(e):
            pytest.skip("this surfreg was built without GDAL")
        raise
    expected = cli_json("measure", a, b, "--lod=0.5", "--sigma_reference=0.3")
    assert isinstance(t, surfreg.TerrainChange) and dod.exists()
    same_measure(t.measure, expected)
    for key in ("count", "mean", "median", "nmad", "stddev", "rmse", "le90"):
        assert getattr(t.dz, key) == expected["dz"][key], key
    change = expected["change"]
    assert (t.fill, t.cut, t.net) == (change["fill"], change["cut"], change["net"])
    assert t.net_sigma_independent == change["uncertainty"]["net_sigma_independent"]
    assert t.metric and "EPSG:2193" in t.frame
    assert " m^3" in t.report() and "units" not in t.report()
    assert np.count_nonzero(np.isfinite(t.dz_a)) == t.dz.count
    assert np.isnan(t.net_sigma_spatial) and t.variogram == {}
    # The spatially correlated error model, as the CLI computes it.
    v = surfreg.terrain_change(a, b, lod_confidence=0.95, error_model="variogram")
    expected = cli_json("measure", a, b, "--lod_confidence=0.95", "--error_model=variogram")["change"]["uncertainty"]
    assert v.net_sigma_spatial == expected["net_sigma_spatial"] > 0
    assert (v.fill_sigma_spatial, v.cut_sigma_spatial) == (expected["fill_sigma_spatial"], expected["cut_sigma_spatial"])
    assert list(v.variogram["ranges"]) == expected["variogram"]["ranges"]
    assert v.variogram["stable_cells"] == expected["variogram"]["stable_cells"]


# --- bad input ------------------------------------------------------------


def test_asymmetry_equals_the_cli_json(tmp_path):
    face = str(pathlib.Path(__file__).resolve().parents[2] / "configs" / "data" / "face_a.xyz")
    square = [(2.0, -8.0), (7.0, -8.0), (7.0, -2.0), (2.0, -2.0)]
    polygon = tmp_path / "cheek.txt"
    polygon.write_text("".join("%r %r\n" % p for p in square))
    expected = cli_json("asymmetry", face, "--regions=cheek:%s" % polygon)
    got = surfreg.asymmetry(face, regions={"cheek": square})
    assert list(got.regions) == list(expected["regions"])
    for name, region in expected["regions"].items():
        for key, value in region.items():
            assert got.regions[name][key] == pytest.approx(value, rel=1e-9, abs=1e-12), (name, key)
    assert got.plane["normal"] == pytest.approx(expected["refined"]["plane"]["normal"], abs=1e-12)
    assert got.angle_deg == pytest.approx(expected["angle_deg"], rel=1e-9)
    assert got.noise_sigma == pytest.approx(expected["noise_sigma"], rel=1e-12)
    assert got.refined.rho_d == pytest.approx(expected["refined"]["rho_d"], rel=1e-12)
    assert got.points.shape == (expected["points"], 3) and got.difference.shape == (expected["points"],)
    # The array form: the same face in its frame gives the same indices.
    again = surfreg.asymmetry(got.points)
    assert again.regions["face"]["rms"] == pytest.approx(got.regions["face"]["rms"], rel=1e-9)
    with pytest.raises(surfreg.InputError, match="region 'two words'"):
        surfreg.asymmetry(face, regions={"two words": square})


def test_too_few_points():
    a = sample(100, 0.0, 10.0, seed=6)
    with pytest.raises(ValueError, match=r"^array reference: 2 points; a surface needs at least 3"):
        surfreg.align(a[:2], a)


def test_nan_coordinates():
    a = sample(100, 0.0, 10.0, seed=6)
    b = a.copy()
    b[3, 2] = np.nan
    with pytest.raises(ValueError, match=r"^array B: point 4 is not finite$"):
        surfreg.measure(a, b)


def test_wrong_array_shape():
    a = sample(100, 0.0, 10.0, seed=6)
    with pytest.raises(ValueError, match=r"^array A: expected an \(N, 3\) or \(N, 4\) array .*shape \(100, 2\)"):
        surfreg.measure(a[:, :2], a)
    with pytest.raises(ValueError, match=r"array moving: expected a Surface, a file path or an \(N, 3\)"):
        surfreg.align(a, {"x": 1})
    with pytest.raises(ValueError, match=r"^keyword 'initial_matrix': not a rigid motion"):
        surfreg.align(a, a, initial_matrix=2 * np.eye(4))


def test_unknown_keys_say_what_was_meant():
    a = sample(100, 0.0, 10.0, seed=6)
    with pytest.raises(ValueError, match=r"^keyword 'max_iteration': unknown key 'max_iteration' "
                                         r"\(did you mean 'max_iterations'\?\)"):
        surfreg.align(a, a, max_iteration=5)
    with pytest.raises(ValueError, match=r"^keyword 'volum': unknown key 'volum' \(did you mean 'volume'\?\)"):
        surfreg.measure(a, a, volum="union")
    with pytest.raises(ValueError, match=r"^keyword 'dod_png': terrain_change does not take it"):
        surfreg.terrain_change(a, a, dod_png="x.png")


def test_bad_values_carry_the_cli_message(tmp_path):
    a = write_xyz(tmp_path / "a.xyz", sample(100, 0.0, 10.0, seed=6))
    # The CLI says where with "flag '--KEY'", the module with "keyword 'KEY'";
    # the rest of the message is the same text (one key table).
    for key, value, flag_value in [("cost", "fast", "fast"), ("max_iterations", 0, "0"),
                                   ("free", ["rx", "up"], "[rx, up]"), ("trim_fraction", 0.75, "0.75")]:
        message = cli_error("align", a, a, f"--{key}={flag_value}")
        assert message.startswith(f"flag '--{key}'"), message
        with pytest.raises(ValueError) as raised:
            surfreg.align(a, a, **{key: value})
        assert str(raised.value) == f"keyword '{key}'" + message[len(f"flag '--{key}'"):]
    message = cli_error("align", a, a, "--domain=fast")  # measure's domain key is align's
    with pytest.raises(ValueError) as raised:
        surfreg.measure(a, a, domain="fast")
    assert str(raised.value) == message.replace("flag '--domain'", "keyword 'domain'")


def test_file_errors_are_the_cli_message(tmp_path):
    missing = str(tmp_path / "missing.xyz")
    a = write_xyz(tmp_path / "a.xyz", sample(100, 0.0, 10.0, seed=6))
    # The CLI starts with the argument ("argument B: "), the module with the file.
    with pytest.raises(ValueError) as raised:
        surfreg.measure(a, missing)
    assert "argument B: " + str(raised.value) == cli_error("measure", a, missing)
    with pytest.raises(ValueError) as raised:
        surfreg.align(missing, a)
    assert cli_error("align", missing, a).endswith(": " + str(raised.value))
    assert issubclass(surfreg.InputError, ValueError)


# --- installed -------------------------------------------------------------


def test_installed_module_imports(tmp_path):
    cmake, build = os.environ.get("SURFREG_CMAKE"), os.environ.get("SURFREG_BUILD_DIR")
    if not cmake or not build:
        pytest.skip("SURFREG_CMAKE and SURFREG_BUILD_DIR not set; ctest sets them")
    prefix = tmp_path / "prefix"
    done = subprocess.run([cmake, "--install", build, "--component", "python", "--prefix", str(prefix)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    site = prefix / "lib" / "python3" / "dist-packages"  # README "Use from Python"
    environment = dict(os.environ, PYTHONPATH=str(site))
    done = subprocess.run([sys.executable, "-c", "import surfreg; print(surfreg.__file__)"],
                          capture_output=True, text=True, env=environment, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert pathlib.Path(done.stdout.strip()).parent == site


# --- the GIL ----------------------------------------------------------------


def test_other_threads_run_while_align_runs():
    # If align held the GIL, this thread could not record a single tick
    # between the worker's two timestamps (only around them, while the
    # worker is in Python code); the middle half of the call has none then.
    reference, moving, _ = known_pair(n=20000)
    span = {}

    def work():
        span["start"] = time.perf_counter()
        span["result"] = surfreg.align(reference, moving, cost="axial")
        span["end"] = time.perf_counter()

    worker = threading.Thread(target=work)
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.002)
    worker.join()
    assert span["result"].verdict == "converged_improved"
    length = span["end"] - span["start"]
    assert length > 0.05, "the alignment was too short to tell"
    middle = [t for t in ticks if span["start"] + 0.25 * length < t < span["end"] - 0.25 * length]
    assert len(middle) >= 3, (len(middle), length)
