"""lhr.solve: the arrays it returns and their agreement with `lhr solve`."""

import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import lhr
from conftest import CORNELL, QUICK_CLASSICAL, QUICK_LINEAR, lhr_executable, run_cli_solve


def test_shapes_and_dtypes(quick_linear):
    r = quick_linear
    n, m = len(r.vertices), len(r.faces)
    assert n > 100 and m > 100
    assert r.vertices.shape == (n, 3) and r.vertices.dtype == np.float64
    assert r.faces.shape == (m, 3) and np.issubdtype(r.faces.dtype, np.integer)
    assert r.radiance.shape == (n, 3) and r.radiance.dtype == np.float64
    assert r.colors.shape == (n, 3) and r.colors.dtype == np.uint8
    assert r.faces.min() >= 0 and r.faces.max() < n
    assert isinstance(r.stats, dict)
    assert r.stats["exported_vertices"] == n and r.stats["exported_triangles"] == m


def test_radiance_is_finite_non_negative_and_lit(quick_linear):
    radiance = quick_linear.radiance
    assert np.isfinite(radiance).all()
    assert (radiance >= 0).all()
    # The light and what it shines on: not a black result.
    assert radiance.max() > 0
    assert len(np.unique(quick_linear.colors, axis=0)) > 10


def test_same_mesh_as_the_command(quick_linear, cli_quick_linear):
    (ply, faces), _, _ = cli_quick_linear
    r = quick_linear
    assert len(ply["x"]) == len(r.vertices)
    # mesh.ply stores float32: the same values rounded.
    stored = np.stack([ply["x"], ply["y"], ply["z"]], axis=1)
    np.testing.assert_array_equal(r.vertices.astype(np.float32), stored)
    np.testing.assert_array_equal(r.faces, faces)
    radiance = np.stack([ply["radiance_r"], ply["radiance_g"], ply["radiance_b"]], axis=1)
    np.testing.assert_array_equal(r.radiance.astype(np.float32), radiance)
    colors = np.stack([ply["red"], ply["green"], ply["blue"]], axis=1)
    np.testing.assert_array_equal(r.colors, colors)


def test_same_stats_as_the_command(quick_linear, cli_quick_linear):
    _, cli_stats, _ = cli_quick_linear
    ours = dict(quick_linear.stats)
    # Timings vary from run to run; the module writes no files and leaves
    # out the interpreter's peak memory.
    ours_seconds, cli_seconds = ours.pop("seconds"), cli_stats.pop("seconds")
    cli_stats.pop("peak_memory_mib")
    assert set(ours_seconds) == set(cli_seconds) - {"output"}
    assert ours == cli_stats
    assert ours["method"] == "linear" and ours["parameters"]["eps_link"] == 400.0
    assert ours["parameters"]["max_edge"] == 140.0


def test_classical_matches_the_command(tmp_path):
    r = lhr.solve(str(CORNELL), **QUICK_CLASSICAL)
    (ply, faces), stats, _ = run_cli_solve(CORNELL, tmp_path, QUICK_CLASSICAL)
    assert r.stats["method"] == "classical" == stats["method"]
    assert r.stats["parameters"]["eps_bf"] == 0.05
    np.testing.assert_array_equal(r.faces, faces)
    radiance = np.stack([ply["radiance_r"], ply["radiance_g"], ply["radiance_b"]], axis=1)
    np.testing.assert_array_equal(r.radiance.astype(np.float32), radiance)
    assert (r.radiance >= 0).all() and r.radiance.max() > 0


def test_version_matches_the_command(quick_linear):
    out = subprocess.run([lhr_executable(), "--version"], check=True, capture_output=True, text=True).stdout
    assert lhr.__version__ in out
    assert quick_linear.stats["lhr_version"] == lhr.__version__


def test_warnings_start_with_the_loaders(quick_linear):
    loaded = lhr.load_scene(CORNELL).warnings
    assert loaded and quick_linear.warnings[:len(loaded)] == loaded


def test_budget_warning_names_the_keyword():
    r = lhr.solve(CORNELL, max_links=1, **QUICK_LINEAR)
    assert r.stats["link_budget_reached"] is True
    assert any("max_links reached" in w for w in r.warnings), r.warnings


def test_missing_scene_raises_with_its_name(tmp_path):
    missing = tmp_path / "no_such.scene.json"
    with pytest.raises(lhr.InputError, match="no_such.scene.json"):
        lhr.solve(missing)
    assert issubclass(lhr.InputError, ValueError)


def test_broken_scene_file_raises_with_file_and_problem(tmp_path):
    scene = tmp_path / "broken.scene.json"
    scene.write_text('{\n  "mesh": "nothing.obj",\n  "camera": 3\n}\n')
    with pytest.raises(lhr.InputError) as error:
        lhr.solve(scene, **QUICK_LINEAR)
    message = str(error.value)
    assert "broken.scene.json" in message and "\n" not in message


@pytest.mark.parametrize("keywords, name", [
    ({"eps_link": -1.0}, "eps_link"),
    ({"eps_bf": 0.0}, "eps_bf"),
    ({"eps_power": 0.0}, "eps_power"),
    ({"max_iterations": 0}, "max_iterations"),
    ({"max_edge": -5.0}, "max_edge"),
    ({"gamma": 0.0}, "gamma"),
    ({"tone_map": "reinhard"}, "tone_map"),
    ({"method": "radiant"}, "method"),
    ({"threads": -1}, "threads"),
])
def test_bad_option_raises_value_error_naming_it(keywords, name):
    with pytest.raises(ValueError, match=name):
        lhr.solve(CORNELL, **{**QUICK_LINEAR, **keywords})


def test_solve_releases_the_gil():
    ticks = 0
    done = threading.Event()
    worker = threading.Thread(target=lambda: (lhr.solve(CORNELL, **QUICK_LINEAR), done.set()))
    worker.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.005)
    worker.join()
    # Held through the solve (well over a second), the GIL would let this
    # loop run only before and after it.
    assert ticks > 20


def test_signal_handler_stops_a_long_solve():
    class Stop(Exception):
        pass

    def stop(signum, frame):
        raise Stop()

    previous = signal.signal(signal.SIGALRM, stop)
    start = time.monotonic()
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.3)
        with pytest.raises(Stop):
            # The default thresholds: tens of seconds when not stopped.
            lhr.solve(CORNELL, max_edge=140.0, threads=2)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    assert time.monotonic() - start < 8.0
