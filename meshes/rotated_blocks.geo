// The stacked blocks of the contact patch test, rotated by theta (degrees) about the
// origin, so that their common face is inclined: lower [0, 1] x [0, 1] (nl x nl quad4),
// upper [0, 1] x [1, 2] (nu x nu quad4) before the rotation; no node shared, non-matching
// along the common face. Physical groups: surfaces "lower", "upper"; curves
// "lower_bottom", "lower_top", "lower_left", "upper_bottom", "upper_top", "upper_left".
// gmsh -2 -format msh41 -setnumber nl 4 -setnumber nu 6 rotated_blocks.geo -o rotated_blocks_4_6.msh
Geometry.AutoCoherence = 0;  // keep the two bodies apart (no merged points)
If (!Exists(nl))
  nl = 4;
EndIf
If (!Exists(nu))
  nu = 6;
EndIf
If (!Exists(theta))
  theta = 30;
EndIf
Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};
Point(5) = {0, 1, 0}; Point(6) = {1, 1, 0}; Point(7) = {1, 2, 0}; Point(8) = {0, 2, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Transfinite Curve{1, 2, 3, 4} = nl + 1; Transfinite Surface{1}; Recombine Surface{1};
Transfinite Curve{5, 6, 7, 8} = nu + 1; Transfinite Surface{2}; Recombine Surface{2};
Rotate {{0, 0, 1}, {0, 0, 0}, theta * Pi / 180} { Surface{1, 2}; }
Physical Surface("lower") = {1};
Physical Surface("upper") = {2};
Physical Curve("lower_bottom") = {1};
Physical Curve("lower_top") = {3};
Physical Curve("lower_left") = {4};
Physical Curve("upper_bottom") = {5};
Physical Curve("upper_top") = {7};
Physical Curve("upper_left") = {8};
