#!/usr/bin/env python3
"""Write the small fixture models used by the acsg tests into fixtures/.

Python 3.11, standard library only, deterministic (same bytes every run).
Run from anywhere:  python3 scripts/make_fixtures.py

All good models are closed, consistently oriented solids whose polygons wind
counter-clockwise seen from outside (outward normals by the right-hand rule).
Coordinates are integers or exact binary fractions, kept as `Fraction` while
computing and written with integer / shortest round-trip float formatting, so
every text file is exact.  The exception are the 32-sided round parts
(`round_peg`, `block_with_round_hole`): their coordinates are irrational, so
each is computed to 60 significant digits with `decimal` (no libm, hence the
same on every platform) and rounded once to the nearest double; from there on
they are exact `Fraction`s of those doubles.  Their self-checks use tolerances
relative to the part size (see REL_TOL).

After writing, the script re-reads every file it wrote and checks it
independently (signed volume by the divergence theorem against the analytic
volume, every undirected edge used exactly twice in opposite directions, and
B-rep counts recovered from the refined STL against the hand-derived table in
fixtures/README.md).  Bad-input fixtures are checked to carry their defect.
Any failed check raises SystemExit with a non-zero status.
"""

from __future__ import annotations

import math
import struct
import sys
from decimal import Decimal, localcontext
from fractions import Fraction
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "fixtures"
BAD = OUT / "bad"

F = Fraction


# --------------------------------------------------------------------------
# formatting
# --------------------------------------------------------------------------

def fmt(x) -> str:
    """Integers as '150', other values as the shortest round-trip float."""
    if isinstance(x, Fraction):
        if x.denominator == 1:
            return str(x.numerator)
        fx = float(x)
        assert Fraction(fx) == x, f"{x} is not exactly representable"
        return repr(fx)
    if isinstance(x, int):
        return str(x)
    x = float(x)
    if math.isfinite(x) and x.is_integer():
        return str(int(x))  # also turns -0.0 into 0
    return repr(x)


def fmt3(p) -> str:
    return " ".join(fmt(c) for c in p)


# --------------------------------------------------------------------------
# vector helpers (exact, on tuples of Fractions)
# --------------------------------------------------------------------------

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def newell(pts):
    """Newell normal (twice the vector area) of a polygon."""
    n = [F(0), F(0), F(0)]
    k = len(pts)
    for i in range(k):
        x0, y0, z0 = pts[i]
        x1, y1, z1 = pts[(i + 1) % k]
        n[0] += (y0 - y1) * (z0 + z1)
        n[1] += (z0 - z1) * (x0 + x1)
        n[2] += (x0 - x1) * (y0 + y1)
    return tuple(n)


def is_zero(v):
    return v[0] == 0 and v[1] == 0 and v[2] == 0


# --------------------------------------------------------------------------
# regular polygons (decimal arithmetic, 60 digits, one rounding to double)
# --------------------------------------------------------------------------

DPREC = 60


def d_pi():
    """pi to the context precision (recipe from the `decimal` docs)."""
    with localcontext() as ctx:
        ctx.prec += 2
        lasts, t, s, n, na, d, da = 0, Decimal(3), 3, 1, 0, 0, 24
        while s != lasts:
            lasts = s
            n, na = n + na, na + 8
            d, da = d + da, da + 32
            t = (t * n) / d
            s += t
    return +s


def d_cos(x):
    with localcontext() as ctx:
        ctx.prec += 2
        i, lasts, s, fact, num, sign = 0, 0, Decimal(1), 1, Decimal(1), 1
        while s != lasts:
            lasts = s
            i += 2
            fact *= i * (i - 1)
            num *= x * x
            sign *= -1
            s += num / fact * sign
    return +s


def d_sin(x):
    with localcontext() as ctx:
        ctx.prec += 2
        i, lasts, s, fact, num, sign = 1, 0, x, 1, x, 1
        while s != lasts:
            lasts = s
            i += 2
            fact *= i * (i - 1)
            num *= x * x
            sign *= -1
            s += num / fact * sign
    return +s


def d_to_double(x):
    """Nearest double of a Decimal, as an exact Fraction."""
    return F(float(x))  # float(Decimal) goes through str: correctly rounded


def ngon_xy(cx, cy, R, n):
    """Vertices of the regular n-gon with circumradius R (a Decimal) centred at
    (cx, cy), vertex k at angle 2*pi*k/n (CCW seen from +z), each coordinate
    rounded once to the nearest double."""
    with localcontext() as ctx:
        ctx.prec = DPREC
        two_pi = 2 * d_pi()
        out = []
        for k in range(n):
            a = two_pi * k / n
            out.append((d_to_double(cx + R * d_cos(a)), d_to_double(cy + R * d_sin(a))))
    return out


def ngon_area(R, n):
    """Area n/2 R^2 sin(2 pi/n) of the regular n-gon, as a Decimal."""
    with localcontext() as ctx:
        ctx.prec = DPREC
        return Decimal(n) / 2 * R * R * d_sin(2 * d_pi() / n)


def frustum_volume(h, a1, a2):
    """h/3 (A1 + A2 + sqrt(A1 A2)) for similar parallel end faces."""
    with localcontext() as ctx:
        ctx.prec = DPREC
        return Decimal(h) / 3 * (a1 + a2 + (a1 * a2).sqrt())


N_ROUND = 32


def d_round_radii(n=N_ROUND):
    """(hole circumradius 15, top-of-chamfer circumradius) as Decimals: the
    chamfer moves every side face of the hole out by 3 (measured perpendicular
    to the side) over a height of 3, i.e. 45 deg; the top n-gon has apothem
    15 cos(pi/n) + 3, so circumradius 15 + 3 / cos(pi/n)."""
    with localcontext() as ctx:
        ctx.prec = DPREC
        return Decimal(15), Decimal(15) + 3 / d_cos(d_pi() / n)


# --------------------------------------------------------------------------
# mesh model: vertices (Fraction triples) + polygons (index lists)
# --------------------------------------------------------------------------

class Mesh:
    def __init__(self, name, verts, polys):
        self.name = name
        self.verts = [tuple(F(c) for c in v) for v in verts]
        self.polys = [list(p) for p in polys]


def box_mesh(name, x0, x1, y0, y1, z0, z1):
    xs, ys, zs = (x0, x1), (y0, y1), (z0, z1)
    # vertex index = ix + 2*iy + 4*iz
    verts = [(xs[i & 1], ys[(i >> 1) & 1], zs[(i >> 2) & 1]) for i in range(8)]

    def v(ix, iy, iz):
        return ix + 2 * iy + 4 * iz

    polys = [
        [v(0, 0, 0), v(0, 1, 0), v(1, 1, 0), v(1, 0, 0)],  # -z bottom
        [v(0, 0, 1), v(1, 0, 1), v(1, 1, 1), v(0, 1, 1)],  # +z top
        [v(0, 0, 0), v(1, 0, 0), v(1, 0, 1), v(0, 0, 1)],  # -y front
        [v(0, 1, 0), v(0, 1, 1), v(1, 1, 1), v(1, 1, 0)],  # +y back
        [v(0, 0, 0), v(0, 0, 1), v(0, 1, 1), v(0, 1, 0)],  # -x left
        [v(1, 0, 0), v(1, 1, 0), v(1, 1, 1), v(1, 0, 1)],  # +x right
    ]
    return Mesh(name, verts, polys)


def l_block_mesh():
    # profile in the xz-plane; CCW in (x, z) coordinates means normal x^ x z^ = -y
    prof = [(0, 0), (200, 0), (200, 150), (150, 150), (150, 50), (0, 50)]
    n = len(prof)
    verts = [(x, 0, z) for x, z in prof] + [(x, 100, z) for x, z in prof]
    polys = [list(range(n)),                               # y=0 cap, normal -y
             [n + i for i in reversed(range(n))]]          # y=100 cap, normal +y
    for i in range(n):
        j = (i + 1) % n
        polys.append([j, i, n + i, n + j])                 # side faces
    return Mesh("l_block", verts, polys)


def block_with_hole_mesh():
    outer = [(0, 0), (100, 0), (100, 100), (0, 100)]
    inner = [(35, 35), (65, 35), (65, 65), (35, 65)]
    verts = []
    for z in (0, 50):
        verts += [(x, y, z) for x, y in outer]             # 0..3 / 8..11
        verts += [(x, y, z) for x, y in inner]             # 4..7 / 12..15

    def o(i, top):
        return i % 4 + (8 if top else 0)

    def h(i, top):
        return 4 + i % 4 + (8 if top else 0)

    polys = []
    for i in range(4):
        j = i + 1
        # top (z=50, normal +z): trapezoid outer i -> outer j -> inner j -> inner i
        polys.append([o(i, 1), o(j, 1), h(j, 1), h(i, 1)])
    for i in range(4):
        j = i + 1
        # bottom (z=0, normal -z): reversed
        polys.append([h(i, 0), h(j, 0), o(j, 0), o(i, 0)])
    for i in range(4):
        j = i + 1
        # outer walls, outward
        polys.append([o(i, 0), o(j, 0), o(j, 1), o(i, 1)])
    for i in range(4):
        j = i + 1
        # hole walls, normals point into the hole (away from the material)
        polys.append([h(j, 0), h(i, 0), h(i, 1), h(j, 1)])
    return Mesh("block_with_hole", verts, polys)


