"""Kinematic analysis of a drive: ratio, member speeds, mesh frequencies, cone angles,
and the nutating gear's angular velocity over one input revolution."""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr

from ..errors import ReducerlabError
from ..kinematics import DriveKinematics
from ..kinematics.euler import angular_velocity_body, angular_velocity_fixed
from ..numformat import Column, Table, fmt
from ..results import Result, provenance
from ..units import RPM, TWO_PI

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["KinematicsResult", "kinematics"]


def kinematics(
    drive: DriveKinematics,
    input_speed: float,
    *,
    points: int = 361,
    title: str = "",
    metadata: dict[str, Any] | None = None,
) -> KinematicsResult:
    """Evaluate a drive's kinematics at an input speed.

    Parameters
    ----------
    drive : DriveKinematics
    input_speed : float
        rad/s (non-zero).
    points : int
        Samples of the nutating gear's angular velocity over one input revolution.
    title : str
        Title for tables and figures (the drive's own by default).
    metadata : dict, optional
        Provenance (design, design hash).
    """
    if not isinstance(drive, DriveKinematics):
        raise ReducerlabError(f"drive must be a DriveKinematics, got {type(drive).__name__}")
    if not (isinstance(input_speed, int | float) and math.isfinite(input_speed) and input_speed):
        raise ReducerlabError(f"input_speed must be a finite non-zero rad/s, got {input_speed!r}")
    if not (isinstance(points, int) and points >= 2):
        raise ReducerlabError(f"points must be an integer >= 2, got {points!r}")
    speeds = drive.speeds(input_speed)
    meshes = drive.mesh_frequencies(input_speed)
    cones = drive.cone_angles()
    data = xr.Dataset(
        {
            "speed": ("member", list(speeds.values()), {"units": "rad/s"}),
            "speed_rpm": ("member", [v * RPM for v in speeds.values()], {"units": "rpm"}),
            "mesh_frequency": ("mesh", list(meshes.values()), {"units": "Hz"}),
            "cone_angle": ("gear", list(cones.values()), {"units": "rad"}),
        },
        coords={"member": list(speeds), "mesh": list(meshes), "gear": list(cones)},
        attrs={
            "title": title or drive.title,
            "ratio": drive.ratio,
            "input_speed_rad_s": float(input_speed),
            **provenance(metadata),
        },
    )
    motion = drive.nutating_motion(input_speed)
    if motion is not None:
        period = TWO_PI / abs(input_speed)
        t = np.linspace(0.0, period, points)
        phi, theta, psi = motion.angles(t)
        body = angular_velocity_body(theta, psi, motion.dphi, 0.0, motion.dpsi)
        fixed = angular_velocity_fixed(phi, theta, motion.dphi, 0.0, motion.dpsi)
        data = data.assign(
            omega=(
                ("frame", "time", "component"),
                np.stack([body, fixed]),
                {"units": "rad/s", "long_name": "nutating gear angular velocity"},
            ),
            input_angle=("time", np.degrees(phi * np.sign(input_speed)), {"units": "deg"}),
        ).assign_coords(
            time=("time", t, {"units": "s"}),
            frame=["body", "fixed"],
            component=["1", "2", "3"],
        )
        data.attrs.update(
            nutation_angle_rad=motion.theta,
            spin_rate_rad_s=motion.dpsi,
            precession_rate=motion.dphi,
        )
    return KinematicsResult(data)


class KinematicsResult(Result):
    """Ratio (attribute), member speeds, mesh frequencies, cone angles, and the
    nutating gear's angular velocity (``omega``: frame x time x component)."""

    kind: ClassVar[str] = "kinematics"

    @property
    def ratio(self) -> float:
        """``omega_input / omega_output`` (signed)."""
        return float(self.data.attrs["ratio"])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (keys ``ratio``, ``speeds_rad_s``, ``speeds_rpm``,
        ``mesh_frequencies_hz``, ``cone_angles_deg``, ``design_hash``,
        ``reducerlab_version``; the full provenance is :attr:`provenance`)."""
        ds = self.data

        def pairs(var: str, dim: str, f=float) -> dict[str, float]:
            return {str(k): f(v) for k, v in zip(ds[dim].values, ds[var].values, strict=True)}

        return {
            "title": ds.attrs.get("title", ""),
            "ratio": self.ratio,
            "input_speed_rpm": ds.attrs["input_speed_rad_s"] * RPM,
            "speeds_rad_s": pairs("speed", "member"),
            "speeds_rpm": pairs("speed_rpm", "member"),
            "mesh_frequencies_hz": pairs("mesh_frequency", "mesh"),
            "cone_angles_deg": pairs("cone_angle", "gear", lambda v: math.degrees(float(v))),
            "design_hash": ds.attrs.get("design_hash"),
            "reducerlab_version": ds.attrs.get("reducerlab_version"),
        }

    def to_json(self) -> str:
        """:meth:`to_dict` as JSON."""
        return json.dumps(self.to_dict(), indent=2)

    def table(self) -> str:
        """Plain-text summary."""
        d = self.to_dict()
        lines = [f"{d['title']}", f"  ratio i = omega_in / omega_out = {fmt(d['ratio'], 'ratio')}"]
        parts = [("member speeds:", Column("member", kind="text"), Column("speed", "rpm", "speed"),
                  d["speeds_rpm"]),
                 ("mesh frequencies:", Column("mesh", kind="text"),
                  Column("frequency", "Hz", "frequency"), d["mesh_frequencies_hz"]),
                 ("pitch cone angles:", Column("gear", kind="text"),
                  Column("cone angle", "deg", "angle"), d["cone_angles_deg"])]  # fmt: skip
        for title, name, value, rows in parts:
            if rows:
                t = Table([name, value], [(k, v) for k, v in rows.items()])
                lines += [f"  {title}", t.text(indent="    ")]
        return "\n".join(lines)

    def plot(self) -> Figure:
        """Angular-velocity components of the nutating gear over one input revolution."""
        from ..plot.kinematics import plot_angular_velocity

        return plot_angular_velocity(self)
