"""The common style of the Campbell diagrams (:mod:`.campbell`): mode colours distinct
for any number of modes, a colour and dash per excitation line with its name and order,
the whirl markers and what they mean, the damping colour scale, the frequency axis
(where excitations can meet modes: a margin above the highest excitation frequency over
the operating range, naming the modes above it and the lines left off), repeated
frequencies (coincident tracked modes) and the crossings grouped where they are one
point of the diagram."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ReducerlabError
from ..units import TWO_PI

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "CAP",
    "COINCIDENT",
    "CROSSING_COLOUR",
    "MARGIN",
    "OUTSIDE_COLOUR",
    "WHIRL",
    "FrequencyAxis",
    "coincident",
    "coincident_dash",
    "damping_scale",
    "excitation_label",
    "excitation_styles",
    "frequency_axis",
    "hz",
    "mode_colours",
    "modes_span",
    "modes_text",
    "short_name",
    "sig",
    "spread",
    "unique_crossings",
    "whirl_marks",
]

#: Whirl class -> (matplotlib marker, plotly symbol, what it means).
WHIRL = {
    "forward": ("^", "triangle-up", "forward whirl (orbit turns with the spin)"),
    "backward": ("v", "triangle-down", "backward whirl (orbit turns against the spin)"),
    "planar": ("o", "circle", "planar (straight-line orbit, no whirl)"),
    "none": ("s", "square", "no lateral motion (no whirl)"),
    "ccw": ("<", "triangle-left", "ccw: anticlockwise orbit about +z, no spin (at rest)"),
    "cw": (">", "triangle-right", "cw: clockwise orbit about +z, no spin (at rest)"),
    "rigid": ("_", "line-ew", "rigid-body motion"),
}

#: Colours of the excitation lines: dark tones, apart from the modes' bright ones, cycled
#: with :data:`DASHES`.
EXCITATION_COLOURS = ("#000000", "#8c510a", "#542788", "#1b7837", "#b2182b", "#2166ac",
                      "#c51b7d", "#4d4d4d")  # fmt: skip
#: Dashes of the excitation lines: (matplotlib, plotly).
DASHES = (("--", "dash"), ("-.", "dashdot"), (":", "dot"), ((0, (8, 2, 2, 2, 2, 2)), "longdashdot"))

#: The frequency axis reaches an excitation line's frequency at the top of the operating
#: range up to this many times the highest natural frequency shown (x 1.1); higher lines
#: are named in the figure as off the chart.
CAP = 2.0
#: The frequency axis ends this factor above the highest excitation frequency in the
#: operating range (and above the lowest elastic mode).
MARGIN = 1.1
#: Tracked modes within this relative difference at every speed are one line drawn
#: twice (a repeated frequency): the later one dashed, and labelled together.
COINCIDENT = 1e-3

#: Colour of a crossing marker in the operating range, and of one outside it.
CROSSING_COLOUR, OUTSIDE_COLOUR = "#d62728", "#333333"


def mode_colours(n: int) -> list[str]:
    """``n`` distinct colours (hex), one per mode: matplotlib's ten-colour cycle up to
    ten modes, the ``turbo`` map beyond, sampled in golden-ratio steps so that
    neighbouring modes (the ones that lie close or repeat) get far-apart hues."""
    import matplotlib as mpl
    from matplotlib.colors import to_hex

    if n <= 10:
        return [to_hex(f"C{i}") for i in range(n)]
    cmap = mpl.colormaps["turbo"].resampled(4096)
    return [to_hex(cmap(0.04 + 0.92 * ((0.5 + i * 0.6180339887) % 1.0))) for i in range(n)]


def excitation_styles(n: int) -> list[tuple[str, Any, str]]:
    """``(colour, matplotlib dash, plotly dash)`` of ``n`` excitation lines: a colour
    each up to eight, then colour and dash together distinct up to 32."""
    return [(EXCITATION_COLOURS[k % 8], *DASHES[(k + k // 8) % len(DASHES)]) for k in range(n)]


def excitation_label(name: str, order: float) -> str:
    """``"1x mesh (order 30)"``: an excitation line's name and its order (multiple of
    the input rotation frequency)."""
    return f"{name} (order {float(order):.4g})"


@dataclass(frozen=True)
class FrequencyAxis:
    """The top of a Campbell diagram's frequency axis (Hz), the excitation lines left
    off (``(name, frequency at the top of the operating range in Hz)``) and the tracked
    modes above it (``(mode, lowest Hz, highest Hz)``)."""

    top: float
    clipped: tuple[tuple[str, float], ...]
    above: tuple[tuple[int, float, float], ...] = ()

    def note(self, rpm: float) -> str:
        """``"modes 7-12 above 3.3 kHz: 5.1-27 kHz; off the chart at 1230 rpm: 2x mesh
        1353 Hz"`` (empty when nothing is left off)."""
        parts = []
        if self.above:
            modes = modes_span([m for m, _, _ in self.above])
            lo = min(a for _, a, _ in self.above)
            hi = max(b for _, _, b in self.above)
            what = "mode" if len(self.above) == 1 else "modes"
            span = hz(lo) if hz(lo) == hz(hi) else f"{hz(lo, False)}-{hz(hi)}"
            parts.append(f"{what} {modes} above {hz(self.top)}: {span}")
        if self.clipped:
            lines = ", ".join(f"{n} {f:.4g} Hz" for n, f in self.clipped)
            parts.append(f"off the chart at {rpm:.4g} rpm: {lines}")
        return "; ".join(parts)