def holed_block_mesh(name, rings, corner_idx):
    """Block x,y in [0,100] with a prismatic/chamfered through-hole along z.

    rings: [(z, [(x, y), ...]), ...] hole cross-sections from the bottom (z=0)
    to the top face (z = top of the block), all with the same number n of
    vertices, CCW seen from +z, index k of one ring joined to index k of the
    next by a straight edge.  Consecutive rings are joined by quads (hole
    walls, chamfer faces) whose normals point into the hole.
    corner_idx: for the outer corners (0,0), (100,0), (100,100), (0,100), the
    hole vertex each is joined to; the holed bottom and top faces are split
    along these 4 joins into 4 pieces (no new vertices, no T-junctions): a
    trapezoid per side for a square hole, an 11-gon for a 32-gon hole.
    """
    outer = [(0, 0), (100, 0), (100, 100), (0, 100)]
    z_top = rings[-1][0]
    n = len(rings[0][1])
    verts = [(x, y, 0) for x, y in outer] + [(x, y, z_top) for x, y in outer]
    for z, ring in rings:
        assert len(ring) == n
        verts += [(x, y, z) for x, y in ring]

    def o(i, top):
        return i % 4 + (4 if top else 0)

    def h(r, k):
        return 8 + r * n + k % n

    m = list(corner_idx) + [corner_idx[0] + n]
    assert all(m[i] < m[i + 1] for i in range(4)) and m[4] - m[0] == n
    last = len(rings) - 1
    polys = []
    for i in range(4):
        # top piece (normal +z): outer i -> outer i+1 -> hole m[i+1] down to m[i]
        polys.append([o(i, 1), o(i + 1, 1)] + [h(last, k) for k in range(m[i + 1], m[i] - 1, -1)])
    for i in range(4):
        # bottom piece (normal -z): reversed
        polys.append([h(0, k) for k in range(m[i], m[i + 1] + 1)] + [o(i + 1, 0), o(i, 0)])
    for i in range(4):
        # outer walls, outward
        polys.append([o(i, 0), o(i + 1, 0), o(i + 1, 1), o(i, 1)])
    for r in range(last):
        for k in range(n):
            # hole walls / chamfer faces, normals point into the hole
            polys.append([h(r, k + 1), h(r, k), h(r + 1, k), h(r + 1, k + 1)])
    return Mesh(name, verts, polys)


def block_with_chamfered_hole_mesh():
    sq = lambda a, b: [(a, a), (b, a), (b, b), (a, b)]
    rings = [(0, sq(35, 65)), (45, sq(35, 65)), (50, sq(30, 70))]
    return holed_block_mesh("block_with_chamfered_hole", rings, [0, 1, 2, 3])


def block_with_tight_hole_mesh():
    # 0.125 mm clearance per side to `peg` (x,y [36,64]): exact binary fractions
    sq = lambda a, b: [(a, a), (b, a), (b, b), (a, b)]
    lo, hi = F(287, 8), F(513, 8)  # 35.875, 64.125
    rings = [(0, sq(lo, hi)), (50, sq(lo, hi))]
    return holed_block_mesh("block_with_tight_hole", rings, [0, 1, 2, 3])


def cross_ring(a, b, c, d):
    """The outline of a plus sign, CCW seen from +z: arms between a and b (a < b)
    reaching from c to d (c < a, b < d), starting at the lower arm's tip."""
    return [(a, c), (b, c), (b, a), (d, a), (d, b), (b, b), (b, d), (a, d), (a, b), (c, b), (c, a), (a, a)]


def prism_mesh(name, ring, z0=10, z1=90):
    """The prism over an outline (CCW seen from +z) from z0 to z1, as the pegs are."""
    n = len(ring)
    verts = [(x, y, z0) for x, y in ring] + [(x, y, z1) for x, y in ring]
    polys = [list(range(n - 1, -1, -1)),                 # bottom, normal -z
             list(range(n, 2 * n))]                      # top, normal +z
    for k in range(n):
        j = (k + 1) % n
        polys.append([k, j, n + j, n + k])               # sides, outward
    return Mesh(name, verts, polys)


def plus_peg_mesh():
    # arms x or y in [40,60], reaching from 25 to 75; z[10,90]
    return prism_mesh("plus_peg", cross_ring(40, 60, 25, 75))


def block_with_plus_hole_mesh():
    # the peg's outline grown by 1 on every side: arms [39,61], reaching from 24 to 76;
    # corners (0,0), (100,0), (100,100), (0,100) joined to the hole's inner corners
    # (39,39), (61,39), (61,61), (39,61): ring indices 11, 2, 5, 8
    rings = [(0, cross_ring(39, 61, 24, 76)), (50, cross_ring(39, 61, 24, 76))]
    return holed_block_mesh("block_with_plus_hole", rings, [11, 14, 17, 20])


HEX_Q = 2 ** 20  # hexagon coordinates are rounded to multiples of 2^-20


def hex_half_height(r):
    """r sin(60 deg) = r sqrt(3)/2 rounded to the nearest multiple of 2^-20, as an
    exact Fraction (60-digit decimal, so platform independent; never a tie)."""
    with localcontext() as ctx:
        ctx.prec = DPREC
        return F(round(Decimal(3).sqrt() / 2 * r * HEX_Q), HEX_Q)


def hex_ring(r):
    """The regular hexagon of circumradius r centred at (50, 50), vertex k at angle
    60 k deg (CCW seen from +z), every coordinate rounded to the nearest multiple
    of 2^-20: cos 60k deg is +-1/2 or +-1, so only the y = 50 +- r sqrt(3)/2
    coordinates are rounded (round(50 q + x) = 50 q + round(x), round(-x) =
    -round(x): the rounded hexagon keeps both mirror symmetries). Exact binary
    fractions, so the faces over it are exactly planar."""
    c, h, hr = F(50), hex_half_height(r), F(r, 2)
    return [(c + r, c), (c + hr, c + h), (c - hr, c + h), (c - r, c), (c - hr, c - h), (c + hr, c - h)]


def hex_area(r):
    """Exact area of `hex_ring(r)`: the rectangle |x - 50| <= r/2, |y - 50| <= h
    (r * 2h) plus two triangles of base 2h and height r/2 (r h together): 3 r h."""
    return 3 * r * hex_half_height(r)


def hex_peg_mesh():
    # circumradius 14, z[10,90]
    return prism_mesh("hex_peg", hex_ring(14))


def block_with_hex_hole_mesh():
    # circumradius 15, same phase as the peg: 1 mm clearance at the corners, cos 30 deg across the flats;
    # corners (0,0), (100,0), (100,100), (0,100) joined to the hole vertices at 240, 300, 420 = 60, 480 = 120 deg
    rings = [(0, hex_ring(15)), (50, hex_ring(15))]
    return holed_block_mesh("block_with_hex_hole", rings, [4, 5, 7, 8])


def round_peg_mesh(n_sides=N_ROUND, name="round_peg"):
    return prism_mesh(name, ngon_xy(50, 50, Decimal(14), n_sides))


def block_with_round_hole_mesh(n_sides=N_ROUND, name="block_with_round_hole"):
    assert n_sides % 8 == 0, "the block's corners are joined to hole vertices at 225, 315, 45, 135 deg"
    r15, r_top = d_round_radii(n_sides)
    hole = ngon_xy(50, 50, r15, n_sides)
    top = ngon_xy(50, 50, r_top, n_sides)
    rings = [(0, hole), (47, hole), (50, top)]
    # corners (0,0), (100,0), (100,100), (0,100) lie at 225, 315, 45, 135 deg
    q = n_sides // 8
    return holed_block_mesh(name, rings, [5 * q, 7 * q, 9 * q, 11 * q])


# --------------------------------------------------------------------------
# triangulation and refinement
# --------------------------------------------------------------------------

def is_convex_poly(pts):
    n = newell(pts)
    k = len(pts)
    for i in range(k):
        a, b, c = pts[i - 1], pts[i], pts[(i + 1) % k]
        if dot(cross(sub(b, a), sub(c, b)), n) <= 0:
            return False
    return True


def ear_clip(pts):
    """Triangulate a simple planar polygon (indices into pts), CCW w.r.t. its normal."""
    n = newell(pts)
    idx = list(range(len(pts)))
    tris = []

    def inside(p, a, b, c):
        return (dot(cross(sub(b, a), sub(p, a)), n) >= 0 and
                dot(cross(sub(c, b), sub(p, b)), n) >= 0 and
                dot(cross(sub(a, c), sub(p, c)), n) >= 0)

    while len(idx) > 3:
        for k in range(len(idx)):
            ia, ib, ic = idx[k - 1], idx[k], idx[(k + 1) % len(idx)]
            a, b, c = pts[ia], pts[ib], pts[ic]
            if dot(cross(sub(b, a), sub(c, b)), n) <= 0:
                continue  # reflex or degenerate corner
            if any(inside(pts[j], a, b, c) for j in idx if j not in (ia, ib, ic)):
                continue
            tris.append((ia, ib, ic))
            idx.pop(k)
            break
        else:
            raise RuntimeError("ear clipping failed")
    tris.append(tuple(idx))
    return tris


