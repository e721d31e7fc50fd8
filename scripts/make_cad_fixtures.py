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

The chamfered peg (`chamfered_peg.step`, `chamfered_peg.igs`) is written by this
script itself, with the standard library only (no kernel was at hand offline), in the
form OpenCASCADE gives a chamfer: its four chamfer faces are degree (1,1)
`B_SPLINE_SURFACE_WITH_KNOTS` / IGES 128 surfaces with four coplanar control points
(one a rational complex instance, as OpenCASCADE writes rational ones), and the edges
around them are degree-1 `B_SPLINE_CURVE_WITH_KNOTS` / IGES 126 curves (one STEP edge a
`TRIMMED_CURVE` of a `LINE`); the other faces are planes, the other edges lines. The
peg is the plain peg (x, y in [36, 64], z in [10, 90]) with its four bottom edges
chamfered by 2 mm: 10 faces, 20 edges, 12 vertices, volume 62720 - 1568 + 4064/3.
`python3 scripts/make_cad_fixtures.py` writes these whenever it runs, and the others
only when OpenCASCADE (`OCP`) can be imported.

The time stamps the writers put in the headers are replaced by a fixed one, so
a rerun with the same kernel version gives the same bytes. The acsg tests read
the committed outputs and never need the package.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

try:
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakePolygon
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakePrism
    from OCP.gp import gp_Pnt, gp_Vec
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.IGESControl import IGESControl_Controller, IGESControl_Writer
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    HAVE_OCP = True
except ImportError:
    HAVE_OCP = False

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


# ---------------------------------------------------------------------------
# The chamfered peg, written without a kernel (standard library only).
# ---------------------------------------------------------------------------

def chamfered_peg():
    """Vertices and faces (loops counter-clockwise seen from outside) of the peg
    x, y in [36, 64], z in [10, 90] with its bottom edges chamfered by 2."""
    lo, hi, c = 36.0, 64.0, 2.0
    corners = [(lo, lo), (hi, lo), (hi, hi), (lo, hi)]
    top = [(x, y, 90.0) for x, y in corners]                       # T0..T3
    ring = [(x, y, 10.0 + c) for x, y in corners]                  # R0..R3
    bottom = [(x + (c if x == lo else -c), y + (c if y == lo else -c), 10.0)
              for x, y in corners]                                  # B0..B3
    v = top + ring + bottom
    T, R, B = (0, 1, 2, 3), (4, 5, 6, 7), (8, 9, 10, 11)
    faces = [("plane", [T[0], T[1], T[2], T[3]]),
             ("plane", [B[0], B[3], B[2], B[1]])]
    for k in range(4):
        n = (k + 1) % 4
        faces.append(("plane", [R[k], R[n], T[n], T[k]]))
    for k in range(4):
        n = (k + 1) % 4
        faces.append(("bspline", [B[k], B[n], R[n], R[k]]))
    return v, faces


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    n = math.sqrt(sum(x * x for x in a))
    return tuple(x / n for x in a)


def newell(points):
    n = [0.0, 0.0, 0.0]
    for i, p in enumerate(points):
        q = points[(i + 1) % len(points)]
        n[0] += (p[1] - q[1]) * (p[2] + q[2])
        n[1] += (p[2] - q[2]) * (p[0] + q[0])
        n[2] += (p[0] - q[0]) * (p[1] + q[1])
    return unit(n)


def real(x: float) -> str:
    """A real as OpenCASCADE writes it: `36.`, `-0.5`, `1.E-07`."""
    if x == int(x) and abs(x) < 1e15:
        return f"{int(x)}." if x != 0 or math.copysign(1, x) > 0 else "-0."
    text = repr(float(x)).upper()
    return text.replace("E-0", "E-0") if "E" in text else text


def edges_of(faces):
    """Each edge once: (a, b) in the direction of the first face that uses it, and
    whether it borders a chamfer (then it is written as a B-spline curve)."""
    edges, index, spline = [], {}, []
    for kind, loop in faces:
        for k, a in enumerate(loop):
            b = loop[(k + 1) % len(loop)]
            key = (min(a, b), max(a, b))
            if key not in index:
                index[key] = len(edges)
                edges.append((a, b))
                spline.append(False)
            if kind == "bspline":
                spline[index[key]] = True
    return edges, index, spline


