"""Report what ParaView's own readers see in VTK XML files written by fissure.

Run with ParaView's interpreter (Debian: packages `paraview` + `python3-paraview`):

    pvpython tests/paraview/check_vtk.py FILE [FILE ...] [--expect-json E.json | --expect '{...}']
                                          [--rtol 1e-12] [--atol 0]

FILE is a `.vtu` (read with XMLUnstructuredGridReader) or a `.pvd` (read with PVDReader, every
time step). Exactly one line of JSON goes to stdout (ParaView may log to stderr):

- one FILE: the description of that file;
- several FILEs: {"ok": bool, "paraview": "5.11.0", "files": [description, ...]}.

Description of a `.vtu`:
    {"path", "kind": "vtu", "ok", "paraview", "errors": [...], "warnings": [...],
     "class": "vtkUnstructuredGrid", "points", "cells", "cell_types": {"<vtk id>": count},
     "bounds": [xmin, xmax, ymin, ymax, zmin, zmax],
     "point_data": {name: array}, "cell_data": {name: array}}
    array = {"components", "tuples", "type" (e.g. "double"),
             "range": [min, max] over all components,
             "component_ranges": [[min, max] per component],
             "magnitude_range": [min, max] (only if components > 1)}
    A range is null when the array has no tuples.
Description of a `.pvd`:
    {"path", "kind": "pvd", "ok", "paraview", "errors", "warnings", "times": [t0, t1, ...],
     "steps": [{"time", "data_time", "class", "blocks": [block, ...]}, ...]}
    block = the `.vtu` description fields (class, points, cells, ...) plus "name" (the
    nearest block name in the multiblock tree, null for a single-part collection) and
    "index" (leaf order).

"errors" and "warnings" are the messages VTK sent to its output window while reading (the
readers do not raise: a missing or corrupt file only shows up there). "ok" is false when
there is any error.

Expectations: a JSON object matched as a subset of the description: every key of the
expectation must exist with an equal value (numbers within rtol/atol, lists element by
element with equal lengths, objects recursively). With several FILEs the expectation is a
list, one object (or null) per file. The result is added as "expect": {"ok", "mismatches"}.

Exit status: 0 all read without errors (and expectations met); 1 a reader error; 2 bad
usage (unknown extension, unreadable expectation); 3 an expectation not met.
"""

import argparse
import json
import math
import os
import sys


def fail_usage(message):
    print(json.dumps({"ok": False, "usage_error": message}))
    sys.exit(2)


class Messages:
    """Collects the errors and warnings VTK sends to its output window."""

    def __init__(self):
        from vtkmodules.util import vtkConstants
        from vtkmodules.util.misc import calldata_type
        from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow

        self.errors = []
        self.warnings = []

        @calldata_type(vtkConstants.VTK_STRING)
        def on_error(_obj, _event, text):
            self.errors.append(clean(text))

        @calldata_type(vtkConstants.VTK_STRING)
        def on_warning(_obj, _event, text):
            self.warnings.append(clean(text))

        # Keep the callbacks alive as long as this object.
        self._callbacks = (on_error, on_warning)
        window = vtkOutputWindow.GetInstance()
        window.AddObserver(vtkCommand.ErrorEvent, on_error)
        window.AddObserver(vtkCommand.WarningEvent, on_warning)

    def take(self):
        errors, warnings = self.errors, self.warnings
        self.errors, self.warnings = [], []
        return errors, warnings


def clean(text):
    text = text if isinstance(text, str) else str(text)
    return " ".join(text.split())


def finite_or_none(x):
    return x if math.isfinite(x) else None


def array_range(array, component):
    lo, hi = array.GetRange(component)
    lo, hi = finite_or_none(lo), finite_or_none(hi)
    return None if lo is None or hi is None else [lo, hi]


