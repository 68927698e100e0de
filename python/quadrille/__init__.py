"""Quadrille: quadrilateral meshes of CAD models and triangle meshes.

    >>> import quadrille
    >>> m = quadrille.mesh("part.step")          # a QuadMesh
    >>> m.nodes.shape, m.quads.shape             # (n, 3) float64, (m, 4) int64
    >>> m.write("part.msh")                      # MSH 4.1 (meshio and Gmsh read it)
    >>> m.stats(m.model)["sicn"]                 # the numbers of `quadrille stats`

Functions: :func:`load` (a CAD model or triangle mesh), :func:`mesh`,
:func:`read_mesh` (MSH 4.1 / 2.2 from any mesher), :func:`field` (cross field
and singularities). Classes: :class:`Model`, :class:`QuadMesh`. Errors:
:class:`Error` and its subclasses :class:`FileError`, :class:`OptionError`,
:class:`MeshingError`.

Meshing runs in Rust with the interpreter free (other Python threads run);
Ctrl-C raises KeyboardInterrupt at once.
"""

# the arrays' module, imported with the package rather than inside the first
# call that returns an array (its import takes tens of milliseconds)
import numpy as _numpy  # noqa: F401

from ._quadrille import (
    Error,
    FileError,
    MeshingError,
    Model,
    OptionError,
    QuadMesh,
    __version__,
    field,
    load,
    mesh,
    read_mesh,
)

__all__ = [
    "Error",
    "FileError",
    "MeshingError",
    "Model",
    "OptionError",
    "QuadMesh",
    "__version__",
    "field",
    "load",
    "mesh",
    "read_mesh",
]
