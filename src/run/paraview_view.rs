//! The ParaView view script of a 3D cracked run, `<stem>_view.py`, written next to the
//! `.pvd`: `paraview --script=<stem>_view.py` opens the crack view directly (the body
//! block clipped by a plane through the crack and shown translucent in grey, the crack lips coloured
//! by the contact pressure or the opening, both warped by the displacement at a scale
//! that keeps every cell right side out, the last load step).
//!
//! Entry point: [`write_view_script`].

use std::fmt::Write;
use std::path::Path;

/// What the view is built from.
#[derive(Debug, Clone)]
pub struct ViewSpec {
    /// The case stem (names the script) and the `.pvd` file name.
    pub stem: String,
    pub pvd: String,
    /// A point of the crack (the centre of its front) and its unit normal.
    pub crack_centre: [f64; 3],
    pub crack_normal: [f64; 3],
    /// The crack's size: the largest distance of its front from `crack_centre` (the
    /// camera frames a region a few times this size).
    pub crack_size: f64,
    /// Diagonal of the mesh's bounding box.
    pub size: f64,
    /// Largest nodal displacement over the steps.
    pub max_displacement: f64,
    /// Colour the lips by `pressure` (contact) rather than `normal_opening`.
    pub contact: bool,
}

/// The warp scale of the view: the largest displacement drawn as at most 5% of the
/// model's size (`size`, its bounding-box diagonal), rounded down to 1, 2 or 5 times a
/// power of ten. A displacement field whose largest value is 5% of the size changes
/// lengths by about a tenth where the strain is spread over the body, so the cells stay
/// right side out (a scale that draws the displacement as large as the body flattens or
/// inverts it under compression).
pub fn warp_scale(size: f64, max_displacement: f64) -> f64 {
    if !(max_displacement > 0.0) || !max_displacement.is_finite() || !(size > 0.0) {
        return 1.0;
    }
    let s = 0.05 * size / max_displacement;
    let p = 10f64.powf(s.log10().floor());
    let m = s / p;
    let m = if m >= 5.0 {
        5.0
    } else if m >= 2.0 {
        2.0
    } else {
        1.0
    };
    m * p
}

/// The axis of the clip plane: the global axis most nearly in the crack plane; of axes
/// within 1e-9 of each other (two axes in the plane, the facet normals' round-off aside) the
/// first, so that the choice does not hang on round-off (a surface crack in y = 0 is cut by
/// x = const, through its depth, not by z = const).
fn clip_normal(n: [f64; 3]) -> [f64; 3] {
    let mut best = 0;
    for i in 1..3 {
        if n[i].abs() < n[best].abs() - 1e-9 {
            best = i;
        }
    }
    let mut a = [0.0; 3];
    a[best] = 1.0;
    a
}

