"""acsg: Assembly Contact State Graphs of two polyhedral parts, from Python.

Part A is held fixed, part B is carried by a robot whose misalignment is bounded;
:func:`generate` lists every contact state that can occur within the bounds, how the
states connect, and a pose that proves each one (its witness).

>>> import acsg, trimesh
>>> graph = acsg.generate(trimesh.load("l_block.stl"), trimesh.load("box.stl"),
...                       bounds={"x": (-5, 5), "y": (-5, 5), "z": (0, 240),
...                               "rx": (-18, 18), "ry": (-18, 18), "rz": (-18, 18)})
>>> graph.to_networkx()

Parts can be given as paths (OFF, OBJ, STL, PLY, STEP/IGES with planar faces), as
:class:`Part`, as ``trimesh.Trimesh`` (anything with ``.vertices`` and ``.faces``) or as
``(vertices, faces)`` arrays. Lengths are in the parts' units; angles in degrees unless
``degrees=False`` (the graph's JSON and :attr:`Witness.pose` are always radians).

The heavy lifting is done by the Rust library (the extension module ``acsg._acsg``);
this module turns its JSON document (``schema/graph.schema.json``) into objects and
numpy arrays. Errors are :class:`AcsgError` (parts, graph files) or ``ValueError``
(bounds, poses, options), with the library's messages.
"""

from __future__ import annotations

import json
import os
import sys
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _acsg
from ._acsg import AcsgError, Part

__version__: str = _acsg.__version__

__all__ = [
    "AcsgError",
    "Part",
    "Element",
    "Contact",
    "Witness",
    "State",
    "Graph",
    "ContactReport",
    "COMPONENTS",
    "part",
    "generate",
    "contacts",
    "generate_many",
]

#: The pose components, in order: lengths x, y, z, then rotations rx, ry, rz
#: (``p_A = G (R p_B + t)`` with ``R = Rz(rz) Ry(ry) Rx(rx)``).
COMPONENTS: Tuple[str, ...] = ("x", "y", "z", "rx", "ry", "rz")

PartLike = Union[str, "os.PathLike[str]", Part, Any]


def part(obj: PartLike, *, units: Optional[str] = None, facet: Optional[float] = None, name: Optional[str] = None) -> Part:
    """A :class:`Part` from a path, a ``Part``, a mesh with ``.vertices`` and ``.faces``
    (``trimesh.Trimesh``) or a ``(vertices, faces)`` pair of arrays.

    ``units`` (mm, cm, m, in) and ``facet`` are as the CLI's ``--units`` and ``--facet``;
    ``name`` labels a mesh in messages and in the graph's JSON (default: the trimesh's
    ``metadata["file_name"]`` or ``metadata["name"]`` when it has one, else ``"mesh"``).
    """
    if isinstance(obj, Part):
        return obj
    if isinstance(obj, (str, os.PathLike)):
        return Part.from_path(os.fspath(obj), units=units, facet=facet)
    if hasattr(obj, "vertices") and hasattr(obj, "faces"):
        vertices, faces = obj.vertices, obj.faces
        if name is None:
            metadata = getattr(obj, "metadata", None)
            if isinstance(metadata, Mapping):
                given = metadata.get("file_name") or metadata.get("name")
                name = given if isinstance(given, str) else None
    elif isinstance(obj, (tuple, list)) and len(obj) == 2:
        vertices, faces = obj
    else:
        raise TypeError(
            f"cannot make a part of {type(obj).__name__}: give a path, an acsg.Part, a mesh with "
            ".vertices and .faces (trimesh.Trimesh) or a (vertices, faces) pair"
        )
    v = np.asarray(vertices, dtype=np.float64)
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"vertices must be an array of shape (n, 3), not {v.shape}")
    if isinstance(faces, np.ndarray) or (isinstance(faces, (list, tuple)) and faces and _same_lengths(faces)):
        f = np.asarray(faces)
        if f.ndim != 2 or f.shape[1] < 3:
            raise ValueError(f"faces must be an array of shape (m, k >= 3) or a list of polygons, not {f.shape}")
        if f.size and (not np.issubdtype(f.dtype, np.integer)):
            raise ValueError(f"faces must hold integer vertex indices, not {f.dtype}")
        if f.size and (f.min() < 0 or f.max() >= len(v)):
            raise ValueError(f"faces index vertices 0..{len(v) - 1}, but hold {f.min()}..{f.max()}")
        polygons = f.tolist()
    else:
        polygons = [[_index(i, len(v)) for i in polygon] for polygon in faces]
    return Part.from_arrays(v.tolist(), polygons, name=name or "mesh", units=units)