def triangulate(mesh):
    tris = []
    for poly in mesh.polys:
        pts = [mesh.verts[i] for i in poly]
        if is_convex_poly(pts):
            local = [(0, k, k + 1) for k in range(1, len(poly) - 1)]  # fan
        else:
            local = ear_clip(pts)
        tris += [tuple(poly[i] for i in t) for t in local]
    return list(mesh.verts), tris


def subdivide(verts, tris, round_mid=False):
    """One round of 1-to-4 midpoint subdivision with shared midpoints.
    round_mid: round each midpoint coordinate to the nearest double (needed
    when the endpoints are arbitrary doubles: their exact midpoint may need
    one more bit than a double has)."""
    verts = list(verts)
    mids = {}

    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in mids:
            pa, pb = verts[a], verts[b]
            m = tuple((pa[k] + pb[k]) / 2 for k in range(3))
            if round_mid:
                m = tuple(F(float(c)) for c in m)
            verts.append(m)
            mids[key] = len(verts) - 1
        return mids[key]

    out = []
    for a, b, c in tris:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return verts, out


def unit_normal(p0, p1, p2):
    n = cross(sub(p1, p0), sub(p2, p0))
    nf = [float(c) for c in n]
    ln = math.sqrt(sum(c * c for c in nf))
    return [c / ln for c in nf] if ln > 0 else [0.0, 0.0, 0.0]


# --------------------------------------------------------------------------
# writers
# --------------------------------------------------------------------------

def off_text(verts, polys, comment=None):
    lines = ["OFF"]
    if comment:
        lines.append("# " + comment)
    lines.append(f"{len(verts)} {len(polys)} 0")
    lines += [fmt3(v) if not isinstance(v, str) else v for v in verts]
    lines += [" ".join([str(len(p))] + [str(i) for i in p]) for p in polys]
    return "\n".join(lines) + "\n"


def obj_text(name, verts, polys, comment=None):
    lines = []
    if comment:
        lines.append("# " + comment)
    lines.append(f"o {name}")
    lines += ["v " + (fmt3(v) if not isinstance(v, str) else v) for v in verts]
    lines += ["f " + " ".join(str(i + 1) for i in p) for p in polys]
    return "\n".join(lines) + "\n"


def stl_ascii_text(name, verts, tris):
    lines = [f"solid {name}"]
    for t in tris:
        p = [verts[i] for i in t]
        lines.append("  facet normal " + fmt3(unit_normal(*p)))
        lines.append("    outer loop")
        lines += ["      vertex " + fmt3(q) for q in p]
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append(f"endsolid {name}")
    return "\n".join(lines) + "\n"


def stl_binary_bytes(name, verts, tris, declared=None):
    header = f"binary STL {name} (acsg fixture)".encode("ascii")
    assert not header.startswith(b"solid")
    header = header.ljust(80, b" ")
    out = bytearray(header)
    out += struct.pack("<I", len(tris) if declared is None else declared)
    for t in tris:
        p = [verts[i] for i in t]
        vals = unit_normal(*p) + [float(c) for q in p for c in q]
        for q in p:
            for c in q:
                assert Fraction(struct.unpack("<f", struct.pack("<f", float(c)))[0]) == c
        out += struct.pack("<12fH", *vals, 0)
    return bytes(out)


def ply_text(verts, polys):
    lines = ["ply", "format ascii 1.0", "comment acsg fixture l_block",
             f"element vertex {len(verts)}",
             "property float x", "property float y", "property float z",
             f"element face {len(polys)}",
             "property list uchar int vertex_indices", "end_header"]
    lines += [fmt3(v) for v in verts]
    lines += [" ".join([str(len(p))] + [str(i) for i in p]) for p in polys]
    return "\n".join(lines) + "\n"


WRITTEN: list[Path] = []


def write(path: Path, data):
    path.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(data, str):
        data = data.encode("ascii")
    path.write_bytes(data)
    WRITTEN.append(path)


# --------------------------------------------------------------------------
# readers (independent of the writers; used by the self-check)
# --------------------------------------------------------------------------

class ParseError(Exception):
    pass


def num(tok):
    try:
        v = float(tok)
    except ValueError:
        raise ParseError(f"not a number: {tok!r}")
    if not math.isfinite(v):
        raise ParseError(f"non-finite coordinate: {tok!r}")
    return Fraction(v)


def read_off(path):
    toks = []
    for line in path.read_text("ascii").splitlines():
        line = line.split("#", 1)[0]
        toks += line.split()
    if not toks:
        raise ParseError("empty file")
    if toks[0] != "OFF":
        raise ParseError("missing OFF header")
    nv, nf = int(toks[1]), int(toks[2])
    pos = 4
    verts = []
    for _ in range(nv):
        verts.append(tuple(num(t) for t in toks[pos:pos + 3]))
        pos += 3
    polys = []
    for _ in range(nf):
        k = int(toks[pos])
        p = [int(t) for t in toks[pos + 1:pos + 1 + k]]
        pos += 1 + k
        if any(i < 0 or i >= nv for i in p):
            raise ParseError(f"vertex index out of range in face {p}")
        polys.append(p)
    if pos != len(toks):
        raise ParseError("trailing tokens")
    return verts, polys


def read_obj(path):
    verts, polys, names = [], [], []
    for line in path.read_text("ascii").splitlines():
        t = line.split()
        if not t or t[0].startswith("#"):
            continue
        if t[0] == "v":
            verts.append(tuple(num(x) for x in t[1:4]))
        elif t[0] == "f":
            p = [int(x.split("/")[0]) - 1 for x in t[1:]]
            if any(i < 0 or i >= len(verts) for i in p):
                raise ParseError("bad index")
            polys.append(p)
        elif t[0] == "o":
            names.append(t[1])
        else:
            raise ParseError(f"unexpected line {line!r}")
    return verts, polys, names


def read_ply(path):
    lines = path.read_text("ascii").splitlines()
    end = lines.index("end_header")
    head = lines[:end]
    assert head[0] == "ply" and head[1] == "format ascii 1.0"
    nv = nf = None
    for h in head:
        t = h.split()
        if t[:2] == ["element", "vertex"]:
            nv = int(t[2])
        if t[:2] == ["element", "face"]:
            nf = int(t[2])
    assert "property list uchar int vertex_indices" in head
    body = lines[end + 1:]
    verts = [tuple(num(x) for x in l.split()) for l in body[:nv]]
    polys = []
    for l in body[nv:nv + nf]:
        t = [int(x) for x in l.split()]
        assert t[0] == len(t) - 1
        polys.append(t[1:])
    assert len(body) == nv + nf
    return verts, polys


def read_stl_ascii(path):
    """Returns a list of (normal, (p0, p1, p2)) with exact coordinates."""
    toks = path.read_text("ascii").split()
    if not toks:
        raise ParseError("empty file")
    assert toks[0] == "solid"
    facets = []
    i = 2
    while toks[i] == "facet":
        assert toks[i + 1] == "normal"
        n = tuple(float(x) for x in toks[i + 2:i + 5])
        assert toks[i + 5:i + 7] == ["outer", "loop"]
        i += 7
        pts = []
        for _ in range(3):
            assert toks[i] == "vertex"
            pts.append(tuple(num(x) for x in toks[i + 1:i + 4]))
            i += 4
        assert toks[i:i + 2] == ["endloop", "endfacet"]
        i += 2
        facets.append((n, tuple(pts)))
    assert toks[i] == "endsolid" and i + 2 == len(toks)
    return facets


def read_stl_binary(path):
    data = path.read_bytes()
    if data[:5] == b"solid":
        raise ParseError("binary STL header starts with 'solid'")
    if len(data) < 84:
        raise ParseError("too short")
    (n,) = struct.unpack_from("<I", data, 80)
    if len(data) != 84 + 50 * n:
        raise ParseError(f"size {len(data)} != 84 + 50*{n}")
    facets = []
    for k in range(n):
        vals = struct.unpack_from("<12fH", data, 84 + 50 * k)
        pts = tuple(tuple(Fraction(c) for c in vals[3 + 3 * j:6 + 3 * j]) for j in range(3))
        facets.append((vals[0:3], pts))
    return facets


def facets_to_mesh(facets):
    """Merge STL facet corners by exact coordinate."""
    index, verts, tris = {}, [], []
    for _, pts in facets:
        t = []
        for p in pts:
            if p not in index:
                index[p] = len(verts)
                verts.append(p)
            t.append(index[p])
        tris.append(tuple(t))
    return verts, tris


# --------------------------------------------------------------------------
# checks
# --------------------------------------------------------------------------

def directed_edges(polys):
    out = []
    for p in polys:
        for k in range(len(p)):
            out.append((p[k], p[(k + 1) % len(p)]))
    return out


def edge_report(polys):
    """Returns (ok, problems): ok iff every undirected edge is used exactly twice,
    once in each direction."""
    use = {}
    for a, b in directed_edges(polys):
        use.setdefault((min(a, b), max(a, b)), []).append((a, b))
    problems = []
    for key, ds in use.items():
        if len(ds) != 2:
            problems.append(("count", key, len(ds)))
        elif ds[0] == ds[1]:
            problems.append(("same-direction", key, 2))
    return not problems, problems


