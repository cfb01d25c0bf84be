"""Coulomb friction at the mesh contacts of the quasi-static torsion test.

A bench twists a reducer slowly with its input held: every loaded tooth contact is
compressed along its normal and, because each gear turns about its own axis while its
mate is held or turns less, its flanks also slide over each other. Coulomb friction
resists that sliding, so the torque needed to wind the drive up is larger than the
torque it gives back on unloading: the hysteresis loop opens and its area is the work
friction dissipates per cycle.

Each mesh line carries a Jenkins element at its mean contact point (Iwan's model of
micro-slip; a tangential spring in series with a Coulomb slider):

* sliding displacement ``s = S q`` (``S``: the line's ``Mesh.sliding`` coefficients, m
  per unit DOF; the builder derives them at the pitch point: a rotation of a gear moves
  its flank point by ``R phi`` along the pitch circle's tangent, ``r_b phi`` of it
  along the normal, ``r_b tan(alpha) phi`` along the flanks);
* tangential force ``tau = k_t (s - p)`` while ``|tau| <= mu F`` (stick), else
  ``tau = mu F sgn(tau)`` and the slip ``p`` moves (slip; ``F``: the line's normal
  force, ``mu``: the Coulomb coefficient);
* ``k_t = kappa k`` with Mindlin's ratio of the tangential to the normal stiffness of
  an elastic contact, ``kappa = 2 (1 - nu) / (2 - nu)`` (R. D. Mindlin, J. Appl. Mech.
  16, 1949; K. L. Johnson, *Contact Mechanics*, 1985, Sec. 7.2), ``k`` the line's
  stiffness (its tangent at the reference deflection for a power law).

The equilibrium of the free DOFs becomes ``K q + G^T F + S^T tau = b T``; each torque
step is one backward-Euler step of the slip (a return mapping from the previous step's
slip), solved by the test's Newton iteration with the consistent tangent (stick:
``k_t S^T S``; slip: ``mu sgn(tau) F' S^T G``). Within a branch the motion is monotone,
so the return mapping is exact for the states it reaches. The work friction dissipates,
``sum |tau| |dp|`` (trapezoidal in the force over each step), is reported beside the
loop's area (energy balance: the two agree to the discretisation of the steps).

Not modelled: friction in bearings, seals and couplings; the rolling balls of the
cycloid-ball drive (a ball rolls, it does not slide: its lines carry no ``sliding``);
the sliding caused by the tilt of a nutating gear.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..model.elements import Mesh

__all__ = ["FrictionBench", "friction_bench", "mindlin_ratio", "sliding_matrix"]

Array = NDArray[np.float64]


def mindlin_ratio(poisson: float) -> float:
    """Mindlin's ratio ``k_t / k_n = 2 (1 - nu) / (2 - nu)`` of the initial tangential to
    the normal stiffness of an elastic contact of two bodies of the same material
    (Johnson 1985, Eqs. 7.39 and 3.41): 0.824 for ``nu = 0.3``."""
    return 2.0 * (1.0 - poisson) / (2.0 - poisson)


def sliding_matrix(model: Any, line_names: list[str] | tuple[str, ...]) -> Array:
    """The lines' sliding rows ``S`` (lines x model DOFs) from the ``sliding`` of each
    :class:`~reducerlab.model.elements.Mesh` (zero rows for lines without one)."""
    names = list(model.dof_names)
    index = {n: i for i, n in enumerate(names)}
    S = np.zeros((len(line_names), len(names)))
    row = {name: i for i, name in enumerate(line_names)}
    for e in model.elements:
        if isinstance(e, Mesh) and e.sliding is not None and e.name in row:
            for dof, value in e.sliding.items():
                S[row[e.name], index[dof]] = value
    return S


@dataclass
class FrictionBench:
    """A torsion-test bench (``analysis.torsion_test``'s ``_Bench``) with a Jenkins
    element on each line that slides: the same interface (``residual``, ``jacobian``,
    ``forces`` and the arrays), plus the slip state that :meth:`commit` advances."""

    base: Any
    S: Array  # (lines, free DOFs) sliding coefficients
    mu: float
    kt: Array  # (lines,) tangential stiffness (N/m)
    slip: Array = field(init=False)
    tau: Array = field(init=False)
    work: float = field(init=False, default=0.0)

    def __post_init__(self) -> None:
        self.slip = np.zeros(self.S.shape[0])
        self.tau = np.zeros(self.S.shape[0])

    friction = True

    @property
    def frictionless(self) -> Any:
        return self.base

    def __getattr__(self, name: str) -> Any:  # K, G, k, e, h, p, d, b, c, ...
        if name in ("base", "S", "mu", "kt", "slip", "tau", "work"):
            raise AttributeError(name)
        return getattr(self.base, name)

    def forces(self, q: Array) -> tuple[Array, Array, Array]:
        return self.base.forces(q)

    def tangential(self, q: Array) -> tuple[Array, Array, Array]:
        """``tau`` (N), the stick mask and ``dtau/dq`` (lines x DOFs) at ``q`` from the
        committed slip (return mapping)."""
        F, slope, _ = self.base.forces(q)
        limit = self.mu * np.maximum(F * np.sign(F), 0.0)  # mu |F|
        trial = self.kt * (self.S @ q - self.slip)
        stick = np.abs(trial) <= limit
        sgn = np.sign(trial)
        tau = np.where(stick, trial, sgn * limit)
        dF = (slope * np.sign(F))[:, None] * self.base.G  # d|F|/dq
        dtau = np.where(stick[:, None], self.kt[:, None] * self.S, self.mu * sgn[:, None] * dF)
        return tau, stick, dtau

    def residual(self, q: Array, T: float) -> Array:
        return self.base.residual(q, T) + self.S.T @ self.tangential(q)[0]

    def jacobian(self, q: Array, floor: float = 0.0) -> Array:
        return self.base.jacobian(q, floor) + self.S.T @ self.tangential(q)[2]

    def start(self, q: Array) -> None:
        """A branch starts at rest at ``q`` with no tangential force (zero normal force:
        the slider has let go)."""
        self.slip = self.S @ q
        self.tau = np.zeros_like(self.slip)

    def commit(self, q: Array) -> None:
        """Accept the solved state ``q``: advance the slip and add the dissipated work
        ``sum 0.5 (|tau_old| + |tau_new|) |dp|`` (J)."""
        tau = self.tangential(q)[0]
        new = self.S @ q - tau / np.where(self.kt > 0, self.kt, 1.0)
        dp = np.abs(new - self.slip)
        self.work += float(np.sum(0.5 * (np.abs(self.tau) + np.abs(tau)) * dp))
        self.slip, self.tau = new, tau


def friction_bench(base: Any, S: Array, mu: float, kappa: float) -> FrictionBench | None:
    """``base`` with friction on its sliding lines, or None when nothing slides
    (``mu = 0`` or no line has sliding coefficients)."""
    if mu == 0.0 or not np.any(S):
        return None
    k_ref = np.asarray(base.k, float)
    return FrictionBench(base=base, S=S, mu=float(mu), kt=kappa * k_ref)
