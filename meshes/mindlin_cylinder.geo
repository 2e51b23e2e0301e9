// Cattaneo-Mindlin: an elastic half disc of radius R = 1 centred at (0, R) (flat top edge
// y = R, the diameter) on the block [-5, 5] x [-5, 0], touching at the origin; full model
// (the tangential load breaks the symmetry). Contact arc: 30 degrees on each side of the
// bottom point. No node shared between the bodies.
// gmsh -2 -format msh41 mindlin_cylinder.geo -o mindlin_cylinder.msh
R = 1.0;
L = 5.0;
If (!Exists(h_c))
  h_c = 0.005;
EndIf
r_fine = 0.16;
a = 30 * Pi / 180;
Point(1) = {0, R, 0};
Point(2) = {0, 0, 0};
Point(3) = {R * Sin(a), R - R * Cos(a), 0};
Point(4) = {R, R, 0};
Point(5) = {-R * Sin(a), R - R * Cos(a), 0};
Point(6) = {-R, R, 0};
Circle(1) = {5, 1, 2};
Circle(2) = {2, 1, 3};
Circle(3) = {3, 1, 4};
Line(4) = {4, 6};
Circle(5) = {6, 1, 5};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Point(11) = {-L, 0, 0};
Point(12) = {L, 0, 0};
Point(13) = {L, -L, 0};
Point(14) = {-L, -L, 0};
Line(11) = {11, 12};
Line(12) = {12, 13};
Line(13) = {13, 14};
Line(14) = {14, 11};
Curve Loop(2) = {-11, -14, -13, -12};  // counter-clockwise: positive cells
Plane Surface(2) = {2};
Field[1] = Distance;
Field[1].PointsList = {2};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_c;
Field[2].SizeMax = 0.5;
Field[2].DistMin = r_fine;
Field[2].DistMax = 4.0;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Physical Surface("cylinder") = {1};
Physical Surface("block") = {2};
Physical Curve("cylinder_contact") = {1, 2};
Physical Curve("cylinder_top") = {4};
Physical Curve("block_top") = {11};
Physical Curve("block_bottom") = {13};
