"""The coupled seal's equations on the cells of a solved contact, line or point.

docs/leakage.md, "The seal under pressure". One discrete form serves both geometries: the mean
gaps ``u`` on the contact's ``n`` cells, the fluid pressure ``p_f`` on ``N`` flow nodes, the
change of approach ``d_delta`` and the flux variable ``phi``. With the pressure law
``p_c = p(u)``, the local gap ``g(p_c)`` of the leak rate and the scaled residual

    gap   (n):   u - u_0 + d_delta - K (p_c + p_l - p_0)            (the solve's operator K)
    force (1):   sum_k w_k (p_c + p_l - p_0)_k                      (the load is held)
    links (N-1): p_f,j - p_f,j+1 - phi R_j / R_0                    (Reynolds flow, in series)
    ends  (2):   p_f,0 - dP,   p_f,N-1

the fluid's load on cell k is ``p_l,k = e_k dP + c_k p_f[il_k] + d_k p_f[ih_k]`` and the
resistance of link j is ``R_j = A_j g^-3[ia_j] + B_j g^-3[ib_j]`` (the viscosity and the seal
length taken out: ``12 eta Q / L = phi / R_0``). The geometry sets the coefficients:

* **line contact** (strips in series): a node at every cell centre, ``p_l = p_f - dP H``
  (the far-field step, module :mod:`fastline.leakage.seal`), links between neighbouring
  centres with ``A = B = dx / 2`` (the trapezoid between the cells);
* **point contact** (rings in series, radial flow out of a hole of radius ``r_h``): nodes at
  ``r_h`` and at the ring edges beyond it, ``e_{m+1} .. e_n``; link j crosses ring ``m + j``
  from ``max(e_{m+j}, r_h)`` to ``e_{m+j+1}`` with ``A_j = ln(outer / inner) / (2 pi)``,
  ``B_j = 0`` (exact for a gap uniform on the ring: Poiseuille flow between two radii). The
  fluid at dP fills the hole: the cells inside it carry ``dP``; a ring the hole's edge cuts
  carries ``dP`` on its share ``f`` of area inside ``r_h`` and the mean of its two nodes on the
  rest; the rings beyond the mean of their two nodes. The load is compact (no far field).

With the rigid body (``rigid``) the gap rows hold ``u = u_0`` and the force row
``d_delta = 0``: the fluid then follows the uncoupled strips (or rings) in series exactly.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from fastline.elastic import influence_coefficients, ring_edges, ring_influence_coefficients

if TYPE_CHECKING:  # annotations only
    from fastline.contact.line import LineContactResult
    from fastline.contact.point import PointContactResult

__all__ = [
    "EDGE",
    "SUPPORTS",
    "System",
    "contact_radius",
    "equations",
    "inverse_cube",
    "line_system",
    "point_system",
    "residual",
    "start",
]

#: where the line contact's far-field fluid load starts to count, and the pressure, as a
#: fraction of the peak, that marks the edge of the dry contact
SUPPORTS, EDGE = ("edge", "axis"), 1e-3


@dataclass
class System:
    """The fixed pieces of the coupled equations of one dry contact (module docstring).

    ``K`` (n x n, m/Pa), ``KL`` (``K`` times the node-to-cell load map, n x N), ``T`` (the
    suffix sums ``T[:, j] = sum_{i > j} KL[:, i]``, n x (N - 1)), ``KL1`` (``KL`` summed over
    the nodes), ``wL`` and ``tau`` the same for the cells' weights ``w`` (m or m^2).
    """

    geometry: str
    x: np.ndarray
    w: np.ndarray
    K: np.ndarray
    u0: np.ndarray
    p0: np.ndarray
    ext: np.ndarray
    il: np.ndarray
    ih: np.ndarray
    cl: np.ndarray
    ch: np.ndarray
    ia: np.ndarray
    ib: np.ndarray
    A: np.ndarray
    B: np.ndarray
    nodes: np.ndarray
    law: object
    log_gap: object
    g_clamp: float
    viscosity: float
    length: float
    rigid: bool
    KL: np.ndarray | None = None
    T: np.ndarray | None = None
    KL1: np.ndarray | None = None
    wL: np.ndarray | None = None
    tau: np.ndarray | None = None

    def __post_init__(self):
        from scipy.sparse import csr_matrix  # lazy: only when a seal is solved

        n, N = self.x.size, self.nodes.size
        rows = np.concatenate([np.arange(n), np.arange(n)])
        L = csr_matrix((np.concatenate([self.cl, self.ch]), (rows, np.concatenate(
            [self.il, self.ih]))), shape=(n, N))  # fmt: skip
        self.KL = np.ascontiguousarray((L.T @ self.K.T).T)  # O(n^2): L has 2 entries a row
        self.wL = np.asarray(L.T @ self.w).ravel()
        suffix = np.cumsum(self.KL[:, ::-1], axis=1)[:, ::-1]  # sum_{i >= j}
        self.KL1 = np.ascontiguousarray(suffix[:, 0])
        self.T = np.ascontiguousarray(suffix[:, 1:])
        self.tau = np.cumsum(self.wL[::-1])[::-1][1:].copy()

    @property
    def n(self) -> int:
        return self.x.size

    @property
    def size(self) -> int:
        """Unknowns (and equations): n gaps, N node pressures, d_delta and phi."""
        return self.x.size + self.nodes.size + 2

    def scales(self) -> tuple[float, float]:
        """(gap scale m, load scale: the dry contact's load) of the residual."""
        return float(np.median(self.u0)), float(self.w @ self.p0)

    def fluid_load(self, pf: np.ndarray, dP: float) -> np.ndarray:
        """The fluid's load on each cell (Pa)."""
        return self.ext * dP + self.cl * pf[self.il] + self.ch * pf[self.ih]

    def resistances(self, inv: np.ndarray) -> np.ndarray:
        """The links' resistances ``R_j`` from the cells' ``g^-3``."""
        return self.A * inv[self.ia] + self.B * inv[self.ib]


def inverse_cube(sys: System, u: np.ndarray) -> tuple[np.ndarray, ...]:
    """(p_c, dp_c/du, g^-3 with the clamp, d(g^-3)/du) at the mean gaps u (central
    differences of the law and of ln g in u, step 1e-6 u)."""
    h = 1e-6 * u
    p = sys.law(u)
    p_up, p_dn = sys.law(u + h), sys.law(u - h)
    dp = (p_up - p_dn) / (2.0 * h)
    floor = math.log(sys.g_clamp)
    lg = np.maximum(sys.log_gap(p)[0], floor)
    lg_up = np.maximum(sys.log_gap(p_up)[0], floor)
    lg_dn = np.maximum(sys.log_gap(p_dn)[0], floor)
    with np.errstate(over="ignore", invalid="ignore"):
        inv = np.exp(-3.0 * lg)
        d_lg = np.where(np.isfinite(lg_up - lg_dn), (lg_up - lg_dn) / (2.0 * h), 0.0)
    return p, dp, inv, np.nan_to_num(-3.0 * inv * d_lg)


def residual(
    sys: System, y: np.ndarray, dP: float, r0: float, law_values: tuple | None = None,
    matvec: Callable | None = None,
) -> np.ndarray:  # fmt: skip
    """The scaled residual (module docstring) at ``y = (u, p_f, d_delta, phi)`` (``matvec(K,
    v)``: the product with K, default NumPy's)."""
    n, N = sys.n, sys.nodes.size
    u, pf, dd, phi = y[:n], y[n : n + N], y[n + N], y[n + N + 1]
    pc, _, inv, _ = inverse_cube(sys, u) if law_values is None else law_values
    su, sf = sys.scales()
    load = pc + sys.fluid_load(pf, dP) - sys.p0
    F = np.empty(sys.size)
    Kl = 0.0 if sys.rigid else (sys.K @ load if matvec is None else matvec(sys.K, load))
    F[:n] = (u - sys.u0 + dd - Kl) / su
    F[n] = dd / su if sys.rigid else float(sys.w @ load) / sf
    F[n + 1 : n + N] = (pf[:-1] - pf[1:] - phi * sys.resistances(inv) / r0) / dP
    F[n + N], F[n + N + 1] = (pf[0] - dP) / dP, pf[-1] / dP
    return F


def equations(
    sys: System, y: np.ndarray, dP: float, r0: float, jac: bool
) -> tuple[np.ndarray, np.ndarray | None]:
    """Scaled residual and, with ``jac``, its dense Jacobian: rows gap (n), force (1), links
    (N - 1), the two ends (2); columns u, p_f, d_delta and phi."""
    vals = inverse_cube(sys, y[: sys.n])
    F = residual(sys, y, dP, r0, vals)
    if not jac:
        return F, None
    n, N = sys.n, sys.nodes.size
    _, dpc, inv, dinv = vals
    phi = y[n + N + 1]
    su, sf = sys.scales()
    J = np.zeros((sys.size, sys.size))
    if sys.rigid:
        J[:n, :n] = np.eye(n) / su
        J[:n, n + N] = J[n, n + N] = 1.0 / su
    else:
        J[:n, :n] = (np.eye(n) - sys.K * dpc) / su
        J[:n, n : n + N] = -sys.KL / su
        J[:n, n + N] = 1.0 / su
        J[n, :n], J[n, n : n + N] = dpc * sys.w / sf, sys.wL / sf
    k = np.arange(N - 1)
    rows = n + 1 + k
    J[rows, n + k], J[rows, n + 1 + k] = 1.0 / dP, -1.0 / dP
    np.add.at(J, (rows, sys.ia), -phi * sys.A * dinv[sys.ia] / r0 / dP)
    np.add.at(J, (rows, sys.ib), -phi * sys.B * dinv[sys.ib] / r0 / dP)
    J[rows, n + N + 1] = -sys.resistances(inv) / r0 / dP
    J[n + N, n], J[n + N + 1, n + N - 1] = 1.0 / dP, 1.0 / dP
    return F, J


def line_system(
    result: LineContactResult, law: Callable, log_gap: Callable, g_clamp: float,
    flow: tuple[float, float], rigid: bool, support: str,
) -> System:  # fmt: skip
    """The coupled equations of a line contact: strips in series (module docstring)."""
    n = result.x.size
    x = np.asarray(result.x, dtype=float)
    dx = float(result.dx)
    p0 = np.asarray(result.pressure, dtype=float)
    from scipy.linalg import toeplitz  # lazy: only when a seal is solved

    K = toeplitz(influence_coefficients(n)) * (dx / result.E_star)
    step = 0.0 if support == "axis" else float(x[np.argmax(p0 >= EDGE * p0.max())])
    upstream = np.where(x < step, 1.0, np.where(x == step, 0.5, 0.0))
    cells, links = np.arange(n), np.arange(n - 1)
    return System(
        geometry="line", x=x, w=np.full(n, dx), K=K,
        u0=np.asarray(result.separation, dtype=float), p0=p0, ext=-upstream,
        il=cells, ih=cells, cl=np.ones(n), ch=np.zeros(n), ia=links, ib=links + 1,
        A=np.full(n - 1, 0.5 * dx), B=np.full(n - 1, 0.5 * dx), nodes=x.copy(), law=law,
        log_gap=log_gap, g_clamp=g_clamp, viscosity=flow[0], length=flow[1], rigid=bool(rigid),
    )  # fmt: skip


def contact_radius(result: PointContactResult) -> float:
    """The outer edge (m) of the outermost ring of a point contact with ``p_0 >= EDGE p_0,max``."""
    p0 = np.asarray(result.pressure, dtype=float)
    e = ring_edges(p0.size) * float(result.dr)
    return float(e[1:][np.nonzero(p0 >= EDGE * p0.max())[0][-1]])


def point_system(
    result: PointContactResult, law: Callable, log_gap: Callable, g_clamp: float,
    flow: tuple[float, float], rigid: bool, hole: float,
) -> System:  # fmt: skip
    """The coupled equations of a point contact: rings in series out of a hole of radius
    ``hole`` (module docstring; the hole lies inside the contact, checked by the caller)."""
    n, dr = result.r.size, float(result.dr)
    e = ring_edges(n) * dr
    m = int(np.searchsorted(e, hole, side="right")) - 1  # the ring the hole's edge cuts
    lo, hi = e[:-1], e[1:]
    frac = np.clip((hole**2 - lo**2) / (hi**2 - lo**2), 0.0, 1.0)  # area share inside r_h
    N = n - m + 1
    j = np.arange(n) - m  # a flow cell's inner node
    inside = j < 0
    il = np.where(inside, 0, j)
    half = np.where(inside, 0.0, 0.5 * (1.0 - frac))
    links = np.arange(m, n)
    inner = np.maximum(lo[links], hole)
    K = np.ascontiguousarray(ring_influence_coefficients(n)) * (dr / result.E_star)
    return System(
        geometry="point", x=np.asarray(result.r, dtype=float), w=np.pi * (hi - lo) * (hi + lo),
        K=K, u0=np.asarray(result.separation, dtype=float),
        p0=np.asarray(result.pressure, dtype=float), ext=frac, il=il,
        ih=np.where(inside, 0, j + 1), cl=half, ch=half, ia=links, ib=links,
        A=np.log(hi[links] / inner) / (2.0 * math.pi), B=np.zeros(N - 1),
        nodes=np.concatenate([[hole], hi[m:]]), law=law, log_gap=log_gap, g_clamp=g_clamp,
        viscosity=flow[0], length=flow[1], rigid=bool(rigid),
    )  # fmt: skip


def start(sys: System, dP: float) -> tuple[np.ndarray, float]:
    """The uncoupled state at dP (the dry gaps and the fluid pressure of the links in series)
    and the total resistance ``R_0`` of the dry contact."""
    r = sys.resistances(inverse_cube(sys, sys.u0)[2])
    r0 = float(np.sum(r))
    pf = dP * (1.0 - np.concatenate([[0.0], np.cumsum(r)]) / r0)
    return np.concatenate([sys.u0, pf, [0.0, dP]]), r0