def describe_array(array):
    n_comp = array.GetNumberOfComponents()
    n_tuples = array.GetNumberOfTuples()
    out = {
        "components": n_comp,
        "tuples": n_tuples,
        "type": array.GetDataTypeAsString(),
    }
    if n_tuples == 0:
        out["range"] = None
        out["component_ranges"] = [None] * n_comp
        if n_comp > 1:
            out["magnitude_range"] = None
        return out
    comps = [array_range(array, c) for c in range(n_comp)]
    out["component_ranges"] = comps
    if all(r is not None for r in comps):
        out["range"] = [min(r[0] for r in comps), max(r[1] for r in comps)]
    else:
        out["range"] = None
    if n_comp > 1:
        out["magnitude_range"] = array_range(array, -1)
    return out


def describe_attributes(data):
    out = {}
    for i in range(data.GetNumberOfArrays()):
        array = data.GetAbstractArray(i)
        name = array.GetName()
        if array.IsA("vtkDataArray"):
            out[name] = describe_array(array)
        else:
            out[name] = {
                "components": array.GetNumberOfComponents(),
                "tuples": array.GetNumberOfTuples(),
                "type": array.GetDataTypeAsString(),
            }
    return out


def describe_dataset(ds):
    out = {"class": ds.GetClassName()}
    n_points = ds.GetNumberOfPoints()
    n_cells = ds.GetNumberOfCells()
    out["points"] = n_points
    out["cells"] = n_cells
    types = {}
    for c in range(n_cells):
        t = str(ds.GetCellType(c))
        types[t] = types.get(t, 0) + 1
    out["cell_types"] = types
    out["bounds"] = [finite_or_none(b) for b in ds.GetBounds()] if n_points else None
    out["point_data"] = describe_attributes(ds.GetPointData())
    out["cell_data"] = describe_attributes(ds.GetCellData())
    return out


def leaves(data, name=None, found=None):
    """Leaf data sets of a (possibly nested) multiblock, each with its nearest block name."""
    found = [] if found is None else found
    if data is None:
        return found
    if data.IsA("vtkMultiBlockDataSet"):
        for i in range(data.GetNumberOfBlocks()):
            child_name = name
            if data.HasMetaData(i):
                meta = data.GetMetaData(i)
                if meta.Has(data.NAME()):
                    child_name = meta.Get(data.NAME())
            leaves(data.GetBlock(i), child_name, found)
    elif data.IsA("vtkDataSet"):
        found.append((name, data))
    else:
        found.append((name, None))
    return found


def as_list(value):
    try:
        return [float(v) for v in value]
    except TypeError:
        return [float(value)]


def read_vtu(path, simple):
    reader = simple.XMLUnstructuredGridReader(FileName=[path])
    reader.UpdatePipeline()
    data = reader.GetClientSideObject().GetOutputDataObject(0)
    out = describe_dataset(data)
    simple.Delete(reader)
    return out


def read_pvd(path, simple):
    from vtkmodules.vtkCommonDataModel import vtkDataObject

    reader = simple.PVDReader(FileName=path)
    times = as_list(reader.TimestepValues) if reader.TimestepValues is not None else []
    steps = []
    for t in times or [None]:
        if t is None:
            reader.UpdatePipeline()
        else:
            reader.UpdatePipeline(t)
        data = reader.GetClientSideObject().GetOutputDataObject(0)
        info = data.GetInformation()
        data_time = info.Get(vtkDataObject.DATA_TIME_STEP()) if info.Has(vtkDataObject.DATA_TIME_STEP()) else None
        blocks = []
        for index, (name, leaf) in enumerate(leaves(data)):
            block = {"name": name, "index": index}
            if leaf is None:
                block["class"] = None
            else:
                block.update(describe_dataset(leaf))
            blocks.append(block)
        steps.append({"time": t, "data_time": data_time, "class": data.GetClassName(), "blocks": blocks})
    simple.Delete(reader)
    return {"times": times, "steps": steps}


def close(a, b, rtol, atol):
    return abs(a - b) <= atol + rtol * max(abs(a), abs(b))


