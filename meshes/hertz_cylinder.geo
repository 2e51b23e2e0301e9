// Hertz contact of a cylinder on a plane, 2D plane strain, half model (x >= 0).
// Cylinder: the quarter disc of radius R = 1 centred at (0, R): contact arc from the
// bottom point (0, 0) to 30 degrees, then the rest of the arc to (R, R), the loaded top
// edge y = R and the symmetry edge x = 0. Block: [0, 5] x [-5, 0], its top y = 0 touching
// the cylinder at the origin (no node shared: the two bodies are separate surfaces).
// Mesh size h_c within r_fine of the contact point, growing to the far sizes.
// gmsh -2 -format msh41 hertz_cylinder.geo -o hertz_cylinder.msh
R = 1.0;
L = 5.0;
If (!Exists(h_c))
  h_c = 0.004;
EndIf
r_fine = 0.16;
a = 30 * Pi / 180;
// Cylinder.
Point(1) = {0, R, 0};                              // centre
Point(2) = {0, 0, 0};                              // bottom (contact) point
Point(3) = {R * Sin(a), R - R * Cos(a), 0};        // end of the contact arc
Point(4) = {R, R, 0};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Line(3) = {4, 1};
Line(4) = {1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
// Block.
Point(11) = {0, 0, 0};
Point(12) = {L, 0, 0};
Point(13) = {L, -L, 0};
Point(14) = {0, -L, 0};
Line(11) = {11, 12};
Line(12) = {12, 13};
Line(13) = {13, 14};
Line(14) = {14, 11};
Curve Loop(2) = {-11, -14, -13, -12};  // counter-clockwise: positive cells
Plane Surface(2) = {2};
// Sizes: fine around the contact point, coarse far from it.
Field[1] = Distance;
Field[1].PointsList = {2, 11};
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
Physical Curve("cylinder_contact") = {1};
Physical Curve("cylinder_top") = {3};
Physical Curve("cylinder_axis") = {4};
Physical Curve("block_top") = {11};
Physical Curve("block_axis") = {14};
Physical Curve("block_bottom") = {13};
