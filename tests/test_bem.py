"""fastline.bem against closed forms (Hertz, Poiseuille, series/parallel strips), quadrature
references (Boussinesq over a cell, a dense Reynolds solve) and invariants."""

from __future__ import annotations

import logging
import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
from naive import boussinesq_cell, cell_mean_spectrum, reynolds_dense

import fastline as fl
from fastline import bem
from fastline.bem import _profile
from fastline.bem.halfspace import ALIAS_ORDER, _alias_sum

# tiered tolerances
RTOL_EXACT = 1e-12  # identities that hold to round-off (Parseval, load balance, Poiseuille)
RTOL_QUAD = 1e-10  # closed forms against SciPy quadrature / dense solves
ATOL_ALIAS = 1e-5  # alias-sum truncation in real space [dx/E*] (measured 3e-6 at order 16)
ATOL_IMAGES = 1.5e-5  # periodic vs Love near a loaded cell [dx/E*]: truncation 3e-6 plus the
#                       images' field (2.26/pi) r^2/L^3 = 6e-6 at r = 3 sqrt(2), L = 128 cells
RTOL_HERTZ = 1e-2  # smooth contacts against Hertz (required: 1 %)
RTOL_IMAGE_SHIFT = 0.1  # measured image shift of s against -(pi^2/12)(a/Lx)^2, relative
RTOL_COMPLEMENTARITY = 1e-6  # |gap| on contact cells and penetration, relative to delta
RTOL_CELL_MEAN = 2e-3  # generator's cell means vs quadrature: sub-cell rule and normalising factor
RTOL_CELL_EDGE = 3e-2  # the same for cells cut by q1 (measured 1.7 %, C there is 1e-6 of the peak)
RTOL_LATTICE_SLOPE = 1e-2  # rms slope of the surfaces vs psd.rms_slope (measured <= 0.6 %)
Z_MODES = 4.0  # Gaussian amplitudes: mean h_rms^2 of a few seeds within 4 sigma of the modes


def approx(expected, rel):
    """pytest.approx without its 1e-12 absolute floor (conductances here are ~1e-15 SI)."""
    return pytest.approx(expected, rel=rel, abs=0.0)


E_STAR = 1e7  # Pa
RADIUS = 0.01  # m
PSD = fl.SelfAffinePSD(0.5e-6, 0.8, 1e4, 2e4, 32e4)


# ---- influence coefficients ------------------------------------------------------------------
@pytest.mark.parametrize(
    "X, Y", [(0.0, 0.0), (0.2, -0.3), (0.5, 0.1), (1.0, 0.0), (2.5, 3.0), (-10.0, 7.0)]
)
def test_love_matches_boussinesq_quadrature(X, Y):
    dx, dy = 1.0e-6, 0.6e-6
    ref = boussinesq_cell(X * dx, Y * dy, dx, dy, E_STAR)
    assert bem.love_coefficient(X * dx, Y * dy, dx, dy, E_STAR) == approx(ref, RTOL_QUAD)


def test_isolated_patch_is_love_convolution():
    """One loaded cell on the isolated patch: exactly Love's coefficients everywhere."""
    grid = bem.Grid(20, 30, 1e-6, 0.5e-6)
    op = bem.ElasticHalfSpace(grid.nx, grid.ny, grid.dx, grid.dy, E_STAR, periodic=False)
    p = np.zeros(grid.shape)
    p[3, 7] = 2.0
    X = (np.arange(20) - 3)[:, None] * grid.dx
    Y = (np.arange(30) - 7)[None, :] * grid.dy
    ref = 2.0 * bem.love_coefficient(X, Y, grid.dx, grid.dy, E_STAR)
    np.testing.assert_allclose(op.apply(p), ref, rtol=1e-12, atol=1e-12 * ref.max())


def test_periodic_kernel_near_a_cell_is_love():
    """Periodic cell: displacement differences near the load equal Love's up to the images."""
    n, dx = 128, 1e-6
    op = bem.ElasticHalfSpace(n, n, dx, dx, E_STAR)
    p = np.zeros((n, n))
    p[0, 0] = 1.0
    u = op.apply(p)
    scale = dx / E_STAR
    for i, j in [(0, 1), (1, 1), (0, 3), (2, 3), (3, 3)]:
        love = bem.love_coefficient(i * dx, j * dx, dx, dx, E_STAR) - op.self_coefficient
        assert abs((u[i, j] - u[0, 0]) - love) / scale < ATOL_IMAGES


def test_alias_sum_truncation():
    """The extrapolated alias sum against a 4x longer one, as real-space kernels [dx/E*]."""
    for aspect in (0.5, 1.0, 3.0):
        ref = np.fft.irfft2(_alias_sum(32, 24, aspect, 4 * ALIAS_ORDER), s=(32, 24))
        got = np.fft.irfft2(_alias_sum(32, 24, aspect, ALIAS_ORDER), s=(32, 24))
        assert np.abs(got - ref).max() < ATOL_ALIAS
        # without the extrapolation (order 4 alone) the test would fail
        crude = np.fft.irfft2(_alias_sum(32, 24, aspect, 4), s=(32, 24))
        assert np.abs(crude - ref).max() > 10 * ATOL_ALIAS


