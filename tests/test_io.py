"""Tests for hullstress.io: exact round trips, every format, one-line errors."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from hullstress.cli import main
from hullstress.errors import InputFileError
from hullstress.io import (parse_float, points_file_bytes, read_faces, read_points, read_points_bytes, write_faces,
                           write_points)

finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@pytest.mark.parametrize("fmt,ext", [("npy", ".npy"), ("csv", ".csv"), ("qhull", ".txt"), ("xyz", ".xyz"), ("off", ".off")])
@given(pts=hnp.arrays(np.float64, st.tuples(st.integers(1, 8), st.just(3)), elements=finite))
def test_points_round_trip_is_bit_exact(tmp_path_factory, fmt, ext, pts):
    path = tmp_path_factory.mktemp("rt") / f"p{ext}"
    back = read_points(write_points(path, pts, fmt))
    # Compare bits, so that -0.0 vs 0.0 and subnormals count.
    assert back.dtype == np.float64 and back.shape == pts.shape
    assert np.array_equal(back.view(np.int64), pts.view(np.int64))


@pytest.mark.parametrize("fmt,ext", [("npy", ".npy"), ("csv", ".csv"), ("qhull", ".txt"), ("xyz", ".xyz"), ("off", ".off")])
@given(pts=hnp.arrays(np.float64, st.tuples(st.integers(1, 8), st.sampled_from([2, 3])), elements=finite))
def test_the_bytes_of_a_points_file_are_the_file_and_read_back_the_same(tmp_path_factory, fmt, ext, pts):
    # points_file_bytes is what write_points writes, and read_points_bytes reads it as read_points
    # reads the file: triage proves a minimal case survives its file this way, without the disk.
    if fmt == "off" and pts.shape[1] != 3:
        return
    path = write_points(tmp_path_factory.mktemp("bytes") / f"p{ext}", pts, fmt)
    data = points_file_bytes(pts, fmt)
    assert path.read_bytes() == data
    back = read_points_bytes(data, name=f"p{ext}")
    assert np.array_equal(back.view(np.int64), read_points(path).view(np.int64))


@given(pts=hnp.arrays(np.float64, st.tuples(st.integers(1, 6), st.just(2)), elements=finite))
def test_hex_float_round_trip(tmp_path_factory, pts):
    path = tmp_path_factory.mktemp("hex") / "p.txt"
    back = read_points(write_points(path, pts, "qhull", hex_floats=True))
    assert np.array_equal(back.view(np.int64), pts.view(np.int64))


def test_decimal_literals_are_correctly_rounded(tmp_path):
    # 0.1 + 2**-56 boundary cases: float() rounds correctly, naive digit accumulation would not.
    literals = ["0.1", "2.2250738585072011e-308", "4.9e-324", "1.7976931348623157e308", "0x1.fffffffffffffp+1023"]
    path = tmp_path / "p.csv"
    path.write_text("x,y\n" + "\n".join(f"{s},1" for s in literals) + "\n")
    got = read_points(path)[:, 0]
    expected = [float(s) if not s.startswith("0x") else float.fromhex(s) for s in literals]
    assert got.tolist() == expected
    assert parse_float("-0x1.8p-3") == -0.1875


def test_rbox_header_with_comment_and_count(tmp_path):
    path = tmp_path / "r.txt"
    path.write_text("3 rbox 4 D3 t1\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n")
    assert read_points(path).shape == (4, 3)
    path.write_text("4 3\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n")  # count then dimension, one line
    assert read_points(path).shape == (4, 3)


def test_xyz_count_line_and_whitespace_csv(tmp_path):
    path = tmp_path / "p.xyz"
    path.write_text("2\n1 2 3\n4 5 6\n")
    assert read_points(path).tolist() == [[1, 2, 3], [4, 5, 6]]
    path = tmp_path / "p.csv"
    path.write_text("# comment\n1 2\n3 4\n")
    assert read_points(path).tolist() == [[1, 2], [3, 4]]


def test_integer_npy_points_are_accepted_when_exact(tmp_path):
    path = tmp_path / "i.npy"
    np.save(path, np.array([[1, 2], [3, 4]], dtype=np.int32))
    assert read_points(path).dtype == np.float64
    np.save(path, np.array([[2**60, 1], [0, 0]], dtype=np.int64))
    with pytest.raises(InputFileError, match="2\\*\\*53"):
        read_points(path)


NON_FINITE = [
    ("rows.csv", "x,y\n1,2\n3,4\nnan,3\n5,inf\n", "point 2 at line 4 has a non-finite coordinate 'nan' (2 points in all)"),
    ("one.xyz", "0 0 0\n1 0 0\n0 -inf 1\n", "point 2 at line 3 has a non-finite coordinate '-inf'"),
    ("rbox.txt", "2 rbox 3 D2\n3\n0 0\n1e999 0\n0 1\n", "point 1 at line 4 has a non-finite coordinate '1e999'"),
    ("mesh.off", "OFF\n3 0 0\n0 0 0\nNaN 1 0\n0 1 1\n", "point 1 at line 4 has a non-finite coordinate 'NaN'"),
    ("hex.csv", "0x1p0,0\n0,0x1p2000\n", "point 1 at line 2 has a non-finite coordinate '0x1p2000'"),
]

BAD_POINTS = [
    ("missing.csv", None, "does not exist"),
    ("empty.csv", "", "is empty"),
    ("ragged.csv", "1,2,3\n4,5\n", "ragged rows: line 2 has 2 values, expected 3"),
    ("word.csv", "1,2\n3,abc\n", "non-numeric token 'abc' at line 2"),
    ("fourd.csv", "1,2,3,4\n", "wrong dimension"),
    ("oned.xyz", "1\n2\n3\n", "wrong dimension"),
    ("nan.csv", "1,2\nnan,3\n", "non-finite"),
    ("count.txt", "2\n5\n0 0\n1 1\n", "announces 5 points, the file has 2"),
    ("bad.off", "OFF\n2 0 0\n0 0 0\n", "announces 2 vertices"),
    *NON_FINITE,  # named by point index and line
]


#: Bad contents read from bytes as from a file (the file-only problems, a missing file, excepted).
BAD_POINTS_IN_MEMORY = [(n, t.encode(), m) for n, t, m in BAD_POINTS if t is not None] + [
    ("latin.csv", "1,2\n3,\xe9\n".encode("latin-1"), "is not UTF-8 text"),
    ("junk.npy", b"\x93NUMPY garbage", "is not a readable .npy array"),
]


@pytest.mark.parametrize("name,text,message", BAD_POINTS_IN_MEMORY)
def test_bad_points_bytes_raise_the_files_error(tmp_path, name, text, message):
    path = tmp_path / name
    path.write_bytes(text)
    with pytest.raises(InputFileError) as from_file:
        read_points(path)
    with pytest.raises(InputFileError) as from_bytes:
        read_points_bytes(text, name=name)
    assert message in str(from_bytes.value)
    assert str(from_bytes.value) == str(from_file.value).replace(str(path), name)


@pytest.mark.parametrize("name,text,message", BAD_POINTS)
def test_bad_points_files_raise_one_line(tmp_path, name, text, message):
    path = tmp_path / name
    if text is not None:
        path.write_text(text)
    with pytest.raises(InputFileError) as info:
        read_points(path)
    msg = str(info.value)
    assert message in msg and name in msg and "\n" not in msg


def test_dimension_requested_must_match(tmp_path):
    path = write_points(tmp_path / "p.csv", np.zeros((3, 2)))
    with pytest.raises(InputFileError, match="expected 3 coordinates per point, got 2"):
        read_points(path, dim=3)


def test_faces_formats(tmp_path):
    tri = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]])
    for fmt, ext in [("npy", ".npy"), ("csv", ".csv"), ("qhull", ".i")]:
        got = read_faces(write_faces(tmp_path / f"f{ext}", tri, fmt))
        assert np.array_equal(np.asarray(got), tri)
    pts = np.eye(3)
    path = write_points(tmp_path / "m.off", np.vstack([pts, [[0, 0, 0]]]), "off", faces=[[0, 1, 2], [0, 3, 1, 2]])
    assert read_faces(path) == [[0, 1, 2], [0, 3, 1, 2]]
    assert read_points(path).shape == (4, 3)


def test_2d_faces_forms(tmp_path):
    path = tmp_path / "poly.txt"
    path.write_text("0 3 1 2\n")
    assert read_faces(path, dim=2) == [0, 3, 1, 2]
    path.write_text("0\n3\n1\n2\n")
    assert read_faces(path, dim=2) == [0, 3, 1, 2]
    path.write_text("4\n0 3\n1 2\n3 1\n2 0\n")  # Qhull 'i' in 2D: directed edges
    assert read_faces(path, dim=2) == [0, 3, 1, 2]
    path.write_text("4\n0 3\n1 2\n1 3\n2 0\n")  # one edge reversed
    with pytest.raises(InputFileError, match="starts two edges|do not close"):
        read_faces(path, dim=2)
    path.write_text("4\n0 1\n1 0\n2 3\n3 2\n")  # two cycles
    with pytest.raises(InputFileError, match="more than one cycle"):
        read_faces(path, dim=2)


def test_bad_faces_files(tmp_path):
    path = tmp_path / "f.txt"
    path.write_text("0 1 x\n")
    with pytest.raises(InputFileError, match="non-integer token 'x' at line 1"):
        read_faces(path)
    path = tmp_path / "f.npy"
    np.save(path, np.zeros((2, 3)))
    with pytest.raises(InputFileError, match="integer array"):
        read_faces(path)
    with pytest.raises(InputFileError, match="does not exist"):
        read_faces(tmp_path / "nope.i")


def test_non_finite_npy_rows_are_named_by_array_row(tmp_path):
    path = tmp_path / "p.npy"
    np.save(path, np.array([[0.0, 0.0], [1.0, 2.0], [np.inf, 0.0], [0.0, np.nan]]))
    with pytest.raises(InputFileError) as info:
        read_points(path)
    msg = str(info.value)
    assert "point 2 (row 2 of the array) has a non-finite coordinate inf (2 points in all)" in msg
    assert "p.npy" in msg and "\n" not in msg


@pytest.mark.parametrize("name,text,message", NON_FINITE[:3], ids=[n for n, _, _ in NON_FINITE[:3]])
def test_run_with_a_non_finite_points_file_exits_2_with_one_line(tmp_path, capsys, name, text, message):
    path = tmp_path / name
    path.write_text(text)
    assert main(["run", "--points-file", str(path), "--out", str(tmp_path / "out"), "--workers", "0"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err and "Traceback" not in err
