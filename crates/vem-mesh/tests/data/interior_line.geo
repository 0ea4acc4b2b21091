// Broken fixture: the physical curve "crack" (curve 5) runs through the interior of the
// square, so its line elements are not boundary edges.
// Regenerate (Gmsh 4.x): gmsh -2 -format msh41 interior_line.geo -o interior_line.msh
Point(1) = {0, 0, 0, 0.5};
Point(2) = {1, 0, 0, 0.5};
Point(3) = {1, 1, 0, 0.5};
Point(4) = {0, 1, 0, 0.5};
Point(5) = {0.3, 0.5, 0, 0.5};
Point(6) = {0.7, 0.5, 0, 0.5};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Line(5) = {5, 6};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve{5} In Surface{1};
Physical Curve("bottom") = {1};
Physical Curve("crack") = {5};
Physical Surface("body") = {1};
