"""Rendered figures of generated gear solids (paper 001): one tooth, the gear pair in mesh.

Figures are drawn with ``mpl_toolkits.mplot3d`` (``Poly3DCollection``, flat shading by a
fixed light) on a plain :class:`matplotlib.figure.Figure` (no pyplot, Agg-safe). Axes
are in mm. Keep the meshes coarse (a few 10^4 triangles): matplotlib sorts polygons
by depth, it does not z-buffer.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..geometry.solid import GearSolid, TriangleMesh

__all__ = ["gear_to_mesh_frame", "plot_gear_pair", "plot_tooth", "tooth_section"]

_LIGHT = np.array([0.4, -0.5, 0.77])


def _shade(tri: NDArray[np.float64], rgb: ArrayLike) -> NDArray[np.float64]:
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    k = 0.35 + 0.65 * np.abs(n @ (_LIGHT / np.linalg.norm(_LIGHT)))
    return np.clip(np.broadcast_to(np.asarray(rgb, float), (len(tri), 3)) * k[:, None], 0, 1)


def _add(ax, mesh: TriangleMesh, rgb: ArrayLike) -> None:
    """One depth-sorted collection; ``rgb`` is one colour or one per face."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    tri = mesh.vertices[mesh.faces] * 1e3
    ax.add_collection3d(Poly3DCollection(tri, facecolors=_shade(tri, rgb), linewidths=0))


def _equal(ax, pts: NDArray[np.float64]) -> None:
    """Equal axes around ``pts`` (mm), at most four ticks each, small labels."""
    from matplotlib.ticker import MaxNLocator

    lo, hi = pts.min(axis=0), pts.max(axis=0)
    c, r = 0.5 * (lo + hi), 0.5 * float(np.max(hi - lo))
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_box_aspect((1, 1, 1))
    for axis, name in ((ax.xaxis, "x"), (ax.yaxis, "y"), (ax.zaxis, "z")):
        axis.set_major_locator(MaxNLocator(nbins=4, steps=[1, 2, 5, 10]))
        axis.set_label_text(f"{name} (mm)", fontsize=8)
        axis.labelpad = 2
    ax.tick_params(labelsize=7, pad=1)


def _tight(ax, pts: NDArray[np.float64]) -> None:
    """Limits hugging ``pts`` (mm) on each axis, one scale on all three (the box's
    sides in proportion to the ranges: no empty cube around a slender tooth), at most
    four ticks each, small labels."""
    from matplotlib.ticker import MaxNLocator

    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = np.maximum(hi - lo, 0.08 * float(np.max(hi - lo)))  # a flat side keeps a depth
    pad = 0.04 * span
    for put, a, b in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), lo - pad, lo + span + pad,
                         strict=True):  # fmt: skip
        put(a, b)
    for axis, name, n in zip((ax.xaxis, ax.yaxis, ax.zaxis), "xyz", span, strict=True):
        small = n < 0.35 * float(np.max(span))  # a short side: fewer ticks, no crowding
        axis.set_major_locator(MaxNLocator(nbins=2 if small else 4, steps=[1, 2, 5, 10]))
        axis.set_label_text(f"{name} (mm)", fontsize=8)
        axis.labelpad = 4
    ax.tick_params(labelsize=7, pad=1)
    ax.set_box_aspect(tuple(span + 2 * pad), zoom=0.9)


#: The tooth sector's view elevation is kept within these (deg): from straight above or
#: from the side the sector's depth collapses and its tick labels crowd.
ELEVATION = (18.0, 35.0)


