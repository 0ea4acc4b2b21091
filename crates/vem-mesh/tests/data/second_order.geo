// Broken fixture: second-order triangles (element type 9), which the reader rejects.
// Regenerate (Gmsh 4.x): gmsh -2 -order 2 -format msh41 second_order.geo -o second_order.msh
Point(1) = {0, 0, 0, 0.5};
Point(2) = {1, 0, 0, 0.5};
Point(3) = {1, 1, 0, 0.5};
Point(4) = {0, 1, 0, 0.5};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(7) = {1};
Physical Curve("boundary") = {1, 2, 3, 4};
Physical Surface("body") = {7};
