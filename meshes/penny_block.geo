// Block [-5, 5]^3 (side 10 a for a penny crack of radius a = 1 in the plane z = 0),
// linear tetrahedra (tet4) graded towards the crack: size 0.09 within 0.25 of the front
// (the circle r = 1, z = 0), 0.1 within 0.3 of the crack disc, growing to 0.7 beyond 4.
// The far field must not be coarse: the crack's compliance (hence K) depends on the
// stiffness of the body within a few radii (with 1.2 there, the opening was 10% low).
// Groups: "domain" (volume), "left", "right", "bottom", "top", "back", "front"
// (x = -5, x = 5, y = -5, y = 5, z = -5, z = 5, as the box generator names them).
// Generate:
//   gmsh -3 -format msh41 penny_block.geo -o penny_block.msh
SetFactory("OpenCASCADE");
Box(1) = {-5, -5, -5, 10, 10, 10};
Circle(100) = {0, 0, 0, 1.0, 0, 2*Pi};
Disk(200) = {0, 0, 0, 1.0};
Field[1] = Distance;
Field[1].CurvesList = {100};
Field[1].Sampling = 400;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = 0.09;
Field[2].SizeMax = 0.7;
Field[2].DistMin = 0.25;
Field[2].DistMax = 4.0;
Field[3] = Distance;
Field[3].SurfacesList = {200};
Field[3].Sampling = 60;
Field[4] = Threshold;
Field[4].InField = 3;
Field[4].SizeMin = 0.1;
Field[4].SizeMax = 0.7;
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
Physical Surface("left") = Surface In BoundingBox{-5-eps, -5-eps, -5-eps, -5+eps, 5+eps, 5+eps};
Physical Surface("right") = Surface In BoundingBox{5-eps, -5-eps, -5-eps, 5+eps, 5+eps, 5+eps};
Physical Surface("bottom") = Surface In BoundingBox{-5-eps, -5-eps, -5-eps, 5+eps, -5+eps, 5+eps};
Physical Surface("top") = Surface In BoundingBox{-5-eps, 5-eps, -5-eps, 5+eps, 5+eps, 5+eps};
Physical Surface("back") = Surface In BoundingBox{-5-eps, -5-eps, -5-eps, 5+eps, 5+eps, -5+eps};
Physical Surface("front") = Surface In BoundingBox{-5-eps, -5-eps, 5-eps, 5+eps, 5+eps, 5+eps};
