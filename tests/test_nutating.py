"""Nutating body in steady precession and stationary damping in rotating coordinates
(issue 17: the elements that put paper 000's nutating gear and paper 003's rotating
frame into complex modes).

Oracles, all independent of the element's closed form:
- a direct time integration of Euler's rigid-body equations in the fixed frame
  (quaternions, scipy's DOP853) for a body on tilt springs carried by a nutating crank:
  its tilt oscillation frequencies, measured in the crank frame, against the element's
  eigenfrequencies;
- Euler's equations for the steady precession (``kinematics.gyroscopic_moment``, paper
  002): the moment that holds it;
- at zero nutation, the spinning disc (Friswell et al., *Dynamics of Rotating
  Machines*, 2010, Sec. 3.4) seen from a frame turning at Omega_p: ``omega -/+ Omega_p``;
- a damper fixed in the housing seen from a rotating frame: the fixed-frame model's
  eigenvalues (Friswell et al., Sec. 5.6).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from reducerlab.analysis.complex_modal import complex_modes
from reducerlab.errors import ModelError
from reducerlab.kinematics import gyroscopic_moment
from reducerlab.model import (
    Centripetal,
    Coriolis,
    Dof,
    Gyroscopic,
    Inertia,
    Model,
    Nutating,
    StationaryDamping,
    Support,
)

# a disc-like body (J_p < 2 J_d) on a steep crank, spinning against the precession as
# the nutating gear of paper 000 does: every coefficient of the element is far from 0
JD, JP, KT = 1.0, 1.6, 100.0  # kg m^2, kg m^2, N m/rad
OMEGA, SPIN, THETA = 3.0, -2.0, 0.35  # rad/s (crank), psi' / Omega, rad


def _tilt_model(theta: float = THETA, spin: float = SPIN, speed: float = OMEGA) -> Model:
    dofs = [Dof("b", k) for k in ("rx", "ry", "rz")]
    elements = [
        Inertia("b.rx", JD),
        Inertia("b.ry", JD),
        Inertia("b.rz", JP),
        Support("b.rx", KT),
        Support("b.ry", KT),
        Nutating(("b.rx", "b.ry", "b.rz"), JP, JD, theta, spin),
    ]
    return Model(dofs, elements, speed=speed)


def _elastic(model: Model) -> np.ndarray:
    r = complex_modes(model)
    return np.sort(r.frequencies[r.data.whirl.values != "rigid"])


def _Ry(a: float) -> np.ndarray:
    return Rotation.from_rotvec([0.0, a, 0.0]).as_matrix()


def _simulate(a0: float, periods: float = 30.0, samples: int = 2**14):
    """Euler's equations in body axes for the body of :func:`_tilt_model`, its tilts
    held by springs about the crank ``C(t) = R_z(Omega t) R_y(theta)`` and the steady
    moment; returns the crank-frame tilts ``(a, b)`` sampled uniformly."""
    J = np.array([JD, JD, JP])
    steady = Nutating(("b.rx", "b.ry", "b.rz"), JP, JD, THETA, SPIN).steady_moment(OMEGA)

    def crank(t: float) -> np.ndarray:
        return Rotation.from_rotvec([0.0, 0.0, OMEGA * t]).as_matrix() @ _Ry(THETA)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, w = y[:4], y[4:]
        R = Rotation.from_quat(q).as_matrix()
        C = crank(t)
        D = C.T @ R  # body in the crank frame: R_x(a) R_y(b) R_z(psi)
        d = D[:, 2]
        b = math.asin(d[0])
        a = math.atan2(-d[1], d[2])
        ex = np.array([1.0, 0.0, 0.0])
        ey = Rotation.from_rotvec([a, 0.0, 0.0]).as_matrix()[:, 1]
        # generalised forces Q_a = -k a, Q_b = steady - k b, Q_psi = 0 through the
        # partial angular velocities (e_x, e_y', d) of the three angles
        m_crank = np.linalg.solve(np.array([ex, ey, d]), [-KT * a, steady - KT * b, 0.0])
        m_body = R.T @ (C @ m_crank)
        dw = (m_body - np.cross(w, J * w)) / J
        wq = np.concatenate([0.5 * w, [0.0]])  # q' = 1/2 q (x) (w, 0), scalar last
        x, y_, z, s = q
        Q = np.array([[s, -z, y_, x], [z, s, -x, y_], [-y_, x, s, z], [-x, -y_, -z, s]])
        return np.concatenate([Q @ wq, dw])

    R0 = crank(0.0) @ Rotation.from_rotvec([a0, 0.0, 0.0]).as_matrix()
    w0 = R0.T @ np.array([0.0, 0.0, OMEGA]) + np.array([0.0, 0.0, SPIN * OMEGA])
    t_end = periods * 2 * math.pi / math.sqrt(KT / JD)
    t = np.linspace(0.0, t_end, samples)
    sol = solve_ivp(rhs, (0.0, t_end), np.concatenate([Rotation.from_matrix(R0).as_quat(), w0]),
                    method="DOP853", rtol=1e-11, atol=1e-13, t_eval=t)  # fmt: skip
    assert sol.success
    tilts = np.empty((2, t.size))
    for k in range(t.size):
        R = Rotation.from_quat(sol.y[:4, k]).as_matrix()
        d = (crank(t[k]).T @ R)[:, 2]
        tilts[:, k] = math.atan2(-d[1], d[2]), math.asin(d[0])
    return t, tilts


def _peaks(t: np.ndarray, x: np.ndarray, count: int) -> list[float]:
    """The ``count`` strongest frequencies (Hz) of ``x``, each refined by a quadratic
    fit through the log-magnitude of a Hann-windowed, 16x zero-padded spectrum."""
    n = 16 * t.size
    X = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(t.size), n))
    f = np.fft.rfftfreq(n, t[1] - t[0])
    is_peak = (X[1:-1] > X[:-2]) & (X[1:-1] > X[2:])
    idx = np.flatnonzero(is_peak) + 1
    idx = idx[np.argsort(X[idx])[::-1][:count]]
    out = []
    for i in idx:
        y0, y1, y2 = np.log(X[i - 1 : i + 2])
        out.append(f[i] + 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2) * (f[1] - f[0]))
    return sorted(out)


def test_steady_precession_moment_is_eulers():
    """The moment that holds the steady precession is that of Euler's equations for the
    Euler-angle motion (paper 002's kinematics, paper 000's L_1)."""
    e = Nutating(("b.rx", "b.ry", "b.rz"), JP, JD, THETA, SPIN)
    M = gyroscopic_moment((JD, JD, JP), 0.0, THETA, 0.0, OMEGA, 0.0, SPIN * OMEGA)
    # tight: both are closed forms of the same motion, round-off apart
    assert abs(e.steady_moment(OMEGA)) == pytest.approx(float(np.linalg.norm(M)), rel=1e-12)


def test_tilt_frequencies_match_a_rigid_body_simulation():
    """Linearised crank-frame tilts vs the nonlinear rigid body integrated in the fixed
    frame. Tolerance 2e-5: the spectral peak estimate of a 30-period record (Hann
    window, 16x zero padding, quadratic refinement of the log-magnitude) lands within
    1.4e-6 of the frequency here; the 1e-4 rad amplitude makes nonlinear shifts ~1e-8.
    A slip in any coefficient of the element (each is ~10-50 % of the spring's
    stiffness or of J_d omega) moves a frequency by far more."""
    expected = _elastic(_tilt_model())
    assert expected.size == 2 and expected[1] - expected[0] > 0.1  # a clear split
    t, (a, b) = _simulate(1e-4)
    assert np.max(np.abs(b)) < 1e-3  # the steady moment holds the precession
    measured = _peaks(t, a, 2)
    np.testing.assert_allclose(measured, expected, rtol=2e-5)


def test_zero_nutation_is_the_spinning_disc_seen_from_the_crank():
    """theta = 0: the fixed-frame disc frequencies (Gyroscopic at the absolute spin)
    shifted by the crank speed, forward down and backward up (exact to round-off)."""
    absolute = SPIN + 1.0  # psi' + Omega_p cos(0), per unit model speed
    fixed = Model(
        [Dof("b", "rx"), Dof("b", "ry")],
        [Inertia("b.rx", JD), Inertia("b.ry", JD), Support("b.rx", KT), Support("b.ry", KT),
         Gyroscopic(("b.rx", "b.ry"), JP, absolute)],
        speed=OMEGA,
    )  # fmt: skip
    f_fixed = _elastic(fixed)
    f_crank = _elastic(_tilt_model(theta=0.0))
    # the spin is negative (SPIN < -1): the backward (lower) branch whirls
    # counterclockwise and the crank, turning counterclockwise, sees it slower by
    # Omega_p; the forward branch whirls clockwise and is seen faster
    shift = OMEGA / (2 * math.pi)
    expected = np.sort(np.abs([f_fixed[0] - shift, f_fixed[1] + shift]))
    np.testing.assert_allclose(f_crank, expected, rtol=1e-10)


def test_nutating_at_rest_and_parameter_derivatives():
    """At zero speed the element adds nothing; its parameters have exact derivatives."""
    m = _tilt_model(speed=0.0)
    mats = m.matrices()
    assert not np.any(mats.C) and np.allclose(mats.K, np.diag([KT, KT, 0.0]))
    m = _tilt_model()
    d = m.derivative("nutating:b.nutation")
    h = 1e-6
    fd = _tilt_model(theta=THETA + h).matrices().K - _tilt_model(theta=THETA - h).matrices().K
    np.testing.assert_allclose(d.K, fd / (2 * h), rtol=1e-6, atol=1e-9)


def test_nutating_rejects_wrong_dofs_and_values():
    with pytest.raises(ModelError, match=r"\(rx, ry, rz\)"):
        wrong = Nutating(("b.x", "b.y", "b.rz"), 1.0, 1.0, 0.1, 1.0)
        dofs = [Dof("b", k) for k in ("x", "y", "rz")]
        Model(dofs, [Inertia(d.name, 1.0) for d in dofs] + [wrong], speed=1.0).matrices()
    with pytest.raises(ModelError, match="polar"):
        Nutating(("b.rx", "b.ry", "b.rz"), -1.0, 1.0, 0.1, 1.0)
    with pytest.raises(ModelError, match="nutation"):
        Nutating(("b.rx", "b.ry", "b.rz"), 1.0, 1.0, float("nan"), 1.0)


def test_stationary_damping_in_a_rotating_frame_matches_the_fixed_frame():
    """A mass on an isotropic spring and a housing-fixed damper: in the fixed frame
    ``lambda`` solves ``m l^2 + c l + k = 0``; seen from a frame turning at Omega the
    eigenvalues are ``lambda -/+ i Omega`` (same decay rates). Without the circulatory
    term the rotating-frame model would give other decay rates."""
    m, k, c, W = 2.0, 5e4, 30.0, 40.0
    lam = np.roots([m, c, k])

    def rotating(circulatory: bool) -> Model:
        el = [Inertia("p.x", m), Inertia("p.y", m), Support("p.x", k, c), Support("p.y", k, c)]
        el += [Coriolis(("p.x", "p.y"), m), Centripetal("p.x", m), Centripetal("p.y", m)]
        if circulatory:
            el.append(StationaryDamping(("p.x", "p.y"), c))
        return Model([Dof("p", "x"), Dof("p", "y")], el, speed=W)

    r = complex_modes(rotating(True))
    wd, sigma = abs(lam[0].imag), lam[0].real
    # exact to round-off: one state-space eigenproblem against a quadratic's roots
    np.testing.assert_allclose(np.sort(2 * math.pi * r.frequencies), [abs(wd - W), wd + W],
                               rtol=1e-9)  # fmt: skip
    np.testing.assert_allclose(r.data.growth_rate.values, [sigma, sigma], rtol=1e-9)
    wrong = complex_modes(rotating(False)).data.growth_rate.values
    assert not np.allclose(wrong, [sigma, sigma], rtol=1e-3)


def test_lumped_design_declares_nutating_and_stationary_damping(tmp_path):
    """A design file writes the same elements; their DOFs are checked by the schema."""
    from reducerlab.drives import build_model, load_design
    from reducerlab.errors import DesignError

    tables = [
        {"type": "inertia", "dof": "b.rx", "moment_of_inertia": f"{JD} kg*m^2"},
        {"type": "inertia", "dof": "b.ry", "moment_of_inertia": f"{JD} kg*m^2"},
        {"type": "inertia", "dof": "b.rz", "moment_of_inertia": f"{JP} kg*m^2"},
        {"type": "support", "dof": "b.rx", "torsional_stiffness": f"{KT} N*m/rad"},
        {"type": "support", "dof": "b.ry", "torsional_stiffness": f"{KT} N*m/rad"},
        {"type": "nutating", "triple": ["b.rx", "b.ry", "b.rz"], "polar_moment": f"{JP} kg*m^2",
         "diametral_moment": f"{JD} kg*m^2", "nutation_angle": f"{math.degrees(THETA)!r} deg",
         "spin_ratio": SPIN},
        {"type": "inertia", "dof": "p.x", "mass": "1 kg"},
        {"type": "inertia", "dof": "p.y", "mass": "1 kg"},
        {"type": "support", "dof": "p.x", "stiffness": "1e4 N/m", "damping": "3 N*s/m"},
        {"type": "support", "dof": "p.y", "stiffness": "1e4 N/m", "damping": "3 N*s/m"},
        {"type": "stationary_damping", "pair": ["p.x", "p.y"], "damping": "3 N*s/m"},
    ]  # fmt: skip
    dofs = ", ".join(f'{{ body = "{n[0]}", kind = "{n[2:]}" }}'
                     for n in ("b.rx", "b.ry", "b.rz", "p.x", "p.y"))  # fmt: skip
    text = f'type = "lumped"\nspeed = "{OMEGA} rad/s"\ndofs = [{dofs}]\n'
    for t in tables:
        text += "\n[[elements]]\n" + "".join(
            f"{k} = {v!r}\n".replace("'", '"') if not isinstance(v, float) else f"{k} = {v}\n"
            for k, v in t.items()
        )
    path = tmp_path / "nut.toml"
    path.write_text(text)
    model = build_model(load_design(path))
    r = complex_modes(model)
    # the body and the mass are uncoupled: the body's frequencies are those of the model
    # built in code (round-off apart)
    for f in _elastic(_tilt_model()):
        assert np.min(np.abs(r.frequencies - f)) <= 1e-10 * f
    with pytest.raises(DesignError, match=r"elements\.5\.triple.*rx, ry, rz"):
        load_design(path, ["elements.5.triple=['b.rx', 'b.rz', 'b.ry']"])