def _same_lengths(polygons: Sequence[Sequence[int]]) -> bool:
    return len({len(p) for p in polygons}) == 1


def _index(i: Any, n: int) -> int:
    k = int(i)
    if k != i or not 0 <= k < n:
        raise ValueError(f"a face holds {i!r}, not an index of the {n} vertices")
    return k


def _bounds(bounds: Union[Mapping[str, Tuple[float, float]], Sequence[Sequence[float]]]) -> Tuple[List[float], List[float]]:
    """``{"x": (lo, hi), ...}`` (omitted components fixed at 0) or ``(min6, max6)``."""
    if isinstance(bounds, Mapping):
        unknown = sorted(set(bounds) - set(COMPONENTS))
        if unknown:
            raise ValueError(f"unknown bounds component(s) {unknown}: use {list(COMPONENTS)}")
        lo, hi = [0.0] * 6, [0.0] * 6
        for k, name in enumerate(COMPONENTS):
            if name in bounds:
                pair = tuple(bounds[name])
                if len(pair) != 2:
                    raise ValueError(f"bounds[{name!r}] must be (min, max), not {bounds[name]!r}")
                lo[k], hi[k] = float(pair[0]), float(pair[1])
        return lo, hi
    pair = list(bounds)
    if len(pair) != 2:
        raise ValueError("bounds must be a dict {'x': (min, max), ...} or a pair (min6, max6)")
    lo, hi = [float(v) for v in pair[0]], [float(v) for v in pair[1]]
    if len(lo) != 6 or len(hi) != 6:
        raise ValueError("bounds as (min, max) need 6 values each: x, y, z, rx, ry, rz")
    return lo, hi


def _placement(pose: Any) -> List[float]:
    """6 pose values or a 4x4 matrix, flattened."""
    a = np.asarray(pose, dtype=np.float64)
    if a.shape not in ((6,), (4, 4)):
        raise ValueError(f"a pose is 6 values (x, y, z, rx, ry, rz) or a 4x4 matrix, not shape {a.shape}")
    return a.reshape(-1).tolist()


@dataclass(frozen=True)
class Element:
    """An element of a part: a vertex, an edge or a face, with its geometry in the
    part's own frame."""

    #: ``"f3"``, ``"e5"``, ``"v7"``: what the graph's JSON calls it.
    id: str
    #: ``"vertex"``, ``"edge"`` or ``"face"``.
    kind: str
    #: Its index among the part's elements of that kind.
    index: int
    #: Its points, shape (k, 3): the vertex, the edge's two ends, the face's outer loop
    #: (counter-clockwise seen from outside).
    points: np.ndarray = field(repr=False, compare=False)
    #: Whether it is convex (vertices and edges; faces are always ``True``).
    convex: bool = True
    #: A face's outward unit normal; ``None`` for vertices and edges.
    normal: Optional[np.ndarray] = field(default=None, repr=False, compare=False)
    #: A face's holes, each a (k, 3) array of points.
    holes: Tuple[np.ndarray, ...] = field(default=(), repr=False, compare=False)


class _Elements:
    """A part's elements as the graph's JSON writes them (``fixed`` / ``moving``)."""

    def __init__(self, record: Mapping[str, Any]):
        self.record = record
        self.vertices = np.asarray(record["vertices"], dtype=np.float64).reshape(-1, 3)

    def element(self, eid: str) -> Element:
        kind, index = eid[0], int(eid[1:])
        r = self.record
        if kind == "v":
            return Element(eid, "vertex", index, self.vertices[[index]], bool(r["convex_vertices"][index]))
        if kind == "e":
            return Element(eid, "edge", index, self.vertices[list(r["edges"][index])], bool(r["convex_edges"][index]))
        loops = r["faces"][index]
        return Element(
            eid,
            "face",
            index,
            self.vertices[list(loops[0])],
            True,
            np.asarray(r["face_normals"][index], dtype=np.float64),
            tuple(self.vertices[list(h)] for h in loops[1:]),
        )


