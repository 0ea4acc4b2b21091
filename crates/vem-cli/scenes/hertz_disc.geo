// The indenter of the Hertz scenes: the half-disc {x^2 + (y-1)^2 <= 1, y <= 1} of radius
// R = 1, flat side "top" on y = 1, curved side "arc" touching y = 0 at the point (0, 0).
// Adapted from crates/vem-mesh/tests/data/half_disc.geo: the mesh size is h_contact within
// 0.12 of the contact point (the whole contact zone of the scenes, a ~ 0.1) and grows
// linearly to h at distance 0.5.
// Regenerate (Gmsh 4.x; CI never runs gmsh, the .msh is committed):
//   gmsh -2 -format msh41 hertz_disc.geo -o hertz_disc.msh
h = 0.08;
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
Field[1] = Distance;
Field[1].PointsList = {3};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_contact;
Field[2].SizeMax = h;
Field[2].DistMin = 0.12;
Field[2].DistMax = 0.5;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Physical Curve("arc") = {1, 2};
Physical Curve("top") = {3};
Physical Surface("body") = {1};
