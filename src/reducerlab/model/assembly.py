"""The generic lumped-parameter :class:`Model` and its assembly.

``M q'' + C q' + K_lin q + sum_m g_m [k_m(t) f(g_m . q - e_m(t)) + c_m (g_m . q' - e_m'(t))]
= F(t)``

The assembler walks the elements in their given order (deterministic summation) and adds
each :class:`~reducerlab.model.elements.Contribution` into the global arrays. It never
branches on element type.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError
from .dofs import Dof
from .elements import Contribution, Element
from .laws import TimeLaw
from .system import NonlinearSystem

__all__ = ["Matrices", "Model"]

_COMPLEX_STEP = 1e-30


@dataclass(frozen=True)
class Matrices:
    """Global mass (``M``), damping (``C``) and mean stiffness (``K``) matrices in SI."""

    M: NDArray[np.float64]
    C: NDArray[np.float64]
    K: NDArray[np.float64]


def _scatter(target: NDArray, idx: list[int], block: Any) -> None:
    """``target[ix_(idx, idx)] += block`` for the small blocks of elements (no index
    arrays built: elements couple one to a few DOFs)."""
    if len(idx) <= 4 and np.ndim(block) == 2:
        rows = block.tolist() if isinstance(block, np.ndarray) else block
        for a, ia in enumerate(idx):
            for b, ib in enumerate(idx):
                target[ia, ib] += rows[a][b]
        return
    target[np.ix_(idx, idx)] += block


class Model:
    """A lumped-parameter model: named DOFs and elements.

    Parameters
    ----------
    dofs : sequence of Dof
        Generalised coordinates; their order is the order of every matrix and vector.
    elements : sequence of Element
        Inertias, supports, couplings, meshes, speed terms and loads.
    speed : float
        Reference (input) speed ``Omega`` (rad/s) used by speed-dependent elements.
    name : str
        Title for results.
    metadata : dict, optional
        Free-form provenance (design, design hash) copied into results.

    Examples
    --------
    >>> from reducerlab.model import Dof, Inertia, Support, Model
    >>> m = Model([Dof("a", "x")], [Inertia("a.x", 2.0), Support("a.x", 8.0)])
    >>> m.matrices().K
    array([[8.]])
    """

    def __init__(
        self,
        dofs: Sequence[Dof],
        elements: Iterable[Element],
        *,
        speed: float = 0.0,
        name: str = "",
        metadata: dict[str, Any] | None = None,
    ) -> None:
        self.dofs: tuple[Dof, ...] = tuple(dofs)
        self.elements: tuple[Element, ...] = tuple(elements)
        try:
            self.speed = float(speed)
        except (TypeError, ValueError):
            raise ModelError(f"Model: speed must be a number in rad/s, got {speed!r}") from None
        self.name = name
        self.metadata = dict(metadata or {})
        self._check()

    # ------------------------------------------------------------------ structure
    def _check(self) -> None:
        if not self.dofs:
            raise ModelError("Model: needs at least one DOF")
        for d in self.dofs:
            if not isinstance(d, Dof):
                raise ModelError(f"Model: dofs must be Dof objects, got {d!r}")
        names = [d.name for d in self.dofs]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ModelError(f"Model: duplicate DOF names {dup}")
        enames = []
        for e in self.elements:
            if not isinstance(e, Element):
                raise ModelError(f"Model: elements must be Element objects, got {e!r}")
            enames.append(e.name)
            missing = [d for d in e.dofs if d not in self.index]
            if missing:
                raise ModelError(
                    f"element {e.name!r} refers to unknown DOF(s) {missing}; the model has {names}"
                )
            if len(set(e.dofs)) != len(e.dofs):
                raise ModelError(f"element {e.name!r} lists a DOF twice: {list(e.dofs)}")
        dup = sorted({n for n in enames if enames.count(n) > 1})
        if dup:
            raise ModelError(f"Model: duplicate element names {dup}; give each a unique name")
        if not np.isfinite(self.speed):
            raise ModelError(f"Model: speed must be finite, got {self.speed!r}")

    @cached_property
    def index(self) -> dict[str, int]:
        """DOF name -> row index."""
        return {d.name: i for i, d in enumerate(self.dofs)}

    @property
    def dof_names(self) -> list[str]:
        """DOF names in matrix order."""
        return [d.name for d in self.dofs]

    @property
    def n(self) -> int:
        """Number of DOFs."""
        return len(self.dofs)

    def element(self, name: str) -> Element:
        """The element called ``name``."""
        for e in self.elements:
            if e.name == name:
                return e
        raise ModelError(
            f"no element named {name!r}; elements are {[e.name for e in self.elements]}"
        )

    def _local(self, e: Element, speed: float | complex | None = None) -> Contribution:
        return e.contribution(
            [self.dofs[self.index[d]] for d in e.dofs], self.speed if speed is None else speed
        )

    # ------------------------------------------------------------------ assembly
    def element_matrices(
        self, e: Element, speed: float | complex | None = None
    ) -> tuple[NDArray[np.intp], Matrices]:
        """Global indices and local ``M, C, K`` of one element, mean mesh terms included."""
        idx = np.array([self.index[d] for d in e.dofs], dtype=np.intp)
        c = self._local(e, speed)
        n = len(idx)
        blocks = []
        for arr in (c.mass, c.damping, c.stiffness):
            blocks.append(np.zeros((n, n)) if arr is None else np.asarray(arr))
        m_, c_, k_ = blocks
        for line in c.lines:
            gg = np.outer(line.g, line.g)
            k_ = k_ + line.stiffness.mean * gg
            c_ = c_ + line.damping * gg
        return idx, Matrices(m_, c_, k_)

    def matrices(self) -> Matrices:
        """Assemble ``M``, ``C`` and the mean ``K`` (mesh stiffness at its time average).

        Raises :class:`ModelError` naming the DOF and element when an entry is not finite
        or the mass and stiffness are out of the range of the eigen-solvers (see
        :meth:`check_numerics`).
        """
        with np.errstate(over="ignore", invalid="ignore"):  # reported below, by DOF
            mats = self._assemble(self.elements)
        self.check_numerics(mats.M, mats.C, mats.K)
        return mats

    def check_numerics(self, M: NDArray, C: NDArray, K: NDArray) -> None:
        """Check assembled matrices before any solver sees them.

        * every entry finite (else the DOF and the elements acting on it are named: an
          extreme value overflowed);
        * when every DOF has inertia: with ``D = diag(M)^-1/2``, the scaled mass
          ``D M D`` (unit diagonal) must have its smallest eigenvalue above
          ``1e-12`` (else the inertia couplings make ``M`` singular to working
          precision), and the scaled stiffness ``D K D`` (squared natural frequencies
          of each DOF alone, rad^2/s^2) must stay within ``1e150`` (else the eigen-
          solvers overflow: an inertia or stiffness value is extreme; the DOF with the
          largest ``K_ii / M_ii`` is named with its inertia).
        """
        for what, a in (("mass", M), ("damping", C), ("stiffness", K)):
            if not np.all(np.isfinite(a)):
                i = int(np.argwhere(~np.isfinite(a))[0][0])
                raise ModelError(
                    f"model {self.name!r}: the {what} at DOF {self.dof_names[i]!r} is not "
                    f"finite: {self._culprits(i)}; an extreme value overflowed (or NaN "
                    "was given): use values within the physical range"
                )
        d = np.real(np.diag(M))
        if not np.all(d > 0):
            return  # massless DOFs: the analyses that need M^-1 say so
        D = 1.0 / np.sqrt(d)
        with np.errstate(over="ignore", invalid="ignore"):
            Ms = np.real(M) * D[:, None] * D[None, :]
            Ks = np.real(K) * D[:, None] * D[None, :]
            ratio = np.abs(np.diag(Ks))
        if not np.all(np.isfinite(Ks)) or np.abs(Ks).max(initial=0.0) > 1e150:
            i = int(np.nanargmax(np.where(np.isfinite(ratio), ratio, np.inf)))
            raise ModelError(
                f"model {self.name!r}: DOF {self.dof_names[i]!r} has stiffness / inertia "
                f"{K[i, i]:.3g} / {M[i, i]:.3g} (SI), a squared frequency beyond the range "
                f"of the eigen-solvers; {self._culprits(i)}: check for an extreme inertia "
                "or stiffness value"
            )
        if self.n > 1:
            lam = np.linalg.eigvalsh(0.5 * (Ms + Ms.T))  # every build: values only
            if lam[0] <= 1e-12 * lam[-1]:
                v = np.abs(np.linalg.eigh(0.5 * (Ms + Ms.T))[1][:, 0])
                dofs = [self.dof_names[i] for i in np.nonzero(v > 0.1 * v.max())[0]]
                raise ModelError(
                    f"model {self.name!r}: the mass matrix is singular to working "
                    f"precision: the inertia couplings of DOFs {dofs} cancel (scaled "
                    f"smallest eigenvalue {lam[0]:.3g}); check their mass elements"
                )

    def _culprits(self, i: int) -> str:
        """The elements acting on DOF ``i`` with their largest local coefficient."""
        dof = self.dof_names[i]
        parts = []
        for e in self.elements:
            if dof not in e.dofs:
                continue
            c = self._local(e)
            vals = [np.abs(np.asarray(b, complex)).max() for b in (c.mass, c.damping,
                    c.stiffness) if b is not None]  # fmt: skip
            vals += [max(abs(line.stiffness.mean), abs(line.damping), abs(line.cubic))
                     for line in c.lines]  # fmt: skip
            if vals:
                parts.append((float(np.nan_to_num(max(vals), nan=np.inf)), e.name))
        parts.sort(reverse=True)
        if not parts:
            return f"no element acts on {dof!r}"
        return "elements on it: " + ", ".join(f"{n!r} (coefficient {v:.3g})" for v, n in parts)

    def _assemble(self, elements: Iterable[Element], speed: Any = None) -> Matrices:
        n = self.n
        out = [np.zeros((n, n)) for _ in range(3)]
        for e in elements:
            idx, mats = self.element_matrices(e, speed)
            ix = np.ix_(idx, idx)
            for k, block in enumerate((mats.M, mats.C, mats.K)):
                if np.iscomplexobj(block) and not np.iscomplexobj(out[k]):
                    out[k] = out[k].astype(complex)
                out[k][ix] += block
        return Matrices(*out)

    def nonlinear(self) -> NonlinearSystem:
        """Flat-array description of the full nonlinear equations of motion.

        Linear elements go into ``M, C, K``; each mesh becomes a row of ``G`` with its
        stiffness law, damping, backlash half width and transmission error law.
        """
        n = self.n
        M, C, K = (np.zeros((n, n)) for _ in range(3))
        G, k_laws, e_laws, c_line, b_line, k3_line, line_names = [], [], [], [], [], [], []
        power: list[tuple[float, float]] = []
        load_dofs, load_laws = [], []
        for e in self.elements:
            idx = [self.index[d] for d in e.dofs]
            c = self._local(e)
            for target, block in ((M, c.mass), (C, c.damping), (K, c.stiffness)):
                if block is not None:
                    _scatter(target, idx, block)
            for j, line in enumerate(c.lines):
                g = np.zeros(n)
                g[idx] = line.g
                G.append(g)
                k_laws.append(line.stiffness)
                e_laws.append(line.error)
                c_line.append(line.damping)
                b_line.append(line.backlash.half_width)
                k3_line.append(line.cubic)
                power.append((line.exponent, line.reference))
                line_names.append(e.name if len(c.lines) == 1 else f"{e.name}[{j}]")
            for local, law in c.loads:
                load_dofs.append(idx[local])
                load_laws.append(law)
        self.check_numerics(M, C, K)
        return NonlinearSystem.from_laws(
            dof_names=self.dof_names,
            M=M,
            C=C,
            K=K,
            G=np.array(G).reshape(len(G), n),
            line_names=line_names,
            stiffness_laws=k_laws,
            line_damping=np.array(c_line, dtype=float),
            half_backlash=np.array(b_line, dtype=float),
            line_cubic=np.array(k3_line, dtype=float),
            line_power=np.array(power, dtype=float).reshape(len(power), 2),
            error_laws=e_laws,
            load_matrix=np.eye(n)[:, load_dofs].reshape(n, len(load_dofs)),
            load_laws=load_laws,
        )

    # ------------------------------------------------------------------ parameters
    def parameter(self, path: str) -> Any:
        """Value of a parameter: ``"speed"`` or ``"element.field[.subfield]"``.

        A path ending on a law (e.g. ``"mesh1.stiffness"``) means the law's mean.
        """
        if path == "speed":
            return self.speed
        elem, fields = self._split(path)
        obj: Any = elem
        for f in fields:
            obj = getattr(obj, f)
        return obj.mean if isinstance(obj, TimeLaw) else obj

    def _split(self, path: str) -> tuple[Element, list[str]]:
        # element names may contain dots ("support:gear.x"): take the longest name that
        # is followed by ".FIELD" in the path
        owners = [
            e for e in self.elements if isinstance(path, str) and path.startswith(e.name + ".")
        ]
        if not owners:
            example = f"{self.elements[0].name}.FIELD" if self.elements else "ELEMENT.FIELD"
            raise ModelError(
                f"parameter path {path!r}: write 'speed' or 'ELEMENT.FIELD' (e.g. {example!r}); "
                f"elements are {[e.name for e in self.elements]}"
            )
        elem = max(owners, key=lambda e: len(e.name))
        ename, rest = elem.name, path[len(elem.name) + 1 :]
        fields = rest.split(".")
        obj: Any = elem
        for i, f in enumerate(fields):
            if not dataclasses.is_dataclass(obj) or f not in {
                x.name for x in dataclasses.fields(obj)
            }:
                names = (
                    sorted(x.name for x in dataclasses.fields(obj) if x.name != "name")
                    if dataclasses.is_dataclass(obj)
                    else []
                )
                where = ".".join([ename, *fields[:i]])
                raise ModelError(
                    f"parameter path {path!r}: {where!r} has no parameter {f!r}"
                    + (f" (parameters: {', '.join(names)})" if names else "")
                )
            obj = getattr(obj, f)
        if isinstance(obj, TimeLaw):
            # the law's mean: a field, or derived (a piecewise polynomial, scaled to it)
            fields.append("mean")
        elif not isinstance(obj, int | float | complex | np.number) or isinstance(obj, bool):
            raise ModelError(f"parameter path {path!r}: not a scalar parameter ({obj!r})")
        return elem, fields

    @staticmethod
    def _replace_unchecked(obj: Any, fields: list[str], value: Any) -> Any:
        """Copy of ``obj`` with the nested field set, skipping validation (complex step)."""
        new = copy.copy(obj)
        if len(fields) == 1:
            # a derived mean (a cached property) is shadowed on the copy: the mean
            # matrices read only the mean
            object.__setattr__(new, fields[0], value)
        else:
            inner = Model._replace_unchecked(getattr(obj, fields[0]), fields[1:], value)
            object.__setattr__(new, fields[0], inner)
        return new

    @staticmethod
    def _replace(obj: Any, fields: list[str], value: Any) -> Any:
        if fields == ["mean"] and isinstance(obj, TimeLaw):
            return obj.with_mean(value)
        if len(fields) == 1:
            return dataclasses.replace(obj, **{fields[0]: value})
        inner = Model._replace(getattr(obj, fields[0]), fields[1:], value)
        return dataclasses.replace(obj, **{fields[0]: inner})

    def with_parameter(self, path: str, value: float) -> Model:
        """A new model with one parameter changed (validated as on construction)."""
        if path == "speed":
            return self.with_speed(value)
        elem, fields = self._split(path)
        new = self._replace(elem, fields, value)
        return Model(
            self.dofs,
            [new if e is elem else e for e in self.elements],
            speed=self.speed,
            name=self.name,
            metadata=self.metadata,
        )

    def with_speed(self, speed: float) -> Model:
        """A new model at another reference speed (rad/s)."""
        return Model(self.dofs, self.elements, speed=speed, name=self.name, metadata=self.metadata)

    def derivative(self, path: str) -> Matrices:
        """Exact ``dM/dp, dC/dp, dK/dp`` of the mean matrices for a parameter ``p``.

        Computed by the complex-step method on the element that owns ``p`` (or on every
        element for ``"speed"``), which is exact to round-off because no difference of
        nearly equal numbers is formed.
        """
        h = _COMPLEX_STEP
        if path == "speed":
            mats = self._assemble(self.elements, speed=self.speed + 1j * h)
        else:
            elem, fields = self._split(path)
            value = self.parameter(path)
            bumped = self._replace_unchecked(elem, fields, value + 1j * h)
            mats = self._assemble([bumped])
        return Matrices(*(np.imag(a) / h for a in (mats.M, mats.C, mats.K)))

    def __repr__(self) -> str:
        return (
            f"Model({self.name!r}, {self.n} DOFs, {len(self.elements)} elements, "
            f"speed={self.speed:g} rad/s)"
        )
