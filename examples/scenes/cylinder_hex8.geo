// A solid cylinder (radius 0.05 m, length 0.05 m, axis along z) meshed with Hex8: the disc
// meshed with unstructured quads (gmsh's Blossom recombination), extruded in 3 layers.
//   gmsh -3 -format msh4 cylinder_hex8.geo -o cylinder_hex8.msh
SetFactory("OpenCASCADE");
Disk(1) = {0, 0, 0, 0.05, 0.05};
Mesh.MeshSizeMin = 0.014;
Mesh.MeshSizeMax = 0.014;


Recombine Surface{1};
out[] = Extrude {0, 0, 0.05} { Surface{1}; Layers{3}; Recombine; };
Physical Volume("body") = {out[1]};
Physical Surface("contact") = {out[2]};   // the lateral surface
