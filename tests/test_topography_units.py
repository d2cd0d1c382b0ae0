"""The units of measured surfaces: a unit the file's header names, in every layout the reader
accepts (one column, x and height columns, one trace per line, a height map); heights whose
spectrum is implausible; and where the warnings of the measured-surface functions point.

Heights are a small seeded Gaussian surface (tp.synthetic_surface) written in micrometres; read
back they must equal the written numbers times the unit's factor (exact up to the text's 18
digits), whichever of the header and the option gives the unit.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import fastline as fl
from fastline.surfaces import analyse_scan
from fastline.surfaces import topography as tp

#: the same numbers read back (savetxt writes 18 digits; one factor of 1e-6 is applied)
RTOL_EXACT = 1e-12
DX = 2e-6  # m
TRUTH = fl.SelfAffinePSD(0.5e-6, 0.8, 2e4, 1e5, 1e9)
LAYOUTS = ("column", "xh", "rows", "map")
CONTRADICTS = r"unit='nm' \(--units nm\) contradicts the file, whose header gives the heights in um"


@pytest.fixture(scope="module")
def surface_um():
    """A 256 x 256 surface in micrometres (h_rms about 0.5)."""
    return tp.synthetic_surface(TRUTH, 256, DX, seed=3) * 1e6


def _export(path, layout: str, h_um: np.ndarray) -> np.ndarray:
    """h_um written in ``layout`` under a header naming um; the heights the file holds (um)."""
    if layout == "column":
        np.savetxt(path, h_um[0], header="z [um]")
        return h_um[0]
    if layout == "xh":
        x = np.arange(h_um.shape[1]) * DX * 1e6
        np.savetxt(path, np.column_stack([x, h_um[0]]), header="x [um], Height [um]")
        return h_um[0]
    block = h_um[::32] if layout == "rows" else h_um[:48, :40]
    np.savetxt(path, block, header="Height [um]")
    return block


def _read(layout: str, path, **kwargs):
    """The reader of each layout: a profile, traces (read_topography), a map (read_map)."""
    if layout == "map":
        return tp.read_map(path, dx=DX, **kwargs)
    if layout == "rows":
        return tp.read_topography(path, dx=DX, **kwargs)
    return tp.read_profile(path, dx=None if layout == "xh" else DX, **kwargs)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_every_layout_reads_the_header_unit(layout, surface_um, tmp_path):
    """The header's um is used without an option and agrees with unit='um'; unit='nm' is
    refused naming both units, with one wording for every layout."""
    path = tmp_path / f"{layout}.txt"
    h_um = _export(path, layout, surface_um)
    for kwargs in ({}, {"unit": "um"}):
        read = _read(layout, path, **kwargs)
        np.testing.assert_allclose(read.heights, h_um * 1e-6, rtol=RTOL_EXACT)
        assert read.dx == pytest.approx(DX, rel=1e-9)
    with pytest.raises(ValueError, match=CONTRADICTS):
        _read(layout, path, unit="nm")


@pytest.mark.parametrize("layout", ["column", "rows"])
def test_a_header_sentence_with_numbers_names_no_unit(layout, surface_um, tmp_path):
    """ "dx = 2 um" above heights in nm is a scan parameter, not the heights' unit: unit='nm'
    is used (not refused as contradicting it), and without it the heights are taken in m."""
    path = tmp_path / f"{layout}.txt"
    h_nm = surface_um[0] * 1e3 if layout == "column" else surface_um[::32] * 1e3
    np.savetxt(path, h_nm, header="4 traces, heights in nm, dx = 2 um")
    read = _read(layout, path, unit="nm")
    np.testing.assert_allclose(read.heights, h_nm * 1e-9, rtol=RTOL_EXACT)
    np.testing.assert_allclose(_read(layout, path).heights, h_nm, rtol=RTOL_EXACT)


@pytest.mark.parametrize("layout", ["rows", "map"])
def test_analyse_scan_takes_the_header_unit_of_traces_and_maps(layout, surface_um, tmp_path):
    """analyse_scan on traces and maps: the header's um gives the surface's h_rms in m (the
    same analysis as unit='um'); --units nm against the header is refused."""
    path = tmp_path / f"{layout}.txt"
    _export(path, layout, surface_um)
    as_map = layout == "map"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tp.TopographyWarning)  # the fit's, not the units'
        scan = analyse_scan(path, dx=DX, as_map=as_map)
        given = analyse_scan(path, dx=DX, as_map=as_map, unit="um")
    assert scan.psd.h_rms == given.psd.h_rms
    assert 1e-7 < scan.psd.h_rms < 1e-5
    with pytest.raises(ValueError, match=CONTRADICTS):
        analyse_scan(path, dx=DX, as_map=as_map, unit="nm")


@pytest.mark.parametrize("as_map", [False, True])
def test_implausible_scan_heights_name_their_unit(as_map, surface_um, tmp_path):
    """Micrometres read as metres (no unit anywhere): the error speaks of the heights, the unit
    they were read in and --units, not of a spectrum file's C and q."""
    path = tmp_path / "bare.txt"
    np.savetxt(path, surface_um[::32] if not as_map else surface_um[:64, :64])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tp.TopographyWarning)  # the slip's warning comes first
        with pytest.raises(ValueError) as refused:
            analyse_scan(path, dx=DX, as_map=as_map)
    text = str(refused.value)
    assert "heights" in text and "read in m" in text and "--units" in text, text
    assert "C in m^4" not in text and "h_rms = " in text


