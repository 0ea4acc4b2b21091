// Unit square split at x = 0.5: structured quadrangles on the left, triangles on the right,
// conforming along x = 0.5. The physical point "probe" lies outside the square: its node is
// used by no 2D element and must be dropped by the reader. Regenerate (Gmsh 4.x):
//   gmsh -2 -format msh41 mixed.geo -o mixed.msh
Point(1) = {0, 0, 0};
Point(2) = {0.5, 0, 0};
Point(3) = {1, 0, 0};
Point(4) = {1, 1, 0};
Point(5) = {0.5, 1, 0};
Point(6) = {0, 1, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Line(7) = {2, 5};
Curve Loop(1) = {1, 7, 5, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {2, 3, 4, -7};
Plane Surface(2) = {2};
Transfinite Curve{1, 5} = 3;
Transfinite Curve{6, 7} = 5;
Transfinite Surface{1};
Recombine Surface{1};
Transfinite Curve{2, 4} = 3;
Transfinite Curve{3} = 5;
Physical Curve("bottom") = {1, 2};
Physical Curve("right") = {3};
Physical Curve("top") = {4, 5};
Physical Curve("left") = {6};
Physical Surface("body") = {1, 2};
Point(7) = {2, 0.5, 0};
Physical Point("probe") = {7};