def hz(f: float, unit: bool = True) -> str:
    """``"3.3 kHz"`` / ``"870 Hz"``: a frequency to two significant digits (three
    from 10 kHz on)."""
    if f >= 1e3:
        v = f"{f / 1e3:.2g}" if f < 1e4 else f"{f / 1e3:.0f}"
        return v + (" kHz" if unit else "")
    return f"{float(f'{f:.2g}'):g}" + (" Hz" if unit else "")


def modes_span(modes: Sequence[int]) -> str:
    """``"7-12"``, ``"3, 5, 8-10"``: mode numbers, runs joined."""
    out: list[str] = []
    ms = sorted(set(int(m) for m in modes))
    i = 0
    while i < len(ms):
        j = i
        while j + 1 < len(ms) and ms[j + 1] == ms[j] + 1:
            j += 1
        out.append(str(ms[i]) if j == i else f"{ms[i]}-{ms[j]}" if j > i + 1
                   else f"{ms[i]}, {ms[j]}")  # fmt: skip
        i = j + 1
    return ", ".join(out)


def frequency_axis(ds: xr.Dataset, fmax: float | None = None) -> FrequencyAxis:
    """The frequency axis of a Campbell diagram: where excitations can meet modes.

    The top is :data:`MARGIN` above the highest excitation frequency over the operating
    range (an excitation line beyond :data:`CAP` times the highest natural frequency x
    1.1 left off and named), and at least :data:`MARGIN` above the lowest elastic mode;
    modes wholly above the top are named (:meth:`FrequencyAxis.note`) rather than
    stretching the axis. Without excitations, 1.1 x the highest natural frequency.

    Parameters
    ----------
    ds : xarray.Dataset
        A Campbell dataset (``frequency``, ``excitation``, ``order``, the operating
        range in its attributes).
    fmax : float, optional
        Top of the axis (Hz) instead.

    Returns
    -------
    FrequencyAxis
    """
    f = ds["frequency"].values
    good = f[np.isfinite(f) & (f > 0)]
    base = 1.1 * float(good.max()) if good.size else 1.0
    hi = float(ds.attrs.get("operating_max_rad_s", 0.0) or 0.0)
    exc = {str(n): float(q) * hi / TWO_PI for n, q in
           zip(ds["excitation"].values, ds["order"].values, strict=True)}  # fmt: skip
    if fmax is not None:
        if isinstance(fmax, bool) or not (isinstance(fmax, int | float) and 0 < fmax < np.inf):
            raise ReducerlabError(f"fmax must be a positive frequency (Hz), got {fmax!r}")
        top = float(fmax)
    else:
        within = [v for v in exc.values() if 0 < v <= CAP * base]
        lowest = [float(np.nanmin(np.where(f[:, j] > 0, f[:, j], np.nan))) for j in
                  range(f.shape[1]) if np.any(f[:, j] > 0)]  # fmt: skip
        top = (max(MARGIN * max(within), MARGIN * min(lowest) if lowest else 0.0)
               if within else base)  # fmt: skip
    above = []
    for j, m in enumerate(ds["mode"].values):
        fj = f[:, j][np.isfinite(f[:, j])]
        if fj.size and fj.min() > top:
            above.append((int(m), float(fj.min()), float(fj.max())))
    return FrequencyAxis(top, tuple((n, v) for n, v in exc.items() if v > top), tuple(above))


