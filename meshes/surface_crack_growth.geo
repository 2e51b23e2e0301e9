// Plate for a semi-elliptical surface crack grown in fatigue (tests/surface_crack_fatigue.rs,
// examples/surface_crack_fatigue_3d.toml): linear tetrahedra (tet4) of size hf over the whole
// region the front sweeps, so that every entry's front lies in cells of the same size.
// The crack itself is not meshed: fissure places it by level sets (an `elliptic_disc`
// centred on the face z = t, half of it outside the body) and grows it.
//
// Plate: x ∈ [−b, b] (width 2b), y ∈ [−h, h] (the load direction), z ∈ [0, t] (thickness t).
// Crack in the plane y = 0 on the face z = t. The front starts on the half ellipse of depth
// a0 = 0.6 and half-length c0 = 1 and grows (Paris, m = 3) towards a ≈ 1, c ≈ 1.33; the
// refined band is the half elliptic disc of semi-axes (c1, a1) = (1.55, 1.2) in y = 0,
// thickened by 0.25 on every side: size hf there, growing to hmax at 3 from it.
//
// Groups: "domain", "left", "right", "bottom", "top", "back", "front" (x = −b, x = b,
// y = −h, y = h, z = 0, z = t, as the box generator names them).
//
// Generate (gmsh 4.8.4; from gmsh 4.11 the Distance option `NumPointsPerCurve` is named
// `Sampling`):
//   gmsh -3 -format msh41 -nt 1 surface_crack_growth.geo -o surface_crack_growth.msh
//   gmsh -3 -format msh41 -nt 1 -setnumber hf 0.15 surface_crack_growth.geo -o surface_crack_growth_coarse.msh
SetFactory("OpenCASCADE");
DefineConstant[ c1 = 1.55, a1 = 1.2, t = 5.0, b = 5.0, h = 5.0, hf = 0.1, hmax = 0.8 ];
Box(1) = {-b, -h, 0, 2*b, 2*h, t};
// The band's elliptic disc, drawn in the plane z = t and turned into y = 0.
Disk(200) = {0, 0, t, c1, a1};
Rotate {{1, 0, 0}, {0, 0, t}, Pi/2} { Surface{200}; }
Field[1] = Distance;
Field[1].SurfacesList = {200};
Field[1].NumPointsPerCurve = 120;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hf;
Field[2].SizeMax = hmax;
Field[2].DistMin = 0.25;
Field[2].DistMax = 3.0;
Background Field = 2;
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
