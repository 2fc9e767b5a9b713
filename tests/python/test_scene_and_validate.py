"""lhr.load_scene, lhr.validate and lhr.read_mesh."""

import numpy as np
import pytest

import lhr
from conftest import CORNELL, read_triangle_ply


def test_load_scene_cornell():
    scene = lhr.load_scene(CORNELL)
    v = scene.vertices
    assert v.ndim == 2 and v.shape[1] == 3 and v.dtype == np.float64 and len(v) > 0
    assert len(scene.faces) == len(scene.face_surface) == len(scene.face_material) > 0
    assert all(len(f) >= 3 and 0 <= min(f) and max(f) < len(v) for f in scene.faces)
    assert scene.face_material.max() < len(scene.materials)
    assert scene.face_surface.max() == len(scene.surfaces) - 1
    assert sum(s["vertex_count"] for s in scene.surfaces) == len(v)
    names = {m["name"] for m in scene.materials}
    assert {"white", "red", "green"} <= names
    assert any(max(m["emission"]) > 0 for m in scene.materials)
    assert all(0 <= c < 1 for m in scene.materials for c in m["reflectance"])
    # The Cornell box is 0..~556 units on each axis.
    assert v.min() > -1 and v.max() < 600
    assert scene.camera["eye"] == [278.0, 273.0, -800.0]
    assert (scene.camera["width"], scene.camera["height"]) == (512, 512)
    assert scene.source.endswith("cornell.scene.json")
    # The published box draws its light on the ceiling; loading moves it off.
    assert any("lies on the plane of ceiling" in w for w in scene.warnings), scene.warnings


def test_load_bare_obj_gets_a_framing_camera():
    scene = lhr.load_scene(CORNELL.with_name("cornell.obj"))
    from_file = lhr.load_scene(CORNELL)
    assert len(scene.surfaces) == len(from_file.surfaces)
    np.testing.assert_array_equal(scene.vertices, from_file.vertices)
    # Not the scene file's camera: one looking at the whole box.
    assert scene.camera["eye"] != from_file.camera["eye"]
    centre = (scene.vertices.min(axis=0) + scene.vertices.max(axis=0)) / 2
    np.testing.assert_allclose(scene.camera["target"], centre, rtol=1e-6)


def test_load_scene_tone_map_is_the_defaults_with_the_files_block_over_them(tmp_path):
    scene_file = tmp_path / "box.scene.json"
    scene_file.write_text('{"mesh": "%s", "tone_map": {"kind": "linear", "gamma": 1.8}}'
                          % CORNELL.with_name("cornell.obj").as_posix())
    tone = lhr.load_scene(scene_file).settings["tone_map"]
    assert tone == {"kind": "linear", "world_adaptation": 0.0, "units_to_cd_m2": 1.0,
                    "display_max_cd_m2": 100.0, "max_contrast": 100.0, "gamma": 1.8, "white": 0.0}
    assert lhr.load_scene(CORNELL).settings["tone_map"]["kind"] == "tumblin-rushmeier"


def test_load_scene_missing_file_names_it(tmp_path):
    with pytest.raises(lhr.InputError, match="absent.obj"):
        lhr.load_scene(tmp_path / "absent.obj")


def write_ascii_ply(path, points, faces):
    lines = ["ply", "format ascii 1.0", f"element vertex {len(points)}", "property float x",
             "property float y", "property float z", f"element face {len(faces)}",
             "property list uchar int vertex_indices", "end_header"]
    lines += [" ".join(str(c) for c in p) for p in points]
    lines += [" ".join(str(i) for i in [len(f), *f]) for f in faces]
    path.write_text("\n".join(lines) + "\n")


SQUARE = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]


def test_validate_accepts_a_good_mesh(tmp_path):
    path = tmp_path / "square.ply"
    write_ascii_ply(path, SQUARE, [(0, 1, 2), (0, 2, 3)])
    assert lhr.validate(path) == []


def test_validate_reports_a_flipped_face(tmp_path):
    path = tmp_path / "flipped.ply"
    write_ascii_ply(path, SQUARE, [(0, 1, 2), (0, 3, 2)])
    violations = lhr.validate(path)
    assert [v.kind for v in violations] == ["orientation"], [str(v) for v in violations]
    assert violations[0].where == "edge (0,2)"


def test_validate_reports_a_non_manifold_edge(tmp_path):
    path = tmp_path / "fin.ply"
    points = SQUARE + [(0.5, 0.5, 1)]
    # Three triangles on the diagonal edge (0,2).
    write_ascii_ply(path, points, [(0, 1, 2), (0, 2, 3), (2, 0, 4)])
    violations = lhr.validate(path)
    assert [(v.kind, v.where) for v in violations] == [("non-manifold-edge", "edge (0,2)")], violations
    assert "shared by 3 faces" in str(violations[0])


def test_validate_the_commands_mesh(cli_quick_linear):
    (ply, faces), stats, out_dir = cli_quick_linear
    mesh_ply = out_dir / "mesh.ply"
    assert lhr.validate(mesh_ply) == []
    mesh = lhr.read_mesh(mesh_ply)
    assert len(mesh.vertices) == stats["exported_vertices"] == len(ply["x"])
    np.testing.assert_array_equal(np.array(mesh.faces), faces)
    assert mesh.radiance.shape == (len(ply["x"]), 3)
    np.testing.assert_array_equal(mesh.radiance[:, 0].astype(np.float32), ply["radiance_r"])


def test_validate_missing_file_names_it(tmp_path):
    with pytest.raises(lhr.InputError, match="gone.ply"):
        lhr.validate(tmp_path / "gone.ply")


def test_read_mesh_without_radiance(tmp_path):
    path = tmp_path / "square.ply"
    write_ascii_ply(path, SQUARE, [(0, 1, 2), (0, 2, 3)])
    mesh = lhr.read_mesh(path)
    np.testing.assert_array_equal(mesh.vertices, np.array(SQUARE, dtype=float))
    assert mesh.faces == [[0, 1, 2], [0, 2, 3]]
    assert mesh.radiance is None
