"""How strongly an excitation line drives the mode it crosses (issue 27).

A Campbell crossing is a resonance only when the excitation can put energy into the
mode. Two measures, one per kind of excitation line
(:func:`~reducerlab.analysis.excitation.excitation_orders`):

* **Mesh orders** (``hx mesh``: transmission error and mesh-stiffness variation) act
  on the drive only through the mesh lines. With the lines at their mean stiffness
  ``k_l`` (the model's mean stiffness ``K``, :attr:`NonlinearSystem.mean_stiffness`),
  the share of mode ``phi``'s strain energy stored in line ``l`` is

      ``s_l = k_l |g_l . phi|^2 / (phi^H K phi)``

  (the modal strain-energy measure of gear dynamics: Lin and Parker, J. Sound Vib. 228,
  1999, 109-128, show it is the eigenvalue's sensitivity to the mesh stiffness, ``s_l =
  (k_l / lambda) d lambda / d k_l``, twice the relative frequency sensitivity). A
  transmission error ``e`` on line ``l`` (force ``k_l e`` along ``g_l``) drives mode
  ``j`` with the modal force ``k_l (g_l . phi_j) e``; at resonance the mesh deflection
  the mode adds is ``s_l e / (2 zeta_j)``. A mode with ``s_l = 0`` (lateral motion
  orthogonal to the line of action, say) is not excited at all, whatever its frequency.

* **The rotation order** (``1x input``: unbalance) is a force turning with the rotor,
  ``m e Omega^2 (cos, sin)``: a forward circular excitation. For every lateral pair
  ``(x, y)`` or ``(rx, ry)`` of a body, the orbit of mode ``phi`` splits into a
  forward and a backward circle, ``r_ccw = (u + i v) / 2`` and ``r_cw = (u - i v) /
  2`` for the amplitudes ``u, v`` (forward = the body's spin sense, as
  :func:`~reducerlab.analysis.complex_modal.spin_signs` gives it). The forward share
  ``sum m |r_fwd|^2 / sum m (|r_fwd|^2 + |r_bwd|^2)`` (masses of the pair) is 1 for a
  forward whirl and 0 for a backward whirl of an isotropic rotor (which unbalance
  does not excite; Friswell, Penny, Garvey and Lees, *Dynamics of Rotating Machines*,
  2010, Ch. 3); a planar (undamped, non-gyroscopic) mode has 1/2, and the elliptical
  whirls of an anisotropic rotor lie in between, so a backward whirl on unequal
  supports is excited in proportion to its forward component.

Both measures are taken over the whole eigenspace of a repeated frequency (an
isotropic pair, the cyclic modes of a planetary set): the largest share of any
combination, a Rayleigh quotient maximised by a generalised eigenproblem of the
group's size. The solver's choice of basis inside a degenerate pair would otherwise
decide whether a crossing counts.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from ..model import Model
from ..model.laws import flat_mean, flat_period
from ..units import RPM, TWO_PI

__all__ = [
    "REPEATED",
    "ROTATION",
    "ModeShapes",
    "excitation_lines",
    "forward_share",
    "mesh_share",
    "mode_shapes",
    "participation",
]

#: The excitation line of the input rotation (unbalance), as ``excitation_orders``
#: names it.
ROTATION = "1x input"

#: Frequencies closer than this share are one repeated eigenvalue (a degenerate pair).
REPEATED = 1e-6

#: Shares below this are round-off of a share that is exactly 0 (a mode orthogonal to
#: the mesh line, a circular backward whirl): reported as 0.
ROUND_OFF = 1e-12

#: A mode whose lateral pairs carry less than this share of its kinetic energy has no
#: whirl to judge (a torsional mode): its forward share is undefined (None).
LATERAL_MIN = 1e-6


class ModeShapes:
    """The modes of a model at one speed, numbered as the resonance verdict numbers
    them (undamped: :func:`~reducerlab.analysis.campbell.undamped_modes_over`; damped:
    :func:`~reducerlab.analysis.complex_modal.complex_modes`), with what the shares
    need: the mean stiffness, the mesh lines and the kinetic-energy weights."""

    def __init__(self, model: Model, speed: float, damped: bool) -> None:
        from .campbell import undamped_modes_over
        from .complex_modal import complex_modes

        at = model.with_speed(float(speed))
        if damped:
            ds = complex_modes(at).data
            self.freq = ds["frequency"].values
            self.phi = ds["shape_real"].values + 1j * ds["shape_imag"].values
        else:
            f, phi = undamped_modes_over(model, np.array([float(speed)]))
            self.freq, self.phi = f[0], phi[0].astype(complex)
        s = at.nonlinear()
        self.K = 0.5 * (s.mean_stiffness + s.mean_stiffness.T)
        self.M = at.matrices().M
        self.G = s.G
        self.k = np.array([abs(flat_mean(int(kd), p)) for kd, p in zip(s.k_kind, s.k_params,
                                                                        strict=True)])  # fmt: skip
        self.model = at

    def group(self, mode: int) -> NDArray:
        """Column indices of the eigenspace of mode ``mode`` (1-based): the modes whose
        frequency is the same to :data:`REPEATED`."""
        j = mode - 1
        f = self.freq
        return np.nonzero(np.abs(f - f[j]) <= REPEATED * max(abs(f[j]), 1e-300))[0]


def _largest_quotient(Phi: NDArray, Q: NDArray, R: NDArray) -> float:
    """``max (v^H Phi^H Q Phi v) / (v^H Phi^H R Phi v)`` over the span of ``Phi``."""
    A = Phi.conj().T @ Q @ Phi
    B = Phi.conj().T @ R @ Phi
    A, B = 0.5 * (A + A.conj().T), 0.5 * (B + B.conj().T)
    scale = float(np.real(np.trace(B)))
    if not scale > 0:
        return 0.0
    B = B + 1e-12 * scale * np.eye(B.shape[0])
    top = float(np.clip(scipy.linalg.eigh(A, B, eigvals_only=True)[-1], 0.0, 1.0))
    return top if top > ROUND_OFF else 0.0


def mesh_share(shapes: ModeShapes, mode: int, lines: Sequence[int]) -> float:
    """Strain-energy share of mode ``mode`` (1-based) in mesh ``lines`` (0..1), the
    largest over its eigenspace (see the module docstring)."""
    if not len(lines):
        return 0.0
    g = shapes.G[list(lines)]
    Q = g.T @ (g * shapes.k[list(lines), None])
    return _largest_quotient(shapes.phi[:, shapes.group(mode)], Q, shapes.K)


def forward_share(shapes: ModeShapes, mode: int) -> float | None:
    """Share of the lateral motion of mode ``mode`` (1-based) that whirls forward (0..1;
    see the module docstring), the largest over its eigenspace; None for a mode without
    lateral motion (no ``(x, y)`` or ``(rx, ry)`` pair moves)."""
    from .complex_modal import spin_signs

    model = shapes.model
    n = model.n
    spins = spin_signs(model)
    default = float(np.sign(model.speed)) or 1.0
    Q = np.zeros((n, n), complex)
    R = np.zeros((n, n), complex)
    mass = np.diag(shapes.M)
    for body in {d.body for d in model.dofs}:
        for a, b in (("x", "y"), ("rx", "ry")):
            ia, ib = model.index.get(f"{body}.{a}"), model.index.get(f"{body}.{b}")
            if ia is None or ib is None:
                continue
            w = mass[ia] + mass[ib]
            sense = spins.get((body, a + b), default) or default
            fwd = np.zeros(n, complex)  # r_fwd = fwd . phi: (u + i v) / 2 counterclockwise
            fwd[ia], fwd[ib] = 0.5, 0.5j * sense
            Q += w * np.outer(fwd.conj(), fwd)
            R[ia, ia] += 0.5 * w
            R[ib, ib] += 0.5 * w
    Phi = shapes.phi[:, shapes.group(mode)]
    if not np.any(R):
        return None
    lateral = _largest_quotient(Phi, 2 * R, shapes.M)
    if lateral < LATERAL_MIN:
        return None
    return _largest_quotient(Phi, Q, R)


def excitation_lines(model: Model, orders: dict[str, float]) -> dict[str, list[int] | None]:
    """The mesh lines through which each excitation acts: None for the rotation line
    (:data:`ROTATION`), else the lines whose stiffness (or error) law repeats at the
    excitation's base mesh order (order / harmonic, at the model speed), or every mesh
    line when none can be matched (a constant law, a model at rest)."""
    s = model.nonlinear()
    line_orders = []
    for kk, kp, ek, ep in zip(s.k_kind, s.k_params, s.e_kind, s.e_params, strict=True):
        period = flat_period(int(kk), kp)
        if not math.isfinite(period):
            period = flat_period(int(ek), ep)
        ok = math.isfinite(period) and period > 0 and model.speed > 0
        line_orders.append(TWO_PI / period / model.speed if ok else math.nan)
    out: dict[str, list[int] | None] = {}
    every = list(range(len(line_orders)))
    for name, order in orders.items():
        if name == ROTATION:
            out[name] = None
            continue
        m = re.match(r"(\d+)x ", name)
        base = order / int(m.group(1)) if m else order
        hit = [i for i, o in enumerate(line_orders) if abs(o - base) <= 1e-6 * base]
        out[name] = hit or every
    return out


def mode_shapes(model: Model, speed: float, damped: bool) -> ModeShapes:
    """The modes of ``model`` at ``speed`` (rad/s), numbered as the verdict numbers
    them (:class:`ModeShapes`)."""
    return ModeShapes(model, speed, damped)


def participation(
    model: Model,
    rows: Sequence[dict[str, Any]],
    orders: dict[str, float],
    damped: bool,
) -> None:
    """Add to each crossing or near row (``mode``, ``excitation`` and ``speed_rad_s`` or
    ``speed_rpm``) how much its excitation drives its mode: ``mesh_share`` and
    ``mesh_lines`` (line names) for a mesh order, ``forward_share`` (None without
    lateral motion) for the rotation. The rows are changed in place."""
    lines = excitation_lines(model, orders)
    names = model.nonlinear().line_names
    cache: dict[float, ModeShapes] = {}
    for row in rows:
        w = float(row["speed_rad_s"]) if "speed_rad_s" in row else float(row["speed_rpm"]) / RPM
        if w not in cache:
            cache[w] = mode_shapes(model, w, damped)
        shapes = cache[w]
        acts = lines.get(row["excitation"], list(range(len(names))))
        if acts is None:
            row["forward_share"] = forward_share(shapes, int(row["mode"]))
        else:
            row["mesh_share"] = mesh_share(shapes, int(row["mode"]), acts)
            row["mesh_lines"] = [names[i] for i in acts]
