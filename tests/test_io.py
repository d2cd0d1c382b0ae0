"""Tests of fastline.io: spectrum files in (with plausibility checks), result CSVs out."""

import os

import numpy as np
import pytest

import fastline as fl
from fastline import io

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLE = os.path.join(ROOT, "examples", "psd_example.txt")


def write(tmp_path, text, name="f.txt"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_read_spectrum_roundtrip(tmp_path):
    psd = fl.SelfAffinePSD(3e-6, 0.8, 1e3, 1e4, 1e8)
    q = np.union1d(np.geomspace(1e3, 1e8, 80), [1e4])  # the roll-off corner is a table point
    body = "\n".join(
        f"{a!r},{b!r}  # comment" for a, b in zip(q.tolist(), psd(q).tolist(), strict=True)
    )
    tab = io.read_spectrum(write(tmp_path, "# q [1/m]  C [m^4]\n\n" + body))
    np.testing.assert_array_equal(tab.q, q)
    # log-log interpolation is exact for piecewise power laws with their corners tabulated
    assert tab.h_rms == pytest.approx(psd.h_rms, rel=1e-9)


def test_example_spectrum_is_plausible():
    tab = io.read_spectrum(EXAMPLE)
    s = io.spectrum_summary(tab)
    assert 1e-7 < s["h_rms"] < 1e-4 and 0.01 < s["rms_slope"] < 10.0
    assert s["longest_wavelength"] == pytest.approx(2 * np.pi / tab.q0, rel=1e-12)


@pytest.mark.parametrize(
    "text, needle",
    [
        ("0 1e-6\n1e-5 2e-6\n2e-5 -1e-6\n", "this looks like a height profile, not a spectrum"),
        ("1e3 1e-20\n1e4 -1e-22\n", "C(q) < 0"),
        ("1e3 1e-20 5\n1e4 1e-22 5\n", "expected two columns"),
        ("1e3 1e-20\n1e4 abc\n", "f.txt:2: not a number"),
        ("q C\n1e3 1e-20\n1e4 1e-22\nend of data\n", "f.txt:4: not a number"),
        ("1e3,1e-20\n1e4,\n", "f.txt:2: a value is missing"),
        ("1e3 1e-20\n", "at least two"),
        ("1e4 1e-20\n1e3 1e-22\n", "strictly increasing"),
    ],
)
def test_read_spectrum_rejects(tmp_path, text, needle):
    with pytest.raises(io.SpectrumFileError, match="f.txt") as e:
        io.read_spectrum(write(tmp_path, text))
    assert needle in str(e.value)
    assert issubclass(io.SpectrumFileError, ValueError)


SPECTRUM_Q = np.geomspace(1e3, 1e7, 9)
SPECTRUM_C = 1e-20 * (SPECTRUM_Q / 1e3) ** -3.6


def _table_text(sep: str, decimal: str = ".") -> str:
    return "\n".join(
        f"{q!r}{sep}{C!r}".replace(".", decimal) if decimal != "." else f"{q!r}{sep}{C!r}"
        for q, C in zip(SPECTRUM_Q.tolist(), SPECTRUM_C.tolist(), strict=True)
    )


@pytest.mark.parametrize(
    "text",
    [
        "q [1/m], C [m^4]\n" + _table_text(","),  # a spreadsheet header without '#'
        "Instrument X export\nq;C\n\n" + _table_text(";"),
        "q\tC\n" + _table_text("\t") + "\n\n",
        "\ufeff" + _table_text(" "),  # UTF-8 byte-order mark
        "\ufeffq;C\r\n" + _table_text(";", decimal=",").replace("\n", "\r\n"),
        "# written by hand\n" + _table_text(", ") + "  # last row\n",
    ],
    ids=["comma-header", "semicolon-headers", "tab", "bom", "decimal-comma-crlf", "comments"],
)
def test_read_spectrum_accepts_exports(tmp_path, text):
    """Spreadsheet and instrument exports: headers without '#', ',', ';' (decimal commas), tabs,
    a byte-order mark, blank lines, CRLF: all read to the same table, exactly."""
    path = tmp_path / "export.csv"
    path.write_bytes(text.encode("utf-8"))
    tab = io.read_spectrum(path)
    np.testing.assert_array_equal(tab.q, SPECTRUM_Q)
    np.testing.assert_array_equal(tab.C, SPECTRUM_C)


def test_read_spectrum_names_the_line_of_a_bad_row(tmp_path):
    body = _table_text(",").splitlines()
    bad = ["q, C"] + body[:3] + ["1e5, 1e-22, 7"] + body[3:]
    with pytest.raises(io.SpectrumFileError, match=r"f.txt:5: 3 columns, expected 2"):
        io.read_spectrum(write(tmp_path, "\n".join(bad)))
    with pytest.raises(io.SpectrumFileError, match=r"f.txt:2: expected two columns .* got 3"):
        io.read_spectrum(write(tmp_path, "x y z\n1 2 3\n4 5 6\n"))
    with pytest.raises(io.SpectrumFileError, match="no numeric data"):
        io.read_spectrum(write(tmp_path, "q [1/m], C [m^4]\n"))


def test_read_spectrum_missing_or_binary(tmp_path):
    with pytest.raises(ValueError, match="cannot read"):
        io.read_spectrum(tmp_path / "nope.txt")
    path = tmp_path / "b.bin"
    for blob in (b"\x89PNG\r\n\x1a\n\x00\x00", b"\xff\xfe\x00\x00\x01\x00" * 10):
        path.write_bytes(blob)  # binary, and binary behind a UTF-16 byte-order mark
        with pytest.raises(ValueError, match="not a text file"):
            io.read_spectrum(path)


@pytest.mark.parametrize("codec", ["utf-16-le", "utf-16-be"])
def test_read_spectrum_utf16_export(tmp_path, codec):
    """A spreadsheet's "Unicode text" export (UTF-16 with its byte-order mark, tabs, CRLF)
    reads as the same table as its UTF-8 original."""
    q = np.geomspace(1e3, 1e9, 25)
    C = 1e-18 * (q / 1e3) ** -2.6
    rows = [f"{a:.17g}\t{b:.17g}\r\n" for a, b in zip(q, C, strict=True)]
    text = "q [1/m]\tC [m^4]\r\n" + "".join(rows)
    path = tmp_path / "unicode.txt"
    path.write_bytes("\ufeff".encode(codec) + text.encode(codec))
    psd = io.read_spectrum(path)
    np.testing.assert_array_equal(psd.q, q)
    np.testing.assert_array_equal(psd.C, C)


def test_csv_header_records_the_scene(tmp_path):
    psd = fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9)
    r = fl.solve_line_contact(psd, 1.33e9, 0.01, 1e4, n=64, gamma=0.4)
    meta = io.scene_metadata(psd, 1.33e9, 0.01, model="persson", gamma=0.4, n=64, source="x.txt")
    io.write_profile_csv(tmp_path / "p.csv", r, meta)
    got, cols = io.read_csv(tmp_path / "p.csv")
    assert got["spectrum"] == "file x.txt" and got["model"] == "persson"
    assert float(got["h_rms_m"]) == psd.h_rms and float(got["rms_slope"]) == psd.rms_slope
    assert float(got["q0_1_per_m"]) == 1e3 and float(got["q1_1_per_m"]) == 1e9
    assert float(got["gamma"]) == 0.4 and int(got["n"]) == 64
    assert got["fastline_version"] == fl.__version__ and got["converged"] == "1"
    assert float(got["p0_Pa"]) == r.p0
    np.testing.assert_array_equal(cols["p_Pa"], r.pressure)  # repr: exact round trip
    io.write_sweep_csv(tmp_path / "s.csv", [r, r], meta)
    _, cols = io.read_csv(tmp_path / "s.csv")
    assert list(cols) == list(io.SWEEP_COLUMNS) and cols["w_over_s"][1] == r.w_over_s


