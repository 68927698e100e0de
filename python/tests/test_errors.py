"""Bad input raises a quadrille.Error subclass naming the file (the bad inputs
of the command line's tests), never a crash; options are checked before any
long work."""

import math

import numpy as np
import pytest

import quadrille
from conftest import CAD

SPHERE = CAD / "s17o_sphere.stp"

STEP_WITHOUT_FACES = b"""ISO-10303-21;
HEADER;
FILE_DESCRIPTION(('a point only'),'2;1');
FILE_NAME('point.step','2026-01-01T00:00:00',(''),(''),'','','');
FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));
ENDSEC;
DATA;
#1=CARTESIAN_POINT('',(0.,0.,0.));
ENDSEC;
END-ISO-10303-21;
"""


def test_the_classes():
    for cls in (quadrille.FileError, quadrille.OptionError, quadrille.MeshingError):
        assert issubclass(cls, quadrille.Error) and issubclass(cls, Exception)
    assert quadrille.FileError.__module__ == "quadrille"


def bad_files(tmp):
    """(path, words the message must hold) for each bad model file."""
    full = (CAD / "i01o_m1.step").read_bytes()
    garbage = bytes((i * 2654435761 >> 13) & 0xFF for i in range(4096))
    files = {
        "empty.step": (b"", "empty"),
        "empty.stl": (b"", ""),
        "truncated.step": (full[: len(full) // 2], ""),
        "garbage.step": (garbage, ""),
        "point_only.step": (STEP_WITHOUT_FACES, "face"),
        "model.xyz": (b"solid nothing", "extension"),
        "garbage.stl": (garbage, ""),
    }
    out = [(tmp / "no_such_model.step", "not found"), (tmp / "no_such_mesh.stl", "")]
    for name, (data, words) in files.items():
        (tmp / name).write_bytes(data)
        out.append((tmp / name, words))
    return out


def test_bad_model_files(tmp_path):
    for path, words in bad_files(tmp_path):
        for call in (quadrille.load, quadrille.mesh, quadrille.field):
            with pytest.raises(quadrille.FileError) as e:
                call(path)
            msg = str(e.value)
            assert path.name in msg, msg
            assert words in msg.lower(), msg


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"size": 0}, "size"),
        ({"size": -1.0}, "size"),
        ({"size": math.nan}, "size"),
        ({"size": math.inf}, "size"),
        ({"size_factor": 0}, "size_factor"),
        ({"size_factor": -2}, "size_factor"),
        ({"size": 1.0, "size_factor": 2.0}, "not both"),
        ({"method": "paving"}, "paving"),
        ({"threads": 0}, "threads"),
        ({"threads": -3}, "threads"),
        ({"quads_per_turn": -1}, "quads_per_turn"),
        ({"max_quads": -1}, "max_quads"),
        ({"method": "baseline", "cavities": False}, "cavities=False"),
        ({"method": "regular", "patterns": False, "defects": False}, "patterns=False, defects=False"),
    ],
)
def test_bad_options(kwargs, words):
    with pytest.raises(quadrille.OptionError, match=words.replace("(", r"\(")):
        quadrille.mesh(SPHERE, **kwargs)


def test_a_far_too_small_size_is_refused_before_meshing():
    # the size guard: one line with the estimate, a size that fits and the
    # option that lifts the limit
    with pytest.raises(quadrille.OptionError) as e:
        quadrille.mesh(CAD / "i01o_m1.step", size=1e-5)
    msg = str(e.value)
    assert "i01o_m1.step" in msg and "quads estimated" in msg, msg
    assert "size_factor" in msg and "max_quads 0" in msg and "\n" not in msg, msg
    # a limit of 10 refuses the default size; 0 lifts it
    with pytest.raises(quadrille.OptionError, match="limit of 10 quads"):
        quadrille.mesh(SPHERE, max_quads=10)
    m = quadrille.mesh(SPHERE, max_quads=0)
    assert len(m.quads) > 10
    assert m.report["estimated_quads"] > 10


def test_options_are_checked_before_loading(tmp_path):
    # a bad option on a missing file: the option is reported (nothing was read)
    with pytest.raises(quadrille.OptionError):
        quadrille.mesh(tmp_path / "missing.step", size=-1)
    with pytest.raises(quadrille.OptionError):
        quadrille.field(tmp_path / "missing.step", size_factor=0)
    with pytest.raises(quadrille.OptionError, match="feature_angle"):
        quadrille.load(SPHERE, feature_angle=0)


def test_wrong_types_are_type_errors():
    with pytest.raises(TypeError):
        quadrille.mesh(42)
    with pytest.raises(TypeError):
        quadrille.mesh(SPHERE, size="big")
    with pytest.raises(TypeError):
        quadrille.read_mesh(None)


def test_bad_outputs_leave_nothing(tmp_path):
    m = quadrille.mesh(SPHERE, size_factor=2)
    blocker = tmp_path / "blocker"
    blocker.write_bytes(b"x")
    for out, cls in [
        (blocker / "out.msh", quadrille.FileError),
        (tmp_path / "out.docx", quadrille.FileError),
        (tmp_path / "out.vtu", None),
    ]:
        if cls is None:
            with pytest.raises(quadrille.OptionError):
                m.write(out, binary=True)
        else:
            with pytest.raises(cls) as e:
                m.write(out)
            assert out.name in str(e.value)
        assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blocker"]


def test_bad_mesh_files(tmp_path):
    broken = tmp_path / "broken.msh"
    broken.write_bytes(b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 5 1 5\n2 1 0 5\n1\n")
    other = tmp_path / "mesh.vtu"
    other.write_bytes(b"<VTKFile/>")
    for path in (broken, other, tmp_path / "missing.msh"):
        with pytest.raises(quadrille.FileError) as e:
            quadrille.read_mesh(path)
        assert path.name in str(e.value)


def test_a_good_call_after_errors_still_works():
    m = quadrille.mesh(SPHERE)
    assert len(m) > 0 and np.isfinite(m.nodes).all()
