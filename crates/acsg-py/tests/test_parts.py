"""Parts from paths, trimesh meshes and arrays; errors with the library's messages."""

import numpy as np
import pytest

import acsg
from conftest import FIXTURES, fixture

CUBE = (
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
)


@pytest.mark.parametrize("name", ["l_block.off", "l_block.obj", "l_block.stl", "l_block_binary.stl", "l_block.ply"])
def test_every_format_gives_the_same_part(name):
    part = acsg.part(fixture(name))
    assert part.counts == (12, 18, 8)
    assert part.volume == pytest.approx(1_500_000)
    # The same B-rep with the same numbering whatever the format (names aside).
    assert _geometry(part) == _geometry(acsg.part(fixture("l_block.off")))


def _geometry(part):
    return part.elements_json().split('"vertices"', 1)[1]


def test_arrays_quads_triangles_and_numpy():
    quads = acsg.part(CUBE)
    assert quads.counts == (8, 12, 6) and quads.volume == pytest.approx(1.0)
    vertices = np.array(CUBE[0], dtype=np.float32)
    triangles = np.array([[p[0], p[k], p[k + 1]] for p in CUBE[1] for k in (1, 2)], dtype=np.int64)
    tri = acsg.part((vertices, triangles), name="cube")
    assert tri.counts == (8, 12, 6) and tri.name == "cube"
    assert tri.elements_json().replace('"cube"', '"mesh"') == quads.elements_json()


def test_trimesh_mesh_is_the_same_part_as_its_file():
    trimesh = pytest.importorskip("trimesh")
    mesh = trimesh.load(fixture("l_block.stl"))
    from_mesh = acsg.part(mesh)
    from_file = acsg.part(fixture("l_block.off"))
    assert from_mesh.counts == from_file.counts
    # The same B-rep with the same numbering (names aside).
    assert _geometry(from_mesh) == _geometry(from_file)


def test_part_errors_carry_the_library_messages():
    with pytest.raises(acsg.AcsgError, match="cannot read the file"):
        acsg.part(FIXTURES / "no_such_part.off")
    with pytest.raises(acsg.AcsgError, match="not a valid solid"):
        acsg.part((CUBE[0], CUBE[1][:-1]), name="open box")
    with pytest.raises(acsg.AcsgError, match="open box"):
        acsg.part((CUBE[0], CUBE[1][:-1]), name="open box")
    with pytest.raises(ValueError, match="index"):
        acsg.part((CUBE[0], [[0, 1, 99]]))
    with pytest.raises(ValueError, match="shape"):
        acsg.part(([[0, 0], [1, 1]], [[0, 1, 2]]))
    with pytest.raises(TypeError, match="cannot make a part"):
        acsg.part(42)
    with pytest.raises(ValueError, match="units"):
        acsg.part(fixture("cube.off"), units="furlong")


def test_bad_fixtures_are_refused():
    for path in sorted((FIXTURES / "bad").iterdir()):
        if path.suffix.lower() in {".off", ".obj", ".stl", ".ply"}:
            with pytest.raises(acsg.AcsgError):
                acsg.part(path)


@pytest.mark.parametrize("name", ["cad/l_block.step", "cad/l_block.igs"])
def test_cad_files_give_the_same_part_as_the_mesh(name):
    assert _geometry(acsg.part(fixture(name))) == _geometry(acsg.part(fixture("l_block.off")))


def test_cad_units_and_facets():
    # A peg written in inches, read in mm (the default for CAD files) and in inches.
    in_mm = acsg.part(fixture("cad/peg_inch.step"))
    in_inches = acsg.part(fixture("cad/peg_inch.step"), units="in")
    assert in_mm.volume == pytest.approx(in_inches.volume * 25.4**3)
    # Curved faces need facet=, and say so.
    with pytest.raises(acsg.AcsgError, match="facet"):
        acsg.part(fixture("cad/round_peg.step"))
    faceted = acsg.part(fixture("cad/round_peg.step"), facet=0.05)
    assert faceted.counts[2] > 10
    with pytest.raises(ValueError, match="facet"):
        acsg.part(fixture("cad/round_peg.step"), facet=-1.0)
