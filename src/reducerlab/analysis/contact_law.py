"""The mesh force law of a loaded contact: its load exponent at the operating torque
(issue 30).

``contact_analysis`` solves each position's complementarity problem at the operating
torque ``T`` and, on the same contact grid and compliance, at :data:`TANGENT_LOAD`
``T`` (``contact.ltca.loaded_contact(..., torques=...)``: one more solve per position,
warm started; the result at ``T`` is unchanged). From the two elastic approaches
``psi(T)`` and ``psi(0.9 T)`` each position's local load exponent is

``p_i = ln(1 / 0.9) / ln(psi_i(T) / psi_i(0.9 T))``

(1 for a linear mesh, 1.5 for Hertz's point contact; more where tooth pairs join as
the load rises), and the mesh's single exponent the one whose power law
``F = k_t (d / p) (delta / d)^p`` (``model.elements.Mesh``) passes through the mean
operating point with the mean tangent ``k_t = sum p_i k_i / n`` (``k_i`` the secant
stiffness ``T / (arm^2 psi_i)``): ``p = mean(p_i k_i) / mean(k_i)``, held to
``[1, 3]``. The tangent law of the mesh is then ``p`` times the secant law (so the
force at the reference deflection ``d`` is the secant's at every position), ``d`` the
mean static deflection along the line ``T / (arm k_m)``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import xarray as xr

__all__ = ["TANGENT_LOAD", "add_load_exponent", "force_law", "split_loads"]

#: the second load of the exponent, as a fraction of the operating torque
TANGENT_LOAD = 0.9


def split_loads(raw: list) -> tuple[list, list]:
    """The positions' contacts at the operating torque and at :data:`TANGENT_LOAD` of
    it, from ``loaded_contact(..., torques=(T, 0.9 T))``."""
    return [r[0] for r in raw], [r[1] for r in raw]


def local_exponents(runs: list, low: list) -> np.ndarray:
    """``p_i`` of each position from the approaches at the two loads (1 where the
    approach does not grow with the load, e.g. a rigid-teeth estimate at round-off)."""
    a = np.array([r.loaded_te for r in runs])
    b = np.array([r.loaded_te for r in low])
    with np.errstate(divide="ignore", invalid="ignore"):
        p = math.log(1.0 / TANGENT_LOAD) / np.log(a / b)
    return np.where(np.isfinite(p) & (p > 0), p, 1.0)


def add_load_exponent(ds: xr.Dataset, runs: list, low: list, arm: float) -> xr.Dataset:
    """``ds`` with ``load_exponent`` (position) and the attributes ``exponent`` (the
    mesh's ``p``, in ``[1, 3]``) and ``reference_deflection_m`` (``d``)."""
    from ..model.elements import EXPONENT_RANGE

    p_i = local_exponents(runs, low)
    k = np.asarray(ds["stiffness"].values, float)
    lo, hi = EXPONENT_RANGE
    p = float(np.clip(np.mean(p_i * k) / np.mean(k), lo, hi))
    out = ds.assign(load_exponent=("position", p_i))
    k_m = float(ds.attrs["k_mean"])
    out.attrs.update(exponent=p, reference_deflection_m=float(runs[0].torque / (arm * k_m)))
    return out


def force_law(result: Any) -> tuple[float, float, float] | None:
    """``(p, d, scale)`` of a contact result's mesh force law: the exponent, the
    reference deflection (m) and the factor (``p``) that turns the secant stiffness law
    into the tangent one; None for a result without them (made before issue 30)."""
    attrs = result.data.attrs
    if "exponent" not in attrs:
        return None
    p = float(attrs["exponent"])
    return p, float(attrs["reference_deflection_m"]), p