def test_periodic_operator_invariants():
    """Uniform pressure -> uniform displacement; K symmetric; <p, K p> > 0 for zero-mean p."""
    rng = np.random.default_rng(1)
    op = bem.ElasticHalfSpace(24, 18, 1e-6, 2e-6, E_STAR)
    u = op.apply(np.full(op.shape, 3.0))
    assert np.ptp(u) < 1e-12 * abs(u.mean())
    a, b = rng.standard_normal(op.shape), rng.standard_normal(op.shape)
    assert np.sum(a * op.apply(b)) == approx(np.sum(op.apply(a) * b), rel=1e-12)
    for _ in range(3):
        z = rng.standard_normal(op.shape)
        z -= z.mean()
        assert np.sum(z * op.apply(z)) > 0.0


# ---- random surfaces -------------------------------------------------------------------------
def mode_spectrum(surf):
    """``c_k`` of every lattice mode of a fixed-amplitude surface, from its DFT [m^4]."""
    g = surf.grid
    h = np.fft.fft2(surf.heights)
    return (g.dx * g.dy) ** 2 / ((2 * math.pi) ** 2 * g.lx * g.ly) * np.abs(h) ** 2


def test_fixed_amplitudes_give_the_discrete_moments_exactly():
    grid = bem.spectral_grid(PSD)
    assert grid.dx <= 2.0 * math.pi / (4.0 * PSD.q1) and grid.lx >= 2.0 * 2.0 * math.pi / PSD.q0
    surf = bem.random_surface(PSD, grid, seed=3)
    assert surf.h_rms == approx(surf.expected_h_rms, rel=RTOL_EXACT)
    assert surf.rms_slope == approx(surf.expected_rms_slope, rel=RTOL_EXACT)
    assert abs(surf.heights.mean()) < 1e-12 * surf.h_rms
    assert bem.lattice_moments(PSD, grid) == (surf.expected_h_rms, surf.expected_rms_slope)
    # explicit sums over the lattice modes of the surface's own DFT
    c = mode_spectrum(surf)
    qx, qy = grid.wavevectors()
    dq2 = (2.0 * math.pi) ** 2 / (grid.lx * grid.ly)
    assert surf.expected_h_rms == approx(math.sqrt(c.sum() * dq2), rel=RTOL_EXACT)
    q2 = qx * qx + qy * qy
    assert surf.expected_rms_slope == approx(math.sqrt((q2 * c).sum() * dq2), rel=RTOL_EXACT)


def test_mode_power_is_the_cell_mean_of_the_spectrum():
    """Each mode carries the mean of C over its lattice cell (adaptive quadrature in
    tests/naive.py): the strongest modes (at q0, cells cut by the annulus) and cells cut by q1."""
    grid = bem.spectral_grid(PSD)
    c = mode_spectrum(bem.random_surface(PSD, grid, seed=1))
    qx, qy = grid.wavevectors()
    dqx, dqy = 2 * math.pi / grid.lx, 2 * math.pi / grid.ly
    q = np.hypot(qx, qy)
    strongest = np.argsort(c.ravel())[::-1][:12]
    edge = np.flatnonzero((np.abs(q - PSD.q1) < 0.5 * dqx).ravel())[:4]
    for flat_index, rtol in [(k, RTOL_CELL_MEAN) for k in strongest] + [
        (k, RTOL_CELL_EDGE) for k in edge
    ]:
        i, j = np.unravel_index(flat_index, c.shape)
        ref = cell_mean_spectrum(PSD, qx[i, 0], qy[0, j], dqx, dqy)
        assert c[i, j] == approx(ref, rel=rtol), (i, j)


def test_discrete_moments_match_the_spectrum_integrals():
    """h_rms exactly (the normalising factor), the rms slope to its quadrature, at 1-8 longest
    wavelengths."""
    for periods in (1, 2, 4, 8):
        h_rms, slope = bem.lattice_moments(PSD, bem.spectral_grid(PSD, periods=periods))
        assert h_rms == approx(PSD.h_rms, rel=RTOL_EXACT)
        assert abs(slope / PSD.rms_slope - 1.0) < 5e-3


def paper_like(ratio=32.0):
    q0 = 2.0 * math.pi / 40e-6
    return fl.SelfAffinePSD(0.5e-6, 0.8, q0, q0, ratio * q0)


