"""Load sharing of a cycloid ball drive's ball track against torque (issue 30).

:func:`ball_track_analysis` runs :func:`reducerlab.contact.ball_track.ball_loads` for a
cycloid ball design (``[cycloid_pair]`` with the ball and groove fields) from zero to
1.5 times the torque its torque flow puts on the centre disc, at several positions of
the ball set over one ball pitch (the ball-engagement period), and returns a
:class:`BallTrackResult`: the force of each contact line of each ball, the loaded balls
and the tangent stiffnesses against torque. The model, its closed forms and its limits:
``contact/ball_track.py`` and ``docs/ball_track.md``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, ClassVar

import numpy as np
import xarray as xr

from ..errors import ReducerlabError
from ..numformat import Column, Table, fmt
from ..results import Result, provenance

__all__ = ["BallTrackResult", "ball_track_analysis"]

#: bounds of the grid (checked before any work)
MAX_TORQUES = 1000
MAX_PHASES = 360


class BallTrackResult(Result):
    """Ball-track equilibrium against torque.

    ``data`` has dimensions ``torque`` (N m on the centre disc), ``phase`` (``psi_0``,
    rad: the ball set's position over one ball pitch), ``ball`` and ``line`` (``+``,
    ``-``). Variables: ``force`` (N) and ``approach`` (m) per line; ``loaded`` (balls
    carrying load), ``loaded_lines``, ``max_force`` (N), ``translational_stiffness``
    (N/m, paper 003's ``K_mx``), ``torsional_stiffness`` (N m/rad about the centre
    disc's axis) and ``radial_stiffness`` (N/m) on ``(torque, phase)``; ``psi`` (rad,
    each ball's angle about the midpoint of the centres, from the pitch point) on
    ``(phase, ball)``; ``undercut`` (phase, ball, line).
    """

    kind: ClassVar[str] = "ball-track"

    @property
    def torques(self) -> np.ndarray:
        """Torques on the centre disc (N m)."""
        return np.asarray(self.data["torque"].values, float)

    def summary(self) -> list[dict[str, float]]:
        """One row a torque: loaded balls (min, max over the phases), mean and range of
        the torsional stiffness, largest ball force."""
        ds = self.data
        rows = []
        for i, t in enumerate(self.torques):
            kt = ds["torsional_stiffness"].values[i]
            n = ds["loaded"].values[i]
            rows.append({
                "torque_N_m": float(t),
                "loaded_min": int(n.min()), "loaded_max": int(n.max()),
                "torsional_stiffness_N_m_per_rad": float(kt.mean()),
                "torsional_stiffness_min": float(kt.min()),
                "torsional_stiffness_max": float(kt.max()),
                "translational_stiffness_N_per_m": float(
                    ds["translational_stiffness"].values[i].mean()),
                "max_force_N": float(ds["max_force"].values[i].max()),
            })  # fmt: skip
        return rows

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: attributes and one row a torque."""
        out = {k: (v.item() if hasattr(v, "item") else v) for k, v in self.data.attrs.items()
               if k != "design"}  # fmt: skip
        out["torques"] = self.summary()
        return out

    def table(self) -> str:
        """Plain-text table: one row a torque."""
        a = self.data.attrs
        t = Table([Column("T", "N m", "torque"), Column("loaded balls", kind="text"),
                   Column("k_t mean", "N m/rad", "stiffness"),
                   Column("k_t min", "N m/rad", "stiffness"),
                   Column("k_t max", "N m/rad", "stiffness"),
                   Column("K_mx", "N/m", "stiffness"), Column("F_max", "N", "force")], title=(
            f"Ball track: {a['balls']} balls, K = {fmt(a['short_width'])}, r_b = "
            f"{fmt(1e3 * a['ball_radius_m'], 'length')} mm, f = {fmt(a['conformity'])}, beta = "
            f"{fmt(a['contact_angle_deg'], 'angle')} deg, clearance "
            f"{fmt(1e6 * a['clearance_m'], 'length')} um; y {a['y']}; rated "
            f"{fmt(a['rated_torque_N_m'], 'torque')} N m on the centre disc; "
            f"{a['undercut_lines']} of {2 * a['balls']} lines undercut at phase 0"))  # fmt: skip
        for r in self.summary():
            t.add(r["torque_N_m"], f"{r['loaded_min']}-{r['loaded_max']}",
                  r["torsional_stiffness_N_m_per_rad"], r["torsional_stiffness_min"],
                  r["torsional_stiffness_max"], r["translational_stiffness_N_per_m"],
                  r["max_force_N"])  # fmt: skip
        return t.text()

    def plot(self) -> Any:
        """Stiffness and loaded balls against torque, and the ball forces round the
        track at the rated torque (:func:`reducerlab.plot.ball_track.plot_ball_track`)."""
        from ..plot.ball_track import plot_ball_track

        return plot_ball_track(self)


def _count(name: str, value: object, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not lo <= value <= hi:
        raise ReducerlabError(f"{name}: must be an integer in [{lo}, {hi}]; got {value!r}")
    return int(value)


def ball_track_analysis(
    design: Any,
    torques: Sequence[float] | None = None,
    points: int = 13,
    phases: int = 8,
    y: str = "free",
    progress: Callable[[int, int], None] | None = None,
) -> BallTrackResult:
    """Ball loads and stiffness of a cycloid ball design against torque.

    Parameters
    ----------
    design : CycloidBallDesign
        With ``cycloid_pair.ball_radius``, ``groove_conformity``, ``groove_half_angle``
        and ``short_width_coefficient``.
    torques : sequence of float, optional
        Torques on the centre disc (N m); default ``points`` from 0 to 1.5 times the
        rated torque of the torque flow.
    points : int
        Torques of the default grid, 2-1000.
    phases : int
        Ball-set positions over one ball pitch, 1-360.
    y : {"free", "held"}
        The planetary disc's freedom along the line of centres.
    progress : callable, optional
        ``progress(done, total)`` after each torque.
    """
    from ..analysis.torque_flow import torque_flow
    from ..contact.ball_track import ball_loads

    if getattr(design, "type", None) != "cycloid_ball":
        raise ReducerlabError(
            f"ball track: a cycloid_ball design is needed; got type = "
            f"{getattr(design, 'type', None)!r}"
        )
    phases = _count("phases", phases, 1, MAX_PHASES)
    if y not in ("free", "held"):
        raise ReducerlabError(f"y: must be 'free' or 'held'; got {y!r}")
    track = design.ball_track()
    rated = abs(torque_flow(design).meshes["cycloid_pairs"].torques[0])
    if torques is None:
        points = _count("points", points, 2, MAX_TORQUES)
        t = np.linspace(0.0, 1.5 * rated, points)
    else:
        t = np.atleast_1d(np.asarray(torques, dtype=float))
        if t.ndim != 1 or not 1 <= t.size <= MAX_TORQUES or not np.all(np.isfinite(t)):
            raise ReducerlabError(
                f"torques: 1 to {MAX_TORQUES} finite torques (N m); got {torques!r}"
            )
    Z = track.balls
    ph = 2 * math.pi / Z * np.arange(phases) / phases
    force = np.zeros((t.size, phases, Z, 2))
    approach = np.zeros_like(force)  # -inf where a wall is undercut: NaN in the file
    scalars = {k: np.zeros((t.size, phases)) for k in (
        "loaded", "loaded_lines", "max_force", "translational_stiffness",
        "torsional_stiffness", "radial_stiffness")}  # fmt: skip
    for i, T in enumerate(t):
        for j, p in enumerate(ph):
            r = ball_loads(track, float(T), float(p), y)  # type: ignore[arg-type]
            force[i, j], approach[i, j] = r.force, r.approach
            for k in scalars:
                scalars[k][i, j] = getattr(r, k)
        if progress is not None:
            progress(i + 1, t.size)
    psi = ph[:, None] + 2 * math.pi * np.arange(Z)[None, :] / Z
    undercut = np.stack([track.undercut(float(p)) for p in ph])
    ds = xr.Dataset(
        {
            "force": (("torque", "phase", "ball", "line"), force,
                      {"units": "N", "long_name": "normal force of each contact line"}),
            "approach": (("torque", "phase", "ball", "line"),
                         np.where(np.isfinite(approach), approach, np.nan),
                         {"units": "m", "long_name": "approach (negative: clear; NaN: undercut)"}),
            "psi": (("phase", "ball"), psi, {"units": "rad"}),
            "undercut": (("phase", "ball", "line"), undercut.astype(np.int8)),
            **{k: (("torque", "phase"), v) for k, v in scalars.items()},
        },
        coords={"torque": t, "phase": ph, "ball": np.arange(Z), "line": ["+", "-"]},
    )  # fmt: skip
    for k, u in (("translational_stiffness", "N/m"), ("torsional_stiffness", "N m/rad"),
                 ("radial_stiffness", "N/m"), ("max_force", "N")):  # fmt: skip
        ds[k].attrs["units"] = u
    ds["torque"].attrs["units"] = "N m"
    ds.attrs.update(provenance(design.provenance))
    clearance = track.clearances
    ds.attrs.update({
        "balls": Z, "short_width": track.short_width, "ball_radius_m": track.ball_radius,
        "conformity": track.conformity, "contact_angle_deg": math.degrees(track.contact_angle),
        "clearance_m": float(clearance.mean()), "y": y, "rated_torque_N_m": float(rated),
        "pitch_radius_m": track.pitch_radius, "ball_circle_radius_m": track.ball_circle_radius,
        "undercut_lines": int(undercut[0].sum()),
        "straight_hertz_constant": track.straight_constant,
    })  # fmt: skip
    return BallTrackResult(ds)
