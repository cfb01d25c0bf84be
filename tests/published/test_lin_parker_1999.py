"""Lin and Parker, "Analytical characterization of the unique properties of planetary
gear free vibration", J. Vib. Acoust. 121 (1999) 316-321: a planetary gear with N
equally spaced planets (sun, ring and carrier with two translations and a rotation
each; each planet with radial, tangential and rotational coordinates in the carrier
frame) has exactly three kinds of modes:

* rotational modes (6, distinct): the central members only rotate, every planet moves
  the same way;
* translational modes (6 pairs of equal frequency): the central members only
  translate;
* planet modes (3 groups of multiplicity N - 3): only the planets move.

With the carrier rotating, Coriolis and centripetal terms act in its frame (Lin and
Parker's rotating-carrier model; Cooley and Parker, J. Vib. Acoust. 134, 2012): the
gyroscopic terms split each translational pair into a forward and a backward whirl of
the central members.

The planetary is composed here from the core elements (Inertia, Support, Coupling,
Mesh, Coriolis, Centripetal), as a user would write it; the properties hold for any
parameter values, and the values below are of the order of Lin and Parker's example
(Table 1). Tolerances: the properties are exact, the eigen-solver's round-off is
~1e-12 of the largest eigenvalue; 1e-8 relative is asserted.
"""

from __future__ import annotations

import math

import numpy as np

from reducerlab.analysis.complex_modal import complex_modes
from reducerlab.analysis.modal import modal
from reducerlab.model import (
    Centripetal,
    Coriolis,
    Coupling,
    Dof,
    Inertia,
    Mesh,
    Model,
    Support,
)

N = 4  # planets
ALPHA = math.radians(24.6)  # pressure angle of both meshes
MASS = {"s": (0.4, 0.39), "r": (2.35, 3.0), "c": (5.43, 6.29), "p": (0.66, 0.61)}  # kg, I/r^2
K_MESH, K_BEARING, K_TORSION = 5e8, 1e8, 1e9  # N/m


def planetary(carrier_speed: float = 0.0) -> Model:
    central = ["s", "r", "c"]
    planets = [f"p{n}" for n in range(N)]
    # u = r theta at r = 0.1 m; its Inertia is the moment of inertia (I/r^2) r^2
    dofs = [Dof(b, k, radius=0.1 if k == "u" else None) for b in [*central, *planets]
            for k in ("x", "y", "u")]  # fmt: skip
    els = []
    for b in [*central, *planets]:
        m, mu = MASS[b[0]]
        els += [Inertia(f"{b}.x", m), Inertia(f"{b}.y", m), Inertia(f"{b}.u", mu * 0.1**2)]
        if carrier_speed:  # the carrier frame rotates: Coriolis and centripetal terms
            els += [Coriolis((f"{b}.x", f"{b}.y"), m), Centripetal(f"{b}.x", m),
                    Centripetal(f"{b}.y", m)]  # fmt: skip
    for b in central:  # bearings of the central members; the ring held in rotation
        els += [Support(f"{b}.x", K_BEARING), Support(f"{b}.y", K_BEARING)]
    els.append(Support("r.u", K_TORSION))
    for n, p in enumerate(planets):
        psi = 2 * math.pi * n / N
        ps, pr = psi - ALPHA, psi + ALPHA
        els.append(Mesh({"s.x": -math.sin(ps), "s.y": math.cos(ps), "s.u": 1.0,
                         f"{p}.x": -math.sin(ALPHA), f"{p}.y": -math.cos(ALPHA), f"{p}.u": 1.0},
                        K_MESH, name=f"sun-{p}"))  # fmt: skip
        els.append(Mesh({"r.x": -math.sin(pr), "r.y": math.cos(pr), "r.u": 1.0,
                         f"{p}.x": math.sin(ALPHA), f"{p}.y": -math.cos(ALPHA), f"{p}.u": -1.0},
                        K_MESH, name=f"ring-{p}"))  # fmt: skip
        els.append(Coupling({"c.x": math.cos(psi), "c.y": math.sin(psi), f"{p}.x": -1.0},
                            K_BEARING, name=f"bearing-{p}-radial"))  # fmt: skip
        tangential = {"c.x": -math.sin(psi), "c.y": math.cos(psi), "c.u": 1.0, f"{p}.y": -1.0}
        els.append(Coupling(tangential, K_BEARING, name=f"bearing-{p}-tangential"))
    return Model(dofs, els, speed=carrier_speed, name="planetary (Lin and Parker)")