def test_csv_writers_take_point_results_in_their_own_layout(tmp_path):
    """write_profile_csv and write_sweep_csv write a sphere's results as the point writers do
    (p(r), the load in N), refuse a mixed sweep, and name what they expect otherwise."""
    psd = fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9)
    pc = fl.PointContact(psd, 1.33e9, 0.01, n=64, warn=False)
    point = pc.solve(1.0)
    io.write_profile_csv(tmp_path / "p.csv", point)
    io.write_point_profile_csv(tmp_path / "q.csv", point)
    assert (tmp_path / "p.csv").read_text() == (tmp_path / "q.csv").read_text()
    got, cols = io.read_csv(tmp_path / "p.csv")
    assert got["geometry"] == "sphere" and float(got["load_N"]) == 1.0
    np.testing.assert_array_equal(cols["r_m"], point.r)
    io.write_sweep_csv(tmp_path / "s.csv", [point, point])
    got, cols = io.read_csv(tmp_path / "s.csv")
    assert list(cols) == list(io.POINT_SWEEP_COLUMNS) and got["geometry"] == "sphere"
    line = fl.solve_line_contact(psd, 1.33e9, 0.01, 1e4, n=64)
    with pytest.raises(ValueError, match="mix line and point"):
        io.write_sweep_csv(tmp_path / "m.csv", [line, point])
    with pytest.raises(TypeError, match="LineContactResult or PointContactResult"):
        io.write_profile_csv(tmp_path / "x.csv", fl.leak_rate(line, 1e4, 1e-3))


def test_output_checks(tmp_path):
    assert io.check_output_file(tmp_path / "a.csv") == str(tmp_path / "a.csv")
    with pytest.raises(ValueError, match="does not exist"):
        io.check_output_file(tmp_path / "no" / "a.csv")
    with pytest.raises(ValueError, match="is a directory"):
        io.check_output_file(tmp_path)
    out = io.check_output_dir(tmp_path / "new" / "deeper")
    assert os.path.isdir(out)
    (tmp_path / "file").write_text("")
    with pytest.raises(ValueError, match="cannot create directory"):
        io.check_output_dir(tmp_path / "file" / "sub")
