"""Catalogue numbers of a reducer read from its torsion-test loop (issue 31).

The loop is the output twist ``theta`` (rad) against the output torque ``T`` (N m) of a
test with the input held, in four monotone branches (:mod:`.torsion_test`): loading to
``+T_r``, unloading to 0, loading to ``-T_r``, unloading to 0. Each number and its rule
(the standards' and catalogues' definitions, as docs/datasheet.md cites them):

* **backlash** (RV catalogue and GB/T 35089-2018: the twist at zero torque on the
  hysteresis curve): the jump of the twist where the loop crosses zero torque,
  ``theta(0+) - theta(0-)`` (end of branch 1 minus start of branch 2);
* **hysteresis loss** (strain-wave catalogue: the twist left when the torque returns
  to zero after ``+T_r``, measured against the return after ``-T_r``): the loop's width
  at zero torque after each excursion, ``theta_1(0) - theta_3(0)``; and the **loop
  area** ``oint T dtheta`` (J), the work lost per cycle, zero without friction;
* **lost motion** at ``a = 3 %`` of ``T_r`` (RV catalogue, GB/T 40731-2021: the twist
  between the midpoints of the loop's width at ``+a T_r`` and ``-a T_r``):
  ``LM = theta_mid(+a T_r) - theta_mid(-a T_r)``, ``theta_mid`` the mean of the two
  branches through that torque; also at ``a = 4 %`` (the strain-wave convention of
  twist at +/-4 % of rated);
* **K1, K2, K3** between ``T1`` and ``T2`` (strain-wave convention, the curve divided
  into three linearised regions ``0..T1, T1..T2, T2..T_r``): secant slopes on each
  loading branch with the twist measured from that branch's zero-torque point,
  ``K1 = T1 / (theta(T1) - theta(0))``, ``K2 = (T2 - T1) / (theta(T2) - theta(T1))``,
  ``K3 = (T_r - T2) / (theta(T_r) - theta(T2))`` (magnitudes), the mean of the two
  directions; ``T1, T2`` are stated fractions of ``T_r`` (default 0.2 and 0.7, the
  range of the catalogue's limit torques over sizes); ``theta1, theta2`` are the
  catalogue's twists at ``T1, T2``: ``T1 / K1`` and ``theta1 + (T2 - T1) / K2``;
* **torsional rigidity** (RV convention, ``b / a`` on the hysteresis curve): the secant
  of the mid curve between ``3 %`` (the end of the lost-motion band) and ``100 %`` of
  ``T_r``, ``0.97 T_r / (theta_mid(T_r) - theta_mid(0.03 T_r))``, mean of both
  directions.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..numformat import fmt

__all__ = ["LoopNumbers", "accuracy_rows", "loop_numbers", "starting_torques"]

Array = NDArray[np.float64]
_ARCMIN = math.pi / (180.0 * 60.0)


@dataclass(frozen=True)
class LoopNumbers:
    """The datasheet numbers in SI (rad, N m, N m/rad, J); see the module's rules."""

    backlash: float
    hysteresis_loss: float
    loop_area: float
    lost_motion_3: float
    lost_motion_4: float
    T1: float
    T2: float
    K1: float
    K2: float
    K3: float
    theta1: float
    theta2: float
    rigidity_rv: float
    stiffness_at_rated: float

    FIELDS: ClassVar[tuple[str, ...]] = (
        "backlash", "hysteresis_loss", "loop_area", "lost_motion_3", "lost_motion_4",
        "T1", "T2", "K1", "K2", "K3", "theta1", "theta2", "rigidity_rv",
        "stiffness_at_rated",
    )  # fmt: skip

    def attrs(self) -> dict[str, float]:
        """The numbers as dataset attributes (SI)."""
        return {k: float(v) for k, v in asdict(self).items()}

    def catalogue(self) -> dict[str, float]:
        """The numbers in catalogue units (arcmin, N m, N m/arcmin, J)."""
        am, stiff = 1.0 / _ARCMIN, _ARCMIN
        return {
            "backlash_arcmin": self.backlash * am,
            "hysteresis_loss_arcmin": self.hysteresis_loss * am,
            "loop_area_J": self.loop_area,
            "lost_motion_3pct_arcmin": self.lost_motion_3 * am,
            "lost_motion_4pct_arcmin": self.lost_motion_4 * am,
            "T1_N_m": self.T1,
            "T2_N_m": self.T2,
            "K1_N_m_per_arcmin": self.K1 * stiff,
            "K2_N_m_per_arcmin": self.K2 * stiff,
            "K3_N_m_per_arcmin": self.K3 * stiff,
            "theta1_arcmin": self.theta1 * am,
            "theta2_arcmin": self.theta2 * am,
            "torsional_rigidity_rv_N_m_per_arcmin": self.rigidity_rv * stiff,
            "tangent_stiffness_at_rated_N_m_per_arcmin": self.stiffness_at_rated * stiff,
        }

    def rows(self) -> list[tuple[str, float, str]]:
        """Table rows: quantity, value, unit (:func:`reducerlab.numformat.quantity_table`)."""
        c = self.catalogue()
        spec = [
            ("backlash (twist jump at zero torque)", "backlash_arcmin", "arcmin"),
            ("hysteresis loss (loop width at zero)", "hysteresis_loss_arcmin", "arcmin"),
            ("loop area (work lost per cycle)", "loop_area_J", "J"),
            ("lost motion at +/-3 % rated", "lost_motion_3pct_arcmin", "arcmin"),
            ("lost motion at +/-4 % rated", "lost_motion_4pct_arcmin", "arcmin"),
            ("T1", "T1_N_m", "N m"),
            ("T2", "T2_N_m", "N m"),
            ("K1 (0..T1)", "K1_N_m_per_arcmin", "N m/arcmin"),
            ("K2 (T1..T2)", "K2_N_m_per_arcmin", "N m/arcmin"),
            ("K3 (T2..rated)", "K3_N_m_per_arcmin", "N m/arcmin"),
            ("theta1 (twist at T1)", "theta1_arcmin", "arcmin"),
            ("theta2 (twist at T2)", "theta2_arcmin", "arcmin"),
            ("torsional rigidity (RV, 3..100 %)", "torsional_rigidity_rv_N_m_per_arcmin",
             "N m/arcmin"),
            ("tangent stiffness at rated", "tangent_stiffness_at_rated_N_m_per_arcmin",
             "N m/arcmin"),
        ]  # fmt: skip
        return [(label, c[key], unit) for label, key, unit in spec]