def test_psd_from_map_of_implausible_heights_speaks_of_heights(surface_um):
    """Heights in micrometres passed as metres: the refusal names the heights and their unit."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tp.TopographyWarning)
        with pytest.raises(ValueError, match=r"psd_from_map: the heights .*in m") as refused:
            tp.psd_from_map(surface_um[:64, :64], DX)
    assert "C in m^4" not in str(refused.value)


def test_warnings_point_at_the_callers_line(surface_um, tmp_path):
    """Every TopographyWarning of the public functions (readers, spectra, fit, analyse_scan)
    is attributed to this file, whichever depth of fastline raised it, and each once a call."""
    bare = tmp_path / "xh.txt"  # no header: x taken in the heights' unit, said by a warning
    x = np.arange(256) * DX * 1e6
    np.savetxt(bare, np.column_stack([x, surface_um[0]]))
    rows = tmp_path / "rows.txt"
    np.savetxt(rows, surface_um[::32], header="traces")  # no unit: unit='mm' decides
    q = np.geomspace(1e4, 1e7, 40)
    C1D = q**-2.6 * (1.0 + 0.6 * (-1.0) ** np.arange(q.size))  # rising steps: noisy C1D
    calls = [
        lambda: tp.read_profile(bare, unit="um"),
        lambda: tp.read_topography(bare, unit="um"),
        lambda: analyse_scan(bare, unit="um"),
        lambda: tp.psd_from_profile(surface_um[:4], DX),  # micrometres read as metres
        lambda: tp.psd_from_map(surface_um[:64, :64] * 1e-3, DX),  # millimetres
        lambda: analyse_scan(rows, dx=DX, unit="mm"),  # slopes x 1e3, beyond 5
        lambda: tp.isotropic_from_1d(q, C1D),
        lambda: tp.fit_self_affine((q, q**-3.6)),  # a power law: no roll-off to resolve
    ]
    seen = set()
    for call in calls:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            call()
        mine = [w for w in caught if issubclass(w.category, tp.TopographyWarning)]
        assert mine, "each call warns"
        texts = [str(w.message) for w in mine]
        assert len(texts) == len(set(texts)), texts  # once a call
        assert {w.filename for w in mine} == {__file__}, [(w.filename, w.lineno) for w in mine]
        seen.update(text.split(":")[0] for text in texts)
    assert {"psd_from_profile", "psd_from_map", "isotropic_from_1d", "fit_self_affine"} <= seen


@pytest.mark.parametrize("layout", ["column", "rows"])
def test_a_unit_of_positions_without_an_x_column_is_refused(layout, surface_um, tmp_path):
    """x_unit (--x-units) names the unit of an x column: for heights alone (their spacing
    is dx, in m) it is refused by name instead of ignored; with an x column it is used."""
    path = tmp_path / f"{layout}.txt"
    _export(path, layout, surface_um)
    with pytest.raises(ValueError, match=r"x_unit \(--x-units\) sets the unit of an x column"):
        _read(layout, path, x_unit="mm")
    xh = tmp_path / "xh.txt"
    _export(xh, "xh", surface_um)
    assert _read("xh", xh, x_unit="um").dx == pytest.approx(DX, rel=1e-9)
