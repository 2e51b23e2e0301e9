// The drilled beam of Bittencourt, Wawrzynek, Ingraffea & Sousa (1996; experiments of
// Ingraffea & Grigoriu 1990), 2D, inches: the beam [0, 20] x [0, 8] with three holes of
// diameter 0.5 at x = 6, centres y = 2.75, 4.75, 6.75; supports at (1, 0) (pin) and
// (19, 0) (roller); the load on the top, on a patch of width w_load centred on x = 10.
// The pre-crack is not meshed: it is placed by level sets in the case (a half_line from
// the bottom edge at x = 4 or x = 5), so one mesh serves both configurations.
// Mesh size hf in the band x in [x_lo, x_hi] (the paths of both configurations, from the
// notches to the load point, with the holes), hf_hole on the holes, growing to hmax
// outside the band over the distance d_grow.
// gmsh -2 -format msh41 drilled_beam.geo -o drilled_beam.msh
// gmsh -2 -format msh41 -setnumber hf 0.1 drilled_beam.geo -o drilled_beam_coarse.msh
L = 20.0;
H = 8.0;
r = 0.25;
x_hole = 6.0;
If (!Exists(hf))
  hf = 0.05;
EndIf
hf_hole = 0.8 * hf;
hmax = 0.5;
x_lo = 3.5;
x_hi = 10.5;
d_grow = 2.0;
w_load = 0.2;
// Outline, counter-clockwise, with the support points and the load patch on it.
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};                    // pin
Point(3) = {19, 0, 0};                   // roller
Point(4) = {L, 0, 0};
Point(5) = {L, H, 0};
Point(6) = {10 + 0.5 * w_load, H, 0};
Point(7) = {10 - 0.5 * w_load, H, 0};
Point(8) = {0, H, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 7};                        // load patch
Line(7) = {7, 8};
Line(8) = {8, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
// Holes (bottom, middle, top), each two half circles.
ys[] = {2.75, 4.75, 6.75};
For k In {0 : 2}
  c = newp; Point(c) = {x_hole, ys[k], 0};
  p1 = newp; Point(p1) = {x_hole, ys[k] - r, 0};
  p2 = newp; Point(p2) = {x_hole, ys[k] + r, 0};
  a1 = newc; Circle(a1) = {p1, c, p2};
  a2 = newc; Circle(a2) = {p2, c, p1};
  hole[k] = 2 + k; Curve Loop(hole[k]) = {a1, a2};
  arcs~{k}[] = {a1, a2};
EndFor
Plane Surface(1) = {1, hole[0], hole[1], hole[2]};
// Sizes: hf in the band, hf_hole on the holes, hmax away from them.
Field[1] = Box;
Field[1].XMin = x_lo;
Field[1].XMax = x_hi;
Field[1].YMin = -1;
Field[1].YMax = H + 1;
Field[1].VIn = hf;
Field[1].VOut = hmax;
Field[1].Thickness = d_grow;
Field[2] = Distance;
Field[2].CurvesList = {arcs~{0}[], arcs~{1}[], arcs~{2}[]};
Field[3] = Threshold;
Field[3].InField = 2;
Field[3].SizeMin = hf_hole;
Field[3].SizeMax = hmax;
Field[3].DistMin = 0.1;
Field[3].DistMax = 1.0;
Field[4] = Min;
Field[4].FieldsList = {1, 3};
Background Field = 4;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Physical Surface("beam") = {1};
Physical Curve("bottom") = {1, 2, 3};
Physical Curve("right") = {4};
Physical Curve("top") = {5, 7};
Physical Curve("load") = {6};
Physical Curve("left") = {8};
Physical Curve("hole_bottom") = {arcs~{0}[]};
Physical Curve("hole_middle") = {arcs~{1}[]};
Physical Curve("hole_top") = {arcs~{2}[]};
Physical Point("pin") = {2};
Physical Point("roller") = {3};
