// A unit square in a few triangles, written in the old MSH 2.2 format on purpose:
// fissure must reject it with a message naming the version.
// Generate:
//   gmsh -2 -format msh22 old_format_v22.geo -o old_format_v22.msh
SetFactory("Built-in");
Point(1) = {0, 0, 0, 1.0};
Point(2) = {1, 0, 0, 1.0};
Point(3) = {1, 1, 0, 1.0};
Point(4) = {0, 1, 0, 1.0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("domain") = {1};
Physical Curve("left") = {4};
