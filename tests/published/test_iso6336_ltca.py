"""Loaded tooth contact analysis of a spur gear pair against ISO 6336-1:2019 clause 9
(method B): single stiffness c' and mesh stiffness c_gamma_alpha.

Oracle: the standard's tooth stiffness parameters (reducerlab.contact.iso6336), which are
a regression ``c'_th = 1/q'`` of Weber/Schmidt-type theoretical calculations of solid
steel disc gears (tooth bending, shear, rim/foundation and Hertzian flattening of an
elastic tooth pair of exact involute geometry), times
``C_M C_R C_B``: ``C_B`` (0.975 for the ISO 53 rack, h_fP = 1.25 m) corrects ``q'``'s
reference rack (h_fP = 1.2 m) to the real tooth depth, a geometric part of the theory;
``C_R = 1`` for solid gears; ``C_M = 0.8`` corrects for the difference between the
theoretical values of solid disc gears and measured ones (ISO 6336-1 as described in
reducerlab.contact.iso6336; measured gear pairs carry profile deviations, running-in
and the compliance of hubs, shafts and test rigs, none of which is in an elastic model
of nominal gears).

What the LTCA should match: it is a linear-elastic model of exact nominal geometry
(finite-element teeth on a rim held at its bore, Boussinesq half-space contact), i.e. a
*theoretical* calculation of the same kind as Weber/Schmidt's. So the asserted oracle is
``c'_th C_B`` (``C_M = 1``; ``single_pair_stiffness(..., correction=1.0)``) and
``c_gamma_alpha`` built on it; the ISO values with ``C_M = 0.8`` are the measured level,
which a theoretical model must exceed (by about 1/0.8 = 1.25). Measured (z 30/30,
m 3 mm, b 15 mm, 300 N/mm, rim 10 m held at its bore, FE tooth elements 0.3 m, 6 x 9
load points, contact cell 0.1 mm, 16 positions over one base pitch):

====================  ==========  =================  ===============
quantity              LTCA        ISO, C_M = 1       ISO, C_M = 0.8
====================  ==========  =================  ===============
c' (pitch point)      16.22       15.98 (+1.5 %)     12.78 (+26.9 %)
c_gamma_alpha (mean)  23.42       23.81 (-1.7 %)     19.05 (+22.9 %)
====================  ==========  =================  ===============

in N/(mm um) (the gmsh mesh varies a little from run to run: +-0.1 %). Tolerance: ISO
6336-1 presents method B as an approximation (a regression of the theory, valid from
100 N/mm, with an empirical C_M); an error band of its own could not be checked (the
text was not available); its q' fit and the 0.75 eps + 0.25 rule for c_gamma_alpha are
commonly read as good to +-15..20 %. The model differs from Weber's plane theory in
known ways (3-D face with free ends: softer; a clamped bore: stiffer, see RIM; contact
beyond the path of contact under load: a stiffer mean), so +-15 % is asserted, the tight
end of that reading. Nothing in the LTCA was adjusted to these numbers.

Discretisation (measured): halving the contact cell (0.1 -> 0.05 mm) changes the
pitch-point stiffness by -0.7 % (asserted < 2 %); 4 x 6 or 8 x 12 load points instead of
6 x 9 change c' and the mean by < 0.2 %; FE tooth elements 0.2 m instead of 0.3 m (and
so load points nearer the root and tip, less extrapolation) change c' by -0.7 % and the
mean by -1.6 % (not in the test: 100 s of FE). Load dependence (Hertz and the loaded
extension of the path, rim 3.5 m): at 600 N/mm c' rises by 2.8 %, the mean by about 4 %.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.contact.flanks import separations
from reducerlab.contact.halfspace import combined_modulus
from reducerlab.contact.iso6336 import (
    ISO_STIFFNESS_TO_SI,
    mesh_stiffness_c_gamma,
    single_pair_stiffness,
)
from reducerlab.contact.ltca import ContactGrid, loaded_contact
from reducerlab.contact.spur_pair import SpurFlank, SpurMeshPair, spur_tooth_compliance
from reducerlab.errors import ReducerlabError
from reducerlab.fe.elasticity import STEEL
from reducerlab.geometry.spur import SpurGear, SpurPair

M, B, Z = 3e-3, 15e-3, 30
GEAR = SpurGear(Z, M, B)  # ISO 53 rack, x = 0, alpha = 20 deg
PAIR = SpurPair(GEAR, GEAR)
MP = SpurMeshPair(PAIR)
#: specific load F_t / b (N/m): 300 N/mm, inside method B's range (>= 100 N/mm)
W = 300e3
CELL = 0.1e-3  # contact cell: ~3 cells across the Hertz width 2 b_H = 0.33 mm
POSITIONS = 16  # over one base pitch, the pitch point of tooth pair 0 in the middle
TOL = 0.15
#: rim below the root circle, held at its bore: 10 m leaves a bore of 22.5 mm (a solid
#: disc gear on its shaft). The default 3.5 m (ISO's least rim of a solid gear) clamped
#: at its bore is stiffer than a disc: c' 16.84 (3.5 m), 16.30 (6 m), 16.22 (10 m)
RIM = 10 * M


@pytest.fixture(scope="module")
def compliance():
    # one FE model (z1 = z2): the wheel's blocks are the pinion's with the teeth reversed
    return MP.tooth_compliances(material=STEEL, rim=RIM)


def _run(compliance, phis, cell, s_max=1e-6):
    ca, cb = compliance
    torque = W * B * PAIR.working_pitch_radii[0]  # T_1 = F_t r_w1
    E_star = combined_modulus(STEEL.E, STEEL.nu, STEEL.E, STEEL.nu)
    return loaded_contact(MP, torque, phis, ContactGrid(cell, s_max=s_max), compliance_a=ca,
                          compliance_b=cb, E_star=E_star)  # fmt: skip


def _stiffness(run):
    """Mesh stiffness per face width (N/(mm um)): normal force along the line of action
    per unit approach along it, k = T_B / (r_b2^2 psi)."""
    k = run.torque / (PAIR.wheel.base_radius**2 * run.loaded_te)
    return k / B / ISO_STIFFNESS_TO_SI


@pytest.fixture(scope="module")
def cycle(compliance):
    phis = MP.pitch_point_position() + GEAR.pitch * (np.arange(POSITIONS) / POSITIONS - 0.5)
    return _run(compliance, phis, CELL)


def test_adapter_follows_the_spur_conventions():
    f = SpurFlank(GEAR, 1)
    u, v = np.array([0.0, 0.3, 1.0]), np.array([0.0, 0.5, 1.0])
    P, N = f.evaluate(u, v)
    P0, N0 = GEAR.flank_points(u, v, 1)
    np.testing.assert_allclose(P, P0, atol=1e-15)
    np.testing.assert_allclose(N, N0, atol=1e-15)
    assert f.inside(P).all()
    off = P.copy()
    off[:, 2] = 0.51 * B  # beyond the face
    assert not f.inside(off).any() and not f.inside(P[2:] * 1.01).any()  # beyond the tip
    assert MP.torque_ratio == 1.0
    assert MP.tooth_angles(1) == pytest.approx((GEAR.pitch, -GEAR.pitch))
    # at the pitch-point position tooth pair 0 touches there: zero separation, and a
    # rotation of the wheel closes gaps with the lever r_b2 (involute: a constant)
    phi = MP.pitch_point_position()
    assert PAIR.contact_roll(phi) == pytest.approx(GEAR.base_radius * math.tan(math.radians(20)))
    xi = GEAR.base_radius * math.tan(math.radians(20))
    u0 = (xi - GEAR.form_roll) / (GEAR.tip_roll - GEAR.form_roll)
    s = separations(MP, phi, 0, [u0], [0.5])
    assert abs(s.distance[0]) < 1e-10
    assert s.lever[0] == pytest.approx(GEAR.base_radius, rel=1e-6)
    with pytest.raises(ReducerlabError, match="flank"):
        SpurFlank(GEAR, 2)
    with pytest.raises(ReducerlabError, match="direction"):
        spur_tooth_compliance(GEAR, 1, direction=0)
    with pytest.raises(ReducerlabError, match="grid"):
        spur_tooth_compliance(GEAR, 1, grid=(1, 5))


def test_single_pair_stiffness_against_iso_c_prime(cycle):
    run = cycle[POSITIONS // 2]  # tooth pair 0 at the pitch point
    assert set(np.unique(run.tooth[run.force > 0])) == {0}  # single-pair contact
    # equilibrium: the normal forces carry T_B on the lever r_b2 (to 1e-4: the cells
    # across the Hertz band lie a little off the line of action, their levers differ)
    assert run.force.sum() * PAIR.wheel.base_radius == pytest.approx(run.torque, rel=1e-3)
    k = _stiffness(run)
    # flat top of the single-pair curve (c' is the single pair's maximum, at about C)
    for j in (POSITIONS // 2 - 1, POSITIONS // 2 + 1):
        assert set(np.unique(cycle[j].tooth[cycle[j].force > 0])) == {0}
        assert _stiffness(cycle[j]) == pytest.approx(k, rel=0.01)
    c_th = single_pair_stiffness(GEAR, GEAR, correction=1.0, specific_load=W)  # C_M = 1
    c_iso = single_pair_stiffness(GEAR, GEAR, specific_load=W)  # C_M = 0.8
    assert c_th == pytest.approx(15.98, abs=0.01)
    assert k == pytest.approx(c_th, rel=TOL)  # measured +1.5 %
    assert k > c_iso  # the measured level lies below the theory (C_M < 1); measured +27 %


def test_mean_mesh_stiffness_against_iso_c_gamma_alpha(cycle):
    k = np.array([_stiffness(r) for r in cycle])
    teeth = [len(np.unique(r.tooth[r.force > 0])) for r in cycle]
    assert set(teeth) == {1, 2}  # single and double contact within the cycle
    assert k.max() > 1.5 * k.min()  # two pairs against one
    c_th = mesh_stiffness_c_gamma(GEAR, GEAR, correction=1.0, specific_load=W)
    c_iso = mesh_stiffness_c_gamma(GEAR, GEAR, specific_load=W)
    assert c_th == pytest.approx(23.81, abs=0.01)
    assert k.mean() == pytest.approx(c_th, rel=TOL)  # measured -1.7 %
    assert k.mean() > c_iso  # measured +22.9 %


def test_stiffness_converges_with_the_contact_cell(compliance, cycle):
    run = cycle[POSITIONS // 2]
    coarse = _stiffness(run)
    # the coarse grid's admitted separation as the first guess saves the doubling of
    # s_max (the completeness check makes the result independent of it)
    fine = _stiffness(_run(compliance, [run.phi], 0.5 * CELL, s_max=run.s_max)[0])
    assert abs(fine / coarse - 1) < 0.02  # measured -0.7 %