def test_surfaces_at_the_default_grids_have_the_spectrum_h_rms():
    """At the default grid options (docs/validation.md: the cylinder at alpha = 1, 4320 x 256
    cells, and the flat cell, 256 x 256), a few seeds' mean h_rms^2 is the spectrum's: exactly
    with fixed amplitudes, within Z_MODES standard deviations with Gaussian ones, where
    h_rms^2 = sum over independent mode pairs of 2 c_k dq^2 X_k, X_k ~ Exp(1), has variance
    2 sum_k (c_k dq^2)^2 (all modes). The point values C(|q_k|) gave +11 % and +25 %."""
    psd, e_star, radius = paper_like(), 10e6, 32.8e-3
    grids = [
        bem.line_contact_scene(psd, e_star, radius, math.pi * e_star * psd.h_rms / 4).grid,
        bem.flat_contact_scene(psd, e_star, 1e4).grid,
    ]
    seeds = range(3)
    for grid in grids:
        first = bem.random_surface(psd, grid, seed=0)
        dq2 = (2.0 * math.pi) ** 2 / (grid.lx * grid.ly)
        power = mode_spectrum(first) * dq2
        sigma = math.sqrt(2.0 * np.sum(power * power) / len(seeds))
        assert first.h_rms**2 == approx(psd.h_rms**2, rel=RTOL_EXACT)
        assert abs(first.rms_slope / psd.rms_slope - 1.0) < RTOL_LATTICE_SLOPE
        h2 = [
            bem.random_surface(psd, grid, seed=s, amplitudes="gaussian").h_rms ** 2 for s in seeds
        ]
        assert abs(np.mean(h2) - psd.h_rms**2) < Z_MODES * sigma


def test_gaussian_amplitudes_statistics():
    """Rayleigh moduli: h_rms^2 = sum over independent mode pairs of 2 c_k X_k, X_k ~ Exp(1),
    so its standard deviation is 2 sqrt(sum c_k^2) over the half lattice; 4-sigma band."""
    grid = bem.spectral_grid(PSD, periods=4)
    qx, qy = grid.wavevectors()
    q = np.hypot(qx, qy)
    c = (
        np.where((q >= PSD.q0) & (q <= PSD.q1), PSD(q), 0.0)
        * (2 * math.pi) ** 2
        / (grid.lx * grid.ly)
    )
    sigma = 2.0 * math.sqrt(0.5 * np.sum(c * c))
    for seed in range(3):
        surf = bem.random_surface(PSD, grid, seed=seed, amplitudes="gaussian")
        assert abs(surf.h_rms**2 - surf.expected_h_rms**2) < 4.0 * sigma


def test_spectrum_is_reproduced():
    grid = bem.spectral_grid(PSD, periods=4)
    dq = 2.0 * math.pi / grid.lx

    def smooth_rings(q):
        """Rings clear of q0, q1 and of the roll-off's kink (where a cell mean is not C(q))."""
        return (q > 1.2 * PSD.q0) & (q < 0.9 * PSD.q1) & (np.abs(q - PSD.qr) > dq)

    surf = bem.random_surface(PSD, grid, seed=5)
    q, C, count = bem.isotropic_spectrum(surf.heights, grid.dx, grid.dy)
    inside = smooth_rings(q)
    # fixed amplitudes: each ring average is C at its modes, i.e. C(q) within the ring's spread
    np.testing.assert_allclose(C[inside], PSD(q[inside]), rtol=0.05)
    # Gaussian amplitudes: ring averages of count/2 independent Exp(1) variables
    surf = bem.random_surface(PSD, grid, seed=5, amplitudes="gaussian")
    q, C, count = bem.isotropic_spectrum(surf.heights, grid.dx, grid.dy)
    inside = smooth_rings(q)
    z = (C[inside] / PSD(q[inside]) - 1.0) / np.sqrt(2.0 / count[inside])
    assert 0.7 < np.sqrt(np.mean(z * z)) < 1.4
    assert np.abs(z).max() < 5.0


def test_surface_is_reproducible():
    grid = bem.Grid(64, 48, 5e-6, 5e-6)
    a = bem.random_surface(PSD, grid, seed=11).heights
    b = bem.random_surface(PSD, grid, seed=np.random.default_rng(11)).heights
    c = bem.random_surface(PSD, grid, seed=12).heights
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, c)


# ---- contact solver: Hertz, invariants, convergence, images ------------------------------------
def hertz_sphere(load):
    a = (3.0 * load * RADIUS / (4.0 * E_STAR)) ** (1.0 / 3.0)
    return a, 3.0 * load / (2.0 * math.pi * a * a)


def check_contact_invariants(res, load, delta):
    assert res.converged, res.message
    assert res.load == approx(load, rel=RTOL_EXACT)
    assert res.pressure.sum() * res.grid.cell_area == approx(load, rel=RTOL_EXACT)
    assert np.all(res.pressure >= 0.0) and np.all(res.gap >= 0.0)
    assert np.all(res.gap[res.pressure > 0.0] == 0.0)
    assert res.max_contact_gap < RTOL_COMPLEMENTARITY * delta
    assert res.max_penetration < RTOL_COMPLEMENTARITY * delta


