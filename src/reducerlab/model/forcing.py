"""Forms of the transmission-error excitation of a mesh (issue 16).

A static transmission error ``e(t)`` can enter a gear model in two ways found in the
literature:

* ``"stiffness"`` (paper 004 Eq. 2, paper 000 Eq. 2-3, the default of every builder):
  inside the mesh deflection, ``F = k(t) f(g^T q - e(t)) + c (g^T q' - e'(t))``; its
  force grows with the mesh stiffness, not with the speed.
* ``"omega2"`` and ``"j-omega2"``: as an inertial excitation of the mesh line. Writing
  the deflection ``x = g^T q - e`` as the coordinate (``q = q' + w e`` with
  ``w = m_e M^-1 g``, ``g^T w = 1``, ``m_e = 1 / (g^T M^-1 g)`` the line's equivalent
  mass) moves ``e`` out of the mesh and into the load ``-m_e g e''(t)``; for a harmonic
  error ``e = sum a_r cos(r W t + phi_r)`` that is ``m_e g sum (r W)^2 a_r cos(...)``:
  an amplitude growing with the square of the speed (the common
  ``m_e Omega^2 e`` forcing of single-DOF gear-rattle models). ``"j-omega2"`` is the
  same load written with the complex amplitude ``m_e (j Omega)^2 E = -m_e Omega^2 E``
  (the sign of ``e''`` rather than of ``-e''``): the load of ``"omega2"`` negated, a
  phase shift of half a period. The substitution is exact for a single line whose
  DOFs no other element couples; in a drive with shafts it is a different model (the
  shafts then do not feel the error), which is why it is a choice, not a default.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from ..errors import ModelError
from .assembly import Model
from .elements import Load, Mesh
from .laws import Constant, Fourier

__all__ = ["ERROR_FORCING", "inertial_error"]

#: The forms of the transmission-error excitation (see the module docstring).
ERROR_FORCING = ("stiffness", "omega2", "j-omega2")


def inertial_error(
    model: Model, form: str = "omega2", meshes: Sequence[str] | None = None
) -> Model:
    """The model with the transmission error of ``meshes`` (default: every mesh with a
    varying error) applied as the inertial load ``-m_e g e''(t)`` (``"omega2"``) or
    ``+m_e g e''(t)`` (``"j-omega2"``) instead of inside the mesh deflection.

    Parameters
    ----------
    model : Model
    form : {"stiffness", "omega2", "j-omega2"}
        ``"stiffness"`` returns ``model`` unchanged.
    meshes : sequence of str, optional
        Names of the Mesh elements to convert.

    Returns
    -------
    Model
        Each converted mesh keeps the mean of its error (a static offset, which has no
        acceleration) and gains one :class:`~reducerlab.model.Load` per DOF of its line,
        ``g_i m_e sum (r W)^2 a_r cos(r W t + phi_r)`` (N), whose frequency follows the
        model speed and whose amplitude follows its square (``Fourier.speed_power``).

    Raises
    ------
    ModelError
        For an unknown form or mesh name, or an error law that is not a Fourier series
        (the acceleration of a piecewise law has impulses).
    """
    if form not in ERROR_FORCING:
        raise ModelError(f"error forcing must be one of {', '.join(ERROR_FORCING)}, got {form!r}")
    if form == "stiffness":
        return model
    names = {e.name for e in model.elements if isinstance(e, Mesh)}
    if meshes is not None:
        unknown = [m for m in meshes if m not in names]
        if unknown:
            raise ModelError(f"inertial_error: no mesh named {unknown}; meshes are {sorted(names)}")
        names = set(meshes)
    Minv = np.linalg.inv(model.matrices().M)
    sign = 1.0 if form == "omega2" else -1.0
    elements = []
    loads = []
    for e in model.elements:
        law = e.error if isinstance(e, Mesh) and e.name in names else None
        if law is None or isinstance(law, Constant):
            elements.append(e)
            continue
        if not isinstance(law, Fourier):
            raise ModelError(
                f"{e.name}: the {form} form of the transmission error needs a Fourier error "
                f"law (its acceleration), got {type(law).__name__}"
            )
        g = np.zeros(model.n)
        g[[model.index[d] for d in e.dofs]] = e.g
        m_e = 1.0 / float(g @ Minv @ g)
        r = np.arange(1, len(law.amplitudes) + 1)
        accel = sign * m_e * (r * law.omega) ** 2 * np.asarray(law.amplitudes)
        for dof, coef in e.coefficients.items():
            loads.append(
                Load(
                    dof,
                    Fourier(0.0, tuple((coef * accel).tolist()), law.omega, law.phases,
                            ref_speed=law.ref_speed, speed_power=2 if law.ref_speed else 0),
                    name=f"{e.name}:error_{form}:{dof}",
                )
            )  # fmt: skip
        elements.append(dataclasses.replace(e, error=Constant(law.mean)))
    return Model(
        model.dofs, [*elements, *loads], speed=model.speed, name=model.name,
        metadata=model.metadata,
    )  # fmt: skip