@dataclass(frozen=True)
class Contact:
    """A principal contact: an element of the fixed part touching one of the moving
    part."""

    #: ``"f-v"``, ``"v-f"``, ``"e-e"``, ``"f-f"``, ...: the elements' kinds.
    type: str
    #: The fixed part's element id (``"f3"``).
    fixed: str
    #: The moving part's element id (``"v7"``).
    moving: str
    #: Degrees of freedom this contact leaves.
    dof: int
    #: Whether it is degenerate (v-v, e-v, v-e, e-e-t between convex elements).
    degenerate: bool
    #: The fixed element with its geometry (fixed part's frame).
    fixed_element: Element = field(repr=False, compare=False)
    #: The moving element with its geometry (moving part's own frame).
    moving_element: Element = field(repr=False, compare=False)

    @property
    def key(self) -> Tuple[str, str, str]:
        """``(type, fixed, moving)``: what identifies the contact."""
        return (self.type, self.fixed, self.moving)


@dataclass(frozen=True)
class Witness:
    """A pose within the bounds showing exactly one state, verified by the library."""

    #: x, y, z, rx, ry, rz, angles in radians.
    pose: Tuple[float, float, float, float, float, float]
    #: The placement of the moving part in the fixed part's frame, 4x4 (G·[R|t]).
    matrix: np.ndarray = field(repr=False, compare=False)

    @property
    def pose_degrees(self) -> Tuple[float, ...]:
        """The pose with its angles in degrees."""
        x, y, z, rx, ry, rz = self.pose
        return (x, y, z, *np.degrees([rx, ry, rz]).tolist())


@dataclass(frozen=True)
class State:
    """One contact state: the principal contacts P(X) at its witness."""

    #: Its index in :attr:`Graph.states`; 0 is free space.
    id: int
    #: Its principal contacts, sorted.
    contacts: Tuple[Contact, ...]
    #: Degrees of freedom left (6 in free space).
    dof: int
    #: Whether one of its contacts is degenerate.
    degenerate: bool
    #: A verified pose showing it (``None`` for free space when no free pose was probed).
    witness: Optional[Witness]

    @property
    def keys(self) -> Tuple[Tuple[str, str, str], ...]:
        """Its contacts as ``(type, fixed, moving)`` triples."""
        return tuple(c.key for c in self.contacts)


def _contact(record: Mapping[str, Any], fixed: _Elements, moving: _Elements) -> Contact:
    return Contact(
        record["type"],
        record["fixed"],
        record["moving"],
        int(record["dof"]),
        bool(record["degenerate"]),
        fixed.element(record["fixed"]),
        moving.element(record["moving"]),
    )


