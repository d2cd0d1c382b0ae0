"""Variants of Persson's u(p): the correction S(P) of the elastic energy and where it enters.

The theory's elastic energy per nominal area is ``U = (pi/2) E* int dq q^2 C P S`` with a
correction ``S(P)`` fitted to simulations (``S = 1`` is Persson's original theory), and
``u(p) = int_p^inf dp'/p' dU/dp'`` (docs/theory.md section 3). The literature uses:

``"yang-persson-energy"`` (default)
    ``S = gamma + (1 - gamma) P^2``, gamma = 0.45: the bracket of the u(p) integral is
    ``d/dP [P S] = gamma + 3 (1 - gamma) P^2`` (C. Yang, B.N.J. Persson, J. Phys.: Condens.
    Matter 20, 215214 (2008), doi:10.1088/0953-8984/20/21/215214; the energy derivation).
``"yang-persson-printed"``
    The bracket ``gamma + (1 - gamma) P^2``, as several papers print the u(p) integral (the
    energy correction ``S = gamma + (1 - gamma) P^2 / 3``). At small p it shifts u by about
    ``2 (1 - gamma) G(0) / gamma * u0`` (0.995 u0 at gamma = 0.45; beta smaller by e^0.995 =
    2.7), absorbed by the rigid approach in a line contact; near full contact the two differ
    more.
``"wang-mueser"``
    ``S = gamma - (2/9) P^2 + (11/9 - gamma) P^4``, gamma = 5/9 (A. Wang, M.H. Mueser,
    "Gauging Persson theory on adhesion", Tribol. Lett. 65, 103 (2017),
    doi:10.1007/s11249-017-0886-9), applied to the contact-area recursion as well:
    the variance of the contact pressure grows as ``dV = S(P) dV_full``. The form of S and its
    use in both the recursion and the energy follow the public MATLAB implementation of
    that paper's correction (github.com/xylcsi/PerssonModelFudgeFactor,
    ``Persson_LE_Area_WM17.m``, ``Persson_LE_SE_WM17.m``); the paper itself was not consulted.
    At small p the contact area is ``erf(x / sqrt(gamma))`` instead of ``erf(x)``, and
    ``u0 = sqrt(gamma) int dq q^2 C w`` (about 1.66 times the default's at gamma = 5/9).

The first two change only the bracket (:mod:`fastline.theory.special`, one universal function F per
gamma); the third also changes the contact area, through the universal functions of
:mod:`fastline.theory.special`. Tables are built lazily, once per variant and gamma.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

__all__ = ["Variant", "VariantName", "VARIANTS", "DEFAULT_VARIANT", "get_variant"]

#: the names ``variant=`` accepts (keys of :data:`VARIANTS`)
VariantName = Literal["yang-persson-energy", "yang-persson-printed", "wang-mueser"]

DEFAULT_VARIANT: VariantName = "yang-persson-energy"


@dataclass(frozen=True)
class Variant:
    """One variant of the Persson u(p) (module docstring).

    Attributes
    ----------
    name : str
    default_gamma : float
        The gamma it is used with in its source.
    area_correction : bool
        Whether S also enters the contact-area recursion (``dV = S dV_full``).
    reference : str
        Where it comes from.
    """

    name: str
    default_gamma: float
    area_correction: bool
    reference: str

    def correction(self, gamma: float) -> tuple[float, float, float]:
        """``(s0, s2, s4)`` of ``S(P) = s0 + s2 P^2 + s4 P^4`` (``S(1) = 1``)."""
        if self.name == "wang-mueser":
            return gamma, -2.0 / 9.0, 11.0 / 9.0 - gamma
        if self.name == "yang-persson-printed":
            return gamma, (1.0 - gamma) / 3.0, 0.0
        return gamma, 1.0 - gamma, 0.0

    def bracket(self, gamma: float) -> tuple[float, float, float]:
        """``(b0, b2, b4)`` of the bracket ``d/dP [P S] = b0 + b2 P^2 + b4 P^4``."""
        if self.name == "wang-mueser":
            _, s2, s4 = self.correction(gamma)
            return gamma, 3.0 * s2, 5.0 * s4
        if self.name == "yang-persson-printed":  # defined by its printed bracket
            return gamma, 1.0 - gamma, 0.0
        return gamma, 3.0 * (1.0 - gamma), 0.0  # fastline 0.1's arithmetic: same tables


VARIANTS: dict[str, Variant] = {
    v.name: v
    for v in (
        Variant(
            "yang-persson-energy",
            0.45,
            False,
            "Yang & Persson, J. Phys.: Condens. Matter 20, 215214 (2008); bracket "
            "gamma + 3 (1 - gamma) P^2 from the energy derivation",
        ),
        Variant(
            "yang-persson-printed",
            0.45,
            False,
            "the bracket gamma + (1 - gamma) P^2 as printed in several papers",
        ),
        Variant(
            "wang-mueser",
            5.0 / 9.0,
            True,
            "Wang & Mueser, Tribol. Lett. 65, 103 (2017), as implemented in "
            "github.com/xylcsi/PerssonModelFudgeFactor (S in the area recursion and the energy)",
        ),
    )
}


def get_variant(name: VariantName | Variant) -> Variant:
    """The :class:`Variant` called ``name``; ValueError naming the allowed names otherwise."""
    if isinstance(name, Variant):
        return name
    if not isinstance(name, str) or name not in VARIANTS:
        raise ValueError(f"variant must be one of {tuple(VARIANTS)}, got {name!r}")
    return VARIANTS[name]
