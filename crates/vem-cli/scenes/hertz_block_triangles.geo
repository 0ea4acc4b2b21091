// The foundation of the Hertz scenes in triangles (the locking tests of
// crates/vem-scene/tests/locking.rs): the block [-2, 2] x [-2, 0] ("left", "right",
// "bottom", "top"), triangles, mesh size h_contact within 0.12 of the contact point
// (0, 0) on its top side, growing linearly to h at distance 1.
// Regenerate (Gmsh 4.x; CI never runs gmsh, the .msh is committed):
//   gmsh -2 -format msh41 hertz_block_triangles.geo -o hertz_block_triangles.msh
h = 0.25;
h_contact = 0.01;
Point(1) = {-2, -2, 0, h};
Point(2) = {2, -2, 0, h};
Point(3) = {2, 0, 0, h};
Point(4) = {0, 0, 0, h_contact};  // contact point
Point(5) = {-2, 0, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Field[1] = Distance;
Field[1].PointsList = {4};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_contact;
Field[2].SizeMax = h;
Field[2].DistMin = 0.12;
Field[2].DistMax = 1.0;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3, 4};
Physical Curve("left") = {5};
Physical Surface("body") = {1};