def test_sphere_hertz():
    load = 0.1
    a, p0 = hertz_sphere(load)
    grid = bem.Grid(128, 128, 3 * a / 128, 3 * a / 128)
    res = bem.solve_contact(bem.sphere_gap(grid, RADIUS), grid, E_STAR, load, periodic=False)
    check_contact_invariants(res, load, a * a / RADIUS)
    assert res.pressure.max() == approx(p0, rel=RTOL_HERTZ)
    a_num = math.sqrt(res.contact_fraction * grid.lx * grid.ly / math.pi)
    assert a_num == approx(a, rel=RTOL_HERTZ)


def test_sphere_converges_with_grid():
    """L1 error of p against Hertz falls with the cell size (observed order ~1.3 at
    64 -> 256 cells across 3a); p0 error falls ~4x per halving."""
    load = 0.1
    a, p0 = hertz_sphere(load)
    errors = []
    for n in (64, 128, 256):
        grid = bem.Grid(n, n, 3 * a / n, 3 * a / n)
        res = bem.solve_contact(bem.sphere_gap(grid, RADIUS), grid, E_STAR, load, periodic=False)
        r2 = grid.x[:, None] ** 2 + grid.y[None, :] ** 2
        exact = p0 * np.sqrt(np.maximum(1.0 - r2 / a**2, 0.0))
        errors.append(np.abs(res.pressure - exact).sum() * grid.cell_area / load)
    assert errors[0] > errors[1] > errors[2]
    assert math.log(errors[0] / errors[2]) / math.log(4.0) > 0.8


def cylinder_s(res):
    grid = res.grid
    p = res.pressure.mean(axis=1)
    return math.sqrt(np.dot(grid.x**2, p) / p.sum() + grid.dx**2 / 12)


def test_cylinder_hertz():
    """Periodic cylinder, Lx = 8 a, images cancelled: p0, a and s against Hertz within 1 %."""
    load = 100.0
    hz = fl.hertz_line_contact(E_STAR, RADIUS, load)
    dx = hz.a / 32
    grid = bem.Grid(256, 4, dx, dx)
    kappa = bem.image_curvature(E_STAR, load, RADIUS, grid.lx)
    g0 = bem.cylinder_gap(grid, RADIUS, kappa)
    res = bem.solve_contact(g0, grid, E_STAR, load * grid.ly)
    check_contact_invariants(res, load * grid.ly, hz.delta)
    p = res.pressure.mean(axis=1)
    assert p.max() == approx(hz.p0, RTOL_HERTZ)
    assert 0.5 * np.count_nonzero(p > 0.0) * dx == approx(hz.a, RTOL_HERTZ)
    assert cylinder_s(res) == approx(hz.s, RTOL_HERTZ)
    assert np.ptp(res.pressure, axis=1).max() < 1e-9 * hz.p0  # uniform along the axis


@pytest.mark.parametrize("widths, corrected_bound", [(4, 5e-3), (8, 1e-3)])
def test_cylinder_domain_size(widths, corrected_bound):
    """The periodic images in x shift s by -kappa/2 = -(pi^2/12)(a/Lx)^2; the curvature
    correction of cylinder_gap removes that to O(kappa^2)."""
    load = 100.0
    hz = fl.hertz_line_contact(E_STAR, RADIUS, load)
    dx = hz.a / 32
    grid = bem.Grid(32 * widths, 4, dx, dx)
    kappa = bem.image_curvature(E_STAR, load, RADIUS, grid.lx)
    assert kappa / 2 == approx((math.pi**2 / 12.0) / widths**2, 1e-12)
    shifts = []
    for k in (0.0, kappa):
        res = bem.solve_contact(bem.cylinder_gap(grid, RADIUS, k), grid, E_STAR, load * grid.ly)
        shifts.append(cylinder_s(res) / hz.s - 1.0)
    assert shifts[0] == approx(-kappa / 2, RTOL_IMAGE_SHIFT)
    assert abs(shifts[1]) < corrected_bound


def test_rough_contact_invariants():
    grid = bem.Grid(128, 64, 2.5e-6, 2.5e-6)
    surf = bem.random_surface(PSD, grid, seed=2)
    load = 20.0 * grid.ly
    g0 = bem.cylinder_gap(grid, RADIUS) - surf.heights
    res = bem.solve_contact(g0, grid, E_STAR, load)
    check_contact_invariants(res, load, PSD.h_rms)
    assert 0.0 < res.contact_fraction < 0.5
    capped = bem.solve_contact(g0, grid, E_STAR, load, max_iter=2)
    assert not capped.converged and capped.iterations == 2 and "not converged" in capped.message


# ---- Reynolds flow -----------------------------------------------------------------------------
ETA = 1e-3


def test_flow_parallel_plates_exact():
    g = 2e-6
    res = bem.reynolds_flow(np.full((10, 7), g), 1e-6, 2e-6, viscosity=ETA, pressure_drop=5.0)
    assert res.conductance == approx(g**3 / (12 * ETA), rel=RTOL_EXACT)
    assert res.flow_rate == approx(g**3 / (12 * ETA) * 5.0 * 14e-6 / 10e-6, RTOL_EXACT)
    assert res.effective_gap == approx(g, rel=RTOL_EXACT)
    assert res.percolating and res.active_fraction == 1.0 and res.balance_error < 1e-12


