"""Shared helpers of the Python package's tests.

Run by ``./run-tests`` (which builds and installs the package, and sets
``QUADRILLE_CLI`` to the ``quadrille`` binary ``cargo test`` built and
``QUADRILLE_REQUIRE_GMSH=1``), or by hand: ``pytest python/tests``.
"""

import json
import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CAD = ROOT / "data" / "cad"
#: Every bundled CAD model.
MODELS = sorted(p for p in CAD.iterdir() if p.suffix in (".step", ".stp"))
#: Small models meshed quickly by every method.
SMALL = [CAD / n for n in ("s17o_sphere.stp", "s11o_cube_cyl.stp", "i10o_simp.step", "twisted_body.step")]
METHODS = ["quasi-structured", "unstructured", "baseline", "regular"]


def required():
    """True when missing test tools are an error (CI), not a skip."""
    return os.environ.get("QUADRILLE_REQUIRE_GMSH") == "1"


def need(module):
    """Imports `module`, or skips the test (fails when `required()`)."""
    try:
        return __import__(module)
    except ImportError:
        if required():
            pytest.fail(f"QUADRILLE_REQUIRE_GMSH=1 but {module} is not importable")
        pytest.skip(f"{module} is not installed")


def _cli_path():
    env = os.environ.get("QUADRILLE_CLI")
    if env:
        return env
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for profile in ("debug", "release"):
        p = target / profile / "quadrille"
        if p.exists():
            return str(p)
    return shutil.which("quadrille")


@pytest.fixture(scope="session")
def cli():
    """A function running the ``quadrille`` binary: ``cli(*args)`` → CompletedProcess (checked)."""
    path = _cli_path()
    if path is None or not os.path.exists(path):
        if required() or os.environ.get("QUADRILLE_CLI"):
            pytest.fail(f"the quadrille binary is missing ({path})")
        pytest.skip("the quadrille binary is not built (cargo build -p cli)")

    def run(*args, check=True):
        r = subprocess.run([path, *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(f"quadrille {' '.join(map(str, args))} failed: {r.stderr}")
        return r

    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    """``cli_json(*args)``: the JSON a command prints."""
    return lambda *args: json.loads(cli(*args).stdout)


def assert_same_quads(points_a, quads_a, points_b, quads_b):
    """The same quads, corner for corner, whatever the node numbering: meshio
    numbers points in the order of the file's node blocks (per entity), not
    by node tag, so after the regular method's edits its order is not ours."""
    import numpy as np

    assert len(points_a) == len(points_b)
    a = np.asarray(points_a)[np.asarray(quads_a)].reshape(len(quads_a), 12)
    b = np.asarray(points_b)[np.asarray(quads_b)].reshape(len(quads_b), 12)
    np.testing.assert_array_equal(a[np.lexsort(a.T[::-1])], b[np.lexsort(b.T[::-1])])
