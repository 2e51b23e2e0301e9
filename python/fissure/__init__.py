"""Python bindings of fissure, the X-FEM crack contact toolkit.

Run a case file or a case written as a Python dict, with overrides of any case key, and
read the results as NumPy arrays::

    import fissure
    r = fissure.run("examples/inclined_crack_friction_2d.toml", out="out/mu03",
                    overrides={"cracks.0.contact.friction": 0.3})
    r.summary["steps"][-1]["contact"]["slip"]     # summary.json as a dict
    r.sif("inclined")["K_II"]                     # the sif.csv table of one crack
    r.lip_fields("inclined")["pressure"]          # the crack-lip fields of a step
    r.displacement()                              # nodal displacements, (nodes, dim)

A run writes exactly what ``fissure run`` writes into ``out`` (VTU/PVD, summary.json,
sif.csv, contact.csv, plots). Overrides are the command line's ``--set`` overrides,
validated like the file. Errors are exceptions: ``CaseError`` (a wrong key or value; its
``file``, ``line``, ``key`` and ``message`` attributes say where and what), ``SolveError``,
``OutputError`` and ``PanicError`` (a defect in fissure, caught before it could abort
the interpreter), all subclasses of ``FissureError``.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Mapping, Optional, Union

import numpy as np

from . import _native
from ._native import CaseError, FissureError, OutputError, PanicError, SolveError

__all__ = [
    "run",
    "to_toml",
    "Result",
    "FissureError",
    "CaseError",
    "SolveError",
    "OutputError",
    "PanicError",
    "__version__",
]

__version__ = _native.VERSION

#: Columns of :meth:`Result.sif`, those of ``sif.csv`` without ``crack``.
SIF_COLUMNS = ("step", "point", "x", "y", "z", "K_I", "K_II", "K_III", "G")

#: Columns of :meth:`Result.contact`, those of ``contact.csv`` without ``crack``.
CONTACT_COLUMNS = (
    "step",
    "points",
    "active",
    "stick",
    "slip",
    "lambda_min",
    "lambda_max",
    "friction_iterations",
    "active_set_iterations",
    "newton_iterations",
    "geometry_iterations",
    "residual",
)


def to_toml(case: Mapping[str, Any]) -> str:
    """The case-file (TOML) text of a case given as a dict.

    Sub-dicts are tables (``{"mesh": {...}}`` is ``[mesh]``), lists of dicts arrays of
    tables (``{"cracks": [{...}]}`` is ``[[cracks]]``), other values TOML values.
    """
    return _native.to_toml(dict(case))


def run(
    case: Union[str, os.PathLike, Mapping[str, Any]],
    out: Union[str, os.PathLike, None] = None,
    overrides: Optional[Mapping[str, Any]] = None,
    *,
    name: str = "case",
    base: Union[str, os.PathLike, None] = None,
    quiet: bool = True,
    verbose: bool = False,
) -> "Result":
    """Solves a case and writes its results into ``out``, like ``fissure run``.

    case: a case file path, or the case as a dict (see :func:`to_toml`).
    out: the output folder (default ``out/<case file stem>`` or ``out/<name>``).
    overrides: ``{"cracks.0.contact.friction": 0.3, ...}``: keys as for ``--set``
        (dotted, array entries by 0-based index), values Python numbers, strings,
        booleans or lists, validated like the file.
    name: for a dict case, the case name (output file names); its text is written to
        ``out/<name>.toml``, the file that errors' line numbers refer to.
    base: for a dict case, where its relative paths (mesh files) start (default: the
        current directory).
    quiet: print nothing (default); ``False`` prints the step tables and warnings.
    verbose: also print every Newton iteration of the contact loops.
    """
    ov = dict(overrides or {})
    show = verbose or not quiet
    if isinstance(case, Mapping):
        out_dir = Path(out) if out is not None else Path("out") / name
        text = to_toml(case)
        out_dir.mkdir(parents=True, exist_ok=True)
        path = out_dir / f"{name}.toml"
        path.write_text(text)
        base_dir = Path(base) if base is not None else Path.cwd()
        native = _native.run(str(path), str(out_dir), text=text, base=str(base_dir), overrides=ov,
                             verbose=show, newton=verbose)
    else:
        path = Path(case)
        out_dir = Path(out) if out is not None else Path("out") / path.stem
        native = _native.run(str(path), str(out_dir), overrides=ov, verbose=show, newton=verbose)
    return Result(native, out_dir)


class Result:
    """The results of a run: the summary as a dict, tables and fields as NumPy arrays.

    Steps are named by their ``index`` in ``summary["steps"]`` (the ``step`` column of
    sif.csv); ``step=None`` is the last one. Cracks are named by their ``name`` or their
    0-based position in the case.
    """

    def __init__(self, native: "_native.Results", out: Path):
        self._native = native
        #: The output folder.
        self.out = Path(out)
        #: ``summary.json`` as a dict.
        self.summary: dict = json.loads(native.summary_json())
        #: 2 or 3.
        self.dim: int = native.dim
        #: The ``index`` of every recorded step, in order.
        self.steps: list = list(native.step_indices())

    def __repr__(self) -> str:
        return f"<fissure.Result {self.summary.get('case')!r}: {len(self.steps)} steps, out={str(self.out)!r}>"

    @property
    def nodes(self) -> np.ndarray:
        """Mesh node coordinates, shape (nodes, dim)."""
        return self._native.nodes()

    def _pos(self, step: Optional[int]) -> int:
        if not self.steps:
            raise IndexError("the run recorded no step")
        if step is None:
            return len(self.steps) - 1
        try:
            return self.steps.index(step)
        except ValueError:
            raise IndexError(f"no step {step}: the recorded steps are {self.steps}") from None

    def _crack(self, crack: Union[str, int]) -> tuple:
        """(position, name) of a crack given by name or position."""
        names = [c["name"] for c in self.summary["steps"][0]["cracks"]] if self.summary.get("steps") else []
        if isinstance(crack, str):
            if crack not in names:
                raise KeyError(f"no crack named {crack!r}; the cracks are {names}")
            return names.index(crack), crack
        if not 0 <= int(crack) < len(names):
            raise IndexError(f"no crack {crack}: the case has {len(names)} cracks {names}")
        return int(crack), names[int(crack)]

    def displacement(self, step: Optional[int] = None) -> np.ndarray:
        """Nodal displacements at a step, shape (nodes, dim), rows in mesh node order."""
        return self._native.displacement(self._pos(step))

    def sif(self, crack: Union[str, int]) -> np.ndarray:
        """The SIF table of a crack: one row per step and front point (2D: per tip), a
        structured array with the fields of :data:`SIF_COLUMNS` (``r.sif(0)["K_II"]``)."""
        k, _ = self._crack(crack)
        rows = []
        for s in self.summary["steps"]:
            for j, p in enumerate(s["cracks"][k]["front"]):
                x = list(p["x"]) + [0.0] * (3 - len(p["x"]))
                rows.append((s["index"], j + 1, x[0], x[1], x[2], p["KI"], p["KII"], p["KIII"], p["G"]))
        dtype = [("step", "i8"), ("point", "i8")] + [(c, "f8") for c in SIF_COLUMNS[2:]]
        return np.array(rows, dtype=dtype)

    def contact(self, crack: Union[str, int]) -> np.ndarray:
        """The contact table of a crack (one row per step, empty without contact), a
        structured array with the fields of :data:`CONTACT_COLUMNS`."""
        _, name = self._crack(crack)
        rows = []
        for s in self.summary["steps"]:
            c = s.get("contact")
            if not c:
                continue
            it = c["iterations"]
            for cc in c["cracks"]:
                if cc["name"] == name:
                    geometry = it.get("geometry") or 0
                    rows.append((s["index"], cc["points"], cc["active"], cc["stick"], cc["slip"],
                                 cc["lambda_min"], cc["lambda_max"], it["friction"], it["active_set"],
                                 it["newton"], geometry, c["residual"]))
        ints = {"step", "points", "active", "stick", "slip", "friction_iterations", "active_set_iterations",
                "newton_iterations", "geometry_iterations"}
        dtype = [(c, "i8" if c in ints else "f8") for c in CONTACT_COLUMNS]
        return np.array(rows, dtype=dtype)

    def lip_fields(self, crack: Union[str, int], step: Optional[int] = None) -> dict:
        """The fields on the lips of a crack at a step, as written to
        ``<name>_crack_stepNNNN.vtu``: a dict of arrays with one row per lip point (each
        crack facet vertex once on each lip). ``x`` (coordinates), ``lip`` (+1 on the +
        side, −1 on the − side), ``displacement``, ``jump`` (+ minus −),
        ``normal_opening``, ``tangential_slip``, ``normal``; with contact also ``lambda``
        (≤ 0 in compression), ``pressure`` (−λ), ``Lambda``, ``Lambda_norm`` and
        ``status`` (0 open, 1 stick, 2 slip). Vectors have shape (n, dim)."""
        k, _ = self._crack(crack)
        return dict(self._native.lip_fields(k, self._pos(step)))
