// The indenter of the Hertz scene in space: the lower half of the ball of radius R = 1
// centred at (0, 0, 1), flat side "top" on z = 1, curved side "sphere" touching z = 0 at the
// origin. The mesh size is h_contact within 0.15 of the contact point (the contact zone of
// the scene, a ~ 0.1) and grows linearly to h at distance 0.6. The ball is turned by 45
// degrees about x before it is cut, so that the poles of the sphere's parametrisation lie far
// from the contact point.
// Regenerate (Gmsh 4.x, through scripts/hertz3d-meshes.sh; CI never runs gmsh, the .msh is
// committed).
SetFactory("OpenCASCADE");
h = 0.25;
h_contact = 0.02;
Sphere(1) = {0, 0, 1, 1};
Rotate {{1, 0, 0}, {0, 0, 1}, Pi/4} { Volume{1}; }
Box(2) = {-2, -2, 1, 4, 4, 2};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Field[1] = MathEval;
Field[1].F = Sprintf("Min(%g, %g + Max(0, Sqrt(x*x + y*y + z*z) - 0.15) * (%g - %g) / 0.45)", h, h_contact, h, h_contact);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
top() = Surface In BoundingBox{-1.1, -1.1, 0.999, 1.1, 1.1, 1.001};
// (OpenCASCADE bounds the sphere's surface by the whole ball's box: up to z = 2.)
sphere() = Surface In BoundingBox{-1.1, -1.1, -0.1, 1.1, 1.1, 2.1};
sphere() -= {top()};
Physical Surface("top") = {top()};
Physical Surface("sphere") = {sphere()};
Physical Volume("ball") = {3};