def signed_volume(verts, polys):
    vol = Fraction(0)
    for p in polys:
        for k in range(1, len(p) - 1):  # fan; exact for planar polygons
            a, b, c = verts[p[0]], verts[p[k]], verts[p[k + 1]]
            vol += dot(a, cross(b, c))
    return vol / 6


def shells(nv, polys):
    parent = list(range(nv))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for p in polys:
        for i in p[1:]:
            parent[find(i)] = find(p[0])
    used = {i for p in polys for i in p}
    return len({find(i) for i in used})


def planar(verts, poly, tol=0):
    """Exactly planar (tol == 0), or every vertex within distance tol of the
    plane through the first vertex with the polygon's Newell normal."""
    pts = [verts[i] for i in poly]
    n = newell(pts)
    if tol == 0:
        return all(dot(n, sub(q, pts[0])) == 0 for q in pts)
    t2 = F(tol) ** 2 * dot(n, n)
    return all(dot(n, sub(q, pts[0])) ** 2 <= t2 for q in pts)


def extent(verts):
    """Part size: the largest side of the axis-aligned bounding box."""
    return max(max(v[k] for v in verts) - min(v[k] for v in verts) for k in range(3))


def brep_counts(verts, tris, tol=0):
    """Recover B-rep counts from a (refined) triangle mesh: group coplanar
    edge-adjacent triangles into faces, find feature edges between different
    faces, B-rep vertices = mesh vertices touching >= 3 faces, B-rep edges =
    chains of feature mesh edges between B-rep vertices, convexity from the
    dihedral sign.  Returns (faces, faces_with_holes, vertices, convex_vertices,
    edges, convex_edges, concave_edges).  tol > 0: two edge-adjacent triangles
    are coplanar when the far vertex of one is within distance tol of the
    other's plane (and the normals agree), instead of exactly."""
    nt = len(tris)
    normals = [cross(sub(verts[b], verts[a]), sub(verts[c], verts[a])) for a, b, c in tris]
    edge_tris = {}
    for t, (a, b, c) in enumerate(tris):
        for u, v in ((a, b), (b, c), (c, a)):
            edge_tris.setdefault((min(u, v), max(u, v)), []).append((t, u, v))
    parent = list(range(nt))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    def coplanar(t1, t2, u, w):
        if tol == 0:
            return is_zero(cross(normals[t1], normals[t2])) and dot(normals[t1], normals[t2]) > 0
        n1 = normals[t1]
        d = dot(n1, sub(verts[w], verts[u]))
        return dot(n1, normals[t2]) > 0 and d * d <= F(tol) ** 2 * dot(n1, n1)

    for key, lst in edge_tris.items():
        assert len(lst) == 2, "mesh not 2-manifold"
        (t1, u, _), (t2, _, _) = lst
        w = [x for x in tris[t2] if x not in key][0]
        if coplanar(t1, t2, u, w):
            parent[find(t1)] = find(t2)
    face_of = [find(t) for t in range(nt)]
    faces = sorted(set(face_of))

    # feature edges and their convexity
    feature = {}
    for key, lst in edge_tris.items():
        (t1, u, v), (t2, _, _) = lst
        if face_of[t1] == face_of[t2]:
            continue
        third = [w for w in tris[t2] if w not in key][0]
        s = dot(normals[t1], sub(verts[third], verts[u]))
        assert s != 0
        feature[key] = s < 0  # True = convex

    # B-rep vertices: touch >= 3 faces
    vfaces = {}
    for t, tri in enumerate(tris):
        for w in tri:
            vfaces.setdefault(w, set()).add(face_of[t])
    bverts = {w for w, fs in vfaces.items() if len(fs) >= 3}

    # B-rep edges: union feature mesh edges through non-B-rep vertices
    keys = list(feature)
    kparent = {k: k for k in keys}

    def kfind(x):
        while kparent[x] != x:
            kparent[x] = kparent[kparent[x]]
            x = kparent[x]
        return x

    at_vertex = {}
    for k in keys:
        for w in k:
            if w not in bverts:
                at_vertex.setdefault(w, []).append(k)
    for w, ks in at_vertex.items():
        assert len(ks) == 2
        kparent[kfind(ks[0])] = kfind(ks[1])
    chains = {}
    for k in keys:
        chains.setdefault(kfind(k), []).append(feature[k])
    edge_convex = {}
    for root, flags in chains.items():
        assert all(f == flags[0] for f in flags), "edge changes convexity"
        edge_convex[root] = flags[0]
    n_edges = len(edge_convex)
    n_convex_edges = sum(1 for c in edge_convex.values() if c)

    # convex vertex: every incident B-rep edge convex
    n_convex_verts = 0
    for w in bverts:
        inc = [edge_convex[kfind(k)] for k in keys if w in k]
        if all(inc):
            n_convex_verts += 1

    # faces with holes: more than one boundary loop
    n_holed = 0
    for f in faces:
        bedges = [k for k, lst in edge_tris.items()
                  if sum(1 for (t, _, _) in lst if face_of[t] == f) == 1]
        p = {}

        def pf(x):
            while p.setdefault(x, x) != x:
                x = p[x]
            return x

        for a, b in bedges:
            p[pf(a)] = pf(b)
        loops = len({pf(w) for e in bedges for w in e})
        if loops > 1:
            n_holed += 1

    return (len(faces), n_holed, len(bverts), n_convex_verts,
            n_edges, n_convex_edges, n_edges - n_convex_edges)


FAILURES: list[str] = []


def check(cond, msg):
    if not cond:
        FAILURES.append(msg)
    return cond


# --------------------------------------------------------------------------
# models
# --------------------------------------------------------------------------

GOOD = [
    # mesh, analytic volume, hand-derived B-rep counts
    # (faces, faces_with_holes, vertices, convex_vertices, edges, convex_edges, concave_edges)
    (l_block_mesh(), 200 * 50 * 100 + 50 * 100 * 100, (8, 0, 12, 10, 18, 17, 1)),
    (box_mesh("box", 50, 150, 10, 90, 50, 150), 100 * 80 * 100, (6, 0, 8, 8, 12, 12, 0)),
    (block_with_hole_mesh(), 100 * 100 * 50 - 30 * 30 * 50, (10, 2, 16, 8, 24, 20, 4)),
    (box_mesh("peg", 36, 64, 36, 64, 10, 90), 28 * 28 * 80, (6, 0, 8, 8, 12, 12, 0)),
    (box_mesh("cube", 0, 10, 0, 10, 0, 10), 1000, (6, 0, 8, 8, 12, 12, 0)),
    (box_mesh("slab", -100, 100, -100, 100, -10, 0), 200 * 200 * 10, (6, 0, 8, 8, 12, 12, 0)),
    # block - square prism hole - chamfer frustum (h/3 (A1 + A2 + sqrt(A1 A2)), squares 30 and 40)
    (block_with_chamfered_hole_mesh(),
     100 * 100 * 50 - 30 * 30 * 45 - F(5, 3) * (900 + 1600 + 1200), (14, 2, 20, 8, 32, 24, 8)),
    # hole side 64.125 - 35.875 = 28.25 = 113/4
    (block_with_tight_hole_mesh(), 100 * 100 * 50 - F(113, 4) ** 2 * 50, (10, 2, 16, 8, 24, 20, 4)),
    # plus outlines: 20 * 50 + 2 * 15 * 20 = 1600 (peg), 22 * 52 + 2 * 15 * 22 = 1804 (hole)
    (plus_peg_mesh(), 1600 * 80, (14, 0, 24, 16, 36, 32, 4)),
    (block_with_plus_hole_mesh(), 100 * 100 * 50 - 1804 * 50, (18, 2, 32, 16, 48, 40, 8)),
    # hexagons of the rounded coordinates: exact area 3 r h, h = r sqrt(3)/2 rounded to 2^-20
    (hex_peg_mesh(), hex_area(14) * 80, (8, 0, 12, 12, 18, 18, 0)),
    (block_with_hex_hole_mesh(), 100 * 100 * 50 - hex_area(15) * 50, (12, 2, 20, 8, 30, 24, 6)),
]
BINARY = {"l_block", "box"}
PLY = {"l_block"}


def round_volumes(n=N_ROUND):
    r15, r_top = d_round_radii(n)
    a14, a15, a_top = (ngon_area(r, n) for r in (Decimal(14), r15, r_top))
    with localcontext() as ctx:
        ctx.prec = DPREC
        peg = a14 * 80
        block = 100 * 100 * 50 - a15 * 47 - frustum_volume(3, a15, a_top)
    return F(peg), F(block)


# 32-sided round parts: coordinates are rounded doubles, so their checks use
# tolerances: planarity / coplanarity within REL_TOL * part size, volume
# within REL_TOL relative; their STL midpoints are rounded to doubles too.
REL_TOL = 1e-12
_V_ROUND_PEG, _V_ROUND_BLOCK = round_volumes()
GOOD += [
    (round_peg_mesh(), _V_ROUND_PEG, (34, 0, 64, 64, 96, 96, 0)),
    (block_with_round_hole_mesh(), _V_ROUND_BLOCK, (70, 2, 104, 8, 172, 108, 64)),
]
ROUND = {"round_peg", "block_with_round_hole"}
NO_OBJ = {"block_with_chamfered_hole", "round_peg", "block_with_round_hole",
          "block_with_tight_hole", "plus_peg", "block_with_plus_hole",
          "hex_peg", "block_with_hex_hole"}  # .off + .stl only