/// Writes `<stem>_view.py` into `dir` (`abs_dir`: the same directory, absolute, for when
/// ParaView does not tell the script where it is).
pub fn write_view_script(spec: &ViewSpec, dir: &Path, abs_dir: &Path) -> std::io::Result<std::path::PathBuf> {
    let scale = warp_scale(spec.size, spec.max_displacement);
    let clip = clip_normal(spec.crack_normal);
    let n = spec.crack_normal;
    // The camera looks at the cut face, from above the crack plane.
    let eye: Vec<f64> = (0..3).map(|i| clip[i] + 0.6 * n[i] + 0.35 * (clip[(i + 1) % 3] + clip[(i + 2) % 3])).collect();
    let len = eye.iter().map(|v| v * v).sum::<f64>().sqrt();
    let distance = 5.0 * spec.crack_size.max(0.02 * spec.size).min(spec.size);
    let eye: Vec<f64> = eye.iter().map(|v| v / len * distance).collect();
    let colour = if spec.contact { "pressure" } else { "normal_opening" };
    let c = spec.crack_centre;
    let mut s = String::new();
    let _ = write!(
        s,
        r#"# {stem}_view.py, written by fissure {version}: the crack view of this run.
#   paraview --script={stem}_view.py
# The body block clipped by the plane through the crack with normal {clip:?} (translucent, grey
# by von_mises), the crack lips coloured by `{colour}`, both warped by the displacement with
# scale {scale:e} (the largest displacement drawn as at most 5% of the model's size: the
# cells stay right side out), at the last load step.
import os

from paraview.simple import *

PVD = {pvd:?}
RUN_DIR = {abs_dir:?}
WARP = {scale:e}
CENTRE = [{c0:e}, {c1:e}, {c2:e}]
CLIP_NORMAL = [{k0}, {k1}, {k2}]
EYE = [{e0:e}, {e1:e}, {e2:e}]
COLOUR = {colour:?}

here = os.path.dirname(os.path.abspath(__file__)) if "__file__" in globals() else RUN_DIR
if not os.path.exists(os.path.join(here, PVD)):
    here = RUN_DIR
reader = PVDReader(registrationName=PVD, FileName=os.path.join(here, PVD))
reader.UpdatePipelineInformation()
times = list(reader.TimestepValues) if hasattr(reader.TimestepValues, "__len__") else [reader.TimestepValues]
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
if times:
    scene.AnimationTime = times[-1]
view = GetActiveViewOrCreate("RenderView")
LoadPalette("WhiteBackground")
view.OrientationAxesVisibility = 1

body = ExtractBlock(registrationName="body", Input=reader, Selectors=["/Root/body"])
body_warped = WarpByVector(registrationName="body warped", Input=body, Vectors=["POINTS", "displacement"], ScaleFactor=WARP)
body_clipped = Clip(registrationName="body clipped", Input=body_warped, ClipType="Plane")
body_clipped.ClipType.Origin = CENTRE
body_clipped.ClipType.Normal = CLIP_NORMAL
body_shown = Show(body_clipped, view)
ColorBy(body_shown, ("CELLS", "von_mises"))
# The colour range: the lower third of von_mises (the tip values are singular).
vm = body_clipped.CellData["von_mises"].GetRange()
GetColorTransferFunction("von_mises").RescaleTransferFunction(vm[0], vm[0] + (vm[1] - vm[0]) / 3.0)
GetColorTransferFunction("von_mises").ApplyPreset("Grayscale", True)
body_shown.SetScalarBarVisibility(view, False)
body_shown.Opacity = 0.6

crack = ExtractBlock(registrationName="crack", Input=reader, Selectors=["/Root/crack"])
crack_warped = WarpByVector(registrationName="crack warped", Input=crack, Vectors=["POINTS", "displacement"], ScaleFactor=WARP)
crack_shown = Show(crack_warped, view)
ColorBy(crack_shown, ("POINTS", COLOUR))
crack_shown.RescaleTransferFunctionToDataRange(True, False)
crack_shown.SetScalarBarVisibility(view, True)

# The camera looks at the crack from a few crack sizes away, above its plane.
view.CameraFocalPoint = CENTRE
view.CameraPosition = [CENTRE[i] + EYE[i] for i in range(3)]
view.CameraViewUp = [{n0}, {n1}, {n2}]
view.CameraViewAngle = 30
SetActiveSource(crack_warped)
Render(view)
"#,
        stem = spec.stem,
        version = crate::VERSION,
        pvd = spec.pvd,
        abs_dir = abs_dir.display().to_string(),
        c0 = c[0],
        c1 = c[1],
        c2 = c[2],
        k0 = clip[0],
        k1 = clip[1],
        k2 = clip[2],
        e0 = eye[0],
        e1 = eye[1],
        e2 = eye[2],
        n0 = n[0],
        n1 = n[1],
        n2 = n[2],
    );
    let path = dir.join(format!("{}_view.py", spec.stem));
    std::fs::write(&path, s)?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_warp_scale_keeps_the_cells_right_side_out() {
        // Largest displacement 1e-3 in a model of size 2: 5% of the size is 0.1, scale 100.
        assert_eq!(warp_scale(2.0, 1e-3), 100.0);
        // Rounded down to 1-2-5: 0.1 / 3e-3 = 33.3 -> 20; 0.1 / 0.6 = 0.167 -> 0.1.
        assert_eq!(warp_scale(2.0, 3e-3), 20.0);
        assert!((warp_scale(2.0, 0.6) - 0.1).abs() < 1e-15);
        assert_eq!(warp_scale(2.0, 0.0), 1.0);
        assert_eq!(clip_normal([0.0, 0.0, 1.0]), [1.0, 0.0, 0.0]);
        assert_eq!(clip_normal([1e-17, 1.0, 0.0]), [1.0, 0.0, 0.0]);
    }
}
