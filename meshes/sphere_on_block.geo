// Hertz contact of a sphere on a block, 3D, quarter model (x >= 0, z >= 0).
// Sphere body: the ball of radius R centred at (0, R, 0) cut to the box
// [0, L] x [0, R] x [0, L]: its lower face is the spherical cap, touching the block's top
// at the origin; its top is the plane y = R. Block: [0, L] x [-H, 0] x [0, L].
// Tetrahedra of size h_c within r_fine of the contact point, growing to h_far.
// gmsh -3 -format msh41 -nt 1 sphere_on_block.geo -o sphere_on_block.msh (gmsh 4.8.4)
SetFactory("OpenCASCADE");
R = 1.0;
L = 0.6;
H = 0.6;
If (!Exists(h_c))
  h_c = 0.01;
EndIf
h_far = 0.15;
r_fine = 0.12;
Sphere(1) = {0, R, 0, R};
Box(2) = {0, 0, 0, L, R, L};
BooleanIntersection(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Box(4) = {0, -H, 0, L, H, L};
e = 1e-6;
origin() = Point In BoundingBox {-e, -e, -e, e, e, e};
Field[1] = Distance;
Field[1].PointsList = {origin()};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_c;
Field[2].SizeMax = h_far;
Field[2].DistMin = r_fine;
Field[2].DistMax = 0.6;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Physical Volume("sphere") = {3};
Physical Volume("block") = {4};
// Sphere faces: the cap (below y = R, not on a symmetry plane), top, x = 0, z = 0.
Physical Surface("sphere_top") = Surface In BoundingBox {-e, R - e, -e, L + e, R + e, L + e};
Physical Surface("sphere_x0") = Surface In BoundingBox {-e, -e, -e, e, R + e, L + e};
Physical Surface("sphere_z0") = Surface In BoundingBox {-e, -e, -e, L + e, R + e, e};
cap() = Boundary{ Volume{3}; };
cap() -= Surface In BoundingBox {-e, R - e, -e, L + e, R + e, L + e};
cap() -= Surface In BoundingBox {-e, -e, -e, e, R + e, L + e};
cap() -= Surface In BoundingBox {-e, -e, -e, L + e, R + e, e};
Physical Surface("sphere_cap") = cap();
blk() = Boundary{ Volume{4}; };
Physical Surface("block_top") = Surface In BoundingBox {-e, -e, -e, L + e, e, L + e};
Physical Surface("block_bottom") = Surface In BoundingBox {-e, -H - e, -e, L + e, -H + e, L + e};
Physical Surface("block_x0") = Surface In BoundingBox {-e, -H - e, -e, e, e, L + e};
Physical Surface("block_z0") = Surface In BoundingBox {-e, -H - e, -e, L + e, e, e};