def test_flow_strips_in_series_and_parallel():
    rng = np.random.default_rng(0)
    gx = rng.uniform(1e-6, 3e-6, 12)
    res = bem.reynolds_flow(np.repeat(gx[:, None], 5, axis=1), 1e-6, viscosity=ETA)
    assert res.conductance == approx(1.0 / np.mean(12 * ETA / gx**3), rel=RTOL_EXACT)
    gy = rng.uniform(1e-6, 3e-6, 9)
    res = bem.reynolds_flow(np.repeat(gy[None, :], 6, axis=0), 1e-6, viscosity=ETA)
    assert res.conductance == approx(np.mean(gy**3 / (12 * ETA)), rel=RTOL_EXACT)


RTOL_FLOW_CG = 1e-9  # conductance of the CG (residual 1e-8; error ~ its square) vs closed forms
RTOL_BALANCE_CG = 1e-4  # inlet vs outlet flux of a CG iterate at residual 1e-8 (measured 5e-6)


@pytest.mark.parametrize("solver", ["iterative", "direct"])
def test_flow_closed_forms_on_multigrid_sized_maps(solver):
    """Poiseuille, series and parallel strips on 64 x 48 cells (three multigrid levels), the flow
    rate balanced between inlet and outlet."""
    rng = np.random.default_rng(1)
    g = 1.5e-6
    res = bem.reynolds_flow(np.full((64, 48), g), 1e-6, 2e-6, viscosity=ETA, solver=solver)
    assert res.conductance == approx(g**3 / (12 * ETA), rel=RTOL_EXACT)
    gx = rng.uniform(0.2e-6, 3e-6, 64)
    res = bem.reynolds_flow(np.repeat(gx[:, None], 48, axis=1), 1e-6, viscosity=ETA, solver=solver)
    assert res.solver == solver and res.balance_error < RTOL_BALANCE_CG
    assert res.conductance == approx(1.0 / np.mean(12 * ETA / gx**3), rel=RTOL_FLOW_CG)
    gy = rng.uniform(0.2e-6, 3e-6, 48)
    res = bem.reynolds_flow(np.repeat(gy[None, :], 64, axis=0), 1e-6, viscosity=ETA, solver=solver)
    assert res.conductance == approx(np.mean(gy**3 / (12 * ETA)), rel=RTOL_FLOW_CG)


def test_flow_blocked_channel_is_zero():
    g = np.full((10, 7), 2e-6)
    g[4, :] = 0.0
    res = bem.reynolds_flow(g, 1e-6)
    assert not res.percolating and res.conductance == 0.0 and res.flow_rate == 0.0
    assert np.all(np.isnan(res.pressure))


def test_flow_closed_island_carries_nothing():
    """An island enclosed by contact is dropped; filling it with contact changes nothing."""
    g = np.full((12, 12), 1e-6)
    g[3:9, 3] = g[3:9, 8] = g[3, 3:9] = g[8, 3:9] = 0.0
    res = bem.reynolds_flow(g, 1e-6)
    assert np.all(np.isnan(res.pressure[4:8, 4:8]))
    filled = g.copy()
    filled[4:8, 4:8] = 0.0
    assert res.conductance == approx(bem.reynolds_flow(filled, 1e-6).conductance, RTOL_QUAD)


def test_flow_matches_dense_reference():
    rng = np.random.default_rng(4)
    g = np.abs(rng.standard_normal((14, 11))) * 1e-6
    g[g < 0.6e-6] = 0.0  # ~45 % contact: islands and dead ends
    res = bem.reynolds_flow(g, 1e-6, 1.5e-6, viscosity=ETA, pressure_drop=2.0)
    ref = reynolds_dense(g, 1e-6, 1.5e-6, ETA, 2.0)
    assert res.percolating and ref > 0.0
    assert res.conductance == approx(ref, rel=RTOL_QUAD)
    assert res.balance_error < 1e-10


# ---- ensembles -----------------------------------------------------------------------------------
def test_jackknife_of_a_mean_is_the_standard_error():
    x = np.random.default_rng(0).standard_normal((7, 3))
    full, err = _profile.jackknife(x, lambda m: tuple(m))
    np.testing.assert_allclose(full, x.mean(axis=0), rtol=RTOL_EXACT)
    np.testing.assert_allclose(err, x.std(axis=0, ddof=1) / math.sqrt(7), rtol=1e-12)


def test_central_peak_bias():
    """The even quartic over |u| <= 0.75 s recovers the peak of Hertz and Gaussian profiles."""
    u = np.linspace(-3.0, 3.0, 601)
    gauss = 7.0 * np.exp(-0.5 * u * u)
    assert _profile.central_peak(u, gauss, 1.0) == approx(7.0, 1e-3)
    a = 2.0  # Hertz: s = a/2
    hertz = 7.0 * np.sqrt(np.maximum(1.0 - (u / a) ** 2, 0.0))
    assert _profile.central_peak(u, hertz, 0.5 * a) == approx(7.0, 1e-3)


