// Quarter of a thick cylinder cross-section, 2D, structured linear quadrilaterals (quad4).
// Annulus 1 <= r <= 2, x >= 0, y >= 0 (Lamé problem: inner/outer pressure,
// symmetry on the two straight edges). Exact area: 3 pi / 4.
// 30 elements through the thickness, 60 along each arc (1800 quads).
// Groups: "domain" (surface), "inner" (r = 1 arc), "outer" (r = 2 arc),
// "xsym" (the y = 0 edge), "ysym" (the x = 0 edge).
// Generate:
//   gmsh -2 -format msh41 thick_cylinder.geo -o thick_cylinder.msh
SetFactory("Built-in");

Ri = 1.0;
Ro = 2.0;
n_radial = 30;   // elements through the thickness
n_arc = 60;      // elements along each quarter arc

Point(1) = {0, 0, 0};    // centre (not a mesh node)
Point(2) = {Ri, 0, 0};
Point(3) = {Ro, 0, 0};
Point(4) = {0, Ro, 0};
Point(5) = {0, Ri, 0};

Line(1) = {2, 3};          // y = 0, from r = Ri to r = Ro
Circle(2) = {3, 1, 4};     // outer arc, counter-clockwise
Line(3) = {4, 5};          // x = 0, from r = Ro to r = Ri
Circle(4) = {5, 1, 2};     // inner arc, clockwise

Curve Loop(1) = {1, 2, 3, 4};   // counter-clockwise around the region
Plane Surface(1) = {1};         // normal +z: counter-clockwise cells

Transfinite Curve{1, 3} = n_radial + 1;
Transfinite Curve{2, 4} = n_arc + 1;
Transfinite Surface{1} = {2, 3, 4, 5};
Recombine Surface{1};

Physical Surface("domain") = {1};
Physical Curve("inner") = {4};
Physical Curve("outer") = {2};
Physical Curve("xsym") = {1};
Physical Curve("ysym") = {3};
