// Plate with a central circular hole, 2D, linear triangles (tri3).
// Plate x in [-5, 5], y in [-4, 4]; hole of radius 1 centred at the origin.
// Exact area: 80 - pi. Mesh size 0.1 on the hole, 0.5 on the outer edges.
// Generate:
//   gmsh -2 -format msh41 plate_with_hole.geo -o plate_with_hole.msh
//   gmsh -2 -format msh41 -bin plate_with_hole.geo -o plate_with_hole_binary.msh
SetFactory("Built-in");

W = 5.0;   // half width  (x)
H = 4.0;   // half height (y)
R = 1.0;   // hole radius
lc_out = 0.5;
lc_hole = 0.1;

Point(1) = {-W, -H, 0, lc_out};
Point(2) = { W, -H, 0, lc_out};
Point(3) = { W,  H, 0, lc_out};
Point(4) = {-W,  H, 0, lc_out};
Line(1) = {1, 2};   // bottom, y = -H
Line(2) = {2, 3};   // right,  x = +W
Line(3) = {3, 4};   // top,    y = +H
Line(4) = {4, 1};   // left,   x = -W

Point(5) = {0, 0, 0, lc_hole};   // hole centre (not a mesh node)
Point(6) = { R, 0, 0, lc_hole};
Point(7) = { 0, R, 0, lc_hole};
Point(8) = {-R, 0, 0, lc_hole};
Point(9) = { 0, -R, 0, lc_hole};
Circle(5) = {6, 5, 7};
Circle(6) = {7, 5, 8};
Circle(7) = {8, 5, 9};
Circle(8) = {9, 5, 6};

Curve Loop(1) = {1, 2, 3, 4};        // outer boundary, counter-clockwise
Curve Loop(2) = {5, 6, 7, 8};        // hole
Plane Surface(1) = {1, 2};           // normal +z: counter-clockwise triangles

Physical Surface("domain") = {1};
Physical Curve("left") = {4};
Physical Curve("right") = {2};
Physical Curve("bottom") = {1};
Physical Curve("top") = {3};
Physical Curve("hole") = {5, 6, 7, 8};