# The scaling series (the `scale` benchmark): an n-gon peg over a block with a
# chamfered n-gon hole, as `round_peg` + `block_with_round_hole` (n = 32 there).
# Hand-derived B-rep counts: the peg has n + 2 faces, 2n vertices and 3n edges,
# all convex; the block 2n + 6 faces (top and bottom holed, so non-convex),
# 3n + 8 vertices (the 8 block corners convex), 5n + 12 edges of which the 2n
# between hole faces (vertical walls, slanted chamfer edges) are concave.
SCALE = OUT / "scale"
SCALE_SIDES = (8, 16, 32, 64)


def scale_meshes():
    for n in SCALE_SIDES:
        v_peg, v_block = round_volumes(n)
        yield (round_peg_mesh(n, f"round_peg_{n}"), v_peg, (n + 2, 0, 2 * n, 2 * n, 3 * n, 3 * n, 0))
        yield (block_with_round_hole_mesh(n, f"block_with_round_hole_{n}"), v_block,
               (2 * n + 6, 2, 3 * n + 8, 8, 5 * n + 12, 3 * n + 12, 2 * n))


def write_scale():
    for mesh, _, _ in scale_meshes():
        write(SCALE / f"{mesh.name}.off", off_text(mesh.verts, mesh.polys))


def check_scale():
    for mesh, volume, counts in scale_meshes():
        label = f"scale/{mesh.name}.off"
        v, p = read_off(SCALE / f"{mesh.name}.off")
        check(v == mesh.verts and p == mesh.polys, f"{label}: round trip differs")
        check_closed_solid(label, v, p, volume, REL_TOL)
        _, tris = triangulate(Mesh(mesh.name, v, p))
        got = brep_counts(v, tris, F(REL_TOL) * extent(v))
        check(got == counts, f"{label}: B-rep counts {got} != hand-derived {counts}")


def write_good():
    for mesh, _, _ in GOOD:
        n = mesh.name
        write(OUT / f"{n}.off", off_text(mesh.verts, mesh.polys))
        if n not in NO_OBJ:
            write(OUT / f"{n}.obj", obj_text(n, mesh.verts, mesh.polys))
        v, t = triangulate(mesh)
        v1, t1 = subdivide(v, t, round_mid=n in ROUND)
        write(OUT / f"{n}.stl", stl_ascii_text(n, v1, t1))
        if n in BINARY:
            v2, t2 = subdivide(v1, t1)
            write(OUT / f"{n}_binary.stl", stl_binary_bytes(n, v2, t2))
        if n in PLY:
            write(OUT / f"{n}.ply", ply_text(mesh.verts, mesh.polys))


def write_bad():
    cube = box_mesh("cube", 0, 10, 0, 10, 0, 10)
    cv, cp = cube.verts, cube.polys
    TOP = 1  # index of the +z face in box_mesh

    write(BAD / "empty.off", b"")
    write(BAD / "whitespace.stl", "  \n\n    \n \t \n\n   \n")

    write(BAD / "open_box.off",
          off_text(cv, [p for k, p in enumerate(cp) if k != TOP], "cube [0,10]^3 without its top face"))

    # two cubes sharing only the edge x=10,y=10 (z in [0,10]); shared vertices are shared indices
    c2 = box_mesh("c2", 10, 20, 10, 20, 0, 10)
    verts = list(cv)
    remap = {}
    for i, p in enumerate(c2.verts):
        if p in verts:
            remap[i] = verts.index(p)
        else:
            verts.append(p)
            remap[i] = len(verts) - 1
    polys = cp + [[remap[i] for i in p] for p in c2.polys]
    assert len(verts) == 14
    write(BAD / "nonmanifold.off",
          off_text(verts, polys, "cubes [0,10]^3 and [10,20]x[10,20]x[0,10] sharing edge x=10,y=10"))

    polys = [list(p) for p in cp]
    polys[TOP] = polys[TOP][::-1]
    write(BAD / "flipped_face.off", off_text(cv, polys, "cube [0,10]^3, top face winding reversed"))

    write(BAD / "inward.off", off_text(cv, [p[::-1] for p in cp], "cube [0,10]^3, every face reversed"))

    # zero-area sliver: m = (5,0,10) is the midpoint of the top-front edge v4-v5.
    # The top face becomes a fan of 3 triangles around m; the front face keeps
    # its straight edge v5->v4; the sliver (v4, v5, m) closes the gap, so every
    # edge is still used twice in opposite directions.
    verts = list(cv) + [(F(5), F(0), F(10))]
    m = 8
    v4, v5, v6, v7 = 4, 5, 7, 6  # top corners CCW from above: (0,0),(10,0),(10,10),(0,10)
    polys = [p for k, p in enumerate(cp) if k != TOP]
    polys += [[m, v5, v6], [m, v6, v7], [m, v7, v4], [v4, v5, m]]
    write(BAD / "zero_area.off",
          off_text(verts, polys, "cube [0,10]^3, top as 3 triangles + zero-area sliver (0 0 10)(10 0 10)(5 0 10)"))

    verts = [fmt3(p) for p in cv]
    verts[7] = "10 nan 10"
    write(BAD / "nan.off", off_text(verts, cp, "cube [0,10]^3, vertex 7 has y = nan"))

    verts = [fmt3(p) for p in cv]
    verts[7] = "10 10 inf"
    write(BAD / "inf.obj", obj_text("cube", verts, cp, "cube [0,10]^3, vertex 8 has z = inf"))

    verts = list(cv)
    verts[7] = (F(10), F(10), F(11))
    write(BAD / "nonplanar.off", off_text(verts, cp, "cube [0,10]^3, vertex (10,10,10) raised to z=11"))

    v, t = triangulate(cube)
    assert len(t) == 12
    full = stl_binary_bytes("cube", v, t)
    write(BAD / "truncated.stl", full[:84 + 6 * 50 + 25])

    polys = [list(p) for p in cp]
    polys[TOP] = [polys[TOP][0], polys[TOP][1], 42, polys[TOP][3]]
    write(BAD / "bad_index.off", off_text(cv, polys, "cube [0,10]^3, top face refers to vertex 42 of 8"))

    verts = [fmt3(p) for p in cv]
    verts[3] = "10 abc 0"
    write(BAD / "garbage.obj", obj_text("cube", verts, cp, "cube [0,10]^3, vertex 4 has a non-number token"))

    c2 = box_mesh("c2", 20, 30, 0, 10, 0, 10)
    verts = list(cv) + list(c2.verts)
    polys = cp + [[i + 8 for i in p] for p in c2.polys]
    write(BAD / "two_shells.off", off_text(verts, polys, "two disjoint cubes [0,10]^3 and [20,30]x[0,10]x[0,10]"))


# --------------------------------------------------------------------------
# README
# --------------------------------------------------------------------------

DESCRIPTIONS = {
    "l_block": "L-shaped prism: profile (x,z) (0,0) (200,0) (200,150) (150,150) (150,50) (0,50), y in [0,100] (part A)",
    "box": "box x[50,150] y[10,90] z[50,150], sits in the L's inside corner (part B)",
    "block_with_hole": "block x,y[0,100] z[0,50] with through-hole x,y[35,65] along z (part A)",
    "peg": "peg x,y[36,64] z[10,90], stands in the hole, 1 mm clearance per side (part B)",
    "cube": "cube [0,10]^3",
    "slab": "slab x,y[-100,100] z[-10,0]",
    "block_with_chamfered_hole": "block x,y[0,100] z[0,50], through-hole x,y[35,65] for z[0,45], 45 deg chamfer "
                                 "to x,y[30,70] at z=50 (part A; goes with `peg`)",
    "block_with_tight_hole": "block x,y[0,100] z[0,50] with through-hole x,y[35.875,64.125] along z: 0.125 mm "
                             "clearance per side to `peg` (part A; goes with `peg`)",
    "round_peg": "32-sided regular prism, circumradius 14, axis x=y=50, z[10,90], vertex k at angle 2 pi k/32 "
                 "(part B)",
    "block_with_round_hole": "block x,y[0,100] z[0,50], 32-sided prism hole of circumradius 15 (same phase) for "
                             "z[0,47], 45 deg chamfer of depth 3 to apothem 15 cos(pi/32) + 3 at z=50 (part A; "
                             "goes with `round_peg`)",
    "plus_peg": "prism of a plus-sign outline: arms x or y in [40,60] reaching from 25 to 75, z[10,90] (part B)",
    "block_with_plus_hole": "block x,y[0,100] z[0,50] with a plus-shaped through-hole, the peg's outline grown "
                            "by 1 on every side (arms [39,61] reaching from 24 to 76): 1 mm clearance on every "
                            "side, so three parallel walls touch at once (part A; goes with `plus_peg`)",
    "hex_peg": "regular hexagonal prism, circumradius 14, axis x=y=50, z[10,90], vertex k at angle 60k deg, "
               "coordinates rounded to multiples of 2^-20 (part B)",
    "block_with_hex_hole": "block x,y[0,100] z[0,50] with a regular hexagonal through-hole of circumradius 15 "
                           "(same phase and rounding as `hex_peg`): 1 mm clearance at the corners, cos 30 deg "
                           "~ 0.866 mm across the flats (part A; goes with `hex_peg`)",
}


