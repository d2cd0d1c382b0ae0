"""The result of one contact scene: what the line and the point contact share.

:class:`ContactResult` holds the fields every geometry reports (the profile, its measures, the
scene and how the solve went); :class:`~fastline.LineContactResult` adds the line's grid (``x``,
``dx``) and its error estimate, :class:`~fastline.PointContactResult` the rings (``r``, ``dr``)
and the Hertz radius. Units: m, Pa, and N/m (line) or N (point) for loads.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from html import escape
from typing import TYPE_CHECKING

import numpy as np

from fastline.contact.figure import plot_profile, scene_text
from fastline.contact.model import DeferredFields, deferrable

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from fastline.theory.persson import PerssonTheory

__all__ = ["ContactResult"]


def _cell(text: str) -> str:
    """A table cell's text, HTML-escaped (the bold of 'not converged' kept)."""
    return escape(text).replace("&lt;b&gt;", "<b>").replace("&lt;/b&gt;", "</b>")


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

    def plot(
        self, *, hertz: bool = True, label: str | None = None, ax: Axes | None = None
    ) -> Figure:
        """Draw the pressure profile with the Hertz profile at the same load; returns the
        matplotlib Figure (:func:`fastline.plotting.plot_profile`; matplotlib is imported
        now, not with fastline)."""
        return plot_profile(self, hertz=hertz, label=label, ax=ax)

    def _repr_html_(self) -> str:
        """A notebook's view: the scene, the measures of the profile and how the solve went."""
        ok = "converged" if self.converged else "<b>not converged</b>"
        rows = (
            ("scene", f"{self.model}, E* {self.E_star:.4g} Pa, R {self.radius:.4g} m"),
            ("load, alpha", scene_text(self, math=False)),
            ("p0", f"{self.p0:.6g} Pa ({self.p0_ratio:.4g} of Hertz's)"),
            ("s, FWHM w", f"{self.s:.4g} m, {self.fwhm:.4g} m (w/s {self.w_over_s:.4g})"),
            ("solve", f"{ok}: {self.iterations} steps, {self.convolutions} convolutions, "
                      f"residual {self.residual:.3g}"),
        )  # fmt: skip
        body = "".join(
            f"<tr><th style='text-align:left'>{k}</th><td style='text-align:left'>{_cell(v)}</td>"
            "</tr>"
            for k, v in rows
        )
        return f"<table><caption>{type(self).__name__}</caption>{body}</table>"
