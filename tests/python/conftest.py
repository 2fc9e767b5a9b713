"""Fixtures of the Python module's tests (tools/test-python.sh runs them
against the installed module and the installed lhr executable)."""

import json
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import lhr

SOURCE_DIR = Path(__file__).resolve().parents[2]
CORNELL = SOURCE_DIR / "data" / "cornell" / "cornell.scene.json"

# A quick Cornell box: a coarse initial mesh and coarse thresholds, seconds
# on two cores. Keyword -> the value given to both solve() and `lhr solve`.
QUICK_LINEAR = {"method": "linear", "max_edge": 140.0, "eps_pixel": 5.0, "eps_link": 400.0,
                "eps_vertex": 0.0, "threads": 2}
QUICK_CLASSICAL = {"method": "classical", "max_edge": 140.0, "eps_bf": 0.05, "threads": 2}

_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read_triangle_ply(path):
    """Vertex properties (name -> array) and the M x 3 triangles of a binary
    little-endian PLY, parsed here rather than by the library under test."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    elements = []
    for line in data[:end].decode("ascii").splitlines():
        words = line.split()
        if words[:1] == ["format"]:
            assert words[1] == "binary_little_endian", line
        elif words[:1] == ["element"]:
            elements.append((words[1], int(words[2]), []))
        elif words[:1] == ["property"]:
            elements[-1][2].append(words[1:])
    names = [e[0] for e in elements]
    assert names == ["vertex", "face"], names
    (_, n_vertices, vertex_props), (_, n_faces, face_props) = elements
    vertex_dtype = np.dtype([(p[1], "<" + _PLY_TYPES[p[0]]) for p in vertex_props])
    vertices = np.frombuffer(data, vertex_dtype, n_vertices, end)
    # lhr writes triangles only: every face is "3 a b c".
    assert face_props[0][0] == "list" and len(face_props) == 1, face_props
    count_type, index_type = _PLY_TYPES[face_props[0][1]], _PLY_TYPES[face_props[0][2]]
    face_dtype = np.dtype([("n", "<" + count_type), ("v", "<" + index_type, 3)])
    faces = np.frombuffer(data, face_dtype, n_faces, end + vertex_dtype.itemsize * n_vertices)
    assert (faces["n"] == 3).all()
    assert end + vertex_dtype.itemsize * n_vertices + face_dtype.itemsize * n_faces == len(data)
    return {name: vertices[name] for name in vertex_dtype.names}, faces["v"].astype(np.int64)


def lhr_executable():
    exe = os.environ.get("LHR_EXECUTABLE") or shutil.which("lhr")
    if not exe:
        pytest.fail("set LHR_EXECUTABLE to the lhr executable (tools/test-python.sh does)")
    return exe


def cli_flags(keywords):
    flags = []
    for key, value in keywords.items():
        flags += ["--" + key.replace("_", "-"), str(value)]
    return flags


def run_cli_solve(scene, out_dir, keywords):
    subprocess.run([lhr_executable(), "solve", str(scene), "--out", str(out_dir), "--quiet"]
                   + cli_flags(keywords), check=True)
    with open(out_dir / "stats.json") as f:
        stats = json.load(f)
    return read_triangle_ply(out_dir / "mesh.ply"), stats, out_dir


@pytest.fixture(scope="session")
def quick_linear():
    return lhr.solve(CORNELL, **QUICK_LINEAR)


@pytest.fixture(scope="session")
def cli_quick_linear(tmp_path_factory):
    return run_cli_solve(CORNELL, tmp_path_factory.mktemp("cli_linear"), QUICK_LINEAR)

