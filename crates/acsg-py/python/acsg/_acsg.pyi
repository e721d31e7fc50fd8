"""Type stubs of the extension module ``acsg._acsg`` (crates/acsg-py/src/lib.rs).

Use the package ``acsg`` instead: it wraps these functions, turning their JSON text
into objects and numpy arrays.
"""

from typing import Callable, List, Optional, Sequence, Tuple

__version__: str
#: The default contact tolerance, relative to L (the larger bounding-box diagonal).
CONTACT_REL: float

class AcsgError(Exception):
    """An input acsg cannot use: a part that cannot be read or is not a valid solid, a
    graph file that cannot be read. The message names the file, the place and the fix."""

class Part:
    """A validated part: the exact boundary representation of one polyhedral solid."""

    @staticmethod
    def from_path(path: str, units: Optional[str] = None, facet: Optional[float] = None) -> Part:
        """Reads a part from a model file (OFF, OBJ, STL, PLY, or STEP/IGES with planar
        faces); ``units`` (mm, cm, m, in) as the CLI's ``--units``, ``facet`` as
        ``--facet``. Raises :class:`AcsgError` naming the file, the place and the fix."""
    @staticmethod
    def from_arrays(
        vertices: Sequence[Sequence[float]],
        faces: Sequence[Sequence[int]],
        name: str = "mesh",
        units: Optional[str] = None,
    ) -> Part:
        """Builds a part from vertex coordinates and polygons (indices into
        ``vertices``, counter-clockwise seen from outside); coplanar triangles merge
        into faces. Raises :class:`AcsgError` with every defect found."""
    @property
    def name(self) -> str:
        """The part's name (its path as given, or the name given to ``from_arrays``)."""
    @property
    def counts(self) -> Tuple[int, int, int]:
        """The number of vertices, edges and faces of the B-rep."""
    @property
    def volume(self) -> float:
        """The part's volume."""
    def elements_json(self) -> str:
        """The elements with geometry, as the graph's JSON writes them."""

def generate(
    fixed: Part,
    moving: Part,
    bounds_min: Sequence[float],
    bounds_max: Sequence[float],
    degrees: bool = True,
    degenerate: bool = False,
    assembled: Optional[Sequence[float]] = None,
    threads: Optional[int] = None,
    effort: Optional[int] = None,
    progress: Optional[Callable[[int, int, int, int], object]] = None,
    names: Optional[Tuple[str, str]] = None,
    strategy: Optional[str] = None,
) -> str:
    """Generates the contact state graph; returns its JSON document. The GIL is
    released while it runs; ``progress(stage, done, total, states)`` is called between
    batches of searches, and an exception it raises (or Ctrl-C) stops the run and is
    raised here. ``strategy``: ``"full"`` (default) or ``"paper"`` (the paper's
    algorithm, a baseline)."""

def contacts(
    fixed: Part,
    moving: Part,
    pose: Sequence[float],
    degrees: bool = True,
    assembled: Optional[Sequence[float]] = None,
    tol: float = ...,
) -> str:
    """P(X) at one placement (6 pose values or 16 of a row-major 4x4 matrix), as JSON
    with ``contacts``, ``penetration``, ``min_gap``, ``matrix``, ``tolerance``."""

def check_graph_file(path: str) -> None:
    """Reads and checks a graph's JSON file; raises :class:`AcsgError` naming the file
    and the problem."""

def check_graph(text: str, name: str = "<string>") -> None:
    """Checks a graph's JSON text."""

def write_atomic(path: str, text: str) -> None:
    """Writes text to a file atomically."""

def formats() -> List[str]:
    """The file extensions parts are read from."""