def write_chamfered_step(path: Path) -> None:
    v, faces = chamfered_peg()
    edges, index, spline = edges_of(faces)
    lines = []
    ids = iter(range(1, 10_000))

    def add(text):
        i = next(ids)
        lines.append(f"#{i} = {text};")
        return i

    def point(p):
        return add(f"CARTESIAN_POINT('',({','.join(real(x) for x in p)}))")

    def direction(d):
        return add(f"DIRECTION('',({','.join(real(x) for x in d)}))")

    header = add("APPLICATION_PROTOCOL_DEFINITION('international standard',\n  'automotive_design',2000,#2)")
    add("APPLICATION_CONTEXT(\n  'core data for automotive mechanical design processes')")
    add("SHAPE_DEFINITION_REPRESENTATION(#4,#10)")
    add("PRODUCT_DEFINITION_SHAPE('','',#5)")
    add("PRODUCT_DEFINITION('design','',#6,#9)")
    add("PRODUCT_DEFINITION_FORMATION('','',#7)")
    add("PRODUCT('Open CASCADE STEP translator 8.0 3',\n  'Open CASCADE STEP translator 8.0 3','',(#8))")
    add("PRODUCT_CONTEXT('',#2,'mechanical')")
    add("PRODUCT_DEFINITION_CONTEXT('part definition',#2,'design')")
    assert header == 1
    shape_rep = add("ADVANCED_BREP_SHAPE_REPRESENTATION('',(#11,#15),#CONTEXT)")
    add("AXIS2_PLACEMENT_3D('',#12,#13,#14)")
    point((0.0, 0.0, 0.0))
    direction((0.0, 0.0, 1.0))
    direction((1.0, 0.0, -0.0))
    solid = add("MANIFOLD_SOLID_BREP('',#16)")
    shell_at = len(lines)
    add("CLOSED_SHELL('',(FACES))")
    vertex = [add(f"VERTEX_POINT('',#{point(p)})") for p in v]
    curve_ids = []
    for k, (a, b) in enumerate(edges):
        pa, pb = v[a], v[b]
        length = math.dist(pa, pb)
        if not spline[k]:
            line = add(f"LINE('',#{point(pa)},#{add(f'VECTOR({chr(39)}{chr(39)},#{direction(unit(sub(pb, pa)))},1.)')})")
            curve_ids.append(line)
        elif k == index[(min(5, 4), max(5, 4))]:
            # One edge as OpenCASCADE writes a trimmed line.
            line = add(f"LINE('',#{point(pa)},#{add(f'VECTOR({chr(39)}{chr(39)},#{direction(unit(sub(pb, pa)))},1.)')})")
            curve_ids.append(add(
                f"TRIMMED_CURVE('',#{line},(PARAMETER_VALUE(0.)),(PARAMETER_VALUE({real(length)})),.T.,\n  .PARAMETER.)"))
        else:
            p1, p2 = point(pa), point(pb)
            curve_ids.append(add(
                f"B_SPLINE_CURVE_WITH_KNOTS('',1,(#{p1},#{p2}),.UNSPECIFIED.,.F.,.F.,\n  (2,2),(0.,{real(length)}),.PIECEWISE_BEZIER_KNOTS.)"))
    edge_ids = [add(f"EDGE_CURVE('',#{vertex[a]},#{vertex[b]},#{curve_ids[k]},.T.)") for k, (a, b) in enumerate(edges)]
    face_ids = []
    chamfers = 0
    for kind, loop in faces:
        oriented = []
        for k, a in enumerate(loop):
            b = loop[(k + 1) % len(loop)]
            e = index[(min(a, b), max(a, b))]
            forward = edges[e] == (a, b)
            oriented.append(add(f"ORIENTED_EDGE('',*,*,#{edge_ids[e]},{'.T.' if forward else '.F.'})"))
        edge_loop = add(f"EDGE_LOOP('',({','.join(f'#{o}' for o in oriented)}))")
        bound = add(f"FACE_BOUND('',#{edge_loop},.T.)")
        pts = [v[i] for i in loop]
        if kind == "plane":
            normal = newell(pts)
            ref = unit(sub(pts[1], pts[0]))
            surface = add(f"PLANE('',#{add(f'AXIS2_PLACEMENT_3D({chr(39)}{chr(39)},#{point(pts[0])},#{direction(normal)},#{direction(ref)})')})")
        else:
            # net[i][j], i along u (loop[0] -> loop[1]), j along v (loop[0] -> loop[3]):
            # S_u x S_v points outward.
            a, b, c, d = (point(p) for p in pts)
            net = f"((#{a},#{d}),(#{b},#{c}))"
            lu, lv = math.dist(pts[0], pts[1]), math.dist(pts[0], pts[3])
            if chamfers == 0:
                surface = add(
                    f"( BOUNDED_SURFACE() B_SPLINE_SURFACE(1,1,{net},\n  .UNSPECIFIED.,.F.,.F.,.F.) "
                    f"B_SPLINE_SURFACE_WITH_KNOTS((2,2),(2,2),(0.,{real(lu)}),\n  (0.,{real(lv)}),.UNSPECIFIED.) "
                    "GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_SURFACE((\n  (1.,1.),(1.,1.))) "
                    "REPRESENTATION_ITEM('') SURFACE() )")
            else:
                surface = add(
                    f"B_SPLINE_SURFACE_WITH_KNOTS('',1,1,{net},\n  .UNSPECIFIED.,.F.,.F.,.F.,(2,2),(2,2),(0.,{real(lu)}),"
                    f"(0.,{real(lv)}),\n  .UNSPECIFIED.)")
            chamfers += 1
        face_ids.append(add(f"ADVANCED_FACE('',(#{bound}),#{surface},.T.)"))
    lines[shell_at] = lines[shell_at].replace("FACES", ",".join(f"#{f}" for f in face_ids))
    context = next(ids)
    mm = context + 1
    lines.append(
        f"#{context} = ( GEOMETRIC_REPRESENTATION_CONTEXT(3) \nGLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{context + 4})) "
        f"GLOBAL_UNIT_ASSIGNED_CONTEXT\n((#{mm},#{mm + 1},#{mm + 2})) REPRESENTATION_CONTEXT('Context #1',\n"
        "  '3D Context with UNIT and UNCERTAINTY') );")
    lines.append(f"#{mm} = ( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );")
    lines.append(f"#{mm + 1} = ( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );")
    lines.append(f"#{mm + 2} = ( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() );")
    lines.append(f"#{context + 4} = UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#{mm},\n"
                 "  'distance_accuracy_value','confusion accuracy');")
    lines.append(f"#{context + 5} = PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#7));")
    lines[shape_rep - 1] = lines[shape_rep - 1].replace("#CONTEXT", f"#{context}")
    assert solid == 15 and lines[15].startswith("#16 = CLOSED_SHELL")
    text = ("ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('Open CASCADE Model'),'2;1');\n"
            "FILE_NAME('Open CASCADE Shape Model','2024-01-01T00:00:00',('Author'),(\n"
            "    'Open CASCADE'),'Open CASCADE STEP processor 8.0','Open CASCADE 8.0'\n  ,'Unknown');\n"
            "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n"
            + "\n".join(lines) + "\nENDSEC;\nEND-ISO-10303-21;\n")
    path.write_text(text)


