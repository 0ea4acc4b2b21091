// Half-disc {x^2 + (y-1)^2 <= 1, y <= 1}: flat side "top" on y = 1, curved side "arc",
// mesh size 0.05, refined towards the bottom point (0, 0) (the Hertz contact point).
// Regenerate (Gmsh 4.x): gmsh -2 -format msh41 half_disc.geo -o half_disc.msh
h = 0.05;
h_contact = 0.01;
Point(1) = {0, 1, 0, h};          // centre
Point(2) = {-1, 1, 0, h};         // left end of the flat side
Point(3) = {0, 0, 0, h_contact};  // bottom point
Point(4) = {1, 1, 0, h};          // right end of the flat side
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Line(3) = {4, 2};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};
// Size grows linearly with the distance from the bottom point, from h_contact to h.
Field[1] = Distance;
Field[1].PointsList = {3};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_contact;
Field[2].SizeMax = h;
Field[2].DistMin = 0.02;
Field[2].DistMax = 0.4;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Physical Curve("arc") = {1, 2};
Physical Curve("top") = {3};
Physical Surface("body") = {1};
