// Block, 3D, linear tetrahedra (tet4).
// x in [0, 2], y in [0, 1], z in [0, 1]; exact volume 2.
// Groups as in src/mesh/generate.rs: left x = 0, right x = 2, bottom y = 0,
// top y = 1, back z = 0, front z = 1; the volume is "domain".
// Generate:
//   gmsh -3 -format msh41 block.geo -o block.msh
//   gmsh -3 -format msh41 -bin block.geo -o block_binary.msh
SetFactory("Built-in");

Lx = 2.0; Ly = 1.0; Lz = 1.0;
lc = 0.15;

Point(1) = {0,  0,  0,  lc};
Point(2) = {Lx, 0,  0,  lc};
Point(3) = {Lx, Ly, 0,  lc};
Point(4) = {0,  Ly, 0,  lc};
Point(5) = {0,  0,  Lz, lc};
Point(6) = {Lx, 0,  Lz, lc};
Point(7) = {Lx, Ly, Lz, lc};
Point(8) = {0,  Ly, Lz, lc};

Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};   // z = 0
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};   // z = Lz
Line(9) = {1, 5}; Line(10) = {2, 6}; Line(11) = {3, 7}; Line(12) = {4, 8};

// Loops oriented with outward normals.
Curve Loop(1) = {-4, -3, -2, -1};  Plane Surface(1) = {1};   // back   z = 0
Curve Loop(2) = {5, 6, 7, 8};      Plane Surface(2) = {2};   // front  z = Lz
Curve Loop(3) = {1, 10, -5, -9};   Plane Surface(3) = {3};   // bottom y = 0
Curve Loop(4) = {3, 12, -7, -11};  Plane Surface(4) = {4};   // top    y = Ly
Curve Loop(5) = {9, -8, -12, 4};   Plane Surface(5) = {5};   // left   x = 0
Curve Loop(6) = {2, 11, -6, -10};  Plane Surface(6) = {6};   // right  x = Lx

Surface Loop(1) = {1, 2, 3, 4, 5, 6};
Volume(1) = {1};

Physical Volume("domain") = {1};
Physical Surface("left") = {5};
Physical Surface("right") = {6};
Physical Surface("bottom") = {3};
Physical Surface("top") = {4};
Physical Surface("back") = {1};
Physical Surface("front") = {2};
