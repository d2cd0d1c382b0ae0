"""The result of one contact scene: what the line and the point contact share.

:class:`ContactResult` holds the fields every geometry reports (the profile, its measures, the
scene and how the solve went); :class:`~fastline.LineContactResult` adds the line's grid (``x``,
``dx``) and its error estimate, :class:`~fastline.PointContactResult` the rings (``r``, ``dr``)
and the Hertz radius. Units: m, Pa, and N/m (line) or N (point) for loads.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from fastline.contact.model import DeferredFields, deferrable

if TYPE_CHECKING:
    from fastline.theory.persson import PerssonTheory

__all__ = ["ContactResult"]


@deferrable("real_area", "diagnostics")
@dataclass
class ContactResult(DeferredFields):
    """The fields of a contact result that every geometry shares.

    ``real_area`` and ``diagnostics`` of a solve are computed when first read (for
    ``diagnostics``, unless the model warns); the values are the same
    (:class:`fastline.contact.model.DeferredFields`). Each geometry's class documents the
    fields in its own coordinates (``x`` or ``r``) and load unit.

    Attributes
    ----------
    pressure, separation : ndarray
        Nominal contact pressure in Pa and mean interfacial separation in m on the cells.
    real_area : ndarray or None
        Real contact area fraction P(q1, p) (None for a law that does not know it).
    p0, s, fwhm, w_over_s, p0_ratio : float
        Peak pressure (Pa), standard deviation (m), full width at half maximum (m),
        ``fwhm / s`` and ``p0 / p0_Hertz``.
    alpha, delta, u1 : float
        ``h_rms / delta``, the Hertz penetration (m) and the rigid approach (m).
    converged : bool
    iterations, convolutions : int
    residual : float
    message, model, method : str
    load, radius, E_star : float
        The scene: load (N/m or N), radius (m), effective modulus (Pa).
    force_error, edge_pressure : float
        Relative load error and the pressure at the domain edge relative to p0.
    diagnostics : dict
        Solver counts and validity checks (:func:`fastline.contact.diagnostics.assess`).
    theory : PerssonTheory or None
        The theory the scene was solved with (None for hertz and for user laws).
    """

    pressure: np.ndarray
    separation: np.ndarray
    real_area: np.ndarray | None
    p0: float
    s: float
    fwhm: float
    w_over_s: float
    p0_ratio: float
    alpha: float
    delta: float
    u1: float
    converged: bool
    iterations: int
    convolutions: int
    residual: float
    message: str
    model: str
    method: str
    load: float
    radius: float
    E_star: float
    force_error: float
    edge_pressure: float
    diagnostics: dict = field(default_factory=dict)
    theory: PerssonTheory | None = field(default=None, repr=False, compare=False)

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}(model={self.model!r}, alpha={self.alpha:.4g}, "
            f"p0={self.p0:.6g} Pa, w_over_s={self.w_over_s:.5g}, p0_ratio={self.p0_ratio:.5g}, "
            f"converged={self.converged}, convolutions={self.convolutions})"
        )
