"""Mesh stiffness of spur gear pairs after ISO 6336-1 (method B), with profile shift,
and the parabolic single/double-tooth time law of paper 004 (Eq. 7-10).

``q' = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2 + C8 x1^2
+ C9 x2^2`` (mm um/N), the single-pair stiffness per unit face width is ``c' = 1/q'``
and, with the correction factor 0.8 of solid gears, the pitch-point stiffness of a
pair of face width ``b`` is ``k_C = 0.8 b / q'`` (paper 004 Eq. 7, with b in mm it is
N/um; here everything is SI). For internal gearing paper 004 (Eq. 8) flips the signs of
the two ``x2`` terms; ``internal=True`` does the same.
"""

from __future__ import annotations

from ..errors import ReducerlabError
from ..model import PiecewisePolynomial

__all__ = ["ISO6336_Q", "iso6336_q", "pitch_point_stiffness", "single_double_law"]

#: Coefficients C1..C9 of ISO 6336-1 for q' (mm um / N). Paper 004 prints C1 = 0.04732;
#: the standard's value is 0.04723 (see docs/assumptions.md).
ISO6336_Q = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)


def iso6336_q(z1: float, z2: float, x1: float, x2: float, *, internal: bool = False) -> float:
    """Minimum flexibility ``q'`` of a tooth pair (mm um/N) for equivalent tooth numbers
    ``z1, z2`` and shift coefficients ``x1, x2`` (paper 004 Eq. 8)."""
    c1, c2, c3, c4, c5, c6, c7, c8, c9 = ISO6336_Q
    s = -1.0 if internal else 1.0  # the x2 terms: "+" for inner gearing in paper 004
    q = (
        c1 + c2 / z1 + c3 / z2 + c4 * x1 + c5 * x1 / z1
        + s * c6 * x2 + s * c7 * x2 / z2 + c8 * x1**2 + c9 * x2**2
    )  # fmt: skip
    if not q > 0:
        raise ReducerlabError(f"ISO 6336 flexibility q' = {q:.4g} is not positive")
    return q


def pitch_point_stiffness(
    face_width: float, z1: float, z2: float, x1: float, x2: float, *, internal: bool = False,
    correction: float = 0.8,
) -> float:  # fmt: skip
    """Single-pair stiffness at the pitch point ``k_C = 0.8 b / q'`` (N/m; b in m).

    ``q'`` is in mm um/N, so ``b[mm] / q'`` is in N/um: ``k_C = 0.8 b[mm] / q' * 1e6``
    N/m (paper 004 Eq. 7 writes ``0.8e3 b / q`` in N/mm).
    """
    if not face_width > 0:
        raise ReducerlabError(f"face width must be > 0 m, got {face_width!r}")
    q = iso6336_q(z1, z2, x1, x2, internal=internal)
    return correction * (face_width * 1e3) / q * 1e6


def single_double_law(k_pitch: float, contact_ratio: float, mesh_period: float,
                      ref_speed: float | None = None) -> PiecewisePolynomial:  # fmt: skip
    """Mesh stiffness over one mesh period (paper 004 Eq. 9, intervals derived).

    A single pair along its path of contact ``tau in [0, eps]`` (in base pitches) has
    the parabola ``k_s(tau) = A tau^2 + B tau + C`` with ``A = -2k'/eps^2``,
    ``B = 2k'/eps``, ``C = k'``: ``k'`` at engagement and exit, ``1.5 k' = k_C`` at
    mid-path. Within a mesh period (phase ``s in [0, 1)``) two pairs mesh for
    ``s < eps - 1`` (``k_s(s) + k_s(s + 1)``) and one pair after it (``k_s(s)``); the
    printed Eq. 9 assigns the two expressions to the opposite intervals. The mean is
    the exact integral, ``(4/3) k' eps = 0.8889 eps k_C``.
    """
    if not 1.0 < contact_ratio < 2.0:
        raise ReducerlabError(
            f"the single/double-tooth law needs 1 < contact ratio < 2, got {contact_ratio:.4g}"
        )
    kp = k_pitch / 1.5
    e = contact_ratio
    A, B, C = -2 * kp / e**2, 2 * kp / e, kp
    return PiecewisePolynomial(
        period=mesh_period,
        breaks=(0.0, e - 1.0),
        coefficients=((A + B + 2 * C, 2 * (A + B), 2 * A), (C, B, A)),
        ref_speed=ref_speed,
    )