def _at(torque: Array, twist: Array, value: float) -> float:
    """Twist of a monotone branch at ``value`` (N m), by linear interpolation (exact
    at a solved point)."""
    order = np.argsort(torque, kind="stable")
    t, th = torque[order], twist[order]
    if not (t[0] - 1e-12 * abs(t).max() <= value <= t[-1] + 1e-12 * abs(t).max()):
        raise ReducerlabError(f"datasheet: torque {value:.6g} N m is outside a branch")
    return float(np.interp(value, t, th))


def loop_numbers(
    torque: Array,
    twist: Array,
    branch: Array,
    rated: float,
    T1: float,
    T2: float,
    tangent_at_rated: float = math.nan,
) -> LoopNumbers:
    """The datasheet numbers of a loop (see the module's rules).

    Parameters
    ----------
    torque, twist, branch : ndarray
        The loop's states in test order (N m, rad, branch 0..3).
    rated, T1, T2 : float
        ``T_r`` and the K-fit's limit torques (N m), ``0 < T1 < T2 < T_r``.
    tangent_at_rated : float
        Tangent stiffness at ``+/-T_r`` (N m/rad), reported as given.
    """
    torque, twist, branch = (np.asarray(a) for a in (torque, twist, branch))
    if set(np.unique(branch).tolist()) != {0, 1, 2, 3}:
        raise ReducerlabError("datasheet: the loop needs its four branches (0..3)")
    if not (0 < T1 < T2 < rated):
        raise ReducerlabError(f"datasheet: need 0 < T1 < T2 < rated; got {T1}, {T2}, {rated}")
    br = [(torque[branch == j], twist[branch == j]) for j in range(4)]

    def mid(value: float) -> float:
        pair = (0, 1) if value > 0 else (2, 3)
        return 0.5 * sum(_at(*br[j], value) for j in pair)

    backlash = _at(*br[1], 0.0) - _at(*br[2], 0.0)
    hysteresis = _at(*br[1], 0.0) - _at(*br[3], 0.0)
    # oint T dtheta over the closed polygon, vertical jumps included (no area there)
    area = float(np.sum(0.5 * (torque[1:] + torque[:-1]) * np.diff(twist)))
    area += 0.5 * (torque[0] + torque[-1]) * (twist[0] - twist[-1])
    lm3 = mid(0.03 * rated) - mid(-0.03 * rated)
    lm4 = mid(0.04 * rated) - mid(-0.04 * rated)
    ks = []
    for j, sign in ((0, 1.0), (2, -1.0)):
        t, th = br[j]
        z = _at(t, th, 0.0)
        a1, a2, a3 = (sign * (_at(t, th, sign * v) - z) for v in (T1, T2, rated))
        ks.append((T1 / a1, (T2 - T1) / (a2 - a1), (rated - T2) / (a3 - a2)))
    K1, K2, K3 = (0.5 * (ks[0][i] + ks[1][i]) for i in range(3))
    rv = [0.97 * rated / (sign * (mid(sign * rated) - mid(sign * 0.03 * rated)))
          for sign in (1.0, -1.0)]  # fmt: skip
    return LoopNumbers(
        backlash=backlash, hysteresis_loss=hysteresis, loop_area=area, lost_motion_3=lm3,
        lost_motion_4=lm4, T1=T1, T2=T2, K1=K1, K2=K2, K3=K3, theta1=T1 / K1,
        theta2=T1 / K1 + (T2 - T1) / K2, rigidity_rv=0.5 * (rv[0] + rv[1]),
        stiffness_at_rated=tangent_at_rated,
    )  # fmt: skip


