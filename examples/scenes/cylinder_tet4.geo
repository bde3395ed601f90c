// A solid cylinder (radius 0.05 m, length 0.05 m, axis along z) meshed with Tet4 by gmsh
// (unstructured, size 0.02 m): the lateral surface is the candidate contact boundary.
//   gmsh -3 -format msh4 cylinder_tet4.geo -o cylinder_tet4.msh
SetFactory("OpenCASCADE");
Cylinder(1) = {0, 0, 0, 0, 0, 0.05, 0.05};
Mesh.MeshSizeMin = 0.02;
Mesh.MeshSizeMax = 0.02;
Physical Volume("body") = {1};
Physical Surface("contact") = {1};   // the lateral surface (OpenCASCADE numbers it first)
