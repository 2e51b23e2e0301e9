// A penny crack for `shape = "mesh"`: the disc of radius 1 in the plane z = 0, centred at
// the origin, in triangles of size 0.05 (126 edges on the front circle, whose chords lie
// within 1 - cos(pi/126) = 3e-4 of the circle), with the front circle in the curve group
// "front". The normal of the first triangle (+z here) gives the + side.
// Generate:
//   gmsh -2 -format msh41 crack_disc.geo -o crack_disc.msh
SetFactory("OpenCASCADE");
Disk(1) = {0, 0, 0, 1.0};
Mesh.MeshSizeMin = 0.05;
Mesh.MeshSizeMax = 0.05;
Physical Surface("crack") = {1};
Physical Curve("front") = {1};
