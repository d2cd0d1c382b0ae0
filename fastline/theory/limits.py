"""Analytic limits of the rough line contact (docs/theory.md section 5) and point contact
(docs/sphere.md).

Two closed-form pressure profiles bracket the rough line contact (Tiwari & Persson,
"Cylinder-flat contact mechanics with surface roughness"):

* the smooth Hertz line contact (alpha -> 0; paper eqs. 6-9), an ellipse of half-width ``a``;
* the Gaussian limit (alpha >> 1; paper eqs. 12-14) obtained from the exponential
  pressure-separation law ``p ~ beta E* exp(-u / u0)`` with bulk deformation neglected.

Here ``delta = 4 f_N / (pi E*)`` is the Hertz penetration and ``alpha = h_rms / delta`` the
roughness parameter.  The profile width is reported by its standard deviation ``s`` (about the
centroid) and its full width at half maximum ``w``; the ratio ``w/s`` is ``2 sqrt(3)`` for Hertz
and ``2 sqrt(2 ln 2)`` for the Gaussian.

The sphere on a flat (point contact) has the same two limits: the Hertz sphere (Johnson 1985,
section 4.2), ``p = p0 sqrt(1 - r^2/a^2)`` with ``a^3 = 3 F R / (4 E*)``, and the Gaussian
``p = p0 exp(-r^2 / (2 s^2))``, ``s^2 = R u0``, ``p0 = F / (2 pi s^2)`` (paper, section 2).
There ``s`` is defined by ``s^2 = <r^2>/2 = int r^2 p dA / (2 F)``, the variance of the
pressure along one diameter direction, and ``w`` is the FWHM along a diameter: ``w/s`` is
``sqrt(15)`` for Hertz (``s = a / sqrt(5)``, ``w = sqrt(3) a``) and ``2 sqrt(2 ln 2)`` for the
Gaussian, and ``p0(Gaussian) / p0(Hertz) = 1 / (3 gamma_u alpha)`` with ``delta = a^2 / R``.

SI units throughout: Pa, m, N/m (load per unit cylinder length), N (load on a sphere).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import finite_array, positive

__all__ = [
    "WS_GAUSSIAN",
    "WS_HERTZ",
    "WS_HERTZ_SPHERE",
    "GaussianLineContact",
    "GaussianPointContact",
    "HertzLineContact",
    "HertzPointContact",
    "alpha",
    "gaussian_line_contact",
    "gaussian_point_contact",
    "hertz_line_contact",
    "hertz_point_contact",
    "p0_ratio_gaussian",
    "p0_ratio_gaussian_sphere",
    "penetration",
    "hertz_line_unchecked",
    "gaussian_line_unchecked",
]

#: FWHM / standard deviation of the Hertz (elliptical) profile, ``2 sqrt(3)`` (~3.464).
WS_HERTZ = 2.0 * math.sqrt(3.0)
#: FWHM / standard deviation of a Gaussian profile, ``2 sqrt(2 ln 2)`` (~2.355); the same for
#: the line and the point contact.
WS_GAUSSIAN = 2.0 * math.sqrt(2.0 * math.log(2.0))
#: FWHM along a diameter / s of the Hertz sphere, ``sqrt(15)`` (~3.873), with
#: ``s^2 = int r^2 p dA / (2 F) = a^2 / 5`` and ``w = sqrt(3) a`` (module docstring).
WS_HERTZ_SPHERE = math.sqrt(15.0)


def _representable(what: str, given: dict, derived: dict) -> None:
    """A ValueError naming the inputs when a closed form's ``derived`` quantities are not
    finite and > 0 in float64 (inputs each > 0 but so far apart, e.g. a load of 1e-320 N or
    1e300 N/m, that the result under- or overflows): no 0, inf or ZeroDivisionError."""
    bad = {k: v for k, v in derived.items() if not (0.0 < v < math.inf)}
    if bad:
        inputs = ", ".join(f"{k}={v!r}" for k, v in given.items())
        out = ", ".join(f"{k} = {v!r}" for k, v in bad.items())
        raise ValueError(
            f"{what} of {inputs} is not representable in float64 ({out}): the inputs lie "
            "outside any physical range (the solvers accept E_star in [1, 1e13] Pa and radius "
            "in [1e-9, 1e3] m)"
        )


def _as_result(out: np.ndarray) -> float | np.ndarray:
    """A Python float for 0-d results, the array otherwise."""
    return float(out) if out.ndim == 0 else out


def penetration(E_star: float, load: float) -> float:
    """Hertz penetration ``delta = 4 f_N / (pi E*)`` of a line contact.

    Parameters
    ----------
    E_star : float
        Effective modulus ``E*`` [Pa], > 0.
    load : float
        Normal load per unit length ``f_N`` [N/m], > 0.

    Returns
    -------
    float
        ``delta`` [m] (paper eq. 9 solved for ``delta``; ``a = sqrt(R delta)``, eq. 8).
    """
    E_star = positive("E_star", E_star, "Pa")
    load = positive("load", load, "N/m")
    delta = 4.0 * load / (math.pi * E_star)
    _representable("the penetration", {"E_star": E_star, "load": load}, {"delta": delta})
    return delta


def alpha(h_rms: float, E_star: float, load: float) -> float:
    """Roughness parameter ``alpha = h_rms / delta`` (paper, text after eq. 5).

    Parameters
    ----------
    h_rms : float
        Combined rms roughness amplitude [m], > 0.
    E_star : float
        Effective modulus [Pa], > 0.
    load : float
        Normal load per unit length [N/m], > 0.

    Returns
    -------
    float
        ``alpha`` (dimensionless); Hertz-like below ~0.01, Gaussian-like above ~10.
    """
    h_rms = positive("h_rms", h_rms, "m")
    out = h_rms / penetration(E_star, load)
    _representable("alpha", {"h_rms": h_rms, "E_star": E_star, "load": load}, {"alpha": out})
    return out


@dataclass(frozen=True)
class HertzLineContact:
    """Smooth cylinder on an elastic half-space, plane strain (paper eqs. 6-9).

    Attributes
    ----------
    E_star : float
        Effective modulus [Pa].
    radius : float
        Cylinder radius ``R`` [m].
    load : float
        Load per unit length ``f_N`` [N/m].
    p0 : float
        Peak pressure ``sqrt(E* f_N / (pi R))`` [Pa] (paper eq. 7).
    a : float
        Contact half-width ``sqrt(R delta)`` [m] (paper eq. 8).
    delta : float
        Penetration ``4 f_N / (pi E*)`` [m] (paper eq. 9).
    """

    E_star: float
    radius: float
    load: float
    p0: float
    a: float
    delta: float

    @property
    def s(self) -> float:
        """Standard deviation of the pressure profile, ``a / 2`` [m]."""
        return 0.5 * self.a

    @property
    def fwhm(self) -> float:
        """Full width at half maximum, ``sqrt(3) a`` [m] (so ``fwhm / s = WS_HERTZ``)."""
        return math.sqrt(3.0) * self.a

    def pressure(self, x: ArrayLike) -> float | np.ndarray:
        """Pressure ``p0 sqrt(1 - (x/a)^2)`` for ``|x| < a``, 0 outside (paper eq. 6).

        Parameters
        ----------
        x : float or array_like
            Position(s) from the contact centre [m], finite.

        Returns
        -------
        float or ndarray
            Pressure [Pa], same shape as ``x``.
        """
        t = finite_array("x", x) / self.a
        inside = np.abs(t) < 1.0
        out = np.zeros_like(t)
        ti = t[inside]
        out[inside] = self.p0 * np.sqrt((1.0 - ti) * (1.0 + ti))
        return _as_result(out)


@dataclass(frozen=True)
class GaussianLineContact:
    """Gaussian limit of the rough line contact, alpha >> 1 (paper eqs. 12-13).

    With the exponential law ``p ~ exp(-u/u0)`` and rigid bulk, ``u = u1 + x^2 / (2R)`` gives
    ``p = p0 exp(-x^2 / (2 s^2))``.

    Attributes
    ----------
    u0 : float
        Decay length of the exponential law ``p ~ exp(-u/u0)`` (paper eqs. 5, 10),
        ``gamma_u h_rms`` [m].
    radius : float
        Cylinder radius ``R`` [m].
    load : float
        Load per unit length ``f_N`` [N/m].
    s : float
        Standard deviation ``sqrt(R u0)`` [m] (text after paper eq. 12).
    p0 : float
        Peak pressure ``f_N / (s sqrt(2 pi))`` [Pa] (paper eq. 13).
    """

    u0: float
    radius: float
    load: float
    s: float
    p0: float

    @property
    def fwhm(self) -> float:
        """Full width at half maximum, ``2 sqrt(2 ln 2) s`` [m] (``fwhm / s = WS_GAUSSIAN``)."""
        return WS_GAUSSIAN * self.s

    def pressure(self, x: ArrayLike) -> float | np.ndarray:
        """Pressure ``p0 exp(-x^2 / (2 s^2))`` (paper eq. 12).

        Parameters
        ----------
        x : float or array_like
            Position(s) from the contact centre [m], finite.

        Returns
        -------
        float or ndarray
            Pressure [Pa], same shape as ``x``.
        """
        t = finite_array("x", x) / self.s
        return _as_result(self.p0 * np.exp(-0.5 * t * t))


def hertz_line_contact(E_star: float, radius: float, load: float) -> HertzLineContact:
    """Hertz solution for a smooth cylinder pressed on a half-space (paper eqs. 6-9).

    Parameters
    ----------
    E_star : float
        Effective plane-strain modulus ``E*`` [Pa], > 0 (paper eq. 1).
    radius : float
        Cylinder radius ``R`` [m], > 0.
    load : float
        Normal load per unit length ``f_N`` [N/m], > 0.

    Returns
    -------
    HertzLineContact
        ``p0 = sqrt(E* f_N / (pi R))``, ``delta = 4 f_N / (pi E*)``, ``a = sqrt(R delta)``.
    """
    E_star = positive("E_star", E_star, "Pa")
    radius = positive("radius", radius, "m")
    load = positive("load", load, "N/m")
    hz = hertz_line_unchecked(E_star, radius, load)
    given = {"E_star": E_star, "radius": radius, "load": load}
    _representable("the Hertz line contact", given, {"p0": hz.p0, "a": hz.a, "delta": hz.delta})
    return hz


def hertz_line_unchecked(E_star: float, radius: float, load: float) -> HertzLineContact:
    """:func:`hertz_line_contact` of values already checked (a solver's own), no checks."""
    delta = 4.0 * load / (math.pi * E_star)  # penetration(E_star, load)
    return HertzLineContact(
        E_star=E_star,
        radius=radius,
        load=load,
        p0=math.sqrt(E_star * load / (math.pi * radius)),
        a=math.sqrt(radius * delta),
        delta=delta,
    )


def gaussian_line_contact(u0: float, radius: float, load: float) -> GaussianLineContact:
    """Gaussian (large-alpha) limit of the rough line contact (paper eqs. 12-13).

    Parameters
    ----------
    u0 : float
        Decay length of the exponential pressure-separation law [m], > 0 (``u0 = gamma_u
        h_rms``, paper eq. 5).
    radius : float
        Cylinder radius ``R`` [m], > 0.
    load : float
        Normal load per unit length ``f_N`` [N/m], > 0.

    Returns
    -------
    GaussianLineContact
        ``s = sqrt(R u0)`` and ``p0 = f_N / (s sqrt(2 pi))``.
    """
    u0 = positive("u0", u0, "m")
    radius = positive("radius", radius, "m")
    load = positive("load", load, "N/m")
    given = {"u0": u0, "radius": radius, "load": load}
    _representable("the Gaussian line contact", given, {"s": math.sqrt(radius * u0)})
    gs = gaussian_line_unchecked(u0, radius, load)
    _representable("the Gaussian line contact", given, {"p0": gs.p0})
    return gs


def gaussian_line_unchecked(u0: float, radius: float, load: float) -> GaussianLineContact:
    """:func:`gaussian_line_contact` of values already checked (a solver's own), no checks."""
    s = math.sqrt(radius * u0)
    return GaussianLineContact(
        u0=u0, radius=radius, load=load, s=s, p0=load / (s * math.sqrt(2.0 * math.pi))
    )


def p0_ratio_gaussian(alpha: ArrayLike, gamma_u: float) -> float | np.ndarray:
    """Peak-pressure ratio ``p0(rough) / p0(smooth)`` in the Gaussian limit (paper eq. 14).

    ``(pi / (8 gamma_u alpha))^(1/2)``: the Gaussian ``p0`` with ``u0 = gamma_u h_rms`` over the
    Hertz ``p0`` at the same load and radius, where ``alpha = h_rms / delta``.

    Parameters
    ----------
    alpha : float or array_like
        Roughness parameter(s) ``h_rms / delta``, each > 0 and finite.
    gamma_u : float
        Ratio ``u0 / h_rms`` of the exponential law, > 0 (the paper uses ~0.4).

    Returns
    -------
    float or ndarray
        The ratio (dimensionless), same shape as ``alpha``.
    """
    a = finite_array("alpha", alpha)
    if np.any(a <= 0.0):
        raise ValueError("alpha must be > 0 everywhere (allowed range (0, inf))")
    gamma_u = positive("gamma_u", gamma_u)
    return _as_result(np.sqrt(math.pi / (8.0 * gamma_u * a)))


# ----------------------------------------------------------------------------------------------
# point contact (sphere on a flat)
# ----------------------------------------------------------------------------------------------
def _radial(r: ArrayLike) -> np.ndarray:
    """|r| as a float array (a profile along a diameter may pass negative positions)."""
    return np.abs(finite_array("r", r))


@dataclass(frozen=True)
class HertzPointContact:
    """Smooth sphere on an elastic half-space (Johnson 1985, section 4.2; docs/sphere.md).

    Attributes
    ----------
    E_star : float
        Effective modulus [Pa].
    radius : float
        Sphere radius ``R`` [m].
    load : float
        Normal load ``F`` [N].
    p0 : float
        Peak pressure ``3 F / (2 pi a^2)`` [Pa].
    a : float
        Contact radius ``(3 F R / (4 E*))^(1/3)`` [m].
    delta : float
        Penetration (rigid approach) ``a^2 / R`` [m].
    """

    E_star: float
    radius: float
    load: float
    p0: float
    a: float
    delta: float

    @property
    def s(self) -> float:
        """``sqrt(int r^2 p dA / (2 F)) = a / sqrt(5)`` [m]."""
        return self.a / math.sqrt(5.0)

    @property
    def fwhm(self) -> float:
        """Full width at half maximum along a diameter, ``sqrt(3) a`` [m]
        (``fwhm / s = WS_HERTZ_SPHERE``)."""
        return math.sqrt(3.0) * self.a

    def pressure(self, r: ArrayLike) -> float | np.ndarray:
        """Pressure ``p0 sqrt(1 - r^2/a^2)`` for ``|r| < a``, 0 outside.

        Parameters
        ----------
        r : float or array_like
            Distance(s) from the contact centre [m] (signed positions along a diameter are
            accepted), finite.

        Returns
        -------
        float or ndarray
            Pressure [Pa], same shape as ``r``.
        """
        t = _radial(r) / self.a
        out = np.zeros_like(t)
        inside = t < 1.0
        ti = t[inside]
        out[inside] = self.p0 * np.sqrt((1.0 - ti) * (1.0 + ti))
        return _as_result(out)

    def displacement(self, r: ArrayLike) -> float | np.ndarray:
        """Elastic displacement of the half-space inside the contact,
        ``(pi p0 / (4 a E*)) (2 a^2 - r^2)`` [m] for ``|r| <= a`` (Johnson 1985, eq. 3.41); NaN
        outside (not provided).

        Parameters
        ----------
        r : float or array_like
            Distance(s) from the contact centre [m], finite.
        """
        r = _radial(r)
        u = np.pi * self.p0 / (4.0 * self.a * self.E_star) * (2.0 * self.a**2 - r * r)
        return _as_result(np.where(r <= self.a, u, np.nan))


@dataclass(frozen=True)
class GaussianPointContact:
    """Gaussian limit of the rough point contact, alpha >> 1 (paper, section 2).

    With the exponential law ``p ~ exp(-u/u0)`` and rigid bulk, ``u = u1 + r^2 / (2R)`` gives
    ``p = p0 exp(-r^2 / (2 s^2))``.

    Attributes
    ----------
    u0 : float
        Decay length of the exponential law, ``gamma_u h_rms`` [m].
    radius : float
        Sphere radius ``R`` [m].
    load : float
        Normal load ``F`` [N].
    s : float
        ``sqrt(R u0)`` [m] (``s^2 = int r^2 p dA / (2 F)`` for this profile).
    p0 : float
        Peak pressure ``F / (2 pi s^2)`` [Pa].
    """

    u0: float
    radius: float
    load: float
    s: float
    p0: float

    @property
    def fwhm(self) -> float:
        """Full width at half maximum along a diameter, ``2 sqrt(2 ln 2) s`` [m]."""
        return WS_GAUSSIAN * self.s

    def pressure(self, r: ArrayLike) -> float | np.ndarray:
        """Pressure ``p0 exp(-r^2 / (2 s^2))`` [Pa] at distance(s) ``r`` [m] from the centre."""
        t = _radial(r) / self.s
        return _as_result(self.p0 * np.exp(-0.5 * t * t))


def hertz_point_contact(E_star: float, radius: float, load: float) -> HertzPointContact:
    """Hertz solution for a smooth sphere pressed on a half-space (Johnson 1985, section 4.2).

    Parameters
    ----------
    E_star : float
        Effective modulus ``E*`` [Pa], > 0 (paper eq. 1).
    radius : float
        Sphere radius ``R`` [m], > 0.
    load : float
        Normal load ``F`` [N], > 0.

    Returns
    -------
    HertzPointContact
        ``a = (3 F R / (4 E*))^(1/3)``, ``p0 = 3 F / (2 pi a^2)``, ``delta = a^2 / R``.
    """
    E_star = positive("E_star", E_star, "Pa")
    radius = positive("radius", radius, "m")
    load = positive("load", load, "N")
    a = (3.0 * load * radius / (4.0 * E_star)) ** (1.0 / 3.0)
    given = {"E_star": E_star, "radius": radius, "load": load}
    _representable("the Hertz point contact", given, {"a": a, "a^2": a * a})
    _representable("the Hertz point contact", given, {"p0": 3.0 * load / (2.0 * math.pi * a * a)})
    _representable("the Hertz point contact", given, {"delta": a * a / radius})
    return HertzPointContact(
        E_star=E_star,
        radius=radius,
        load=load,
        p0=3.0 * load / (2.0 * math.pi * a * a),
        a=a,
        delta=a * a / radius,
    )


def gaussian_point_contact(u0: float, radius: float, load: float) -> GaussianPointContact:
    """Gaussian (large-alpha) limit of the rough point contact (paper, section 2).

    Parameters
    ----------
    u0 : float
        Decay length of the exponential pressure-separation law [m], > 0.
    radius : float
        Sphere radius ``R`` [m], > 0.
    load : float
        Normal load ``F`` [N], > 0.

    Returns
    -------
    GaussianPointContact
        ``s = sqrt(R u0)`` and ``p0 = F / (2 pi s^2)``.
    """
    u0 = positive("u0", u0, "m")
    radius = positive("radius", radius, "m")
    load = positive("load", load, "N")
    s = math.sqrt(radius * u0)
    given = {"u0": u0, "radius": radius, "load": load}
    _representable("the Gaussian point contact", given, {"s": s, "s^2": s * s})
    _representable("the Gaussian point contact", given, {"p0": load / (2 * math.pi * s * s)})
    return GaussianPointContact(
        u0=u0, radius=radius, load=load, s=s, p0=load / (2 * math.pi * s * s)
    )


def p0_ratio_gaussian_sphere(alpha: ArrayLike, gamma_u: float) -> float | np.ndarray:
    """Peak-pressure ratio ``p0(rough) / p0(smooth)`` of a point contact in the Gaussian limit.

    ``1 / (3 gamma_u alpha)``: the Gaussian ``p0 = F / (2 pi R u0)`` with ``u0 = gamma_u h_rms``
    over the Hertz ``p0 = 3 F / (2 pi a^2)``, with ``a^2 = R delta`` and ``alpha = h_rms / delta``
    (the sphere's analogue of paper eq. 14; docs/sphere.md).

    Parameters
    ----------
    alpha : float or array_like
        Roughness parameter(s) ``h_rms / delta``, ``delta = a^2 / R``; each > 0 and finite.
    gamma_u : float
        ``u0 / h_rms`` of the exponential law, > 0.

    Returns
    -------
    float or ndarray
        The ratio (dimensionless), same shape as ``alpha``.
    """
    a = finite_array("alpha", alpha)
    if np.any(a <= 0.0):
        raise ValueError("alpha must be > 0 everywhere (allowed range (0, inf))")
    gamma_u = positive("gamma_u", gamma_u)
    return _as_result(1.0 / (3.0 * gamma_u * a))
