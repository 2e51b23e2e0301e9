// Plate with a semi-elliptical surface crack (Newman–Raju geometry), linear tetrahedra
// (tet4) graded towards the crack front. The crack itself is not meshed: fissure places it
// by level sets (`shape = "elliptic_disc"` centred on the face z = t, half of it outside
// the body, which fissure ignores).
//
// Plate: width 2b along x (x ∈ [−b, b]), height 2h along y (y ∈ [−h, h], the load
// direction), thickness t along z (z ∈ [0, t]). Crack in the plane y = 0, on the face
// z = t, depth a (along −z) and half-length c (along x): the front is
// x = c cos φ, z = t − a sin φ, 0 ≤ φ ≤ π (φ Newman–Raju's parametric angle).
// Defaults: a = c = 1, t = 5, b = h = 5 (a/c = 1, a/t = 0.2, c/b = 0.2), for
// tests/surface_crack_newman_raju.rs; needs c ≥ a (the ellipse's major axis along x).
//
// Grading (the technique of penny_block.geo): a Distance field to the whole ellipse (its
// outer half lies outside the plate and only refines what is near the front's ends) and
// one to the crack's elliptic disc; Threshold fields give size hf within 0.25 of the front
// and hd within 0.3 of the crack surface, growing to hmax 4 away.
//
// Groups: "domain" (volume), "left", "right", "bottom", "top", "back", "front"
// (x = −b, x = b, y = −h, y = h, z = 0, z = t, as the box generator names them; the crack
// opens in "front").
//
// Generate (gmsh 4.8.4; from gmsh 4.11 the Distance option `NumPointsPerCurve` is named
// `Sampling`):
//   gmsh -3 -format msh41 surface_crack_plate.geo -o surface_crack_plate.msh
//   gmsh -3 -format msh41 -setnumber hf 0.2 -setnumber hd 0.25 -setnumber hmax 1.0 \
//        surface_crack_plate.geo -o surface_crack_plate_coarse.msh
// Any parameter can be set the same way (-setnumber a 0.5 -setnumber t 2.5 ...).
SetFactory("OpenCASCADE");
DefineConstant[ a = 1.0, c = 1.0, t = 5.0, b = 5.0, h = 5.0, hf = 0.09, hd = 0.12, hmax = 0.8 ];
Box(1) = {-b, -h, 0, 2*b, 2*h, t};
// The front ellipse and the crack disc, drawn in the plane z = t and turned into y = 0.
If (a == c)
  Circle(100) = {0, 0, t, c, 0, 2*Pi};
  Disk(200) = {0, 0, t, c};
Else
  Ellipse(100) = {0, 0, t, c, a, 0, 2*Pi};
  Disk(200) = {0, 0, t, c, a};
EndIf
Rotate {{1, 0, 0}, {0, 0, t}, Pi/2} { Curve{100}; Surface{200}; }
Field[1] = Distance;
Field[1].CurvesList = {100};
Field[1].NumPointsPerCurve = 400;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hf;
Field[2].SizeMax = hmax;
Field[2].DistMin = 0.25;
Field[2].DistMax = 4.0;
Field[3] = Distance;
Field[3].SurfacesList = {200};
Field[3].NumPointsPerCurve = 60;
Field[4] = Threshold;
Field[4].InField = 3;
Field[4].SizeMin = hd;
Field[4].SizeMax = hmax;
Field[4].DistMin = 0.3;
Field[4].DistMax = 4.0;
Field[5] = Min;
Field[5].FieldsList = {2, 4};
Background Field = 5;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Optimize = 1;
eps = 1e-6;
Physical Volume("domain") = {1};
Physical Surface("left") = Surface In BoundingBox{-b-eps, -h-eps, -eps, -b+eps, h+eps, t+eps};
Physical Surface("right") = Surface In BoundingBox{b-eps, -h-eps, -eps, b+eps, h+eps, t+eps};
Physical Surface("bottom") = Surface In BoundingBox{-b-eps, -h-eps, -eps, b+eps, -h+eps, t+eps};
Physical Surface("top") = Surface In BoundingBox{-b-eps, h-eps, -eps, b+eps, h+eps, t+eps};
Physical Surface("back") = Surface In BoundingBox{-b-eps, -h-eps, -eps, b+eps, h+eps, eps};
Physical Surface("front") = Surface In BoundingBox{-b-eps, -h-eps, t-eps, b+eps, h+eps, t+eps};
