// A straight 2D crack for `shape = "mesh"`: the segment from a = (-0.31, -0.207) to
// b = (0.343, 0.251) in 7 line elements (direction a -> b, so the + side is on the left,
// as for `shape = "segment"`; the ends lie off the nodes and edges of the 60 x 60
// test mesh of [-1, 1]^2), with its two tips in the point group "tips".
// Generate:
//   gmsh -1 -format msh41 crack_segment.geo -o crack_segment.msh
Point(1) = {-0.31, -0.207, 0};
Point(2) = {0.343, 0.251, 0};
Line(1) = {1, 2};
Transfinite Curve{1} = 8;
Physical Curve("crack") = {1};
Physical Point("tips") = {1, 2};