def fmt_volume(vol, inexact):
    if inexact:
        return f"~{float(vol):.6f}"
    vol = F(vol)
    if vol.denominator == 1:
        return str(vol.numerator)
    return f"{vol.numerator}/{vol.denominator} (~{float(vol):.3f})"

BAD_DESC = [
    ("empty.off", "zero bytes", "empty file"),
    ("whitespace.stl", "only spaces/tabs/newlines", "empty file (no solid)"),
    ("open_box.off", "cube missing its +z face", "not closed: 4 boundary edges"),
    ("nonmanifold.off", "cubes [0,10]^3 and [10,20]x[10,20]x[0,10] sharing only the edge x=10,y=10 (vertices shared)",
     "non-manifold edge: 4 faces meet at it"),
    ("flipped_face.off", "cube, +z face winding reversed", "inconsistent orientation (4 edges used twice in the same direction)"),
    ("inward.off", "cube, every face reversed", "consistently oriented but inward (signed volume -1000)"),
    ("zero_area.off", "cube, +z face = 3 triangles fanned from (5,0,10) + sliver (0,0,10)(10,0,10)(5,0,10)",
     "zero-area (collinear) face; still closed and consistently oriented"),
    ("nan.off", "cube, vertex 7 is `10 nan 10`", "non-finite coordinate (NaN)"),
    ("inf.obj", "cube, vertex 8 is `10 10 inf`", "non-finite coordinate (inf)"),
    ("nonplanar.off", "cube, vertex (10,10,10) raised to z=11, faces stay quads", "face not planar: only the +z quad (the +x and +y quads stay in x=10 / y=10, planar trapezoids)"),
    ("truncated.stl", "binary STL of the cube, header says 12 triangles, 409 bytes = 84 + 6*50 + 25",
     "truncated: cut 25 bytes into triangle 7 (1-based)"),
    ("bad_index.off", "cube, +z face refers to vertex 42 of 8", "vertex index out of range"),
    ("garbage.obj", "cube, vertex 4 is `v 10 abc 0`", "non-numeric token"),
    ("two_shells.off", "two disjoint cubes [0,10]^3 and [20,30]x[0,10]x[0,10]", "two shells (disconnected) in one file"),
]


