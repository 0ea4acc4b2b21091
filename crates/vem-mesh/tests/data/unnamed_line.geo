// Broken fixture: the physical curve group 5 has no name.
// Regenerate (Gmsh 4.x): gmsh -2 -format msh41 unnamed_line.geo -o unnamed_line.msh
Point(1) = {0, 0, 0, 0.5};
Point(2) = {1, 0, 0, 0.5};
Point(3) = {1, 1, 0, 0.5};
Point(4) = {0, 1, 0, 0.5};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("bottom", 1) = {1};
Physical Curve(5) = {3};
Physical Surface("body", 2) = {1};
