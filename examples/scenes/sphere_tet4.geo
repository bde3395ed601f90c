// A solid sphere (radius 0.05 m) meshed with Tet4 by gmsh (unstructured, size 0.02 m): its
// surface is the candidate contact boundary.
//   gmsh -3 -format msh4 sphere_tet4.geo -o sphere_tet4.msh
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 0.05};
Mesh.MeshSizeMin = 0.02;
Mesh.MeshSizeMax = 0.02;
Physical Volume("body") = {1};
Physical Surface("contact") = {1};