def _parts(model: Model, phi: np.ndarray) -> dict[str, float]:
    idx = model.index
    mag = float(np.max(np.abs(phi)))
    central_t = max(abs(phi[idx[f"{b}.{k}"]]) for b in "src" for k in "xy") / mag
    central_u = max(abs(phi[idx[f"{b}.u"]]) for b in "src") / mag
    planets = np.array([[phi[idx[f"p{n}.{k}"]] for k in "xyu"] for n in range(N)])
    same = float(np.max(np.abs(planets - planets[0]))) / mag
    return {"central_t": central_t, "central_u": central_u, "planets_differ": same}


def _kinds(model: Model, shapes: np.ndarray) -> list[str]:
    """Lin and Parker's kind of every mode (column of ``shapes``), or "other"."""
    kinds = []
    for j in range(model.n):
        p = _parts(model, shapes[:, j])
        if p["central_t"] < 1e-8 and p["central_u"] < 1e-8:
            kinds.append("planet")
        elif p["central_t"] < 1e-8 and p["planets_differ"] < 1e-8:
            kinds.append("rotational")
        elif p["central_u"] < 1e-8:
            kinds.append("translational")
        else:
            kinds.append("other")
    return kinds


def test_three_mode_types_of_the_stationary_carrier():
    model = planetary()
    res = modal(model)
    f = res.frequencies
    phi = res.data["shape"].values
    kinds = _kinds(model, phi)
    assert kinds.count("other") == 0
    assert kinds.count("rotational") == 6  # one of them the rigid rotation (0 Hz)
    assert kinds.count("translational") == 12
    assert kinds.count("planet") == 3 * (N - 3)
    # translational modes come in pairs of equal frequency, rotational ones are single
    ft = np.sort(f[np.array(kinds) == "translational"])
    np.testing.assert_allclose(ft[0::2], ft[1::2], rtol=1e-8)
    fr = np.sort(f[np.array(kinds) == "rotational"])
    assert np.all(np.diff(fr) > 1e-6 * fr[-1])


def test_carrier_rotation_splits_translational_pairs_into_whirls():
    still = modal(planetary())
    turning = complex_modes(planetary(carrier_speed=300.0))
    # the pairs of equal frequency split (Coriolis), each branch whirling forward or
    # backward; 300 rad/s against modes of ~1-10 kHz: splits of a few Hz
    res = turning.data
    moving = res["whirl"].values[res["frequency"].values > 0]
    assert {"forward", "backward"} <= set(moving.tolist())
    f0 = np.sort(still.frequencies[still.frequencies > 0])
    pairs = np.flatnonzero(np.isclose(f0[1:], f0[:-1], rtol=1e-8))
    assert pairs.size >= 6
    f1 = np.sort(turning.frequencies[turning.frequencies > 0])
    # no pair is left degenerate
    assert not np.any(np.isclose(f1[1:], f1[:-1], rtol=1e-9))
    assert np.all(res["stable"].values)


def test_mode_types_survive_the_rotating_carrier():
    # Cooley and Parker (2012): with gyroscopic terms the modes keep their three kinds
    # (cyclic symmetry of the planets); the complex shapes show it
    model = planetary(carrier_speed=300.0)
    res = complex_modes(model).data
    shapes = res["shape_real"].values + 1j * res["shape_imag"].values
    kinds = _kinds(model, shapes)
    assert (kinds.count("rotational"), kinds.count("translational"),
            kinds.count("planet"), kinds.count("other")) == (6, 12, 3 * (N - 3), 0)  # fmt: skip
    # in the translational ones the central members whirl: their dominant (x, y) orbit
    # is a circle (|Im(conj(u) v)| = |u| |v|, by the planets' cyclic symmetry), half
    # of them turning each way
    senses = []
    for j in np.flatnonzero(np.array(kinds) == "translational"):
        b = max("src", key=lambda b: abs(shapes[model.index[f"{b}.x"], j]))
        u, v = shapes[model.index[f"{b}.x"], j], shapes[model.index[f"{b}.y"], j]
        sense = -np.imag(np.conj(u) * v) / (abs(u) * abs(v))
        assert abs(abs(sense) - 1.0) < 1e-6
        senses.append(np.sign(sense))
    assert senses.count(1.0) == senses.count(-1.0) == 6