def match(expected, actual, where, rtol, atol, mismatches):
    if isinstance(expected, dict):
        if not isinstance(actual, dict):
            mismatches.append(f"{where}: expected an object, got {json.dumps(actual)}")
            return
        for key, value in expected.items():
            if key not in actual:
                mismatches.append(f"{where}.{key}: missing (have {sorted(actual)})")
            else:
                match(value, actual[key], f"{where}.{key}", rtol, atol, mismatches)
    elif isinstance(expected, list):
        if not isinstance(actual, list) or len(actual) != len(expected):
            mismatches.append(f"{where}: expected {json.dumps(expected)}, got {json.dumps(actual)}")
            return
        for i, (e, a) in enumerate(zip(expected, actual)):
            match(e, a, f"{where}[{i}]", rtol, atol, mismatches)
    elif isinstance(expected, bool) or expected is None or isinstance(expected, str):
        if expected != actual:
            mismatches.append(f"{where}: expected {json.dumps(expected)}, got {json.dumps(actual)}")
    elif isinstance(expected, (int, float)):
        if isinstance(actual, bool) or not isinstance(actual, (int, float)) or not close(expected, actual, rtol, atol):
            mismatches.append(f"{where}: expected {expected!r}, got {json.dumps(actual)}")
    else:
        mismatches.append(f"{where}: unsupported expectation {expected!r}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("files", nargs="+", help=".vtu or .pvd files")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--expect-json", metavar="FILE", help="expectation file (JSON)")
    group.add_argument("--expect", metavar="JSON", help="expectation as a JSON string")
    parser.add_argument("--rtol", type=float, default=1e-12, help="relative tolerance for numbers")
    parser.add_argument("--atol", type=float, default=0.0, help="absolute tolerance for numbers")
    args = parser.parse_args()

    expectation = None
    try:
        if args.expect_json is not None:
            with open(args.expect_json) as f:
                expectation = json.load(f)
        elif args.expect is not None:
            expectation = json.loads(args.expect)
    except (OSError, ValueError) as e:
        fail_usage(f"cannot read the expectation: {e}")
    if len(args.files) > 1 and expectation is not None:
        if not isinstance(expectation, list) or len(expectation) != len(args.files):
            fail_usage("with several files the expectation must be a list with one entry per file")
    if len(args.files) > 1 and expectation is not None:
        expectations = expectation
    else:
        expectations = [expectation] * len(args.files)

    for path in args.files:
        if os.path.splitext(path)[1].lower() not in (".vtu", ".pvd"):
            fail_usage(f"{path}: expected a .vtu or .pvd file")

    from paraview import simple

    version = simple.GetParaViewSourceVersion().replace("paraview version ", "")
    messages = Messages()

    results = []
    any_error = False
    any_mismatch = False
    for path, expected in zip(args.files, expectations):
        out = {"path": path, "kind": os.path.splitext(path)[1].lower()[1:], "paraview": version}
        try:
            if not os.path.isfile(path):
                messages.errors.append(f"no such file: {path}")
            elif out["kind"] == "vtu":
                out.update(read_vtu(os.path.abspath(path), simple))
            else:
                out.update(read_pvd(os.path.abspath(path), simple))
        except Exception as e:  # a reader crash in Python is a reader error too
            messages.errors.append(f"{type(e).__name__}: {e}")
        errors, warnings = messages.take()
        out["errors"] = errors
        out["warnings"] = warnings
        out["ok"] = not errors
        any_error = any_error or bool(errors)
        if expected is not None:
            mismatches = []
            match(expected, out, "$", args.rtol, args.atol, mismatches)
            out["expect"] = {"ok": not mismatches, "mismatches": mismatches}
            any_mismatch = any_mismatch or bool(mismatches)
        results.append(out)

    if len(results) == 1:
        document = results[0]
    else:
        document = {"ok": all(r["ok"] for r in results), "paraview": version, "files": results}
    sys.stdout.write(json.dumps(document, allow_nan=False) + "\n")
    sys.stdout.flush()
    sys.exit(1 if any_error else 3 if any_mismatch else 0)


if __name__ == "__main__":
    main()
