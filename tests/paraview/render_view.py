"""Render the recommended ParaView view of fissure runs to PNG files, offscreen.

Run with ParaView's interpreter under a virtual X server (Debian: `paraview`,
`python3-paraview`, `xvfb`):

    xvfb-run -a pvpython tests/paraview/render_view.py JOBS.json

JOBS.json is a list of jobs, each one of:

    {"png": OUT.png, "script": RUN/<stem>_view.py}
        run the view script a 3D cracked run writes (what `paraview --script=` does), then
        save the active view;
    {"png": OUT.png, "pvd": RUN/<stem>.pvd, "block": "body" | null, "warp": SCALE | null,
     "colour": [ASSOCIATION, ARRAY, COMPONENT | null]}
        the recipe of an example's header: the last time step, the block (null: a
        single-part collection), Warp By Vector on `displacement` with SCALE (null: none),
        coloured by the array (COMPONENT: an index, "Magnitude", or null for a scalar);
        optional "look_along": [dx, dy, dz] (the camera's direction of view, default −z)
        and "view_up" (default [0, 0, 1]).

Every job draws in a new render view (the sources of earlier jobs are not shown in it).
One line of JSON goes to stdout:
    {"ok": bool, "paraview": "5.11.0", "jobs": [{"png", "ok", "error"}]}
Exit status 0 when every image was written, 1 otherwise.
"""

import json
import os
import sys
import traceback

from paraview.simple import (
    ColorBy,
    CreateView,
    ExtractBlock,
    GetActiveViewOrCreate,
    GetAnimationScene,
    PVDReader,
    Render,
    SaveScreenshot,
    SetActiveView,
    Show,
    WarpByVector,
)
import paraview.simple as simple

RESOLUTION = [900, 600]


def new_view():
    view = CreateView("RenderView")
    view.ViewSize = RESOLUTION
    SetActiveView(view)
    return view


def white(view):
    simple.LoadPalette("WhiteBackground")


def recipe(job):
    reader = PVDReader(FileName=job["pvd"])
    reader.UpdatePipelineInformation()
    times = reader.TimestepValues
    times = list(times) if hasattr(times, "__len__") else [times]
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    if times:
        scene.AnimationTime = times[-1]
    source = reader
    if job.get("block"):
        source = ExtractBlock(Input=source, Selectors=["/Root/" + job["block"]])
    if job.get("warp") is not None:
        source = WarpByVector(Input=source, Vectors=["POINTS", "displacement"], ScaleFactor=job["warp"])
    view = GetActiveViewOrCreate("RenderView")
    white(view)
    shown = Show(source, view)
    association, array, component = job["colour"]
    if isinstance(component, str):
        ColorBy(shown, (association, array, component))
    else:
        ColorBy(shown, (association, array))
        if component is not None:
            lut = simple.GetColorTransferFunction(array)
            lut.VectorMode = "Component"
            lut.VectorComponent = component
    shown.RescaleTransferFunctionToDataRange(True, False)
    shown.SetScalarBarVisibility(view, True)
    if job.get("look_along"):
        # A 3D interface is seen edge-on from the default camera (along −z).
        d = job["look_along"]
        view.CameraFocalPoint = [0.0, 0.0, 0.0]
        view.CameraPosition = [-d[0], -d[1], -d[2]]
        view.CameraViewUp = job.get("view_up", [0.0, 0.0, 1.0])
    view.ResetCamera(False)
    Render(view)
    return view


def from_script(job):
    script = job["script"]
    scope = {"__file__": script, "__name__": "__main__"}
    with open(script) as f:
        exec(compile(f.read(), script, "exec"), scope)
    view = GetActiveViewOrCreate("RenderView")
    Render(view)
    return view


def main():
    if len(sys.argv) != 2:
        print(json.dumps({"ok": False, "usage_error": "pvpython render_view.py JOBS.json"}))
        sys.exit(2)
    with open(sys.argv[1]) as f:
        jobs = json.load(f)
    from paraview import servermanager

    version = "%d.%d.%d" % (
        servermanager.vtkSMProxyManager.GetVersionMajor(),
        servermanager.vtkSMProxyManager.GetVersionMinor(),
        servermanager.vtkSMProxyManager.GetVersionPatch(),
    )
    results = []
    for job in jobs:
        new_view()
        result = {"png": job["png"], "ok": False, "error": None}
        try:
            view = from_script(job) if "script" in job else recipe(job)
            SaveScreenshot(job["png"], view, ImageResolution=RESOLUTION)
            result["ok"] = os.path.exists(job["png"])
            if not result["ok"]:
                result["error"] = "no image written"
        except Exception:
            result["error"] = traceback.format_exc()
        results.append(result)
    ok = all(r["ok"] for r in results)
    print(json.dumps({"ok": ok, "paraview": version, "jobs": results}), flush=True)
    sys.stderr.flush()
    # Skip the interpreter's teardown: ParaView 5.11 can crash there under xvfb (SIGSEGV
    # after the images are written), which would hide the real outcome.
    os._exit(0 if ok else 1)


if __name__ == "__main__":
    main()
