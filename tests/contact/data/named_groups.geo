// A 1 m x 0.2 m block whose boundary groups carry the mesher's own names (not the roles
// fixed / load / contact): a scene maps them with [geometry] groups = {...}.
// gmsh -2 -format msh41 named_groups.geo -o named_groups.msh
h = 0.1;
Point(1) = {0, 0, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {1, 0.2, 0, h};
Point(4) = {0, 0.2, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("Base line") = {1};
Physical Curve("Clamp") = {3};
Physical Curve("Right side") = {2};
Physical Surface("Steel") = {1};