def test_smooth_ensembles_give_hertz():
    line = bem.run_ensemble(bem.line_contact_scene(None, E_STAR, RADIUS, 100.0), 1)
    assert line.converged and line.realizations == 1 and math.isnan(line.p0_error)
    assert line.p0_ratio == approx(1.0, rel=RTOL_HERTZ)
    assert line.s == approx(0.5 * line.a_hertz, rel=RTOL_HERTZ)
    assert line.w_over_s == approx(fl.WS_HERTZ, rel=RTOL_HERTZ)
    ball = bem.run_ensemble(bem.point_contact_scene(None, E_STAR, RADIUS, 0.1), 1)
    assert ball.p0_ratio == approx(1.0, rel=RTOL_HERTZ)
    assert ball.s == approx(ball.a_hertz / math.sqrt(5.0), rel=RTOL_HERTZ)
    assert ball.w_over_s == approx(math.sqrt(15.0), rel=RTOL_HERTZ)


LOAD_SMALL = 5.0  # N/m


@pytest.fixture(scope="module")
def small_line_scene():
    """Hertz a = 80 um on Lx = 416 um (5.2 a)."""
    grid = bem.Grid(104, 48, 4e-6, 4e-6)  # 13 full bins of 8 cells, one centred on x = 0
    return bem.line_contact_scene(PSD, E_STAR, RADIUS, LOAD_SMALL, grid=grid, bin_width=8 * grid.dx)


def test_rough_line_ensemble(small_line_scene):
    ens = bem.run_ensemble(small_line_scene, 3, seed=1)
    assert ens.converged and ens.realizations == 3 and ens.iterations.shape == (3,)
    assert np.all(ens.pressure >= 0.0) and np.all(np.isfinite(ens.pressure_error))
    dx_bin = np.diff(ens.coordinate)
    np.testing.assert_allclose(dx_bin, dx_bin[0])
    np.testing.assert_allclose(ens.coordinate, -ens.coordinate[::-1], atol=1e-15)
    assert dx_bin[0] == approx(8 * small_line_scene.grid.dx, RTOL_EXACT)  # exactly 8 cells per bin
    # the binned mean carries the load per unit length
    assert np.sum(ens.pressure) * dx_bin[0] == approx(LOAD_SMALL, rel=RTOL_EXACT)
    for name in ("p0", "s", "fwhm", "w_over_s"):
        value, error = getattr(ens, name), getattr(ens, name + "_error")
        assert value > 0.0 and 0.0 < error < value


def test_executor_gives_the_serial_result(small_line_scene):
    serial = bem.run_ensemble(small_line_scene, 2, seed=7)
    with ThreadPoolExecutor(2) as pool:
        parallel = bem.run_ensemble(small_line_scene, 2, seed=7, executor=pool)
    np.testing.assert_array_equal(serial.pressure, parallel.pressure)
    assert serial.s == parallel.s and serial.p0_error == parallel.p0_error


@pytest.fixture(scope="module")
def dask_client():
    """A dask.distributed cluster in this process (one worker, two threads): the real Client,
    its executor and scheduler address, without starting processes."""
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(
        n_workers=1,
        processes=False,
        threads_per_worker=2,
        dashboard_address=None,
        silence_logs=logging.ERROR,
    )
    client = distributed.Client(cluster)
    yield client
    client.close()
    cluster.close()


def test_dask_gives_the_serial_result(small_line_scene, dask_client):
    """A dask Client, its executor and its scheduler address run the realisations as
    fastline.sweep runs its tasks; the ensemble is the serial one, bit for bit."""
    serial = bem.run_ensemble(small_line_scene, 2, seed=7)
    for executor in (dask_client, dask_client.get_executor(), dask_client.scheduler.address):
        ens = bem.run_ensemble(small_line_scene, 2, seed=7, executor=executor)
        np.testing.assert_array_equal(ens.pressure, serial.pressure)
        assert ens.s == serial.s and ens.p0_error == serial.p0_error
    assert dask_client.status == "running"  # a Client passed in is left running


def test_workers_and_executor_options(small_line_scene):
    serial = bem.run_ensemble(small_line_scene, 2, seed=7)
    one = bem.run_ensemble(small_line_scene, 2, seed=7, workers=1)  # in this process
    np.testing.assert_array_equal(one.pressure, serial.pressure)
    with pytest.raises(ValueError, match="workers applies only"):
        bem.run_ensemble(small_line_scene, 2, executor="serial", workers=2)
    with pytest.raises(ValueError, match="workers"):
        bem.run_ensemble(small_line_scene, 2, workers=0)
    with pytest.raises(ValueError, match="dask scheduler address"):
        bem.run_ensemble(small_line_scene, 2, executor="local")


