// The block of the Hertz scene in space: [-1, 1] x [-1, 1] x [-1, 0], its top "top" on z = 0
// where the ball of hertz3d_ball.geo touches it at the origin. The mesh size is h_contact
// within 0.15 of the origin and grows linearly to h at distance 0.6.
// Regenerate (Gmsh 4.x, through scripts/hertz3d-meshes.sh; CI never runs gmsh, the .msh is
// committed).
SetFactory("OpenCASCADE");
h = 0.25;
h_contact = 0.02;
Box(1) = {-1, -1, -1, 2, 2, 1};
Field[1] = MathEval;
Field[1].F = Sprintf("Min(%g, %g + Max(0, Sqrt(x*x + y*y + z*z) - 0.15) * (%g - %g) / 0.45)", h, h_contact, h, h_contact);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
// The faces of an OpenCASCADE box: 1, 2 at x = -1, 1; 3, 4 at y = -1, 1; 5, 6 at z = -1, 0.
Physical Surface("top") = {6};
Physical Surface("bottom") = {5};
Physical Surface("sides") = {1, 2, 3, 4};
Physical Volume("block") = {1};