def coincident(f: np.ndarray, rtol: float = COINCIDENT) -> list[int]:
    """For each tracked mode (columns of ``f``, speed x mode) the index of the first
    earlier mode it coincides with (within ``rtol`` at every speed where both are
    finite and elastic: a repeated frequency), or -1."""
    out = [-1] * f.shape[1]
    for j in range(f.shape[1]):
        for i in range(j):
            ok = np.isfinite(f[:, i]) & np.isfinite(f[:, j]) & (f[:, i] > 0)
            if ok.any() and np.all(np.abs(f[ok, j] - f[ok, i]) <= rtol * f[ok, i]):
                out[j] = i if out[i] < 0 else out[i]
                break
    return out


def coincident_dash(f: np.ndarray) -> list[int]:
    """How many modes before each one share its line (0: it is drawn solid; 1, 2, ...:
    dashed, dotted, so that the earlier colour shows through)."""
    first = coincident(f)
    count: dict[int, int] = {}
    out = []
    for i in first:
        if i < 0:
            out.append(0)
        else:
            count[i] = count.get(i, 0) + 1
            out.append(count[i])
    return out


def short_name(name: str) -> str:
    """An excitation's name without its parenthesis, for a label at its line's end:
    ``"2x mesh 2"`` of ``"2x mesh 2 (gears 3-4)"`` (the legend gives the whole)."""
    return name.split(" (", 1)[0]


def unique_crossings(rows: Sequence[Mapping[str, Any]]) -> list[list[Mapping[str, Any]]]:
    """Crossing rows grouped where they are one point of the diagram (one excitation,
    the same speed and frequency to 1e-6: the modes of a repeated eigenvalue), in the
    order of their first row."""
    groups: dict[tuple, list[Mapping[str, Any]]] = {}
    for r in rows:
        key = (str(r["excitation"]), float(f"{r['speed_rpm']:.6g}"),
               float(f"{r['frequency_hz']:.6g}"))  # fmt: skip
        groups.setdefault(key, []).append(r)
    return list(groups.values())


def modes_text(group: Sequence[Mapping[str, Any]]) -> str:
    """``"mode 3"`` or ``"modes 1, 2"`` of a group of crossing rows."""
    modes = sorted({int(r["mode"]) for r in group})
    return ("mode " if len(modes) == 1 else "modes ") + ", ".join(map(str, modes))


def spread(values: list[float], gap: float) -> list[float]:
    """Label positions (in the order given) pushed apart to at least ``gap``, upward."""
    order = np.argsort(values, kind="stable")
    out = list(values)
    last = -np.inf
    for i in order:
        out[i] = max(values[i], last + gap)
        last = out[i]
    return out


def damping_scale(ds: xr.Dataset) -> tuple[np.ndarray, Any]:
    """Log decrement (speed, mode) and its colour normalisation."""
    from matplotlib.colors import Normalize

    from ..analysis.complex_modal import log_decrement

    d = (ds["log_decrement"].values if "log_decrement" in ds
         else log_decrement(ds["damping_ratio"].values))  # fmt: skip
    ok = d[np.isfinite(d) & (ds["frequency"].values > 0)]
    lo, hi = (float(ok.min()), float(ok.max())) if ok.size else (0.0, 1.0)
    if hi - lo < 1e-9 * max(abs(hi), 1.0):
        lo, hi = lo - 0.5 * max(abs(lo), 1e-3), hi + 0.5 * max(abs(hi), 1e-3)
    return d, Normalize(lo, hi)


def whirl_marks(whirl: np.ndarray) -> np.ndarray:
    """Sample indices where a branch's whirl is marked: about 24 along it and every
    sample where its whirl changes."""
    n = whirl.size
    idx = set(range(0, n, max(1, n // 24)))
    idx |= set((np.nonzero(whirl[1:] != whirl[:-1])[0] + 1).tolist())
    return np.array(sorted(idx), dtype=int)


def sig(a: Any, digits: int = 4) -> list[Any]:
    """Values rounded to ``digits`` significant digits, NaN as None (compact JSON)."""
    a = np.asarray(a, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        mag = np.where(np.isfinite(a) & (a != 0), np.floor(np.log10(np.abs(a))), 0)
    scale = 10.0 ** (digits - 1 - mag)
    r = np.round(a * scale) / scale
    return [None if not np.isfinite(v) else float(f"{v:.{digits}g}") for v in r]