class Graph:
    """A contact state graph, as :func:`generate` returns it or :meth:`load` reads it.

    It is its JSON document (``schema/graph.schema.json``, the same as the CLI
    writes), with objects for the states: :attr:`document` holds all of it (parts with
    geometry, bounds in radians, undecided candidates, ...).
    """

    def __init__(self, text: str):
        """A graph from its JSON text, checked (use :meth:`from_json` or :meth:`load`)."""
        self._text = text
        self.document: Dict[str, Any] = json.loads(text)
        doc = self.document
        self._fixed = _Elements(doc["fixed"])
        self._moving = _Elements(doc["moving"])
        states = []
        for s in doc["states"]:
            w = s.get("witness")
            witness = None
            if w is not None:
                witness = Witness(tuple(float(v) for v in w["pose"]), np.asarray(w["matrix"], dtype=np.float64))
            states.append(
                State(
                    int(s["id"]),
                    tuple(_contact(c, self._fixed, self._moving) for c in s["contacts"]),
                    int(s["dof"]),
                    bool(s["degenerate"]),
                    witness,
                )
            )
        #: The states; ``states[0]`` is free space.
        self.states: List[State] = states
        #: Neighbour pairs of state ids, ``(smaller, larger)``, sorted.
        self.edges: List[Tuple[int, int]] = [(int(a), int(b)) for a, b in doc["edges"]]
        #: Counts and times of the run (as the CLI's summary and the JSON's ``stats``).
        self.stats: Dict[str, Any] = dict(doc["stats"])
        #: Whether every candidate met was witnessed or proved infeasible: then no
        #: state within the bounds is missing.
        self.complete: bool = bool(doc.get("complete", False))
        #: The candidates left undecided: lists of contacts (states the graph may lack).
        self.undecided: List[Tuple[Contact, ...]] = [
            tuple(_contact(c, self._fixed, self._moving) for c in u["contacts"]) for u in doc.get("undecided", [])
        ]

    @classmethod
    def from_json(cls, text: str, name: str = "<string>") -> "Graph":
        """A graph from JSON text (checked as the CLI checks a graph file)."""
        _acsg.check_graph(text, name)
        return cls(text)

    @classmethod
    def load(cls, path: Union[str, "os.PathLike[str]"]) -> "Graph":
        """Reads a graph's JSON file (written by :meth:`save` or the CLI's ``generate``,
        ``run``, ``demo``)."""
        name = os.fspath(path)
        _acsg.check_graph_file(name)
        # Kept as read: the numbers are exactly the file's.
        with open(name, encoding="utf-8-sig") as f:
            return cls(f.read())

    def to_json(self) -> str:
        """The graph's JSON document, as the CLI writes it."""
        return self._text

    def save(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the JSON document (atomically); ``acsg report``/``export`` read it."""
        _acsg.write_atomic(os.fspath(path), self._text)

    @property
    def bounds(self) -> Dict[str, Tuple[float, float]]:
        """The bounds of the run: lengths, and angles in radians."""
        b = self.document["bounds"]
        return {n: (b["min"][k], b["max"][k]) for k, n in enumerate(COMPONENTS)}

    @property
    def assembled(self) -> np.ndarray:
        """G, the assembled pose of the moving part, 4x4."""
        return np.asarray(self.document["assembled"], dtype=np.float64)

    def fixed_element(self, eid: str) -> Element:
        """An element of the fixed part by id (``"f3"``)."""
        return self._fixed.element(eid)

    def moving_element(self, eid: str) -> Element:
        """An element of the moving part by id (``"v7"``)."""
        return self._moving.element(eid)

    def to_networkx(self) -> Any:
        """The graph as a ``networkx.Graph``: one node per state id, one edge per
        neighbour pair.

        Node attributes: ``dof`` (int), ``degenerate`` (bool), ``n_contacts`` (int),
        ``contacts`` (list of ``(type, fixed, moving)``), ``witness`` (the 6 pose values,
        radians, a numpy array, or ``None``) and ``matrix`` (4x4 numpy array or ``None``).
        Graph attributes: ``complete``, ``stats``, ``bounds``, ``units``.
        """
        import networkx as nx

        g = nx.Graph(
            complete=self.complete,
            stats=dict(self.stats),
            bounds=self.bounds,
            units=dict(self.document.get("units", {})),
        )
        for s in self.states:
            g.add_node(
                s.id,
                dof=s.dof,
                degenerate=s.degenerate,
                n_contacts=len(s.contacts),
                contacts=[c.key for c in s.contacts],
                witness=None if s.witness is None else np.asarray(s.witness.pose, dtype=np.float64),
                matrix=None if s.witness is None else s.witness.matrix.copy(),
            )
        g.add_edges_from(self.edges)
        return g

    def __len__(self) -> int:
        return len(self.states)

    def __repr__(self) -> str:
        done = "complete" if self.complete else f"{len(self.undecided)} undecided"
        return f"<acsg.Graph: {len(self.states)} states, {len(self.edges)} edges, {done}>"


class _Bar:
    """One progress bar for a whole run (tqdm when installed, else a line on stderr):
    each stage-2 level adds to what came before, as the CLI's bar does."""

    def __init__(self) -> None:
        self.base = 0
        self.last: Optional[Tuple[int, int, int]] = None
        try:
            from tqdm.auto import tqdm

            self.bar: Any = tqdm(total=0, unit="search", desc="acsg")
        except ImportError:
            self.bar = None

    def __call__(self, stage: int, done: int, total: int, states: int) -> None:
        if self.last is not None:
            s, d, t = self.last
            if s != stage or d >= t or done < d or total != t:
                self.base += t
        self.last = (stage, done, total)
        position, length = self.base + done, self.base + total
        if self.bar is not None:
            self.bar.total = length
            self.bar.n = position
            self.bar.set_postfix_str(f"stage {stage}, {states} states", refresh=False)
            self.bar.refresh()
        else:
            print(f"\racsg stage {stage}: {position}/{length} searches, {states} states", end="", file=sys.stderr)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
        elif self.last is not None:
            print(file=sys.stderr)


def generate(
    fixed: PartLike,
    moving: PartLike,
    bounds: Union[Mapping[str, Tuple[float, float]], Sequence[Sequence[float]]],
    degrees: bool = True,
    degenerate: bool = False,
    assembled: Any = None,
    threads: Optional[int] = None,
    progress: Union[bool, Callable[[int, int, int, int], Any]] = False,
    effort: Optional[int] = None,
    units: Optional[str] = None,
    strategy: Optional[str] = None,
    work_limit: Optional[int] = None,
) -> Graph:
    """Generates the contact state graph of a fixed and a moving part within bounds.

    :param fixed: part A (held fixed): a path, :class:`Part`, trimesh mesh or
        ``(vertices, faces)``.
    :param moving: part B (moved), in the same frame at the assembled pose.
    :param bounds: ``{"x": (min, max), ..., "rz": (min, max)}`` (omitted components
        fixed at 0), or ``(min6, max6)``; lengths in the parts' units, angles in degrees
        unless ``degrees=False``.
    :param degrees: whether the angles of ``bounds`` and ``assembled`` are degrees.
    :param degenerate: keep states with a degenerate contact.
    :param assembled: G, the assembled pose of B in A's frame: 6 values or a 4x4 matrix
        (default: identity).
    :param threads: worker threads (``None`` or 0: one per core); the graph does not
        depend on it.
    :param progress: ``True`` for a progress bar (tqdm when installed), or a callable
        ``progress(stage, done, total, states)``.
    :param effort: a multiple (1..1000) of the default search budget per candidate.
    :param units: the length unit of paths given (mm, cm, m, in), as the CLI's
        ``--units``.
    :param strategy: ``"full"`` (the default: every candidate decided) or ``"paper"``
        (the paper's algorithm step by step, a baseline that proves nothing
        infeasible), as the CLI's ``--strategy``.
    :param work_limit: stop searching and proving after this much work (boxes of poses
        examined, a local optimisation counting as 50), as the CLI's ``--work-limit``:
        the candidates met after it stay undecided and the graph is not complete
        (``stats.get("work_limit_reached")`` is then true). ``None`` (the default): no
        limit.
    :returns: the :class:`Graph`. The GIL is released while it runs; Ctrl-C stops it
        (``KeyboardInterrupt``).
    :raises AcsgError: a part that cannot be read or is not a valid solid.
    :raises ValueError: bad bounds, assembled pose or option.
    """
    a = part(fixed, units=units)
    b = part(moving, units=units)
    lo, hi = _bounds(bounds)
    bar = _Bar() if progress is True else None
    callback = bar if bar is not None else (progress if callable(progress) else None)
    try:
        text = _acsg.generate(
            a,
            b,
            lo,
            hi,
            degrees=degrees,
            degenerate=degenerate,
            assembled=None if assembled is None else _placement(assembled),
            threads=threads,
            effort=effort,
            progress=callback,
            strategy=strategy,
            work_limit=work_limit,
        )
    finally:
        if bar is not None:
            bar.close()
    return Graph(text)


@dataclass(frozen=True)
class ContactReport:
    """P(X) at one placement: what :func:`contacts` finds."""

    #: The principal contacts, sorted.
    contacts: Tuple[Contact, ...]
    #: How deep the parts penetrate (0 when they touch or are apart).
    penetration: float
    #: The smallest gap between elements that do not touch, when below 1% of L.
    min_gap: Optional[float]
    #: The placement of the moving part in the fixed part's frame, 4x4.
    matrix: np.ndarray = field(repr=False, compare=False)
    #: The absolute contact tolerance used.
    tolerance: float = 0.0

    @property
    def keys(self) -> Tuple[Tuple[str, str, str], ...]:
        """The contacts as ``(type, fixed, moving)`` triples."""
        return tuple(c.key for c in self.contacts)


def contacts(
    fixed: PartLike,
    moving: PartLike,
    pose: Any,
    degrees: bool = True,
    assembled: Any = None,
    tol: float = _acsg.CONTACT_REL,
) -> ContactReport:
    """P(X): the principal contacts between the parts at one pose of the moving part.

    :param pose: 6 values x, y, z, rx, ry, rz (angles in degrees unless
        ``degrees=False``; applied after ``assembled``), or a 4x4 matrix placing the
        moving part in the fixed part's frame (e.g. a :attr:`Witness.matrix`).
    :param assembled: G as 6 values or a 4x4 matrix (default: identity; not used with
        a 4x4 ``pose``).
    :param tol: the contact tolerance relative to L, the larger bounding-box diagonal.
    """
    a, b = part(fixed), part(moving)
    doc = json.loads(
        _acsg.contacts(
            a,
            b,
            _placement(pose),
            degrees=degrees,
            assembled=None if assembled is None else _placement(assembled),
            tol=tol,
        )
    )
    fe, me = _Elements(json.loads(a.elements_json())), _Elements(json.loads(b.elements_json()))
    return ContactReport(
        tuple(_contact(c, fe, me) for c in doc["contacts"]),
        float(doc["penetration"]),
        None if doc["min_gap"] is None else float(doc["min_gap"]),
        np.asarray(doc["matrix"], dtype=np.float64),
        float(doc["tolerance"]),
    )



def _matches(graph: Graph, task: Mapping[str, Any]) -> bool:
    """Whether a graph read back is the output of ``task``: the same part names, bounds
    and options (so that a changed task is generated again)."""
    doc = graph.document
    try:
        a = part(task["fixed"], units=task.get("units"))
        b = part(task["moving"], units=task.get("units"))
        lo, hi = _bounds(task["bounds"])
    except Exception:
        return False
    if task.get("degrees", True):
        lo = lo[:3] + [float(np.radians(v)) for v in lo[3:]]
        hi = hi[:3] + [float(np.radians(v)) for v in hi[3:]]
    same_bounds = np.allclose(doc["bounds"]["min"], lo, rtol=0, atol=1e-12) and np.allclose(
        doc["bounds"]["max"], hi, rtol=0, atol=1e-12
    )
    return (
        same_bounds
        and doc["fixed"]["path"] == a.name
        and doc["moving"]["path"] == b.name
        and doc["options"]["degenerate"] == bool(task.get("degenerate", False))
        # The default strategy is not written.
        and doc["options"].get("strategy", "full") == (task.get("strategy") or "full")
        # Written only when given.
        and doc["options"].get("work_limit") == task.get("work_limit")
    )


def generate_many(
    tasks: Iterable[Mapping[str, Any]],
    progress: Union[bool, Callable[[int, int], Any]] = False,
) -> List[Union[Graph, Exception]]:
    """Generates the graphs of many pairs, one after the other (each run uses every
    core); one pair's error does not stop the others.

    :param tasks: each a dict of :func:`generate`'s arguments (``fixed``, ``moving``,
        ``bounds``, and any of ``degrees``, ``degenerate``, ``assembled``, ``threads``,
        ``effort``, ``units``, ``strategy``, ``work_limit``), plus optionally ``output``: a path the graph's JSON is
        saved to. When that file already holds the graph of the same parts, bounds and
        options (written whole: files are written atomically), it is read instead of
        generated again, so a rerun of an interrupted batch does only what is left.
    :param progress: ``True`` for one progress bar for the whole batch (tqdm when
        installed), or a callable ``progress(done, total)`` called after each pair.
    :returns: a list in the order of ``tasks``: the :class:`Graph` of each pair, or the
        exception that pair raised (:class:`AcsgError`, ``ValueError``, ``TypeError``,
        ``OSError``, ...). ``KeyboardInterrupt`` stops the whole batch.
    """
    tasks = list(tasks)
    results: List[Union[Graph, Exception]] = []
    bar: Any = None
    if progress is True:
        try:
            from tqdm.auto import tqdm

            bar = tqdm(total=len(tasks), unit="pair", desc="acsg")
        except ImportError:
            bar = None
    for k, task in enumerate(tasks):
        try:
            results.append(_one(task))
        except Exception as error:  # each pair's error is its result
            results.append(error)
        if bar is not None:
            bar.update(1)
        elif progress is True:
            print(f"\racsg: {k + 1}/{len(tasks)} pairs", end="", file=sys.stderr)
        elif callable(progress):
            progress(k + 1, len(tasks))
    if bar is not None:
        bar.close()
    elif progress is True and tasks:
        print(file=sys.stderr)
    return results


def _one(task: Mapping[str, Any]) -> Graph:
    if not isinstance(task, Mapping):
        raise TypeError(f"a task is a dict of generate's arguments, not {type(task).__name__}")
    arguments = dict(task)
    output = arguments.pop("output", None)
    arguments.pop("progress", None)
    if output is not None and os.path.exists(output):
        try:
            done = Graph.load(output)
        except AcsgError:
            done = None
        if done is not None and _matches(done, task):
            return done
    graph = generate(**arguments)
    if output is not None:
        graph.save(output)
    return graph
