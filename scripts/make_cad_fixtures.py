#!/usr/bin/env python3
"""Write the STEP and IGES fixtures in fixtures/cad/ with a real CAD kernel.

The parts are built as exact B-reps by OpenCASCADE (through the `cadquery-ocp`
wheel from PyPI, which bundles it) with the same dimensions as the OFF fixtures
of scripts/make_fixtures.py, and written by OpenCASCADE's own STEP and IGES
writers:

* `<part>.step`       STEP AP214, millimetres;
* `<part>.igs`        IGES B-rep form (186 manifold solid, 514 shell, 510 face,
                      508 loop, 504 edge list, 502 vertex list, 190 plane, 110 line),
                      millimetres (`write.iges.brep.mode` = 1);
* `<part>_faces.igs`  IGES trimmed-surface form (144 trimmed surface, 108 plane,
                      142 curve on surface, 102 composite curve, 110 line), mm;
* `peg_inch.step`, `peg_inch.igs`: the peg written in inches, for the unit tests.

Run once, from anywhere (the package is large, so use a throw-away venv):

    python3 -m venv /tmp/cadvenv && /tmp/cadvenv/bin/pip install cadquery-ocp
    /tmp/cadvenv/bin/python scripts/make_cad_fixtures.py

The time stamps the writers put in the headers are replaced by a fixed one, so
a rerun with the same kernel version gives the same bytes. The acsg tests read
the committed outputs and never need the package.
"""

from __future__ import annotations

import re
from pathlib import Path

from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakePolygon
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakePrism
from OCP.gp import gp_Pnt, gp_Vec
from OCP.IFSelect import IFSelect_RetDone
from OCP.IGESControl import IGESControl_Controller, IGESControl_Writer
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

OUT = Path(__file__).resolve().parent.parent / "fixtures" / "cad"


def box(x0, y0, z0, x1, y1, z1):
    return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape()


def l_block():
    """L profile in the (x, z) plane at y = 0, extruded by 100 along y."""
    profile = [(0, 0), (200, 0), (200, 150), (150, 150), (150, 50), (0, 50)]
    poly = BRepBuilderAPI_MakePolygon()
    for x, z in profile:
        poly.Add(gp_Pnt(x, 0, z))
    poly.Close()
    face = BRepBuilderAPI_MakeFace(poly.Wire(), True).Face()
    return BRepPrimAPI_MakePrism(face, gp_Vec(0, 100, 0)).Shape()


def block_with_hole():
    """Block x,y [0,100], z [0,50] with the through-hole x,y [35,65]."""
    return BRepAlgoAPI_Cut(box(0, 0, 0, 100, 100, 50), box(35, 35, -10, 65, 65, 60)).Shape()


def peg():
    """Peg x,y [36,64], z [10,90]."""
    return box(36, 36, 10, 64, 64, 90)


def write_step(shape, path: Path, unit: str) -> None:
    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    Interface_Static.SetCVal_s("write.step.unit", unit)
    writer = STEPControl_Writer()
    if writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone:
        raise SystemExit(f"STEP transfer failed for {path}")
    if writer.Write(str(path)) != IFSelect_RetDone:
        raise SystemExit(f"cannot write {path}")
    text = path.read_text()
    text = re.sub(r"'\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d'", "'2024-01-01T00:00:00'", text, count=1)
    path.write_text(text)


def write_iges(shape, path: Path, unit: str, brep: bool) -> None:
    IGESControl_Controller.Init_s()
    Interface_Static.SetCVal_s("write.iges.unit", unit)
    Interface_Static.SetIVal_s("write.iges.brep.mode", 1 if brep else 0)
    writer = IGESControl_Writer(unit, 1 if brep else 0)
    if not writer.AddShape(shape):
        raise SystemExit(f"IGES transfer failed for {path}")
    writer.ComputeModel()
    if not writer.Write(str(path)):
        raise SystemExit(f"cannot write {path}")
    # Dates are 15-character Hollerith strings: same width, so the columns stay put.
    text = path.read_text()
    text = re.sub(r"15H\d{8}\.\d{6}", "15H20240101.000000", text)
    path.write_text(text)


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    parts = {"l_block": l_block(), "block_with_hole": block_with_hole(), "peg": peg()}
    for name, shape in parts.items():
        write_step(shape, OUT / f"{name}.step", "MM")
        write_iges(shape, OUT / f"{name}.igs", "MM", brep=True)
        write_iges(shape, OUT / f"{name}_faces.igs", "MM", brep=False)
    write_step(parts["peg"], OUT / "peg_inch.step", "INCH")
    write_iges(parts["peg"], OUT / "peg_inch.igs", "IN", brep=True)
    for path in sorted(OUT.iterdir()):
        print(f"{path.relative_to(OUT.parent.parent)}: {path.stat().st_size} bytes")


if __name__ == "__main__":
    main()