def readme_text():
    L = []
    L.append("# Test fixtures")
    L.append("")
    L.append("Generated by `scripts/make_fixtures.py` (Python 3.11, stdlib only, deterministic). "
             "Do not edit by hand; rerun the script. Units: mm. A and B parts are given in the same "
             "frame at the assembled pose (A fixed, B moving): `l_block` + `box`, `block_with_hole` + `peg`, "
             "`block_with_chamfered_hole` + `peg`, `block_with_round_hole` + `round_peg`, "
             "`block_with_tight_hole` + `peg`, `block_with_plus_hole` + `plus_peg`, "
             "`block_with_hex_hole` + `hex_peg`.")
    L.append("")
    L.append("`scale/` holds the scaling series of the `scale` benchmark: `round_peg_N` + "
             "`block_with_round_hole_N` for N = " + ", ".join(str(n) for n in SCALE_SIDES) + ", built as the "
             "32-sided pair (which they equal at N = 32) with N sides. Each is checked for volume and for "
             "the hand-derived B-rep counts (peg: N + 2 faces, 2N vertices, 3N edges; block: 2N + 6 faces, "
             "3N + 8 vertices, 5N + 12 edges of which 2N concave). `.off` only.")
    L.append("")
    L.append("All good models are closed, consistently oriented solids; polygons wind counter-clockwise "
             "seen from outside. Coordinates are integers or exact binary fractions, except in the round parts "
             "(`round_peg`, `block_with_round_hole`): there every coordinate is the nearest double of the exact "
             "value (computed to 60 digits with Python's `decimal`, so platform independent), written with the "
             "shortest round-trip repr. So the round parts' faces are planar only to about 1e-14 mm (the chamfer "
             "quads of `block_with_round_hole` and, in the STL, the faces holding rounded midpoints): readers need "
             "a tolerance there. The script checks them with tolerance 1e-12 x part size (planarity, coplanarity) "
             "and 1e-12 relative (volume).")
    L.append("")
    L.append("* `.off` / `.obj` / `.ply`: one polygon per planar face, except the holed top and bottom of "
             "`block_with_hole`, `block_with_chamfered_hole` and `block_with_tight_hole`, each split into 4 "
             "trapezoids, and of "
             "`block_with_round_hole`, each split into 4 non-convex 11-gons (2 block corners + 9 hole vertices, "
             "cut along the joins from the block corners to the hole vertices at 45/135/225/315 deg); "
             "no T-junctions. The newer models (`block_with_chamfered_hole`, `round_peg`, "
             "`block_with_round_hole`, `block_with_tight_hole`, `plus_peg`, `block_with_plus_hole`, `hex_peg`, "
             "`block_with_hex_hole`) have `.off` and `.stl` only.")
    L.append("* `.stl` (ASCII): polygons triangulated (fan for convex, ear clipping for the L caps and the "
             "11-gons) and then refined once by 1-to-4 midpoint subdivision (conforming). Readers must merge "
             "coplanar triangles and the vertices that only split straight edges. For the round parts each "
             "midpoint is rounded to the nearest double (the exact midpoint of two doubles may need one bit "
             "more), so their split vertices are only within ~1e-14 of the edge / face they split.")
    L.append("* `_binary.stl`: binary little-endian float32, refined twice, header does not start with `solid`.")
    L.append("")
    L.append("## Good models")
    L.append("")
    L.append("B-rep counts below were derived **by hand** from the geometry (see notes), and are "
             "re-checked by the script against counts recovered from the refined ASCII STL.")
    L.append("")
    L.append("| model | files | description | volume mm^3 | faces | faces w/ holes | vertices | convex vertices | edges | convex edges | concave edges |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for mesh, vol, counts in GOOD:
        n = mesh.name
        files = [f"{n}.off", f"{n}.stl"] if n in NO_OBJ else [f"{n}.off", f"{n}.obj", f"{n}.stl"]
        if n in BINARY:
            files.append(f"{n}_binary.stl")
        if n in PLY:
            files.append(f"{n}.ply")
        L.append(f"| {n} | " + ", ".join(f"`{f}`" for f in files) + f" | {DESCRIPTIONS[n]} | "
                 + f"{fmt_volume(vol, n in ROUND)} | "
                 + " | ".join(str(c) for c in counts) + " |")
    L.append("")
    L.append("A convex vertex is one whose incident edges are all convex.")
    L.append("")
    L.append("Hand derivation notes:")
    L.append("")
    L.append("* Boxes (`cube`, `slab`, `box`, `peg`): 6 faces, 8 vertices, 12 edges, all convex.")
    L.append("* `l_block`: 2 profile caps + 6 side faces = 8 faces; 6 profile vertices x 2 = 12 vertices; "
             "6 edges per cap x 2 + 6 lateral edges = 18 edges. The profile has one reflex corner at "
             "(x,z) = (150,50), so the lateral edge x=150, z=50 is concave (the material angle there is 270 deg); "
             "the other 17 edges are convex. Its two end vertices (150,0,50) and (150,100,50) touch the "
             "concave edge, so 12 - 2 = 10 convex vertices. Volume 200*50*100 + 50*100*100 = 1,500,000.")
    L.append("* `block_with_hole`: 4 outer walls + 4 hole walls + top + bottom = 10 faces, top and bottom "
             "each have one hole (2 faces with holes). 8 outer + 8 hole vertices = 16. Edges: 12 of the "
             "outer box + 4 hole rim edges on top + 4 on bottom + 4 vertical hole edges = 24. The 4 vertical "
             "hole edges are concave (material angle 270 deg); the hole rims are convex (90 deg); so 20 "
             "convex, 4 concave. Each hole vertex touches one concave edge, so 8 convex vertices. "
             "Volume 100*100*50 - 30*30*50 = 455,000.")
    L.append("* `block_with_tight_hole`: as `block_with_hole` with the hole x,y[35.875,64.125] (35.875 = 287/8, "
             "64.125 = 513/8, exact binary fractions), so the same counts: 10 faces (2 with holes), 16 vertices "
             "(8 convex), 24 edges (20 convex, 4 concave vertical hole edges). With `peg` (x,y[36,64]) the "
             "clearance is 0.125 mm per side. Volume 100*100*50 - 28.25*28.25*50 = 500,000 - 39,903.125 = "
             "460,096.875.")
    L.append("* `block_with_chamfered_hole`: 4 outer walls + bottom (hole [35,65]^2) + top (hole [30,70]^2) + "
             "4 chamfer trapezoids + 4 hole walls = 14 faces, 2 with holes. Vertices: 8 outer + 3 rings of 4 "
             "around the hole (z=0, z=45, z=50) = 20. Edges: 12 of the outer box + 4 bottom rim (z=0) + 4 "
             "vertical hole edges (z 0..45) + 4 wall/chamfer edges (z=45) + 4 chamfer/chamfer edges (the "
             "diagonals (35,35,45)-(30,30,50) etc.) + 4 top rim (z=50) = 32. Check: V - E + F - (inner loops) "
             "= 20 - 32 + 14 - 2 = 0 = 2(shells - genus) with 1 shell, genus 1. Convexity, by the material "
             "angle in the section perpendicular to each edge: outer box 90 deg, bottom rim 90 deg (convex); "
             "vertical hole edges 270 deg (concave); wall/chamfer at z=45: in the section y = const through "
             "the x=35 wall the material is bounded by the ray straight down (the wall) and the ray up-and-out "
             "at 45 deg (the chamfer), and lies between them on the block side: 90 + 45 = 135 deg, convex (a "
             "chamfer replaces the 90 deg hole rim by two 135 deg convex edges, it never makes a concave one); "
             "chamfer/top at z=50: top ray outward, chamfer ray down-and-in at 45 deg, material below: 135 deg, "
             "convex; chamfer/chamfer diagonals: the empty hole is locally the intersection of the two "
             "half-spaces x + z > 80 and y + z > 80 (a convex wedge of dihedral angle 120 deg, the inward "
             "normals (1,0,1)/sqrt2 and (0,1,1)/sqrt2 make 60 deg), so the material angle is 360 - 120 = 240 "
             "deg, concave. So 12 + 4 + 4 + 4 = 24 convex, 4 + 4 = 8 concave. Every hole vertex touches a "
             "concave edge (z=0 and z=45: the vertical hole edge, z=45 and z=50: a diagonal), so only the 8 "
             "outer corners are convex vertices. Volume 100*100*50 - 30*30*45 - 5/3*(900 + 1600 + sqrt(900*1600)) "
             "= 500,000 - 40,500 - 18,500/3 = 1,360,000/3 = 453,333.33...")
    L.append("* `round_peg`: 2 caps + 32 sides = 34 faces; 32 x 2 = 64 vertices; 32 bottom + 32 top rim + "
             "32 vertical edges = 96 edges (64 - 96 + 34 = 2). All convex: rims 90 deg, side/side 180 - 360/32 "
             "= 168.75 deg. Volume = 80 * A(14) with A(R) = 32/2 R^2 sin(2 pi/32) (area of the regular 32-gon "
             "of circumradius R).")
    L.append("* `block_with_round_hole`: as `block_with_chamfered_hole` with a 32-gon instead of a square: 4 "
             "outer walls + bottom + top + 32 chamfer quads + 32 hole walls = 70 faces, 2 with holes; 8 + 3 x 32 "
             "(rings at z=0, 47, 50) = 104 vertices; 12 + 32 x 5 (bottom rim, vertical hole edges, wall/chamfer "
             "at z=47, chamfer/chamfer, top rim) = 172 edges (104 - 172 + 70 - 2 = 0, genus 1). Convex: outer "
             "12, bottom rim 32 (90 deg), wall/chamfer 32 (135 deg), top rim 32 (135 deg) = 108; concave: "
             "vertical hole edges 32 (180 + 360/32 = 191.25 deg: the hole is locally a convex wedge) and "
             "chamfer/chamfer edges 32 (same reason) = 64. Every hole vertex touches a concave edge: 8 convex "
             "vertices. The chamfer is 45 deg: each side face is moved out by 3, perpendicular to itself, over "
             "the height 3 (z 47..50), i.e. the top 32-gon has apothem 15 cos(pi/32) + 3 and circumradius "
             "15 + 3/cos(pi/32). Volume = 100*100*50 - 47 A(15) - 3/3 (A(15) + A(R_top) + sqrt(A(15) A(R_top))). "
             "Radial clearance to `round_peg`: 15 - 14 = 1 at the corners, cos(pi/32) ~ 0.995 across the flats.")
    L.append("* `plus_peg`: the plus outline has 12 corners, 8 convex (90 deg) and 4 reflex (the inner corners "
             "(40,40), (60,40), (60,60), (40,60), 270 deg): 2 caps + 12 sides = 14 faces, 12 x 2 = 24 vertices, "
             "12 x 2 rim + 12 vertical = 36 edges (24 - 36 + 14 = 2). The 4 vertical edges at the reflex corners "
             "are concave, the other 32 convex; their 8 end vertices are not convex, so 16 convex vertices. "
             "Volume 80 x (20 x 50 + 2 x 15 x 20) = 80 x 1600 = 128,000.")
    L.append("* `block_with_plus_hole`: 4 outer walls + top + bottom + 12 hole walls = 18 faces, 2 with holes; "
             "8 + 12 x 2 = 32 vertices; 12 outer + 12 top rim + 12 bottom rim + 12 vertical hole edges = 48 "
             "edges (32 - 48 + 18 - 2 = 0, genus 1). Seen from the material, the hole's 8 convex corners (the "
             "arms' ends) make 270 deg: 8 concave vertical edges; its 4 reflex corners (39,39), (61,39), "
             "(61,61), (39,61) make 90 deg: convex, like every rim. So 40 convex and 8 concave edges; the 16 "
             "ends of the concave edges are not convex, leaving 8 outer + 8 = 16 convex vertices. Volume "
             "100 x 100 x 50 - 50 x (22 x 52 + 2 x 15 x 22) = 500,000 - 50 x 1804 = 409,800. The top and "
             "bottom are each split into 4 non-convex hexagons by the joins from the block corners to the "
             "hole's reflex corners.")
    L.append("* `hex_peg`: 2 caps + 6 sides = 8 faces; 6 x 2 = 12 vertices; 6 x 2 rim + 6 vertical = 18 "
             "edges (12 - 18 + 8 = 2). All convex: rims 90 deg, side/side 120 deg (the hexagon's interior "
             "angle), so 12 convex vertices and 18 convex edges. Coordinates: cos 60k deg is +-1/2 or +-1, so "
             "x = 50 +- r and 50 +- r/2 are exact; y = 50 +- h(r) with h(r) = round(r sqrt(3)/2 x 2^20) / 2^20 "
             "(60-digit decimal; never a tie, and round(50 x 2^20 +- x) = 50 x 2^20 +- round(x), so the rounded "
             "hexagon keeps both mirror symmetries). h(14) = 12713308 / 2^20 = 3178327/262144 = "
             "12.124355316162109375 (7 sqrt 3 = 12.1243556530...). The rounded hexagon is the rectangle "
             "|x - 50| <= r/2, |y - 50| <= h plus two triangles of base 2h and height r/2: exact area "
             "2rh + rh = 3rh (within 3r 2^-21 of 3 sqrt(3)/2 r^2). Volume 80 x 3 x 14 x h(14) = 3360 h(14) = "
             "333724335/8192 ~ 40,737.834 (unrounded 80 x 3 sqrt(3)/2 x 14^2 ~ 40,737.835).")
    L.append("* `block_with_hex_hole`: 4 outer walls + top + bottom + 6 hole walls = 12 faces, 2 with holes; "
             "8 + 6 x 2 = 20 vertices; 12 outer + 6 top rim + 6 bottom rim + 6 vertical hole edges = 30 edges "
             "(20 - 30 + 12 - 2 = 0, genus 1). The hole is a convex prism: at each vertical hole edge the empty "
             "space is a 120 deg wedge, so the material angle is 360 - 120 = 240 deg: 6 concave edges; the rims "
             "make 90 deg, convex like the outer box: 24 convex, 6 concave. Every hole vertex ends a concave "
             "edge: only the 8 outer corners are convex vertices. h(15) = 13621402 / 2^20 = 6810701/524288 = "
             "12.9903812408447265625 (7.5 sqrt 3 = 12.9903810567...). Volume 100 x 100 x 50 - 50 x 3 x 15 x "
             "h(15) = 500,000 - 2250 h(15) = 123409961375/262144 ~ 470,771.642. The block corners (0,0), "
             "(100,0), (100,100), (0,100) are joined to the hole vertices at 240, 300, 60, 120 deg, so the top "
             "and bottom are each split into 2 trapezoids (below and above the hole) and 2 non-convex pentagons "
             "(left and right: 2 block corners + 3 hole vertices, reflex at the hole vertex at 180 resp. 0 deg). "
             "Clearance to `hex_peg`: 15 - 14 = 1 at the corners, about cos 30 deg ~ 0.866 across the flats: "
             "h(15) - h(14) = 0.8660259246826171875 across the flats y = 50 +- h; the rounding tilts the "
             "slanted flats of peg and hole against each other by ~1.8e-8 rad, so there the clearance runs "
             "from 0.86602541 to 0.86602566 along the flat.")
    L.append("")
    L.append("## Bad inputs (`bad/`)")
    L.append("")
    L.append("Each has exactly one defect; derived from the cube [0,10]^3 unless said.")
    L.append("")
    L.append("| file | what it is | defect |")
    L.append("|---|---|---|")
    for f, what, defect in BAD_DESC:
        L.append(f"| `bad/{f}` | {what} | {defect} |")
    L.append("")
    L.append("Notes: `nonmanifold.off` also has two non-manifold vertices (the ends of the shared edge) as a "
             "consequence of the non-manifold edge. In `zero_area.off` the sliver's long edge is shared "
             "with the -y face, whose straight edge passes through the sliver's middle vertex (5,0,10); "
             "any closed mesh with a collinear triangle has this shape. In `nonplanar.off` the signed "
             "volume is not meaningful because the top face is not planar.")
    L.append("")
    # The CAD files are written by scripts/make_cad_fixtures.py (OpenCASCADE); only
    # their description lives here, so that this README is regenerated whole.
    L.append('## CAD fixtures (`cad/`)')
    L.append("")
    L.append('Written once by OpenCASCADE 8.0 (PyPI wheel `cadquery-ocp`) with '
             '`scripts/make_cad_fixtures.py`; same dimensions and frame as the OFF fixtures, so the same '
             'counts and card(PPC) as above. Header time stamps are replaced by a fixed one.')
    L.append("")
    L.append('| file | what it is |')
    L.append('|---|---|')
    L.append('| `cad/l_block.step`, `cad/block_with_hole.step`, `cad/peg.step` | STEP AP214, millimetres '
             '(`MANIFOLD_SOLID_BREP`, `ADVANCED_FACE` on `PLANE`, `EDGE_CURVE` on `LINE` in `SURFACE_CURVE`) '
             '|')
    L.append('| `cad/l_block.igs`, `cad/block_with_hole.igs`, `cad/peg.igs` | IGES B-rep form (186, 514, 510,'
             ' 508, 504, 502, 190, 116, 123, 110; plus a 402 group), millimetres |')
    L.append('| `cad/l_block_faces.igs`, `cad/block_with_hole_faces.igs`, `cad/peg_faces.igs` | IGES '
             'trimmed-surface form (144, 108, 142, 102, 110; plus a 402 group), millimetres |')
    L.append('| `cad/peg_inch.step`, `cad/peg_inch.igs` | the peg in inches (STEP '
             "`CONVERSION_BASED_UNIT('INCH')`, IGES unit flag 1); read back in millimetres |")
    L.append("")
    L.append('The refusal tests (`crates/acsg/tests/cad.rs`) derive their broken inputs from these files in '
             'memory (a plane turned into a cylindrical or B-spline surface, a line into a circle, cut files,'
             ' changed unit fields).')
    L.append("")
    return "\n".join(L)


# --------------------------------------------------------------------------
# self-check
# --------------------------------------------------------------------------

def check_closed_solid(label, verts, polys, volume, rel=0):
    """rel == 0: exact volume and planarity; rel > 0: volume within rel of
    the analytic value (relative), planarity within rel * part size."""
    ok, probs = edge_report(polys)
    check(ok, f"{label}: edge pairing problems {probs[:3]}")
    vol = signed_volume(verts, polys)
    if rel == 0:
        check(vol == volume, f"{label}: signed volume {vol} != {volume}")
    else:
        check(abs(vol - volume) <= F(rel) * abs(volume),
              f"{label}: signed volume {float(vol)!r} != {float(volume)!r} (rel {rel})")
    check(shells(len(verts), polys) == 1, f"{label}: not one shell")
    tol = F(rel) * extent(verts)
    check(all(planar(verts, p, tol) for p in polys), f"{label}: non-planar polygon")
    used = {i for p in polys for i in p}
    check(len(used) == len(verts), f"{label}: unused vertices")
    for p in polys:
        pts = [verts[i] for i in p]
        check(not is_zero(newell(pts)), f"{label}: zero-area polygon {p}")


def self_check():
    for mesh, volume, counts in GOOD:
        n = mesh.name
        rel = REL_TOL if n in ROUND else 0
        v, p = read_off(OUT / f"{n}.off")
        tol = F(rel) * extent(v)
        check_closed_solid(f"{n}.off", v, p, volume, rel)
        check(v == mesh.verts and p == mesh.polys, f"{n}.off: round trip differs")
        if n not in NO_OBJ:
            v2, p2, names = read_obj(OUT / f"{n}.obj")
            check((v2, p2) == (v, p) and names == [n], f"{n}.obj differs from {n}.off")
        if n in PLY:
            v3, p3 = read_ply(OUT / f"{n}.ply")
            check((v3, p3) == (v, p), f"{n}.ply differs from {n}.off")

        stls = [(f"{n}.stl", read_stl_ascii(OUT / f"{n}.stl"), 4)]
        if n in BINARY:
            stls.append((f"{n}_binary.stl", read_stl_binary(OUT / f"{n}_binary.stl"), 16))
        ntri_poly = sum(len(q) - 2 for q in p)
        for label, facets, factor in stls:
            check(len(facets) == ntri_poly * factor, f"{label}: {len(facets)} triangles")
            tv, tt = facets_to_mesh(facets)
            check_closed_solid(label, tv, tt, volume, rel)
            # facet normals are unit normals of the triangles
            for nrm, pts in facets:
                exp = unit_normal(*pts)
                check(all(abs(a - b) < 1e-6 for a, b in zip(nrm, exp)), f"{label}: facet normal {nrm} != {exp}")
            got = brep_counts(tv, tt, tol)
            check(got == counts, f"{label}: B-rep counts {got} != hand-derived {counts}")
        # the polygon files too
        _, tris = triangulate(Mesh(n, v, p))
        check(brep_counts(v, tris, tol) == counts, f"{n}.off: B-rep counts differ")

    # the chamfers are 45 deg: every face that is neither horizontal nor
    # vertical has a normal with n_z^2 = n_x^2 + n_y^2 (exactly / within REL_TOL)
    for n, rel, count in (("block_with_chamfered_hole", 0, 4), ("block_with_round_hole", REL_TOL, N_ROUND)):
        v, p = read_off(OUT / f"{n}.off")
        slanted = 0
        for q in p:
            nx, ny, nz = newell([v[i] for i in q])
            h2 = nx * nx + ny * ny
            if nz == 0 or h2 == 0:
                continue
            slanted += 1
            check(nz > 0 and abs(nz * nz - h2) <= F(rel) * (nz * nz + h2), f"{n}.off: face {q} is not a 45 deg chamfer")
        check(slanted == count, f"{n}.off: {slanted} slanted faces, expected {count}")

    # bad inputs carry their defect
    def parse_error(fn, path):
        try:
            fn(path)
        except (ParseError, ValueError, struct.error, AssertionError, IndexError):
            return True
        return False

    check((BAD / "empty.off").stat().st_size == 0, "empty.off not empty")
    check((BAD / "whitespace.stl").read_bytes().strip() == b"", "whitespace.stl has content")

    v, p = read_off(BAD / "open_box.off")
    ok, probs = edge_report(p)
    check(not ok and len(probs) == 4 and all(k == "count" and c == 1 for k, _, c in probs), "open_box: defect")

    v, p = read_off(BAD / "nonmanifold.off")
    ok, probs = edge_report(p)
    check(len(probs) == 1 and probs[0][2] == 4 and v[probs[0][1][0]][:2] == (10, 10)
          and v[probs[0][1][1]][:2] == (10, 10), f"nonmanifold: {probs}")
    check(signed_volume(v, p) == 2000, "nonmanifold: volume")

    v, p = read_off(BAD / "flipped_face.off")
    ok, probs = edge_report(p)
    check(len(probs) == 4 and all(k == "same-direction" for k, _, _ in probs), "flipped_face: defect")

    v, p = read_off(BAD / "inward.off")
    check(edge_report(p)[0] and signed_volume(v, p) == -1000, "inward: defect")

    v, p = read_off(BAD / "zero_area.off")
    zero = [q for q in p if is_zero(newell([v[i] for i in q]))]
    check(edge_report(p)[0] and signed_volume(v, p) == 1000 and len(zero) == 1
          and all(planar(v, q) for q in p), "zero_area: defect")

    check(parse_error(read_off, BAD / "nan.off"), "nan.off parses")
    check(parse_error(read_obj, BAD / "inf.obj"), "inf.obj parses")
    check(parse_error(read_obj, BAD / "garbage.obj"), "garbage.obj parses")
    check(parse_error(read_off, BAD / "bad_index.off"), "bad_index.off parses")
    check(parse_error(read_stl_binary, BAD / "truncated.stl"), "truncated.stl parses")
    data = (BAD / "truncated.stl").read_bytes()
    check(len(data) == 409 and struct.unpack_from("<I", data, 80)[0] == 12, "truncated.stl layout")

    v, p = read_off(BAD / "nonplanar.off")
    nonplanar = [q for q in p if not planar(v, q)]
    check(edge_report(p)[0] and len(nonplanar) == 1 and v[7] in [v[i] for i in nonplanar[0]], f"nonplanar: {len(nonplanar)} non-planar faces")

    v, p = read_off(BAD / "two_shells.off")
    check(edge_report(p)[0] and shells(len(v), p) == 2 and signed_volume(v, p) == 2000, "two_shells: defect")

    # cleanliness of the good cube the bad files derive from
    v, p = read_off(OUT / "cube.off")
    check_closed_solid("cube.off (base)", v, p, 1000)


def main():
    write_good()
    write_bad()
    write_scale()
    write(OUT / "README.md", readme_text())
    self_check()
    check_scale()
    total = 0
    for path in WRITTEN:
        size = path.stat().st_size
        total += size
        print(f"{path.relative_to(ROOT).as_posix():40s} {size:7d} bytes")
    print(f"{len(WRITTEN)} files, {total} bytes total")
    check(total < 2 * 1024 * 1024, "total size over 2 MB")
    if FAILURES:
        for f in FAILURES:
            print("SELF-CHECK FAILED:", f, file=sys.stderr)
        sys.exit(1)
    print("self-check passed")


if __name__ == "__main__":
    main()
