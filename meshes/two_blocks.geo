// Two blocks stacked along y that share no nodes (bodies of a contact pair):
// lower [0, 1] x [0, 1] (8 x 8 quads), upper [0, 1] x [1, 2] (5 x 5 quads), non-matching
// along y = 1. Physical groups: surfaces "lower", "upper"; curves "lower_bottom",
// "lower_top", "upper_bottom", "upper_top", "lower_left", "upper_left".
// gmsh -2 -format msh41 two_blocks.geo -o two_blocks.msh
Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};
Point(5) = {0, 1, 0}; Point(6) = {1, 1, 0}; Point(7) = {1, 2, 0}; Point(8) = {0, 2, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Transfinite Curve{1, 2, 3, 4} = 9; Transfinite Surface{1}; Recombine Surface{1};
Transfinite Curve{5, 6, 7, 8} = 6; Transfinite Surface{2}; Recombine Surface{2};
Physical Surface("lower") = {1};
Physical Surface("upper") = {2};
Physical Curve("lower_bottom") = {1};
Physical Curve("lower_top") = {3};
Physical Curve("lower_left") = {4};
Physical Curve("upper_bottom") = {5};
Physical Curve("upper_top") = {7};
Physical Curve("upper_left") = {8};