def iges_real(x: float) -> str:
    return real(x)


def write_chamfered_iges(path: Path) -> None:
    """IGES B-rep form (186, 514, 510, 508, 504, 502) with 190 planes and 110 lines,
    and 128 surfaces and 126 curves for the chamfers, laid out as OpenCASCADE does."""
    v, faces = chamfered_peg()
    edges, index, spline = edges_of(faces)
    entities = []  # [type, form, params (list of str), status]

    def add(kind, params, form=0, status="00010000"):
        entities.append([kind, form, params, status])
        return 2 * len(entities) - 1  # the DE number of the entry

    solid = add(186, ["SHELL", "1", "0"], status="00000000")
    shell = add(514, [], form=1)
    vlist = add(502, [str(len(v))] + [iges_real(x) for p in v for x in p], form=1)
    elist = add(504, [], form=1)
    edge_rows = []
    for k, (a, b) in enumerate(edges):
        pa, pb = v[a], v[b]
        if spline[k]:
            length = math.dist(pa, pb)
            curve = add(126, ["1", "1", "0", "0", "1", "0", "0.", "0.", iges_real(length), iges_real(length),
                              "1.", "1."] + [iges_real(x) for x in pa + pb]
                        + ["0.", iges_real(length), "0.", "0.", "0."])
        else:
            curve = add(110, [iges_real(x) for x in pa + pb])
        edge_rows += [str(curve), str(vlist), str(a + 1), str(vlist), str(b + 1)]
    entities[(elist - 1) // 2][2] = [str(len(edges))] + edge_rows
    face_des = []
    for kind, loop in faces:
        pts = [v[i] for i in loop]
        if kind == "plane":
            normal = newell(pts)
            location = add(116, [iges_real(x) for x in pts[0]] + ["0"], status="00010400")
            axis = add(123, [iges_real(x) for x in normal], status="00010200")
            ref = add(123, [iges_real(x) for x in unit(sub(pts[1], pts[0]))], status="00010200")
            surface = add(190, [str(location), str(axis), str(ref)], form=1)
        else:
            lu, lv = math.dist(pts[0], pts[1]), math.dist(pts[0], pts[3])
            # Control points P(i, j), i (along u) fastest: loop[0], loop[1], loop[3], loop[2].
            net = [pts[0], pts[1], pts[3], pts[2]]
            surface = add(128, ["1", "1", "1", "1", "0", "0", "1", "0", "0",
                                "0.", "0.", iges_real(lu), iges_real(lu), "0.", "0.", iges_real(lv), iges_real(lv),
                                "1.", "1.", "1.", "1."] + [iges_real(x) for p in net for x in p]
                          + ["0.", iges_real(lu), "0.", iges_real(lv)])
        row = []
        for k, a in enumerate(loop):
            b = loop[(k + 1) % len(loop)]
            e = index[(min(a, b), max(a, b))]
            row += ["0", str(elist), str(e + 1), "1" if edges[e] == (a, b) else "0", "0"]
        lp = add(508, [str(len(loop))] + row, form=1)
        face_des.append(add(510, [str(surface), "1", "1", str(lp)], form=1))
    entities[(shell - 1) // 2][2] = [str(len(face_des))] + [x for f in face_des for x in (str(f), "1")]
    entities[(solid - 1) // 2][2][0] = str(shell)

    # Parameter lines: columns 1-64 data, 66-72 the DE pointer.
    p_lines, starts = [], []
    for n, (kind, form, params, status) in enumerate(entities):
        de = 2 * n + 1
        starts.append(len(p_lines) + 1)
        tokens = [str(kind)] + params
        current = ""
        for k, t in enumerate(tokens):
            t += ";" if k == len(tokens) - 1 else ","
            if len(current) + len(t) > 64:
                p_lines.append((current, de))
                current = ""
            current += t
        p_lines.append((current, de))
    d_lines = []
    for n, (kind, form, params, status) in enumerate(entities):
        count = (starts[n + 1] if n + 1 < len(starts) else len(p_lines) + 1) - starts[n]
        d_lines.append(f"{kind:>8}{starts[n]:>8}{0:>8}{0:>8}{0:>8}{0:>8}{0:>8}{0:>8}{status:>8}")
        d_lines.append(f"{kind:>8}{0:>8}{0:>8}{count:>8}{form:>8}{'':>8}{'':>8}{'':>8}{0:>8}")
    start = " " * 72
    template = (OUT / "peg.igs").read_text().splitlines()
    global_lines = [line[:72] for line in template if line[72:73] == "G"]
    out = [f"{start}S{1:07d}"]
    out += [f"{g:<72}G{k + 1:07d}" for k, g in enumerate(global_lines)]
    out += [f"{d}D{k + 1:07d}" for k, d in enumerate(d_lines)]
    out += [f"{data:<64} {de:07d}P{k + 1:07d}" for k, (data, de) in enumerate(p_lines)]
    counts = f"S{1:7d}G{len(global_lines):7d}D{len(d_lines):7d}P{len(p_lines):7d}"
    out.append(f"{counts:<72}T{1:07d}")
    path.write_text("\n".join(out) + "\n")


class Step:
    """A Part 21 file written entity by entity, in OpenCASCADE's layout."""

    def __init__(self):
        self.lines = []

    def add(self, text):
        self.lines.append(text)
        return len(self.lines)

    def point(self, p):
        return self.add(f"CARTESIAN_POINT('',({','.join(real(x) for x in p)}))")

    def direction(self, d):
        return self.add(f"DIRECTION('',({','.join(real(x) for x in d)}))")

    def placement(self, origin, axis, ref):
        o, a, r = self.point(origin), self.direction(axis), self.direction(ref)
        return self.add(f"AXIS2_PLACEMENT_3D('',#{o},#{a},#{r})")

    def vertex(self, p):
        return self.add(f"VERTEX_POINT('',#{self.point(p)})")

    def line(self, p, d):
        vector = self.add(f"VECTOR('',#{self.direction(d)},1.)")
        return self.add(f"LINE('',#{self.point(p)},#{vector})")

    def edge(self, v1, v2, curve, sense=True):
        return self.add(f"EDGE_CURVE('',#{v1},#{v2},#{curve},{'.T.' if sense else '.F.'})")

    def face(self, loops, surface, same_sense=True):
        """`loops`: lists of (edge, forward); the first is the outer bound."""
        bounds = []
        for k, loop in enumerate(loops):
            oriented = [self.add(f"ORIENTED_EDGE('',*,*,#{e},{'.T.' if fwd else '.F.'})") for e, fwd in loop]
            edge_loop = self.add(f"EDGE_LOOP('',({','.join(f'#{o}' for o in oriented)}))")
            kind = "FACE_OUTER_BOUND" if k == 0 and len(loops) > 1 else "FACE_BOUND"
            bounds.append(self.add(f"{kind}('',#{edge_loop},.T.)"))
        return self.add(f"ADVANCED_FACE('',({','.join(f'#{b}' for b in bounds)}),#{surface},"
                        f"{'.T.' if same_sense else '.F.'})")

    def write(self, path: Path, faces):
        head = [
            "APPLICATION_PROTOCOL_DEFINITION('international standard',\n  'automotive_design',2000,#2)",
            "APPLICATION_CONTEXT(\n  'core data for automotive mechanical design processes')",
            "SHAPE_DEFINITION_REPRESENTATION(#4,#10)",
            "PRODUCT_DEFINITION_SHAPE('','',#5)",
            "PRODUCT_DEFINITION('design','',#6,#9)",
            "PRODUCT_DEFINITION_FORMATION('','',#7)",
            "PRODUCT('Open CASCADE STEP translator 8.0 3',\n  'Open CASCADE STEP translator 8.0 3','',(#8))",
            "PRODUCT_CONTEXT('',#2,'mechanical')",
            "PRODUCT_DEFINITION_CONTEXT('part definition',#2,'design')",
            "ADVANCED_BREP_SHAPE_REPRESENTATION('',(#11,#15),#CONTEXT)",
            "AXIS2_PLACEMENT_3D('',#12,#13,#14)",
            "CARTESIAN_POINT('',(0.,0.,0.))",
            "DIRECTION('',(0.,0.,1.))",
            "DIRECTION('',(1.,0.,-0.))",
            "MANIFOLD_SOLID_BREP('',#16)",
            "CLOSED_SHELL('',(FACES))",
        ]
        offset = len(head)
        renumber = lambda text: re.sub(r"#(\d+)", lambda m: f"#{int(m.group(1)) + offset}", text)
        body = [renumber(t) for t in self.lines]
        context = offset + len(body) + 1
        mm = context + 1
        head[9] = head[9].replace("#CONTEXT", f"#{context}")
        head[15] = head[15].replace("FACES", ",".join(f"#{f + offset}" for f in faces))
        lines = [f"#{k + 1} = {t};" for k, t in enumerate(head + body)]
        lines.append(
            f"#{context} = ( GEOMETRIC_REPRESENTATION_CONTEXT(3) \nGLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{context + 4})) "
            f"GLOBAL_UNIT_ASSIGNED_CONTEXT\n((#{mm},#{mm + 1},#{mm + 2})) REPRESENTATION_CONTEXT('Context #1',\n"
            "  '3D Context with UNIT and UNCERTAINTY') );")
        lines.append(f"#{mm} = ( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );")
        lines.append(f"#{mm + 1} = ( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );")
        lines.append(f"#{mm + 2} = ( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() );")
        lines.append(f"#{context + 4} = UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#{mm},\n"
                     "  'distance_accuracy_value','confusion accuracy');")
        lines.append(f"#{context + 5} = PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#7));")
        text = ("ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('Open CASCADE Model'),'2;1');\n"
                "FILE_NAME('Open CASCADE Shape Model','2024-01-01T00:00:00',('Author'),(\n"
                "    'Open CASCADE'),'Open CASCADE STEP processor 8.0','Open CASCADE 8.0'\n  ,'Unknown');\n"
                "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n"
                + "\n".join(lines) + "\nENDSEC;\nEND-ISO-10303-21;\n")
        path.write_text(text)


def circle_edge(step, centre, radius, vertex):
    """A full circle about +z through `vertex` (at angle 0: the reference direction
    +x), as OpenCASCADE writes it: an EDGE_CURVE from the vertex to itself."""
    circle = step.add(f"CIRCLE('',#{step.placement(centre, (0, 0, 1), (1, 0, 0))},{real(radius)})")
    return step.edge(vertex, vertex, step.add(f"SURFACE_CURVE('',#{circle},(),.PCURVE_S1.)"))


def seam_edge(step, v1, p1, v2):
    return step.edge(v1, v2, step.add(f"SEAM_CURVE('',#{step.line(p1, (0, 0, 1))},(),.PCURVE_S1.)"))


def write_round_peg_step(path: Path) -> None:
    """The round peg of scripts/make_fixtures.py as a true cylinder: axis x = y = 50,
    z in [10, 90], radius 14 (the OFF's circumradius), seam at angle 0."""
    step = Step()
    c, r, z0, z1 = (50.0, 50.0), 14.0, 10.0, 90.0
    pb, pt = (c[0] + r, c[1], z0), (c[0] + r, c[1], z1)
    vb, vt = step.vertex(pb), step.vertex(pt)
    bottom = circle_edge(step, (c[0], c[1], z0), r, vb)
    top = circle_edge(step, (c[0], c[1], z1), r, vt)
    seam = seam_edge(step, vb, pb, vt)
    faces = [
        step.face([[(top, True)]], step.add(f"PLANE('',#{step.placement((c[0], c[1], z1), (0, 0, 1), (1, 0, 0))})")),
        step.face([[(bottom, False)]],
                  step.add(f"PLANE('',#{step.placement((c[0], c[1], z0), (0, 0, 1), (1, 0, 0))})"), False),
        step.face([[(bottom, True), (seam, True), (top, False), (seam, False)]],
                  step.add(f"CYLINDRICAL_SURFACE('',#{step.placement((c[0], c[1], z0), (0, 0, 1), (1, 0, 0))},"
                           f"{real(r)})")),
    ]
    step.write(path, faces)


def write_round_hole_step(path: Path) -> None:
    """The block with a round hole of scripts/make_fixtures.py as true surfaces: block
    x, y in [0, 100], z in [0, 50]; a cylinder of radius 15 about x = y = 50 for
    z in [0, 47], then a cone to the radius 15 + 3 / cos(pi / 32) at z = 50 (the OFF's
    chamfer, whose apothem is 15 cos(pi / 32) + 3)."""
    step = Step()
    c, r, z_cone = (50.0, 50.0), 15.0, 47.0
    r_top = 15.0 + 3.0 / math.cos(math.pi / 32)
    corners = [(0.0, 0.0), (100.0, 0.0), (100.0, 100.0), (0.0, 100.0)]
    low = [step.vertex((x, y, 0.0)) for x, y in corners]
    high = [step.vertex((x, y, 50.0)) for x, y in corners]
    bottom_edges, top_edges, vertical = [], [], []
    for k, (x, y) in enumerate(corners):
        nx, ny = corners[(k + 1) % 4]
        d = unit((nx - x, ny - y, 0.0))
        bottom_edges.append(step.edge(low[k], low[(k + 1) % 4], step.line((x, y, 0.0), d)))
        top_edges.append(step.edge(high[k], high[(k + 1) % 4], step.line((x, y, 50.0), d)))
        vertical.append(step.edge(low[k], high[k], step.line((x, y, 0.0), (0, 0, 1))))
    p0, p1, p2 = (c[0] + r, c[1], 0.0), (c[0] + r, c[1], z_cone), (c[0] + r_top, c[1], 50.0)
    h0, h1, h2 = step.vertex(p0), step.vertex(p1), step.vertex(p2)
    circle0 = circle_edge(step, (c[0], c[1], 0.0), r, h0)
    circle1 = circle_edge(step, (c[0], c[1], z_cone), r, h1)
    circle2 = circle_edge(step, (c[0], c[1], 50.0), r_top, h2)
    seam0 = seam_edge(step, h0, p0, h1)
    cone_dir = unit(sub(p2, p1))
    seam1 = step.edge(h1, h2, step.add(f"SEAM_CURVE('',#{step.line(p1, cone_dir)},(),.PCURVE_S1.)"))
    plane = lambda z, n: step.add(f"PLANE('',#{step.placement((0.0, 0.0, z), n, (1, 0, 0))})")
    faces = [
        step.face([[(e, True) for e in top_edges], [(circle2, False)]], plane(50.0, (0, 0, 1))),
        step.face([[(e, False) for e in reversed(bottom_edges)], [(circle0, True)]], plane(0.0, (0, 0, 1)), False),
    ]
    for k, (x, y) in enumerate(corners):
        n = (k + 1) % 4
        normal = cross(unit((corners[n][0] - x, corners[n][1] - y, 0.0)), (0, 0, 1))
        surface = step.add(f"PLANE('',#{step.placement((x, y, 0.0), normal, unit((corners[n][0] - x, corners[n][1] - y, 0.0)))})")
        faces.append(step.face([[(bottom_edges[k], True), (vertical[n], True), (top_edges[k], False),
                                 (vertical[k], False)]], surface))
    cylinder = step.add(f"CYLINDRICAL_SURFACE('',#{step.placement((c[0], c[1], 0.0), (0, 0, 1), (1, 0, 0))},{real(r)})")
    faces.append(step.face([[(circle0, True), (seam0, True), (circle1, False), (seam0, False)]], cylinder, False))
    semi_angle = math.atan2(r_top - r, 50.0 - z_cone)
    cone = step.add(f"CONICAL_SURFACE('',#{step.placement((c[0], c[1], z_cone), (0, 0, 1), (1, 0, 0))},{real(r)},"
                    f"{real(semi_angle)})")
    faces.append(step.face([[(circle1, True), (seam1, True), (circle2, False), (seam1, False)]], cone, False))
    step.write(path, faces)


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    write_round_peg_step(OUT / "round_peg.step")
    write_round_hole_step(OUT / "block_with_round_hole.step")
    write_chamfered_step(OUT / "chamfered_peg.step")
    write_chamfered_iges(OUT / "chamfered_peg.igs")
    print("fixtures/cad/chamfered_peg.step, .igs, round_peg.step, block_with_round_hole.step (standard library)")
    if not HAVE_OCP:
        print("OpenCASCADE (OCP) is not installed: the other fixtures are left as committed")
        return
    occ_main()


def occ_main() -> None:
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