def test_realization_is_a_function_of_seed_and_scene(small_line_scene):
    a = bem.run_realization(np.random.SeedSequence(3), small_line_scene)
    b = bem.run_realization(np.random.SeedSequence(3), small_line_scene)
    np.testing.assert_array_equal(a.profile, b.profile)
    assert a.h_rms > 0.0 and a.converged


def test_flat_ensemble():
    grid = bem.Grid(64, 64, 2 * math.pi / PSD.q1 / 4, 2 * math.pi / PSD.q1 / 4)
    low = bem.run_ensemble(bem.flat_contact_scene(PSD, E_STAR, 2e4, grid=grid), 2)
    assert low.converged and low.percolating_fraction == 1.0
    assert 0.0 < low.contact_fraction < 0.5 and low.effective_gap > 0.0
    assert low.effective_gap < 12 * PSD.h_rms and np.isfinite(low.effective_gap_error)
    high = bem.run_ensemble(bem.flat_contact_scene(PSD, E_STAR, 1e7, grid=grid), 2)
    assert high.contact_fraction > low.contact_fraction
    assert high.conductance < low.conductance


# ---- theory vs BEM ------------------------------------------------------------------------------
class FakeTheory:
    def __init__(self, x, pressure, p0, s, fwhm, load):
        self.x, self.pressure, self.p0, self.s, self.fwhm, self.load = (
            x,
            pressure,
            p0,
            s,
            fwhm,
            load,
        )


def test_compare_counts_error_bars(small_line_scene):
    ens = bem.run_ensemble(small_line_scene, 3, seed=2)
    x = np.linspace(-1e-3, 1e-3, 2001)
    fake = FakeTheory(
        x,
        np.full(x.size, 500.0),
        ens.p0 + 2 * ens.p0_error,
        ens.s - ens.s_error,
        ens.fwhm,
        LOAD_SMALL,
    )
    cmp = bem.compare_line_contact(fake, ens)
    assert cmp.p0.z == approx(2.0, 1e-12) and cmp.s.z == approx(-1.0, 1e-12)
    assert cmp.fwhm.z == 0.0 and cmp.fwhm.relative == 0.0
    np.testing.assert_allclose(cmp.theory_pressure, 500.0, rtol=1e-12)  # bin average of a constant
    ok = np.isfinite(cmp.z_profile)
    core = ens.pressure >= 0.1 * ens.p0
    assert np.array_equal(ok, core & (ens.pressure_error > 0))
    z = (500.0 - ens.pressure[ok]) / ens.pressure_error[ok]
    np.testing.assert_allclose(cmp.z_profile[ok], z, rtol=1e-12)
    assert cmp.chi2_per_bin == approx(np.mean(z * z), 1e-12)
    assert "p0" in cmp.table() and "chi2/bin" in cmp.table()


def test_compare_smooth_theory_with_smooth_bem():
    load = 100.0
    ens = bem.run_ensemble(bem.line_contact_scene(None, E_STAR, RADIUS, load), 1)
    theory = fl.solve_line_contact(None, E_STAR, RADIUS, load, model="hertz")
    cmp = bem.compare_line_contact(theory, ens)
    for name in ("p0", "s", "fwhm", "w_over_s"):
        assert abs(getattr(cmp, name).relative) < RTOL_HERTZ
        assert math.isnan(getattr(cmp, name).z)  # one realisation: no error bar


# ---- bad input -------------------------------------------------------------------------------
def test_a_period_far_shorter_than_the_longest_wavelength_is_drawn_at_once():
    """8 cells of 1 um against 2 pi/q0 = 6 mm: the cell means of C(q) stay a bounded sum
    (once ~6e8 sub-cells per mode), and the surface holds the lattice's modes."""
    psd = fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9)
    grid = bem.Grid(8, 8, 1e-6, 1e-6)
    surface = bem.random_surface(psd, grid, seed=1)
    assert np.all(np.isfinite(surface.heights)) and surface.heights.std() > 0.0