def plot_tooth(solid: GearSolid, title: str | None = None) -> Figure:
    """One tooth sector of ``solid`` (its flanks highlighted) in the gear frame, beside
    its dimensioned transverse section at the mean cone distance (:func:`tooth_section`).
    """
    from matplotlib.figure import Figure

    mesh = solid.tooth_mesh()
    fig = Figure(figsize=(11.5, 5.4), layout="constrained")
    grid = fig.add_gridspec(1, 2, width_ratios=(1.0, 1.15))
    ax = fig.add_subplot(grid[0], projection="3d")
    # colour the faces of each flank: sector loop = [half space, A, land, B, half space]
    nf, npch = solid.loop.shape[:2]
    sp = solid.parts["space"]
    shift = (sp.stop - sp.start) - (sp.stop - sp.start) // 2
    n_s = npch + 1
    idx = np.where(mesh.faces < nf * n_s, mesh.faces % n_s - shift, -1)
    rgb = np.tile([0.62, 0.66, 0.72], (len(mesh.faces), 1))
    for key, c in (("A", (0.85, 0.45, 0.2)), ("B", (0.2, 0.5, 0.85))):
        s = solid.parts[key]
        rgb[np.all((idx >= s.start) & (idx < s.stop), axis=1)] = c
    _add(ax, mesh, rgb)
    _tight(ax, mesh.vertices * 1e3)
    # look at the tooth from outside its tip, a little from the heel
    g = solid.gear
    d, psi = g.cone_angle, float(np.arctan2(*solid.loop[nf // 2, solid.parts["land"].start, 1::-1]))
    out = np.array([math.cos(d) * math.cos(psi), math.cos(d) * math.sin(psi), -math.sin(d)])
    gen = np.array([math.sin(d) * math.cos(psi), math.sin(d) * math.sin(psi), math.cos(d)])
    v = (out if g.kind == "external" else -out) + 0.5 * gen
    v /= np.linalg.norm(v)
    # an oblique view: the direction's azimuth, its elevation kept in ELEVATION (an
    # internal gear's tooth, seen along its axis, was drawn nearly from straight above)
    elev = min(max(math.degrees(math.asin(abs(v[2]))), ELEVATION[0]), ELEVATION[1])
    ax.view_init(elev=math.copysign(elev, v[2]), azim=math.degrees(math.atan2(v[1], v[0])) + 20)
    ax.set_title("one tooth (flanks A orange, B blue)", fontsize=9)
    _draw_section(fig.add_subplot(grid[1]), solid)
    fig.suptitle(
        title or f"{g.kind} gear, z = {g.teeth}, {solid.crown.profile.name} profile",
        fontsize=10,
    )
    return fig


def tooth_section(solid: GearSolid, teeth: int = 3) -> dict[str, Any]:
    """The transverse section of ``solid`` at its mean cone distance, developed.

    The section of a bevel gear by the sphere of radius ``R`` (the cone distance of the
    middle section) about the cone apex, drawn in developed coordinates: ``height``
    (mm) along the sphere's meridian from the pitch cone, towards the tooth tip, and
    ``arc`` (mm) along the pitch circle of that section (radius ``R sin delta``), from
    the middle tooth's centre line.

    Parameters
    ----------
    solid : GearSolid
    teeth : int
        Teeth drawn (odd; the middle one is dimensioned).

    Returns
    -------
    dict
        ``arc``, ``height`` (mm): the section's outline over ``teeth`` pitches;
        ``R`` (mm), ``delta`` (deg); ``d_a``, ``d``, ``d_f`` (mm): the tip, pitch and
        root diameters of the section (twice the largest/smallest radius of the top
        land/space bottom points, and ``2 R sin delta``); ``h_a``, ``h_f`` (mm): the
        addendum and dedendum along the meridian; ``s`` (mm): the tooth thickness on
        the pitch circle (arc) and ``s_ends`` its two ends (arc, mm); ``m_n`` (mm),
        ``alpha_n`` (deg, NaN for a profile without one), ``beta_m`` (deg), ``z``.
    """
    g, crown = solid.gear, solid.crown
    nf = solid.loop.shape[0] // 2
    R = float(solid.L[nf])
    delta = g.cone_angle
    loop = solid.loop[nf]
    land = solid.parts["land"]
    space = solid.parts["space"]
    c_land = loop[land].mean(axis=0)
    centre = math.atan2(c_land[1], c_land[0])
    polar = np.arctan2(np.hypot(loop[:, 0], loop[:, 1]), loop[:, 2])  # from the axis
    up = 1.0 if polar[land].mean() > delta else -1.0  # the tip's side of the pitch cone
    r_p = R * math.sin(delta)
    step = 2 * math.pi / g.teeth
    arcs, heights = [], []
    half = teeth // 2
    for k in range(-half, half + 1):  # tooth k is tooth 0 turned by -k pitches
        th = np.arctan2(loop[:, 1], loop[:, 0]) - k * step - centre
        th = (th + math.pi) % (2 * math.pi) - math.pi
        arcs.append(-r_p * th)  # along the loop: flank A, top land, flank B, space
        heights.append(up * R * (polar - delta))
    order = np.argsort([a.mean() for a in arcs])
    arc = np.concatenate([arcs[i] for i in order])
    height = np.concatenate([heights[i] for i in order])
    radius = np.hypot(loop[:, 0], loop[:, 1])
    tip_r = radius[land].max() if up > 0 else radius[land].min()
    root_r = radius[space].min() if up > 0 else radius[space].max()
    h0, a0 = heights[half], arcs[half]
    ends = []
    for part in (solid.parts["A"], solid.parts["B"]):
        h, a = h0[part], a0[part]
        i = np.argsort(h)
        ends.append(float(np.interp(0.0, h[i], a[i])))
    prof = crown.profile
    alpha = getattr(prof, "pressure_angle", None)
    return {
        "arc": 1e3 * arc, "height": 1e3 * height, "R": 1e3 * R, "delta": math.degrees(delta),
        "d_a": 2e3 * tip_r, "d": 2e3 * r_p, "d_f": 2e3 * root_r,
        "h_a": 1e3 * float(h0[land].mean()), "h_f": -1e3 * float(h0[space].min()),
        "s": 1e3 * abs(ends[1] - ends[0]), "s_ends": (1e3 * min(ends), 1e3 * max(ends)),
        "m_n": 1e3 * prof.module, "alpha_n": math.degrees(alpha) if alpha else math.nan,
        "beta_m": math.degrees(crown.spiral_angle), "z": g.teeth,
    }  # fmt: skip


def _draw_section(ax: Any, solid: GearSolid) -> None:
    """The dimensioned transverse section (:func:`tooth_section`) on ``ax``."""
    sec = tooth_section(solid)
    x, y = sec["arc"], sec["height"]
    bottom = float(y.min()) - 0.6 * sec["h_f"]
    ax.fill(np.r_[x, x[-1], x[0]], np.r_[y, bottom, bottom], color="0.82", lw=0)
    ax.plot(x, y, color="0.15", lw=1.2)
    lo, hi = float(x.min()), float(x.max())
    lines = (
        (sec["h_a"], "tip", "d_a", sec["d_a"]),
        (0.0, "pitch", "d", sec["d"]),
        (-sec["h_f"], "root", "d_f", sec["d_f"]),
    )
    for h, name, sym, dia in lines:
        pitch_line = name == "pitch"
        ax.axhline(h, color="tab:blue" if pitch_line else "0.45", lw=0.8,
                   ls="-." if pitch_line else "--")  # fmt: skip
        ax.text(hi, h, f"{name}: {sym} = {dia:.2f} mm", fontsize=7, color="0.1",
                va="bottom" if name == "tip" else "top", ha="right",
                bbox={"fc": "w", "ec": "none", "alpha": 0.8, "pad": 1})  # fmt: skip
    # the tooth thickness on the pitch circle, and the tooth depth in the next space
    a, b = sec["s_ends"]
    arrow = {"arrowstyle": "<->", "color": "tab:red", "lw": 0.9, "shrinkA": 0, "shrinkB": 0}
    ax.annotate("", (a, 0.0), (b, 0.0), arrowprops=arrow)
    ax.text(0.5 * (a + b), 0.08 * sec["h_a"], f"s = {sec['s']:.2f} mm", color="tab:red",
            fontsize=7, ha="center", va="bottom")  # fmt: skip
    xh = b + 0.5 * (math.pi * sec["d"] / sec["z"] - sec["s"])  # mid-space
    ax.annotate("", (xh, sec["h_a"]), (xh, -sec["h_f"]), arrowprops=arrow)
    ax.text(xh, sec["h_a"] + 0.1 * sec["h_f"],
            f"h = {sec['h_a'] + sec['h_f']:.2f} mm\n(h_a {sec['h_a']:.2f} + h_f {sec['h_f']:.2f})",
            color="tab:red", fontsize=7, ha="center", va="bottom")  # fmt: skip
    alpha = "" if math.isnan(sec["alpha_n"]) else f", alpha_n = {sec['alpha_n']:.4g} deg"
    ax.text(0.01, 0.99,
            f"m_n = {sec['m_n']:.4g} mm{alpha}, beta_m = {sec['beta_m']:.4g} deg\n"
            f"z = {sec['z']}, pitch cone delta = {sec['delta']:.4g} deg\n"
            f"section: sphere R = {sec['R']:.2f} mm (mean cone distance)",
            transform=ax.transAxes, fontsize=7, va="top", ha="left",
            bbox={"fc": "w", "ec": "0.7", "lw": 0.6})  # fmt: skip
    ax.set_xlim(lo, hi)
    ax.set_ylim(bottom, sec["h_a"] + 1.3 * (sec["h_a"] + sec["h_f"]))
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("arc on the pitch circle of the section (mm)", fontsize=8)
    ax.set_ylabel("height from the pitch cone, along the sphere (mm)", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.set_title("transverse section at the mean cone distance (developed), dimensioned",
                 fontsize=9)  # fmt: skip


def gear_to_mesh_frame(solid: GearSolid) -> NDArray[np.float64]:
    """Rotation (3x3) from the gear frame ``S_i`` to the fixed frame ``S0`` at the crown
    angle 0, where both gears of a pair touch the crown gear along ``+y_0`` (in mesh)."""
    from ..geometry.bevel_surface import axis_frame

    return axis_frame(solid.gear.cone_angle).T


def plot_gear_pair(
    external: GearSolid, internal: GearSolid, window: float = math.radians(70)
) -> Figure:
    """The external and internal gears in mesh, axes at the nutation angle.

    Both solids must come from the same crown gear. The internal gear is drawn only
    within ``window`` (rad) of the contact line ``+y_0`` (it would hide the external
    gear), the external gear whole.
    """
    from matplotlib.figure import Figure

    from ..geometry.solid import TriangleMesh

    if external.gear.kind != "external" or internal.gear.kind != "internal":
        raise ReducerlabError(
            "plot_gear_pair: give the external gear's solid first and the internal gear's "
            f"second; got {external.gear.kind} and {internal.gear.kind}"
        )
    if external.crown is not internal.crown and not math.isclose(
        external.crown.teeth, internal.crown.teeth, rel_tol=1e-12
    ):
        raise ReducerlabError(
            "plot_gear_pair: both gears must be generated by the same crown gear (equal "
            f"crown teeth z / sin(delta)); got {external.crown.teeth:.6g} and "
            f"{internal.crown.teeth:.6g}"
        )
    fig = Figure(figsize=(7.5, 6.2), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    allpts = []
    for solid, rgb, cut in (
        (external, (0.35, 0.55, 0.85), None),
        (internal, (0.85, 0.55, 0.3), window),
    ):
        m = solid.gear_mesh()
        V = m.vertices @ gear_to_mesh_frame(solid).T
        F = m.faces
        if cut is not None:
            c = V[F].mean(axis=1)
            az = np.arctan2(c[:, 0], c[:, 1])  # angle from +y_0 about z_0
            F = F[np.abs(az) <= cut]
        mm = TriangleMesh(V, F)
        _add(ax, mm, rgb)
        allpts.append(V[np.unique(F)])
    _equal(ax, np.concatenate(allpts) * 1e3)
    ax.view_init(elev=18, azim=-35)
    theta = internal.gear.cone_angle - external.gear.cone_angle
    fig.suptitle(
        f"nutation spiral bevel pair in mesh: external z = {external.gear.teeth} (blue), "
        f"internal z = {internal.gear.teeth} (orange, part), nutation angle "
        f"{math.degrees(theta):.3g} deg",
        fontsize=9,
    )
    return fig
