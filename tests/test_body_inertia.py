"""Mass and moments of inertia of a finite-element body (``body_modal``'s consistency
figures for the ``run`` verdict) against the closed forms of a rectangular block
(any dynamics textbook, e.g. Meriam & Kraige, Appendix D: ``J = m (a^2 + b^2) / 12``
about a centroidal axis for sides ``a, b`` across it)."""

from __future__ import annotations

import numpy as np
import pytest
from skfem import MeshTet

from reducerlab.analysis.body_modal import _rigid_inertia, _translation_mass
from reducerlab.fe import Material, assemble


@pytest.mark.parametrize("shift", [0.0, 0.03])
def test_block_mass_and_inertia(shift):
    a, b, c, rho = 0.04, 0.03, 0.02, 7850.0  # sides along x, y, z (m)
    mesh = MeshTet.init_tensor(
        np.linspace(-a / 2, a / 2, 5), np.linspace(-b / 2, b / 2, 4),
        np.linspace(shift, shift + c, 3),
    )  # fmt: skip
    _, M, basis = assemble(mesh, Material(206e9, 0.3, rho), order=2)
    m = _translation_mass(basis, M)
    assert m == pytest.approx(rho * a * b * c, rel=1e-12)
    J_x, J_y, J_z = _rigid_inertia(basis, M, m)
    # exact: the rigid fields are linear, which quadratic elements represent exactly;
    # the axial offset ``shift`` of the block must not enter (centroidal J_x, J_y)
    assert J_x == pytest.approx(m * (b**2 + c**2) / 12, rel=1e-10)
    assert J_y == pytest.approx(m * (a**2 + c**2) / 12, rel=1e-10)
    assert J_z == pytest.approx(m * (a**2 + b**2) / 12, rel=1e-10)