def test_bad_inputs():
    grid = bem.Grid(16, 16, 1e-6, 1e-6)
    with pytest.raises(ValueError, match="nx"):
        bem.Grid(1, 4, 1e-6, 1e-6)
    with pytest.raises(ValueError, match="dy"):
        bem.Grid(4, 4, 1e-6, -1.0)
    with pytest.raises(ValueError, match="points_per_wavelength"):
        bem.spectral_grid(PSD, points_per_wavelength=1.5)
    with pytest.raises(TypeError, match="psd"):
        bem.spectral_grid("psd")
    with pytest.raises(ValueError, match="amplitudes"):
        bem.random_surface(PSD, grid, amplitudes="uniform")
    with pytest.raises(ValueError, match="no lattice mode"):
        bem.random_surface(PSD, bem.Grid(4, 4, 1e-7, 1e-7))
    with pytest.raises(ValueError, match="heights"):
        bem.isotropic_spectrum(np.full((4, 4), np.nan), 1e-6)
    with pytest.raises(ValueError, match="E_star"):
        bem.ElasticHalfSpace(8, 8, 1e-6, 1e-6, 0.0)
    with pytest.raises(TypeError, match="periodic"):
        bem.ElasticHalfSpace(8, 8, 1e-6, 1e-6, 1e7, periodic="yes")
    with pytest.raises(ValueError, match="p must have shape"):
        bem.ElasticHalfSpace(8, 8, 1e-6, 1e-6, 1e7).apply(np.zeros(8))
    with pytest.raises(ValueError, match="dx"):
        bem.love_coefficient(0.0, 0.0, 0.0, 1e-6, 1e7)
    with pytest.raises(ValueError, match="g0"):
        bem.solve_contact(np.zeros((8, 8)), grid, 1e7, 1.0)
    with pytest.raises(ValueError, match="load"):
        bem.solve_contact(np.zeros(grid.shape), grid, 1e7, -1.0)
    with pytest.raises(ValueError, match="tol"):
        bem.solve_contact(np.zeros(grid.shape), grid, 1e7, 1.0, tol=0.5)
    with pytest.raises(ValueError, match="p_init"):
        bem.solve_contact(np.zeros(grid.shape), grid, 1e7, 1.0, p_init=-np.ones(grid.shape))
    with pytest.raises(ValueError, match="radius"):
        bem.cylinder_gap(grid, 0.0)
    with pytest.raises(TypeError, match="grid"):
        bem.sphere_gap("grid", 1.0)
    with pytest.raises(ValueError, match="image_curvature"):
        bem.cylinder_gap(grid, 1.0, 0.7)
    with pytest.raises(ValueError, match="lx"):
        bem.image_curvature(E_STAR, 1.0, 1.0, 0.0)
    with pytest.raises(TypeError, match="image_correction"):
        bem.line_contact_scene(PSD, E_STAR, RADIUS, 1.0, image_correction="no")
    for gap in (-np.ones((4, 4)), np.full((4, 4), 1e300)):  # (whose cube overflows)
        with pytest.raises(ValueError, match=r"gap must lie in \[0, 1000\] m"):
            bem.reynolds_flow(gap, 1e-6)
    with pytest.raises(ValueError, match="nominal pressure of 1e\\+06 E"):
        bem.solve_contact(np.zeros(grid.shape), grid, 1e7, 1e300)
    for seed, error in (("x", TypeError), (-1, ValueError), (True, TypeError)):
        with pytest.raises(error, match="seed"):
            bem.random_surface(PSD, grid, seed=seed)
    with pytest.raises(ValueError, match="viscosity"):
        bem.reynolds_flow(np.ones((4, 4)), 1e-6, viscosity=0.0)
    with pytest.raises(ValueError, match="load"):
        bem.line_contact_scene(PSD, E_STAR, RADIUS, 0.0)
    with pytest.raises(ValueError, match="bin_width"):
        bem.point_contact_scene(PSD, E_STAR, RADIUS, 1.0, bin_width=-1.0)
    with pytest.raises(ValueError, match="psd is required"):
        bem.flat_contact_scene(None, E_STAR, 1e5)
    with pytest.raises(TypeError, match="scene"):
        bem.run_realization(0, "scene")
    scene = bem.flat_contact_scene(PSD, E_STAR, 1e5, grid=grid)
    with pytest.raises(ValueError, match="realizations"):
        bem.run_ensemble(scene, 0)
    with pytest.raises(TypeError, match="executor"):
        bem.run_ensemble(scene, 1, executor=object())
    with pytest.raises(TypeError, match="grid"):
        bem.with_grid(scene, None)
    with pytest.raises(TypeError, match="ensemble"):
        bem.compare_line_contact(None, scene)
    line = bem.run_ensemble(bem.line_contact_scene(None, E_STAR, RADIUS, 100.0), 1)
    with pytest.raises(TypeError, match="missing"):
        bem.compare_line_contact(object(), line)
    x = np.linspace(-1e-3, 1e-3, 11)
    with pytest.raises(ValueError, match="differs"):
        bem.compare_line_contact(FakeTheory(x, x * 0, 1.0, 1.0, 1.0, 50.0), line)


def test_spectral_grid_keeps_its_size_for_rounded_wavenumbers():
    """Wavenumbers typed to a few decimals (q1/q0 = 32 to 1e-8) keep the grid the exact ratio
    gives, not the next FFT-friendly size above it; a clearly larger ratio still grows it."""
    exact = fl.SelfAffinePSD(0.5e-6, 0.8, 2 * np.pi / 40e-6, 2 * np.pi / 40e-6, 64 * np.pi / 40e-6)
    typed = fl.SelfAffinePSD(0.5e-6, 0.8, 157079.63, 157079.63, 5026548.2)
    wider = fl.SelfAffinePSD(0.5e-6, 0.8, 157079.63, 157079.63, 5026548.2 * 1.001)
    n_exact = bem.spectral_grid(exact, periods=4).nx
    assert bem.spectral_grid(typed, periods=4).nx == n_exact == 512
    assert bem.spectral_grid(wider, periods=4).nx > n_exact
