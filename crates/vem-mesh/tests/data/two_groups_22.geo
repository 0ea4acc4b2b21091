// A unit square whose bottom side is in two physical curve groups ("a" and "b"), saved in MSH
// 2.2, where Gmsh writes the bottom line element once per group. Regenerate (Gmsh 4.x):
//   gmsh -2 -format msh22 two_groups_22.geo -o two_groups_22.msh
Point(1) = {0, 0, 0, 1};
Point(2) = {1, 0, 0, 1};
Point(3) = {1, 1, 0, 1};
Point(4) = {0, 1, 0, 1};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("a", 1) = {1};
Physical Curve("b", 2) = {1, 2};
Physical Surface("s", 3) = {1};
