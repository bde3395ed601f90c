// A solid half cylinder (radius 0.05 m, length 0.05 m, axis along z through the origin, the
// half y <= 0) meshed with Tet4 by gmsh (unstructured, size 9 mm): the curved surface is the
// candidate contact boundary (a rocker: it rests and rolls on its curved face).
//   gmsh -3 -format msh4 rocker_tet4.geo -o rocker_tet4.msh
SetFactory("OpenCASCADE");
Cylinder(1) = {0, 0, 0, 0, 0, 0.05, 0.05};
Box(2) = {-0.06, 0, -0.01, 0.12, 0.07, 0.07};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Mesh.MeshSizeMin = 0.009;
Mesh.MeshSizeMax = 0.009;
Physical Volume("body") = {3};
Physical Surface("contact") = {1};   // the curved surface (OpenCASCADE numbers it first)