def accuracy_rows(res: Any) -> list[tuple[str, float, str]]:
    """The datasheet rows of a transmission-accuracy result: peak to peak over one
    output revolution (arcsec; under its load when it has one) and the mean wind-up."""
    a = res.data.attrs
    load = float(a.get("load_N_m", 0.0) or 0.0)
    where = f"under {fmt(load, 'torque')} N m" if load else "rigid, unloaded"
    rows = [(f"transmission error p-p, one output turn ({where})", res.peak_to_peak, "arcsec")]
    if load:
        rows.append(
            (
                "mean wind-up of the contacts alone under that load",
                float(a["wind_up_arcsec"]),
                "arcsec",
            )
        )
    return rows


def starting_torques(eff: Any, rated: float) -> dict[str, float]:
    """Efficiency, starting and back-driving torque at the rated output torque.

    Parameters
    ----------
    eff : EfficiencyResult
        Computed at output torques (its ``output_torque``) around ``rated``; its
        ``ratio`` attribute is ``|i|``, input over output speed.
    rated : float
        Rated output torque ``T_r`` (N m).

    Returns
    -------
    dict
        ``efficiency`` (linear in the torque between the computed ones),
        ``starting_torque`` ``T_r / (|i| eta)`` (N m, input) and ``backdriving_torque``
        ``T_r / eta_b`` with ``eta_b = eta`` (N m, output; the module's first-order
        relation).
    """
    ds = eff.data
    out_t = np.asarray(ds["output_torque"].values, float)
    eta_all = np.asarray(ds["efficiency"].values, float)
    if not (out_t.min() * (1 - 1e-9) <= rated <= out_t.max() * (1 + 1e-9)):
        raise ReducerlabError(
            f"datasheet: the efficiency was computed at output torques {out_t.min():.4g} to "
            f"{out_t.max():.4g} N m, not around the rated {rated:.4g} N m"
        )
    eta = float(np.interp(rated, out_t, eta_all))
    ratio = float(ds.attrs["ratio"])
    return {
        "efficiency": eta,
        "starting_torque": rated / (abs(ratio) * eta),
        "backdriving_efficiency": eta,
        "backdriving_torque": rated / eta,
    }
