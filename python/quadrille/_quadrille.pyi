"""Types of the native module ``quadrille._quadrille`` (re-exported by ``quadrille``)."""

import os
import pathlib
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

PathLike = Union[str, "os.PathLike[str]"]
Progress = Union[bool, Callable[[int, int], object], None]

class Error(Exception):
    """Base class of every error quadrille raises."""

class FileError(Error):
    """A file is missing, empty, unreadable, malformed, of an unknown extension, or cannot be written."""

class OptionError(Error):
    """An option is invalid: size, size_factor, method, threads, stage switches, feature_angle."""

class MeshingError(Error):
    """Meshing (or the cross field) failed on a valid model with valid options."""

class Model:
    """A CAD B-rep or a triangle mesh read as one. Made by :func:`load`."""

    @property
    def path(self) -> pathlib.Path:
        """The file the model was read from."""
    @property
    def faces(self) -> int:
        """Number of CAD faces."""
    @property
    def curves(self) -> int:
        """Number of CAD curves."""
    @property
    def corners(self) -> int:
        """Number of CAD corners."""
    @property
    def bounding_box(self) -> Tuple[Tuple[float, float, float], Tuple[float, float, float]]:
        """``((xmin, ymin, zmin), (xmax, ymax, zmax))``."""
    @property
    def diagonal(self) -> float:
        """Length of the bounding-box diagonal (the default quad size is 1/24 of it)."""
    @property
    def warnings(self) -> List[str]:
        """Repairs the triangle-mesh import made (empty for CAD models)."""

class QuadMesh:
    """A surface mesh whose nodes are classified on CAD entities. Arrays are read-only."""

    @property
    def nodes(self) -> npt.NDArray[np.float64]:
        """Node positions, shape (n, 3)."""
    @property
    def quads(self) -> npt.NDArray[np.int64]:
        """Quads as 0-based node indices, shape (m, 4), counter-clockwise seen from outside."""
    @property
    def triangles(self) -> npt.NDArray[np.int64]:
        """Triangles as 0-based node indices, shape (k, 3) (only in files from other meshers)."""
    @property
    def node_entity(self) -> npt.NDArray[np.int64]:
        """(dimension, 1-based id) of each node's CAD entity, shape (n, 2): 0 corner, 1 curve, 2 face; (-1, 0) for none."""
    @property
    def quad_face(self) -> npt.NDArray[np.int64]:
        """1-based CAD face of each quad, shape (m,)."""
    @property
    def triangle_face(self) -> npt.NDArray[np.int64]:
        """1-based CAD face of each triangle, shape (k,)."""
    @property
    def model(self) -> Optional[Model]:
        """The model the mesh was made from (None when read from a file)."""
    @property
    def report(self) -> Optional[Dict[str, Any]]:
        """What meshing did (method, per-step counts, stage times in seconds); None when read from a file."""
    def write(self, path: PathLike, binary: bool = False, parametric: bool = False) -> None:
        """Writes .msh (MSH 4.1), .vtu or .obj, by the extension of ``path``."""
    def stats(self, model: Optional[Model] = None) -> Dict[str, Any]:
        """The dict of ``quadrille stats --json`` (with ``model``: as ``--cad``)."""
    def to_meshio(self) -> Any:
        """The mesh as a ``meshio.Mesh`` (needs meshio)."""
    def __len__(self) -> int:
        """Number of quads."""

def load(path: PathLike, feature_angle: float = 30.0) -> Model:
    """Reads a CAD model (.step .stp .iges .igs .brep .brp) or a triangle mesh (.stl .obj .ply .msh)."""

def mesh(
    model_or_path: Union[Model, PathLike],
    size: Optional[float] = None,
    size_factor: float = 1.0,
    method: str = "quasi-structured",
    threads: Optional[int] = None,
    progress: Progress = None,
    patterns: bool = True,
    defects: bool = True,
    cavities: bool = True,
    regular_pass: bool = True,
    quads_per_turn: float = 20.0,
    max_quads: int = 50_000_000,
) -> QuadMesh:
    """Meshes a model with quads (methods: quasi-structured, unstructured, baseline, regular)."""

def read_mesh(path: PathLike) -> QuadMesh:
    """Reads an MSH 4.1 (ASCII or binary) or 2.2 (ASCII) file from any mesher."""

def field(
    model_or_path: Union[Model, PathLike],
    size: Optional[float] = None,
    size_factor: float = 1.0,
    progress: Progress = None,
    quads_per_turn: float = 20.0,
) -> Dict[str, Any]:
    """The cross field: arrays points, triangles, triangle_face, cross, size_map; singularities; per-face report."""
