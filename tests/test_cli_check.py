"""The ``check`` subcommand: certify a hull from files; exit 0 valid, 1 invalid, 2 bad input."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

import numpy as np
import pytest

import hullstress.cli as cli
from hullstress.adapters.executable import locate_program
from hullstress.checker import qhull_reference
from hullstress.cli import _check
from hullstress.errors import InputFileError
from hullstress.io import write_faces, write_points

wired = pytest.mark.skipif("check" not in cli.SUBCOMMANDS, reason="'check' is not yet in hullstress.cli.SUBCOMMANDS")


def run(argv: list[str]) -> int:
    """Parse with the subcommand's own parser and run its handler in-process."""
    parser = argparse.ArgumentParser()
    _check.add_parser(parser.add_subparsers())
    args = parser.parse_args(["check", *argv])
    return args.handler(args)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("cli")
    rng = np.random.default_rng(3)
    pts3 = rng.normal(size=(150, 3))
    tri = qhull_reference(pts3).faces.triangles()
    pts2 = rng.normal(size=(40, 2))
    poly = qhull_reference(pts2).faces
    out = {
        "p3": write_points(d / "p3.txt", pts3, "qhull"),
        "p3csv": write_points(d / "p3.csv", pts3, "csv"),
        "p3npy": write_points(d / "p3.npy", pts3, "npy"),
        "f3": write_faces(d / "f3.i", tri, "qhull"),
        "f3npy": write_faces(d / "f3.npy", tri, "npy"),
        "f3cw": write_faces(d / "f3cw.i", tri[:, ::-1], "qhull"),
        "f3flip": write_faces(d / "f3flip.csv", np.r_[tri[:1, ::-1], tri[1:]], "csv"),
        "p2": write_points(d / "p2.xyz", pts2, "xyz"),
        "f2": write_faces(d / "f2.txt", poly, "csv"),
        "off": write_points(d / "hull.off", pts3, "off", faces=tri.tolist()),
        "dir": d,
    }
    return out


def test_valid_hulls_exit_0(files, capsys):
    assert run([str(files["p3"]), str(files["f3"])]) == 0
    assert capsys.readouterr().out.startswith("VALID")
    assert run([str(files["p3csv"]), str(files["f3npy"])]) == 0
    assert run([str(files["p3npy"]), str(files["f3cw"]), "--clockwise"]) == 0
    assert run([str(files["p2"]), str(files["f2"])]) == 0
    assert run([str(files["off"]), str(files["off"]), "--no-qhull"]) == 0


def test_invalid_hull_exit_1_with_offending_indices(files, capsys):
    assert run([str(files["p3"]), str(files["f3flip"])]) == 1
    out = capsys.readouterr().out
    assert out.startswith("INVALID") and "offending flipped_faces: 0" in out and "FAIL" in out
    assert run([str(files["p3"]), str(files["f3cw"])]) == 1  # clockwise without --clockwise


def test_json_output(files, capsys):
    assert run([str(files["p3"]), str(files["f3flip"]), "--json", "--max-offending", "2"]) == 1
    row = json.loads(capsys.readouterr().out)
    assert row["ok"] is False and row["manifoldness"] is False and row["qhull_options"] == "Qt"
    assert row["offending"]["flipped_faces"] == [0] and len(row["offending"]["containment"]) == 2


@pytest.mark.parametrize(
    "points,faces,message",
    [
        ("missing.txt", "f3", "does not exist"),
        ("p3", "missing.i", "does not exist"),
        ("bad", "f3", "non-numeric token"),
        ("p3", "badface", "out of range"),
    ],
)
def test_bad_input_raises_input_file_error(files, points, faces, message):
    d = files["dir"]
    (d / "bad").write_text("0 0 0\n1 x 2\n")
    (d / "badface").write_text("0 1 999\n")
    p = files.get(points, d / points)
    f = files.get(faces, d / faces)
    with pytest.raises(InputFileError, match=message):
        run([str(p), str(f)])


@wired
def test_main_exit_statuses(files, capsys):
    assert cli.main(["check", str(files["p3"]), str(files["f3"])]) == 0
    assert cli.main(["check", str(files["p3"]), str(files["f3flip"])]) == 1
    assert cli.main(["check", str(files["dir"] / "nope.txt"), str(files["f3"])]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "does not exist" in err[0]


@wired
def test_subprocess(files):
    proc = subprocess.run(
        [sys.executable, "-m", "hullstress", "check", str(files["p2"]), str(files["f2"])],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert "VALID" in proc.stdout


def test_qconvex_output_is_certified(tmp_path):
    # qconvex comes with the `all` extra (cmeel-qhull, outside PATH: locate_program finds it).
    qconvex = locate_program("qconvex")
    if qconvex is None:
        subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "cmeel-qhull"], capture_output=True,
                       timeout=600)
        qconvex = locate_program("qconvex")
    if qconvex is None:
        pytest.skip("qconvex is not installed and `pip install cmeel-qhull` failed (no network?)")
    pts = np.random.default_rng(4).normal(size=(200, 3))
    path = write_points(tmp_path / "p.txt", pts, "qhull")
    with open(path) as fh:
        faces = subprocess.run([qconvex, "i", "Qt"], stdin=fh, capture_output=True, text=True, check=True).stdout
    (tmp_path / "f.i").write_text(faces)
    assert run([str(path), str(tmp_path / "f.i"), "--clockwise"]) == 0  # Qhull's 'i' output is clockwise
